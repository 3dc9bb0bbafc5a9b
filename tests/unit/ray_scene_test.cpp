// Tests of raycast/ray_scene.h on hand-made geometry whose hits are worked out by hand (a triangle
// and a quad in planes z = const, so the hit distance is a difference of z over the direction's z
// and the barycentrics are affine coordinates in the plane), the [tNear, tFar] limits of both
// queries, concurrent OpenMP queries against serial ones on an icosphere, and the 16-ray packet
// queries (occluded16, intersect16) against the single-ray ones (random rays, partial masks).
#include "geometry/primitive_meshes.h"
#include "raycast/ray_scene.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Triangle 0: a = (0,0,0), b = (1,0,0), c = (0,1,0) in the plane z = 0: the point (x, y, 0) has
// barycentrics u = x, v = y. Quad at z = -2 over [0,2] x [0,2], two triangles:
//   face 1: (0,0,-2) (2,0,-2) (2,2,-2): point (x, y) -> u = (x - y)/2, v = y/2
//   face 2: (0,0,-2) (2,2,-2) (0,2,-2): point (x, y) -> u = x/2, v = (y - x)/2
struct HandScene {
    std::vector<float> positions = {0, 0, 0,  1, 0, 0,  0, 1, 0,  0, 0, -2,  2, 0, -2,  2, 2, -2,  0, 2, -2};
    std::vector<std::uint32_t> faces = {0, 1, 2,  3, 4, 5,  3, 5, 6};
    rad::RayScene scene{positions.data(), positions.size() / 3, faces.data(), faces.size() / 3};
};

TEST(RayScene, HitDistanceFaceAndBarycentricsOnAHandMadeTriangle) {
    HandScene s;
    EXPECT_EQ(s.scene.faceCount(), 3u);
    const rad::RayHit hit = s.scene.intersect({0.2f, 0.3f, 1.0f}, {0, 0, -1}, 0.0f, kInf);
    ASSERT_TRUE(hit.hit);
    EXPECT_EQ(hit.face, 0u);
    EXPECT_NEAR(hit.distance, 1.0f, 1e-6f);
    EXPECT_NEAR(hit.u, 0.2f, 1e-6f);
    EXPECT_NEAR(hit.v, 0.3f, 1e-6f);

    // The distance is in units of the direction's length: direction (0, 0, -2) reaches z = 0 at t = 0.5.
    const rad::RayHit scaled = s.scene.intersect({0.2f, 0.3f, 1.0f}, {0, 0, -2}, 0.0f, kInf);
    ASSERT_TRUE(scaled.hit);
    EXPECT_NEAR(scaled.distance, 0.5f, 1e-6f);

    // An oblique ray: from (0.6, 0.1, 2) along (-0.2, 0.1, -1) it reaches z = 0 at t = 2, at
    // (0.2, 0.3): the same barycentrics.
    const rad::RayHit oblique = s.scene.intersect({0.6f, 0.1f, 2.0f}, {-0.2f, 0.1f, -1.0f}, 0.0f, kInf);
    ASSERT_TRUE(oblique.hit);
    EXPECT_EQ(oblique.face, 0u);
    EXPECT_NEAR(oblique.distance, 2.0f, 1e-5f);
    EXPECT_NEAR(oblique.u, 0.2f, 1e-5f);
    EXPECT_NEAR(oblique.v, 0.3f, 1e-5f);

    // Triangles are hit from both sides (no back-face culling: visibility needs both).
    const rad::RayHit below = s.scene.intersect({0.2f, 0.3f, -1.0f}, {0, 0, 1}, 0.0f, kInf);
    ASSERT_TRUE(below.hit);
    EXPECT_EQ(below.face, 0u);
    EXPECT_NEAR(below.distance, 1.0f, 1e-6f);

    // Missing rays: pointing away, or passing beside the triangle (x + y > 1) and the quad.
    EXPECT_FALSE(s.scene.intersect({0.2f, 0.3f, 1.0f}, {0, 0, 1}, 0.0f, kInf).hit);
    EXPECT_FALSE(s.scene.intersect({3.0f, 3.0f, 1.0f}, {0, 0, -1}, 0.0f, kInf).hit);
}

