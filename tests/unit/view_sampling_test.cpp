// Tests of fit/view_sampling.h: which views give a vertex a sample, and the sample's value.
// The oracle is written here from the definitions: projection with the camera's matrix and
// intrinsics, a brute-force Moller-Trumbore ray test against every triangle (no Embree), bilinear
// interpolation of pixels decoded with the sRGB formula (no lookup table).
#include "fit/view_sampling.h"

#include "camera/pinhole_camera.h"
#include "geometry/triangle_mesh.h"
#include "image/rgb_image.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using Eigen::Vector3d;
constexpr double kPi = 3.14159265358979323846;


// A square [x0, x1] x [y0, y1] at height z (two triangles, normals +z): the occluder.
void addSquare(rad::TriangleMesh& mesh, float x0, float x1, float y0, float y1, float z) {
    const std::uint32_t base = static_cast<std::uint32_t>(mesh.vertexCount());
    mesh.positions.insert(mesh.positions.end(), {x0, y0, z, x1, y0, z, x1, y1, z, x0, y1, z});
    for (int k = 0; k < 4; ++k) mesh.normals.insert(mesh.normals.end(), {0.0f, 0.0f, 1.0f});
    mesh.faces.insert(mesh.faces.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

// Pixels that encode their coordinates (8-bit sRGB codes).
rad::Image8 paintedImage(int w, int h) {
    rad::Image8 image(w, h);
    for (int r = 0; r < h; ++r)
        for (int c = 0; c < w; ++c) {
            std::uint8_t* p = image.pixel(c, r);
            p[0] = static_cast<std::uint8_t>((c * 7) % 256);
            p[1] = static_cast<std::uint8_t>((r * 11) % 256);
            p[2] = static_cast<std::uint8_t>((c * 3 + r * 5) % 256);
        }
    return image;
}

double decodeSrgb(int code) {
    const double c = code / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

// Bilinear interpolation of the decoded pixels at image point (u, v), pixel centres at +0.5
// (the point is at least half a pixel inside, as the margins of the tests guarantee).
Vector3d bilinear(const rad::Image8& image, double u, double v) {
    const double x = u - 0.5, y = v - 0.5;
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const double fx = x - x0, fy = y - y0;
    Vector3d out;
    for (int c = 0; c < 3; ++c) {
        auto at = [&](int i, int j) { return decodeSrgb(image.rgb[(std::size_t(j) * image.width + i) * 3 + c]); };
        out[c] = (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) + fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
    }
    return out;
}

struct Expected {
    bool sampled = false;
    bool facing = false, inFront = false, inFrame = false, occluded = false;
    Vector3d direction, rgb;
    double weight = 0;
};

Expected oracle(const rad::TriangleMesh& mesh, std::size_t v, const rad::PinholeCamera& cam, const rad::Image8& image,
                double margin, double grazingDegrees, double tolerance, bool occlusion) {
    Expected e;
    const Vector3d X(mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]);
    const Vector3d n = Vector3d(mesh.normals[3 * v], mesh.normals[3 * v + 1], mesh.normals[3 * v + 2]).normalized();
    const double dist = (cam.center - X).norm();
    e.direction = (cam.center - X) / dist;
    e.weight = n.dot(e.direction);
    e.facing = e.weight >= std::cos(grazingDegrees * kPi / 180);
    const Vector3d xc = cam.rotation * (X - cam.center);
    e.inFront = xc.z() > 0;
    const double u = cam.fx * xc.x() / xc.z() + cam.cx, vv = cam.fy * xc.y() / xc.z() + cam.cy;
    e.inFrame = e.inFront && u >= margin && vv >= margin && u <= cam.width - margin && vv <= cam.height - margin;
    e.occluded = occlusion && radtest::bruteOccluded(mesh, X, e.direction, tolerance, dist - tolerance);
    e.sampled = e.facing && e.inFrame && !e.occluded;
    if (e.sampled) e.rgb = bilinear(image, u, vv);
    return e;
}

struct Scene {
    rad::TriangleMesh mesh;
    rad::Image8 image;
    rad::PinholeCamera camera;
};

// A 41 x 41 grid, an occluder square above part of it, a few vertices with special normals, and
// a camera whose frame cuts the grid (some vertices out of frame or in the margin).
Scene makeScene() {
    Scene s;
    radtest::addGrid(s.mesh, 41);
    addSquare(s.mesh, -0.337f, 0.061f, -0.283f, 0.117f, 0.5f);
    s.camera = rad::PinholeCamera::lookAt(Vector3d(0.4, -0.3, 3.0), Vector3d(0.1, 0.05, 0), Vector3d(0, 1, 0), 34.0, 96, 72);
    s.image = paintedImage(96, 72);
    // Special normals on some grid vertices: back-facing, and just inside / outside the 80-degree
    // grazing cut-off (tilted away from the direction to the camera).
    for (std::size_t v = 0; v < 41 * 41; v += 13) {
        const Vector3d X(s.mesh.positions[3 * v], s.mesh.positions[3 * v + 1], s.mesh.positions[3 * v + 2]);
        const Vector3d w = (s.camera.center - X).normalized();
        const Vector3d p = w.cross(Vector3d(0.3, 0.9, 0.1)).normalized();
        const double angle = (v / 13) % 3 == 0 ? 150.0 : (v / 13) % 3 == 1 ? 79.0 : 81.0;
        const Vector3d n = std::cos(angle * kPi / 180) * w + std::sin(angle * kPi / 180) * p;
        for (int k = 0; k < 3; ++k) s.mesh.normals[3 * v + k] = static_cast<float>(n[k]);
    }
    return s;
}

TEST(ViewSampling, EveryVertexMatchesTheOracle) {
    const Scene s = makeScene();
    rad::ViewSamplingOptions options;  // grazing 80, margin 2, automatic depth tolerance
    const rad::ViewSampler sampler(s.mesh, {{s.camera, s.image.view()}}, options);
    ASSERT_TRUE(sampler.testsOcclusion());
    // Automatic tolerance: 1e-4 of the bounding box diagonal (box [-1,1]^2 x [0, 0.5]).
    EXPECT_NEAR(sampler.depthTolerance(), 1e-4 * std::sqrt(4.0 + 4.0 + 0.25), 1e-9);
    int sampled = 0, occluded = 0, backFacing = 0, outOfFrame = 0, grazingKept = 0;
    rad::SamplingCounters counters;
    for (std::size_t v = 0; v < s.mesh.vertexCount(); ++v) {
        SCOPED_TRACE("vertex " + std::to_string(v));
        const Expected e = oracle(s.mesh, v, s.camera, s.image, 2.0, 80.0, sampler.depthTolerance(), true);
        rad::DirectionalSample out[1];
        int viewOf[1] = {-1};
        const std::size_t m = sampler.sampleVertex(v, out, &counters, viewOf);
        ASSERT_EQ(m, e.sampled ? 1u : 0u) << "facing " << e.facing << " inFrame " << e.inFrame << " occluded " << e.occluded;
        sampled += e.sampled;
        occluded += e.facing && e.inFrame && e.occluded;
        backFacing += e.weight < 0;
        outOfFrame += e.facing && !e.inFrame;
        if (!e.sampled) continue;
        EXPECT_EQ(viewOf[0], 0);
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(out[0].direction[k], e.direction[k], 1e-6);
            EXPECT_NEAR(out[0].rgb[k], e.rgb[k], 1e-5);
        }
        EXPECT_NEAR(out[0].weight, e.weight, 1e-6);  // weight = cosine to the normal
        if (e.weight < std::cos(75 * kPi / 180)) ++grazingKept;
    }
    // The scene exercises every case.
    EXPECT_GT(sampled, 500);
    EXPECT_GT(occluded, 20);
    EXPECT_GT(backFacing, 20);
    EXPECT_GT(outOfFrame, 20);
    EXPECT_GT(grazingKept, 10);  // the 79-degree normals are kept, with their small weight
    EXPECT_EQ(counters.samples, static_cast<std::size_t>(sampled));
    EXPECT_EQ(counters.occluded, static_cast<std::size_t>(occluded));
    EXPECT_EQ(counters.raysCast, counters.inFrame);
}

TEST(ViewSampling, BlocksOfVerticesMatchTheOracleViewByView) {
    // The packet path: blocks of 16 vertices (and shorter ones at the end) against the brute-force
    // oracle, three views, the occluder, the special normals and a vertex without a normal.
    Scene s = makeScene();
    const std::size_t noNormal = 40;
    for (int k = 0; k < 3; ++k) s.mesh.normals[3 * noNormal + k] = 0.0f;
    const rad::PinholeCamera second =
        rad::PinholeCamera::lookAt(Vector3d(-0.6, 0.5, 2.5), Vector3d(0, 0, 0), Vector3d(0, 1, 0), 40.0, 96, 72);
    const rad::PinholeCamera third =
        rad::PinholeCamera::lookAt(Vector3d(0.2, 0.1, 1.5), Vector3d(0.2, 0.1, 0), Vector3d(0, 1, 0), 50.0, 96, 72);
    const std::vector<rad::PinholeCamera> cameras = {s.camera, second, third};
    std::vector<rad::CalibratedView> views;
    for (const rad::PinholeCamera& c : cameras) views.push_back({c, s.image.view()});
    const rad::ViewSampler sampler(s.mesh, views);
    const std::size_t n = s.mesh.vertexCount(), viewCount = views.size();
    std::vector<rad::DirectionalSample> out(rad::ViewSampler::kBlock * viewCount);
    std::vector<int> viewOf(out.size());
    std::size_t counts[rad::ViewSampler::kBlock];
    rad::SamplingCounters counters;
    std::size_t sampled = 0, occluded = 0;
    for (const int blockSize : {16, 5, 1}) {
        for (std::size_t first = 0; first < n; first += blockSize) {
            const int count = static_cast<int>(std::min<std::size_t>(blockSize, n - first));
            sampler.sampleVertexBlock(first, count, out.data(), counts, blockSize == 16 ? &counters : nullptr, viewOf.data());
            for (int k = 0; k < count; ++k) {
                const std::size_t v = first + k;
                SCOPED_TRACE("vertex " + std::to_string(v) + ", blocks of " + std::to_string(blockSize));
                std::size_t expected = 0;
                for (std::size_t i = 0; i < viewCount; ++i) {
                    const Expected e = v == noNormal ? Expected{}
                                                     : oracle(s.mesh, v, cameras[i], s.image, 2.0, 80.0,
                                                              sampler.depthTolerance(), true);
                    if (blockSize == 16) occluded += e.facing && e.inFrame && e.occluded;
                    if (!e.sampled) continue;
                    ASSERT_LT(expected, counts[k]);
                    const rad::DirectionalSample& got = out[k * viewCount + expected];
                    EXPECT_EQ(viewOf[k * viewCount + expected], static_cast<int>(i));
                    for (int c = 0; c < 3; ++c) {
                        EXPECT_NEAR(got.direction[c], e.direction[c], 1e-6);
                        EXPECT_NEAR(got.rgb[c], e.rgb[c], 1e-5);
                    }
                    EXPECT_NEAR(got.weight, e.weight, 1e-6);
                    ++expected;
                }
                EXPECT_EQ(counts[k], expected);
                if (blockSize == 16) sampled += expected;
            }
        }
    }
    EXPECT_GT(sampled, 1000u);
    EXPECT_GT(occluded, 20u);
    EXPECT_EQ(counters.samples, sampled);
    EXPECT_EQ(counters.occluded, occluded);
}

TEST(ViewSampling, VertexInTheBorderMarginIsSkipped) {
    rad::TriangleMesh mesh;
    const rad::PinholeCamera cam =
        rad::PinholeCamera::lookAt(Vector3d(0, 0, 5), Vector3d(0, 0, 0), Vector3d(0, 1, 0), 40.0, 64, 48);
    const rad::Image8 image = paintedImage(64, 48);
    // Points at depth 5 whose projections are, by construction, at u = 1.5 (in the 2-pixel margin)
    // and u = 2.5 (outside it); normals toward the camera. No faces: no occlusion test.
    for (double u : {1.5, 2.5}) {
        const Vector3d local((u - cam.cx) / cam.fx * 5.0, (20.25 - cam.cy) / cam.fy * 5.0, 5.0);
        const Vector3d X = cam.rotation.transpose() * local + cam.center;
        for (int k = 0; k < 3; ++k) mesh.positions.push_back(static_cast<float>(X[k]));
        const Vector3d n = (cam.center - X).normalized();
        for (int k = 0; k < 3; ++k) mesh.normals.push_back(static_cast<float>(n[k]));
    }
    rad::DirectionalSample out[1];
    {
        const rad::ViewSampler sampler(mesh, {{cam, image.view()}});
        EXPECT_FALSE(sampler.testsOcclusion());
        EXPECT_EQ(sampler.sampleVertex(0, out), 0u);
        ASSERT_EQ(sampler.sampleVertex(1, out), 1u);
        const Vector3d expected = bilinear(image, 2.5, 20.25);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(out[0].rgb[k], expected[k], 2e-5);
    }
    rad::ViewSamplingOptions narrow;
    narrow.borderMarginPixels = 1.0;
    const rad::ViewSampler sampler(mesh, {{cam, image.view()}}, narrow);
    ASSERT_EQ(sampler.sampleVertex(0, out), 1u);
    const Vector3d expected = bilinear(image, 1.5, 20.25);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(out[0].rgb[k], expected[k], 2e-5);
    EXPECT_EQ(sampler.sampleVertex(2, out), 0u);  // out of range
}

TEST(ViewSampling, OccluderHidesTheVertexBehindIt) {
    // A vertex straight below a square that sits between it and the camera: no sample; removing the
    // square's faces (same vertices) gives the sample back; a square beyond the camera does not hide.
    rad::TriangleMesh mesh;
    radtest::addGrid(mesh, 3);  // vertex 4 is the centre (0, 0, 0)
    const rad::PinholeCamera cam =
        rad::PinholeCamera::lookAt(Vector3d(0, 0, 4), Vector3d(0, 0, 0), Vector3d(0, 1, 0), 60.0, 40, 30);
    const rad::Image8 image = paintedImage(40, 30);
    rad::TriangleMesh withOccluder = mesh, behindCamera = mesh;
    addSquare(withOccluder, -0.1f, 0.1f, -0.1f, 0.1f, 1.0f);
    addSquare(behindCamera, -0.1f, 0.1f, -0.1f, 0.1f, 5.0f);
    rad::DirectionalSample out[1];
    EXPECT_EQ(rad::ViewSampler(withOccluder, {{cam, image.view()}}).sampleVertex(4, out), 0u);
    EXPECT_EQ(rad::ViewSampler(mesh, {{cam, image.view()}}).sampleVertex(4, out), 1u);
    EXPECT_EQ(rad::ViewSampler(behindCamera, {{cam, image.view()}}).sampleVertex(4, out), 1u);
    // The occluder's own top vertices are seen (their faces do not hide them: depth tolerance).
    EXPECT_EQ(rad::ViewSampler(withOccluder, {{cam, image.view()}}).sampleVertex(9, out), 1u);
}

TEST(ViewSampling, SeveralViewsInOrderWithTheirIndices) {
    rad::TriangleMesh mesh;
    radtest::addGrid(mesh, 5);
    const rad::Image8 a = paintedImage(50, 40), b = paintedImage(60, 30);
    const rad::PinholeCamera ca = rad::PinholeCamera::lookAt(Vector3d(0.5, 0, 4), Vector3d(0, 0, 0), Vector3d(0, 1, 0), 60, 50, 40);
    const rad::PinholeCamera cb = rad::PinholeCamera::lookAt(Vector3d(0, 0, -4), Vector3d(0, 0, 0), Vector3d(0, 1, 0), 60, 60, 30);
    const rad::PinholeCamera cc = rad::PinholeCamera::lookAt(Vector3d(-1, 1, 3), Vector3d(0, 0, 0), Vector3d(0, 1, 0), 70, 60, 30);
    const rad::ViewSampler sampler(mesh, {{ca, a.view()}, {cb, b.view()}, {cc, b.view()}});
    EXPECT_EQ(sampler.viewCount(), 3u);
    rad::DirectionalSample out[3];
    int viewOf[3];
    ASSERT_EQ(sampler.sampleVertex(12, out, nullptr, viewOf), 2u);  // camera b is below the grid
    EXPECT_EQ(viewOf[0], 0);
    EXPECT_EQ(viewOf[1], 2);
    const Vector3d w = Vector3d(-1, 1, 3).normalized();
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(out[1].direction[k], w[k], 1e-6);
    EXPECT_NEAR(out[1].weight, w.z(), 1e-6);
}

TEST(ViewSampling, FourBytePixelsWithSwappedChannelsReadTheSameColours) {
    // The MeshLab adapter views QImage's 32-bit pixels (B, G, R, A bytes): same samples.
    rad::TriangleMesh mesh;
    radtest::addGrid(mesh, 9);
    const rad::Image8 rgb = paintedImage(64, 48);
    std::vector<std::uint8_t> bgra(64 * 48 * 4);
    for (int i = 0; i < 64 * 48; ++i) {
        bgra[4 * i + 0] = rgb.rgb[3 * i + 2];
        bgra[4 * i + 1] = rgb.rgb[3 * i + 1];
        bgra[4 * i + 2] = rgb.rgb[3 * i + 0];
        bgra[4 * i + 3] = 255;
    }
    rad::ImageView8 view{bgra.data(), 64, 48, 64 * 4, 4, {2, 1, 0}};
    const rad::PinholeCamera cam = rad::PinholeCamera::lookAt(Vector3d(0.2, 0.1, 3), Vector3d(0, 0, 0), Vector3d(0, 1, 0), 60, 64, 48);
    const rad::ViewSampler s1(mesh, {{cam, rgb.view()}}), s2(mesh, {{cam, view}});
    int compared = 0;
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
        rad::DirectionalSample a[1], b[1];
        const std::size_t m = s1.sampleVertex(v, a);
        ASSERT_EQ(m, s2.sampleVertex(v, b));
        if (m == 0) continue;
        ++compared;
        for (int k = 0; k < 3; ++k) EXPECT_EQ(a[0].rgb[k], b[0].rgb[k]);
    }
    EXPECT_GT(compared, 40);
}