TEST(RayScene, QuadTrianglesReportTheirOwnFaceAndBarycentrics) {
    HandScene s;
    // (1.5, 0.5) is outside the triangle (x + y > 1): the ray reaches the quad at z = -2,
    // distance 3, in face 1 (x > y): u = (1.5 - 0.5)/2, v = 0.5/2.
    rad::RayHit hit = s.scene.intersect({1.5f, 0.5f, 1.0f}, {0, 0, -1}, 0.0f, kInf);
    ASSERT_TRUE(hit.hit);
    EXPECT_EQ(hit.face, 1u);
    EXPECT_NEAR(hit.distance, 3.0f, 1e-6f);
    EXPECT_NEAR(hit.u, 0.5f, 1e-6f);
    EXPECT_NEAR(hit.v, 0.25f, 1e-6f);
    // (0.4, 1.8): face 2 (y > x): u = 0.2, v = 0.7.
    hit = s.scene.intersect({0.4f, 1.8f, 1.0f}, {0, 0, -1}, 0.0f, kInf);
    ASSERT_TRUE(hit.hit);
    EXPECT_EQ(hit.face, 2u);
    EXPECT_NEAR(hit.u, 0.2f, 1e-6f);
    EXPECT_NEAR(hit.v, 0.7f, 1e-6f);
    // The hit point rebuilt from the barycentrics: (1 - u - v) a + u b + v c of face 2.
    const Eigen::Vector3f a(0, 0, -2), b(2, 2, -2), c(0, 2, -2);
    EXPECT_LT(((1 - hit.u - hit.v) * a + hit.u * b + hit.v * c - Eigen::Vector3f(0.4f, 1.8f, -2.0f)).norm(), 1e-5f);

    // Closest hit: above (0.2, 0.3) both the triangle (t = 1) and the quad (t = 3) lie on the ray.
    hit = s.scene.intersect({0.2f, 0.3f, 1.0f}, {0, 0, -1}, 0.0f, kInf);
    EXPECT_EQ(hit.face, 0u);
}

TEST(RayScene, NearAndFarLimitsApplyToBothQueries) {
    HandScene s;
    const Eigen::Vector3f origin(0.2f, 0.3f, 1.0f), down(0, 0, -1);
    // Hits at t = 1 (triangle) and t = 3 (quad, face 2 since y > x).
    EXPECT_TRUE(s.scene.occluded(origin, down, 0.0f, kInf));
    // tNear past the triangle: the quad is the closest hit left.
    rad::RayHit hit = s.scene.intersect(origin, down, 1.5f, kInf);
    ASSERT_TRUE(hit.hit);
    EXPECT_EQ(hit.face, 2u);
    EXPECT_NEAR(hit.distance, 3.0f, 1e-6f);
    EXPECT_TRUE(s.scene.occluded(origin, down, 1.5f, kInf));
    // tFar short of the triangle: nothing.
    EXPECT_FALSE(s.scene.intersect(origin, down, 0.0f, 0.9f).hit);
    EXPECT_FALSE(s.scene.occluded(origin, down, 0.0f, 0.9f));
    // Between the two surfaces: nothing.
    EXPECT_FALSE(s.scene.intersect(origin, down, 1.1f, 2.9f).hit);
    EXPECT_FALSE(s.scene.occluded(origin, down, 1.1f, 2.9f));
    // Past both: nothing.
    EXPECT_FALSE(s.scene.occluded(origin, down, 3.1f, kInf));
    // A shadow ray from the quad towards the "light" above the triangle is blocked; one towards a
    // light below the triangle's plane (tFar before it) is not.
    const Eigen::Vector3f onQuad(0.2f, 0.3f, -2.0f), up(0, 0, 1);
    EXPECT_TRUE(s.scene.occluded(onQuad, up, 1e-3f, 5.0f));
    EXPECT_FALSE(s.scene.occluded(onQuad, up, 1e-3f, 1.5f));
    // The limits are in units of the direction's length, like the distance.
    EXPECT_FALSE(s.scene.occluded(origin, 2.0f * down, 0.0f, 0.45f));
    EXPECT_TRUE(s.scene.occluded(origin, 2.0f * down, 0.0f, 0.55f));
}

TEST(RayScene, EmptyIntervalsAreNeverOccludedNorHit) {
    HandScene s;
    const Eigen::Vector3f origin(0.2f, 0.3f, 1.0f), down(0, 0, -1);
    EXPECT_FALSE(s.scene.occluded(origin, down, 2.0f, 1.0f));
    EXPECT_FALSE(s.scene.intersect(origin, down, 2.0f, 1.0f).hit);
    EXPECT_FALSE(s.scene.occluded(origin, down, 0.0f, -1.0f));  // was reported occluded before the fix
    EXPECT_FALSE(s.scene.intersect(origin, down, 0.0f, -1.0f).hit);
    EXPECT_FALSE(s.scene.occluded(origin, down, 0.0f, std::nanf("")));
}

// Rays Embree checks and aborts the process on (an origin beyond 1.844e18, a NaN direction) are
// answered "nothing" by every query instead of reaching Embree (the irradiance grid at 1e14 sent an
// origin at infinity and aborted MeshLab).
TEST(RayScene, RaysEmbreeWouldAbortOnHitNothing) {
    HandScene s;
    const float nan = std::nanf("");
    const Eigen::Vector3f farOrigin(kInf, -kInf, kInf), hugeOrigin(0.2f, 0.3f, 1e19f), down(0, 0, -1);
    EXPECT_FALSE(s.scene.intersect(farOrigin, down, 0.0f, kInf).hit);
    EXPECT_FALSE(s.scene.occluded(hugeOrigin, down, 0.0f, kInf));
    EXPECT_FALSE(s.scene.occluded({0.2f, 0.3f, 1.0f}, {nan, 0, -1}, 0.0f, kInf));
    rad::RayPacket16 packet;
    for (int i = 0; i < 16; ++i) {
        packet.originX[i] = 0.2f;
        packet.originY[i] = 0.3f;
        packet.originZ[i] = 1.0f;
        packet.directionX[i] = packet.directionY[i] = 0.0f;
        packet.directionZ[i] = -1.0f;
        packet.tNear[i] = 0.0f;
        packet.tFar[i] = kInf;
    }
    packet.originX[3] = kInf;
    packet.originZ[5] = 1e19f;
    packet.directionY[7] = nan;
    EXPECT_EQ(s.scene.occluded16(packet, 0xffffu), 0xffffu & ~((1u << 3) | (1u << 5) | (1u << 7)));
    rad::RayHit hits[16];
    s.scene.intersect16(packet, 0xffffu, hits);
    for (int i = 0; i < 16; ++i) EXPECT_EQ(hits[i].hit, i != 3 && i != 5 && i != 7) << "lane " << i;
}

// Far beyond the supported coordinate range Embree's triangle test overflows: whatever it answers,
// a reported hit has a finite distance (a hit at t = inf put the next ray's origin at infinity).
TEST(RayScene, HitsFarBeyondTheSupportedRangeHaveFiniteDistances) {
    const rad::TriangleMesh unit = rad::makeIcosphere(2, 1.0f);
    std::vector<float> positions = unit.positions;
    for (float& x : positions) x *= 1e14f;
    const rad::RayScene scene(positions.data(), unit.vertexCount(), unit.faces.data(), unit.faceCount());
    std::mt19937 rng(3);
    std::normal_distribution<float> normal;
    for (int r = 0; r < 2000; ++r) {
        const Eigen::Vector3f d = Eigen::Vector3f(normal(rng), normal(rng), normal(rng)).normalized();
        const rad::RayHit hit = scene.intersect({3e13f, -2e13f, 1e13f}, d, 0.0f, kInf);
        if (hit.hit) {
            ASSERT_TRUE(std::isfinite(hit.distance)) << "ray " << r;
        }
    }
}

TEST(RayScene, MeshWithoutFacesIsAnEmptySceneThatEveryRayMisses) {
    // A point cloud (MeshLab layers may have no faces): valid input, nothing to hit.
    const std::vector<float> points = {0, 0, 0, 1, 0, 0};
    const rad::RayScene empty(points.data(), 2, nullptr, 0);
    EXPECT_EQ(empty.faceCount(), 0u);
    EXPECT_FALSE(empty.intersect({0, 0, 1}, {0, 0, -1}, 0.0f, kInf).hit);
    EXPECT_FALSE(empty.occluded({0, 0, 1}, {0, 0, -1}, 0.0f, kInf));
    const rad::RayScene nothing(nullptr, 0, nullptr, 0);
    EXPECT_FALSE(nothing.occluded({0, 0, 1}, {0, 0, -1}, 0.0f, kInf));
}