TEST(ViewSampling, UnusableViewsAndMeshesAreRefused) {
    rad::TriangleMesh mesh;
    radtest::addGrid(mesh, 3);
    const rad::Image8 image = paintedImage(40, 30);
    const rad::PinholeCamera cam = rad::PinholeCamera::lookAt(Vector3d(0, 0, 4), Vector3d(0, 0, 0), Vector3d(0, 1, 0), 60, 40, 30);
    EXPECT_EQ(rad::checkView({cam, image.view()}), "");

    rad::PinholeCamera wrongSize = cam;
    wrongSize.width = 80;
    const std::string size = rad::checkView({wrongSize, image.view()});
    EXPECT_NE(size.find("80 x 30"), std::string::npos) << size;
    EXPECT_NE(size.find("40 x 30"), std::string::npos) << size;
    EXPECT_NE(rad::checkView({cam, rad::ImageView8{}}).find("no image"), std::string::npos);
    rad::PinholeCamera badFocal = cam;
    badFocal.fx = 0;
    EXPECT_NE(rad::checkView({badFocal, image.view()}).find("camera"), std::string::npos);
    rad::ImageView8 badLayout = image.view();
    badLayout.channelOffset[1] = 3;
    EXPECT_NE(rad::checkView({cam, badLayout}), "");

    EXPECT_THROW(rad::ViewSampler(mesh, {{cam, image.view()}, {wrongSize, image.view()}}), std::invalid_argument);
    rad::TriangleMesh noNormals = mesh;
    noNormals.normals.clear();
    EXPECT_THROW(rad::ViewSampler(noNormals, {{cam, image.view()}}), std::invalid_argument);
    rad::ViewSamplingOptions bad;
    bad.grazingAngleDegrees = 90;
    EXPECT_NE(bad.validate(), "");
    EXPECT_THROW(rad::ViewSampler(mesh, {{cam, image.view()}}, bad), std::invalid_argument);
    bad = {};
    bad.borderMarginPixels = -1;
    EXPECT_NE(bad.validate(), "");
}

}  // namespace