// Rays from inside a closed mesh aimed exactly at its vertices must not leave it. With Embree's
// default (non-robust) traversal about 5 % of them do (30 of 642 on this icosphere): a shadow or
// visibility ray through a vertex sees through the surface. Setting RTC_SCENE_FLAG_ROBUST on the
// scene fixes it (0 of 642; measured cost ~10-15 % per query). Disabled until that decision is
// taken in ray_scene.cpp (run with --gtest_also_run_disabled_tests).
TEST(RayScene, RaysAimedAtVerticesOfAClosedMeshDoNotLeak) {
    const rad::TriangleMesh mesh = rad::makeIcosphere(3, 1.0f);
    const rad::RayScene scene(mesh.positions.data(), mesh.vertexCount(), mesh.faces.data(), mesh.faceCount());
    int leaks = 0;
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
        const Eigen::Vector3f d(mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]);
        if (!scene.occluded(Eigen::Vector3f::Zero(), d, 0.0f, kInf)) ++leaks;
    }
    EXPECT_EQ(leaks, 0) << "of " << mesh.vertexCount() << " rays";
}

TEST(RayScene, ConcurrentQueriesMatchSerialOnes) {
    const rad::TriangleMesh mesh = rad::makeIcosphere(4, 1.0f);
    const rad::RayScene scene(mesh.positions.data(), mesh.vertexCount(), mesh.faces.data(), mesh.faceCount());
    std::mt19937 rng(21);
    const int n = 20000;
    std::vector<Eigen::Vector3f> origins(n), directions(n);
    for (int i = 0; i < n; ++i) {
        // From a shell of radius 1.5..3 towards random points near the sphere: hits and misses.
        origins[i] = (radtest::randomUnit(rng) * (1.5 + 1.5 * (i % 7) / 7.0)).cast<float>();
        directions[i] = (radtest::randomUnit(rng) * 1.2 - origins[i].cast<double>()).cast<float>();
    }
    std::vector<rad::RayHit> serialHits(n);
    std::vector<char> serialOccluded(n);
    for (int i = 0; i < n; ++i) {
        serialHits[i] = scene.intersect(origins[i], directions[i], 0.0f, kInf);
        serialOccluded[i] = scene.occluded(origins[i], directions[i], 0.0f, kInf);
    }
    std::vector<rad::RayHit> parallelHits(n);
    std::vector<char> parallelOccluded(n);
    int threads = 1;
#pragma omp parallel num_threads(4)
    {
#pragma omp single
        threads = omp_get_num_threads();
        // Interleaved chunks so that threads are really querying at the same time.
#pragma omp for schedule(dynamic, 16)
        for (int i = 0; i < n; ++i) {
            parallelHits[i] = scene.intersect(origins[i], directions[i], 0.0f, kInf);
            parallelOccluded[i] = scene.occluded(origins[i], directions[i], 0.0f, kInf);
        }
    }
    EXPECT_GE(threads, 2);
    int hits = 0;
    for (int i = 0; i < n; ++i) {
        ASSERT_EQ(parallelHits[i].hit, serialHits[i].hit) << i;
        ASSERT_EQ(parallelOccluded[i], serialOccluded[i]) << i;
        ASSERT_EQ(serialOccluded[i] != 0, serialHits[i].hit) << i;  // the two queries agree
        if (!serialHits[i].hit) continue;
        ++hits;
        EXPECT_EQ(parallelHits[i].face, serialHits[i].face);
        EXPECT_EQ(parallelHits[i].distance, serialHits[i].distance);
        EXPECT_EQ(parallelHits[i].u, serialHits[i].u);
        EXPECT_EQ(parallelHits[i].v, serialHits[i].v);
        // And the hit is on the (inscribed) sphere: radius between the icosphere's flat-face
        // minimum and 1.
        const Eigen::Vector3f p = origins[i] + serialHits[i].distance * directions[i];
        EXPECT_NEAR(p.norm(), 1.0f, 5e-3f);
    }
    EXPECT_GT(hits, n / 4);
    EXPECT_LT(hits, n);
}

namespace {
// Packet p of the random packet tests: 16 random rays about the unit sphere, inside and outside it,
// some ending before the surface, a few with empty intervals; inactive lanes sometimes hold NaN
// (must be ignored). Returns the active mask: full, empty, single lanes, then random (bits above
// 15 set too: they must be ignored).
std::uint32_t randomPacket(std::mt19937& rng, int p, rad::RayPacket16& packet) {
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::uniform_int_distribution<std::uint32_t> bits(0, 0xffffffffu);
    const std::uint32_t mask = p == 0 ? 0xffffu : p == 1 ? 0u : p < 18 ? 1u << (p - 2) : bits(rng);
    for (int i = 0; i < 16; ++i) {
        const Eigen::Vector3f o = (radtest::randomUnit(rng) * (0.3 + 2.0 * unit(rng))).cast<float>();
        const Eigen::Vector3f d = radtest::randomUnit(rng).cast<float>();
        const float tNear = unit(rng) < 0.5f ? 0.0f : 0.5f * unit(rng);
        const float tFar = unit(rng) < 0.1f ? tNear - 0.1f : unit(rng) < 0.5f ? kInf : 3.0f * unit(rng);
        packet.originX[i] = o.x();
        packet.originY[i] = o.y();
        packet.originZ[i] = o.z();
        packet.directionX[i] = d.x();
        packet.directionY[i] = d.y();
        packet.directionZ[i] = d.z();
        packet.tNear[i] = tNear;
        packet.tFar[i] = tFar;
        if (!((mask >> i) & 1u) && unit(rng) < 0.5f) packet.originX[i] = std::nanf("");
    }
    return mask;
}
}  // namespace

// Random rays on an icosphere, 16 per packet under random active masks: every active lane gets
// the single-ray answer, every inactive lane 0, whatever garbage it holds.
TEST(RayScene, PacketQueryAgreesWithSingleRaysUnderRandomMasks) {
    const rad::TriangleMesh mesh = rad::makeIcosphere(3, 1.0f);
    const rad::RayScene scene(mesh.positions.data(), mesh.vertexCount(), mesh.faces.data(), mesh.faceCount());
    std::mt19937 rng(77);
    int occludedLanes = 0, activeLanes = 0;
    for (int p = 0; p < 400; ++p) {
        rad::RayPacket16 packet;
        const std::uint32_t mask = randomPacket(rng, p, packet);
        const std::uint32_t result = scene.occluded16(packet, mask);
        for (int i = 0; i < 16; ++i) {
            const bool active = (mask >> i) & 1u;
            const bool got = (result >> i) & 1u;
            if (!active) {
                EXPECT_FALSE(got) << "packet " << p << " lane " << i;
                continue;
            }
            const bool single = scene.occluded({packet.originX[i], packet.originY[i], packet.originZ[i]},
                                               {packet.directionX[i], packet.directionY[i], packet.directionZ[i]},
                                               packet.tNear[i], packet.tFar[i]);
            EXPECT_EQ(got, single) << "packet " << p << " lane " << i;
            ++activeLanes;
            occludedLanes += got;
        }
        EXPECT_EQ(result >> 16, 0u);
    }
    // Both answers are well represented.
    EXPECT_GT(occludedLanes, activeLanes / 5);
    EXPECT_LT(occludedLanes, activeLanes * 4 / 5);
}

TEST(RayScene, PacketIntersectAgreesWithSingleRaysUnderRandomMasks) {
    const rad::TriangleMesh mesh = rad::makeIcosphere(3, 1.0f);
    const rad::RayScene scene(mesh.positions.data(), mesh.vertexCount(), mesh.faces.data(), mesh.faceCount());
    std::mt19937 rng(78);
    int hitLanes = 0, activeLanes = 0;
    for (int p = 0; p < 400; ++p) {
        rad::RayPacket16 packet;
        const std::uint32_t mask = randomPacket(rng, p, packet);
        rad::RayHit hits[16];
        scene.intersect16(packet, mask, hits);
        for (int i = 0; i < 16; ++i) {
            const bool active = (mask >> i) & 1u;
            if (!active || !(packet.tNear[i] <= packet.tFar[i])) {
                EXPECT_FALSE(hits[i].hit) << "packet " << p << " lane " << i;
                continue;
            }
            const rad::RayHit single = scene.intersect({packet.originX[i], packet.originY[i], packet.originZ[i]},
                                                       {packet.directionX[i], packet.directionY[i], packet.directionZ[i]},
                                                       packet.tNear[i], packet.tFar[i]);
            ASSERT_EQ(hits[i].hit, single.hit) << "packet " << p << " lane " << i;
            ++activeLanes;
            if (!single.hit) continue;
            ++hitLanes;
            EXPECT_EQ(hits[i].face, single.face);
            EXPECT_NEAR(hits[i].distance, single.distance, 1e-5f);
            EXPECT_NEAR(hits[i].u, single.u, 1e-5f);
            EXPECT_NEAR(hits[i].v, single.v, 1e-5f);
        }
    }
    EXPECT_GT(hitLanes, activeLanes / 5);
    EXPECT_LT(hitLanes, activeLanes * 4 / 5);
}

// Every lane straight down from above (0.2, 0.3, 1) of the hand-made scene, i.e. through the
// triangle (t = 1) and the quad (t = 3), over [tNear, tFar].
rad::RayPacket16 packetDownThroughTheHandScene(float tNear, float tFar) {
    rad::RayPacket16 packet;
    for (int i = 0; i < 16; ++i) {
        packet.originX[i] = 0.2f;
        packet.originY[i] = 0.3f;
        packet.originZ[i] = 1.0f;
        packet.directionX[i] = 0.0f;
        packet.directionY[i] = 0.0f;
        packet.directionZ[i] = -1.0f;
        packet.tNear[i] = tNear;
        packet.tFar[i] = tFar;
    }
    return packet;
}

TEST(RayScene, PacketQueryOnTheHandMadeScene) {
    HandScene s;
    // Lane i with tFar = 0.25 i + 0.1: occluded from lane 4 on (tFar > 1).
    rad::RayPacket16 packet = packetDownThroughTheHandScene(0.0f, 0.0f);
    for (int i = 0; i < 16; ++i) packet.tFar[i] = 0.25f * i + 0.1f;
    EXPECT_EQ(s.scene.occluded16(packet, 0xffffu), 0xfff0u);
    EXPECT_EQ(s.scene.occluded16(packet, 0x00ffu), 0x00f0u);
    EXPECT_EQ(s.scene.occluded16(packet, 0x000fu), 0u);
    EXPECT_EQ(s.scene.occluded16(packet, 0u), 0u);
    // Between the two surfaces (tNear 1.5, tFar 2.5) nothing; an empty interval neither.
    packet.tNear[5] = 1.5f, packet.tFar[5] = 2.5f;
    packet.tNear[6] = 2.0f, packet.tFar[6] = 1.0f;
    packet.tFar[7] = -kInf;
    EXPECT_EQ(s.scene.occluded16(packet, 0xffffu), 0xff10u);
    // The empty scene: nothing is ever occluded.
    const rad::RayScene nothing(nullptr, 0, nullptr, 0);
    EXPECT_EQ(nothing.occluded16(packet, 0xffffu), 0u);
}

// Lanes outside the mask holding a negative tNear under a wide interval (what Embree 3's ray-stream
// path, taken for 16-wide packets on CPUs without AVX-512, would read as live and abort on), and an
// active lane with a negative tNear (read as 0, as the single-ray query reads it).
TEST(RayScene, NegativeNearLimitsNeitherAbortNorCountOutsideTheMask) {
    HandScene s;
    rad::RayPacket16 packet = packetDownThroughTheHandScene(-1.0f, kInf);
    EXPECT_EQ(s.scene.occluded16(packet, 0x0001u), 0x0001u);
    EXPECT_EQ(s.scene.occluded({0.2f, 0.3f, 1.0f}, {0.0f, 0.0f, -1.0f}, -1.0f, kInf), true);
    rad::RayHit hits[16];
    s.scene.intersect16(packet, 0x0002u, hits);
    EXPECT_TRUE(hits[1].hit);
    EXPECT_NEAR(hits[1].distance, 1.0f, 1e-5f);
    for (int i = 0; i < 16; ++i)
        if (i != 1) EXPECT_FALSE(hits[i].hit) << "lane " << i;
    // Only up to 0.5: nothing between the origin and the triangle at t = 1.
    packet.tFar[0] = 0.5f;
    EXPECT_EQ(s.scene.occluded16(packet, 0x0001u), 0u);
}


}  // namespace

TEST(RayScene, ClosestPointInTheVoronoiRegionsOfAHandMadeTriangle) {
    // Triangle a = (0,0,0), b = (2,0,0), c = (0,2,0) in the z = 0 plane.
    const float positions[] = {0, 0, 0, 2, 0, 0, 0, 2, 0};
    const std::uint32_t faces[] = {0, 1, 2};
    rad::RayScene scene(positions, 3, faces, 1);
    // Above the interior: the foot of the perpendicular, barycentrics (0.25, 0.5).
    rad::ClosestPoint inside = scene.closestPoint(Eigen::Vector3f(0.5f, 1.0f, 3.0f));
    ASSERT_TRUE(inside.found);
    EXPECT_NEAR(inside.distance, 3.0f, 1e-6f);
    EXPECT_NEAR(inside.u, 0.25f, 1e-6f);
    EXPECT_NEAR(inside.v, 0.5f, 1e-6f);
    EXPECT_TRUE(inside.point.isApprox(Eigen::Vector3f(0.5f, 1.0f, 0.0f), 1e-6f));
    // Beyond vertex b: b itself, at distance sqrt(1 + 1 + 1).
    rad::ClosestPoint nearB = scene.closestPoint(Eigen::Vector3f(3.0f, -1.0f, 1.0f));
    ASSERT_TRUE(nearB.found);
    EXPECT_NEAR(nearB.distance, std::sqrt(3.0f), 1e-6f);
    EXPECT_NEAR(nearB.u, 1.0f, 1e-6f);
    EXPECT_NEAR(nearB.v, 0.0f, 1e-6f);
    // Beyond the hypotenuse bc: its midpoint (1, 1, 0), distance sqrt(0.5 + 0.5).
    rad::ClosestPoint nearBc = scene.closestPoint(Eigen::Vector3f(1.5f, 1.5f, 0.0f));
    ASSERT_TRUE(nearBc.found);
    EXPECT_NEAR(nearBc.distance, std::sqrt(0.5f), 1e-6f);
    EXPECT_NEAR(nearBc.u, 0.5f, 1e-6f);
    EXPECT_NEAR(nearBc.v, 0.5f, 1e-6f);
    // The search radius limits the answer.
    EXPECT_FALSE(scene.closestPoint(Eigen::Vector3f(0.5f, 1.0f, 3.0f), 2.9f).found);
    EXPECT_TRUE(scene.closestPoint(Eigen::Vector3f(0.5f, 1.0f, 3.0f), 3.1f).found);
}

TEST(RayScene, ClosestPointAgreesWithDenseSamplingOfEveryTriangle) {
    const rad::TriangleMesh sphere = rad::makeIcosphere(2, 1.0f);
    rad::RayScene scene(sphere.positions.data(), sphere.vertexCount(), sphere.faces.data(), sphere.faceCount());
    std::mt19937 random(7);
    std::uniform_real_distribution<float> coordinate(-1.6f, 1.6f);
    const int steps = 40;  // samples per triangle side
    for (int q = 0; q < 20; ++q) {
        const Eigen::Vector3f query(coordinate(random), coordinate(random), coordinate(random));
        // Brute force: the nearest of a dense barycentric grid on every triangle. Its minimum is
        // an upper bound of the true distance, and at most one grid cell's diameter above it.
        float sampled = std::numeric_limits<float>::infinity();
        float cellDiameter = 0.0f;
        for (std::size_t f = 0; f < sphere.faceCount(); ++f) {
            const auto vertex = [&](int k) {
                return Eigen::Map<const Eigen::Vector3f>(&sphere.positions[3 * sphere.faces[3 * f + k]]);
            };
            const Eigen::Vector3f a = vertex(0), b = vertex(1), c = vertex(2);
            cellDiameter = std::max(cellDiameter, std::max({(b - a).norm(), (c - a).norm(), (c - b).norm()}) / steps);
            for (int i = 0; i <= steps; ++i)
                for (int j = 0; i + j <= steps; ++j) {
                    const Eigen::Vector3f p = a + (b - a) * (float(i) / steps) + (c - a) * (float(j) / steps);
                    sampled = std::min(sampled, (p - query).norm());
                }
        }
        const rad::ClosestPoint found = scene.closestPoint(query);
        ASSERT_TRUE(found.found);
        EXPECT_LE(found.distance, sampled + 1e-5f);
        EXPECT_GE(found.distance, sampled - cellDiameter);
        EXPECT_NEAR((found.point - query).norm(), found.distance, 1e-5f);
    }
}
