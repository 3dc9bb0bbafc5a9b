// Tests of bake/normal_baker.h. Oracles: the ANALYTIC normal of the exact surface (sphere, torus)
// where the texel's ray from the target point p along the target normal N meets it; a tangent
// frame computed here in double from the face's UV derivatives (a 2 x 2 inverse, not the baker's
// formula); for MikkTSpace bakes, the renderer's decoding written here (interpolated corner
// tangents from geometry/mikktspace_tangents.h, which is tested against Blender on its own,
// B = s N x T, normalize(x T + y B + z N)); a linear colour function, whose baked value must be the function at a point of the ray
// on the source; the closest-point fallback counted on a sphere with a hole. The coverage
// (texel -> face, barycentrics) comes from bake/texel_coverage.h, tested on its own.
#include "bake/normal_baker.h"
#include "bake/texel_coverage.h"
#include "bake/texture_atlas.h"
#include "geometry/mikktspace_tangents.h"
#include "geometry/primitive_meshes.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <functional>
#include <limits>
#include <vector>

namespace {

constexpr double kPi = 3.14159265358979323846;

double angleDegrees(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / kPi;
}

Eigen::Vector3d at(const std::vector<float>& a, std::size_t i) {
    return Eigen::Vector3d(a[3 * i], a[3 * i + 1], a[3 * i + 2]);
}

struct TexelGeometry {
    Eigen::Vector3d p, N, T, B;
};

// Target point, unit normal and tangent frame of a covered texel, computed here in double.
TexelGeometry texelGeometry(const rad::TriangleMesh& m, const std::vector<float>& uv, const rad::TexelCoverage& c,
                            std::size_t t) {
    const std::size_t f = std::size_t(c.face[t]);
    const double b1 = c.barycentric[2 * t], b2 = c.barycentric[2 * t + 1], w[3] = {1 - b1 - b2, b1, b2};
    TexelGeometry g;
    g.p.setZero();
    g.N.setZero();
    Eigen::Vector3d corner[3];
    for (int k = 0; k < 3; ++k) {
        corner[k] = at(m.positions, m.faces[3 * f + k]);
        g.p += w[k] * corner[k];
        g.N += w[k] * at(m.normals, m.faces[3 * f + k]);
    }
    g.N.normalize();
    Eigen::Matrix<double, 3, 2> edges;
    edges.col(0) = corner[1] - corner[0];
    edges.col(1) = corner[2] - corner[0];
    Eigen::Matrix2d duv;
    duv << uv[6 * f + 2] - uv[6 * f], uv[6 * f + 4] - uv[6 * f], uv[6 * f + 3] - uv[6 * f + 1],
        uv[6 * f + 5] - uv[6 * f + 1];
    const Eigen::Matrix<double, 3, 2> dP = edges * duv.inverse();  // columns dP/du, dP/dv
    g.T = (dP.col(0) - g.N.dot(dP.col(0)) * g.N).normalized();
    const double s = dP.col(0).cross(dP.col(1)).dot(edges.col(0).cross(edges.col(1))) < 0 ? -1.0 : 1.0;
    g.B = s * g.N.cross(g.T);
    return g;
}

using AnalyticNormal = std::function<Eigen::Vector3d(const Eigen::Vector3d& p, const Eigen::Vector3d& n)>;

Eigen::Vector3d sphereNormal(const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
    const double b = p.dot(n), c = p.squaredNorm() - 1, disc = std::sqrt(std::max(0.0, b * b - c));
    const double t1 = -b + disc, t2 = -b - disc;
    return (p + (std::fabs(t1) < std::fabs(t2) ? t1 : t2) * n).normalized();
}

AnalyticNormal torusNormal(double R, double r) {
    return [R, r](const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
        const auto normalAt = [R](const Eigen::Vector3d& q) {
            return (q - R * Eigen::Vector3d(q.x(), q.y(), 0).normalized()).normalized();
        };
        double t = 0;  // Newton on the distance to the tube along the ray
        for (int i = 0; i < 30; ++i) {
            const Eigen::Vector3d q = p + t * n;
            t -= (std::hypot(std::hypot(q.x(), q.y()) - R, q.z()) - r) / normalAt(q).dot(n);
        }
        return normalAt(p + t * n);
    };
}

struct Errors {
    double objectMean = 0, tangentMean = 0, tangentFrameMax = 0;
    std::size_t texels = 0;
};

Errors bakeErrors(const rad::TriangleMesh& source, const rad::TriangleMesh& target, int size,
                  const AnalyticNormal& analytic) {
    const rad::PerTriangleAtlas atlas = rad::makePerTriangleAtlas(target.faceCount(), size);
    const rad::TexelCoverage cov = rad::rasterizeTexelCoverage(atlas.wedgeUv.data(), target.faceCount(), size, size);
    rad::NormalBakeOptions options;
    options.width = options.height = size;
    options.space = rad::NormalSpace::Object;
    const rad::NormalBakeResult object = rad::bakeNormalMap(target, atlas.wedgeUv.data(), source, nullptr, options);
    options.space = rad::NormalSpace::Tangent;
    options.tangentFrame = rad::TangentFrame::PerFaceUvDerivative;
    const rad::NormalBakeResult tangent = rad::bakeNormalMap(target, atlas.wedgeUv.data(), source, nullptr, options);
    Errors e;
    EXPECT_EQ(object.chartTexels, cov.coveredCount());
    EXPECT_EQ(object.rayHits, object.chartTexels);  // closed surfaces close together: every ray hits
    EXPECT_EQ(object.closestPointFallbacks, 0u);
    for (std::size_t t = 0; t < cov.face.size(); ++t) {
        EXPECT_EQ(object.chart[t], cov.face[t] >= 0 ? 1 : 0);
        if (cov.face[t] < 0) {
            EXPECT_EQ(object.valid[t], 0);
            continue;
        }
        EXPECT_EQ(object.valid[t], 1);
        EXPECT_EQ(tangent.valid[t], 1);
        const TexelGeometry g = texelGeometry(target, atlas.wedgeUv, cov, t);
        const Eigen::Vector3d exact = analytic(g.p, g.N);
        const Eigen::Vector3d n = at(object.normals, t);
        EXPECT_NEAR(n.norm(), 1.0, 1e-5);
        e.objectMean += angleDegrees(n, exact);
        const Eigen::Vector3d nt = at(tangent.normals, t);
        EXPECT_NEAR(nt.norm(), 1.0, 1e-5);
        e.tangentMean += angleDegrees(nt.x() * g.T + nt.y() * g.B + nt.z() * g.N, exact);
        e.tangentFrameMax = std::max({e.tangentFrameMax, angleDegrees(at(tangent.tangents, t), g.T),
                                      angleDegrees(at(object.tangents, t), g.T)});
        ++e.texels;
    }
    e.objectMean /= double(e.texels);
    e.tangentMean /= double(e.texels);
    return e;
}

TEST(NormalBaker, FineSphereOntoCoarseSphereMatchesTheAnalyticNormal) {
    const rad::TriangleMesh source = rad::makeIcosphere(6), target = rad::makeIcosphere(2);
    const Errors e = bakeErrors(source, target, 256, sphereNormal);
    EXPECT_GT(e.texels, 10000u);
    EXPECT_LT(e.objectMean, 0.5);
    EXPECT_LT(e.tangentMean, 0.5);
    EXPECT_LT(e.tangentFrameMax, 0.01);
    // The target's own (interpolated) normals are much further off: the bake did something.
}

TEST(NormalBaker, FineTorusOntoCoarseTorusMatchesTheAnalyticNormal) {
    const rad::TriangleMesh source = rad::makeTorus(1.0f, 0.35f, 256, 128), target = rad::makeTorus(1.0f, 0.35f, 24, 12);
    const Errors e = bakeErrors(source, target, 256, torusNormal(1.0, 0.35));
    EXPECT_GT(e.texels, 10000u);
    EXPECT_LT(e.objectMean, 0.5);
    EXPECT_LT(e.tangentMean, 0.5);
    EXPECT_LT(e.tangentFrameMax, 0.01);
}

TEST(NormalBaker, TiltedSourceInTangentSpaceDecodesWithTheIndependentFrameAlsoForMirroredUvs) {
    // Target: a flat grid (normal +z). Source: the tilted plane z = 0.3 x - 0.2 y + 0.01 (a bigger
    // grid), whose normal (-0.3, 0.2, 1) / |.| is far from the target's, so every component of
    // the tangent-space normal matters. Every third face of the atlas is mirrored inside its
    // cell by a u <-> v swap (handedness s = -1).
    rad::TriangleMesh target;
    radtest::addGrid(target, 9, -1.0f, 1.0f);
    rad::TriangleMesh source;
    radtest::addGrid(source, 41, -2.0f, 2.0f);
    const Eigen::Vector3d exact = Eigen::Vector3d(-0.3, 0.2, 1.0).normalized();
    for (std::size_t v = 0; v < source.vertexCount(); ++v) {
        source.positions[3 * v + 2] = 0.3f * source.positions[3 * v] - 0.2f * source.positions[3 * v + 1] + 0.01f;
        for (int k = 0; k < 3; ++k) source.normals[3 * v + k] = float(exact[k]);
    }
    const int size = 256;
    rad::PerTriangleAtlas atlas = rad::makePerTriangleAtlas(target.faceCount(), size);
    for (std::size_t f = 0; f < target.faceCount(); f += 3)
        for (int k = 0; k < 3; ++k) {
            // Swap u and v relative to the cell's corner: each triangle of a cell is symmetric about
            // the cell's diagonal, so the layout stays the same set of texels, orientation reversed.
            const std::size_t cell = f / 2;
            const float x0 = float((cell % std::size_t(atlas.cellsPerRow)) * atlas.cellSize) / size;
            const float y0 = float((cell / std::size_t(atlas.cellsPerRow)) * atlas.cellSize) / size;
            float* uv = &atlas.wedgeUv[6 * f + 2 * k];
            const float u = uv[0], v = uv[1];
            uv[0] = x0 + (v - y0);
            uv[1] = y0 + (u - x0);
        }
    ASSERT_EQ(rad::checkUvLayout(atlas.wedgeUv.data(), target.faceCount(), size).problem(), "");
    const rad::TexelCoverage cov = rad::rasterizeTexelCoverage(atlas.wedgeUv.data(), target.faceCount(), size, size);
    rad::NormalBakeOptions options;
    options.width = options.height = size;
    options.space = rad::NormalSpace::Tangent;
    options.tangentFrame = rad::TangentFrame::PerFaceUvDerivative;
    options.maxRayDistance = 1.0f;
    const rad::NormalBakeResult tangent = rad::bakeNormalMap(target, atlas.wedgeUv.data(), source, nullptr, options);
    EXPECT_EQ(tangent.rayHits, tangent.chartTexels);
    std::size_t mirrored = 0, checked = 0;
    double largestXY = 0;
    for (std::size_t t = 0; t < cov.face.size(); ++t) {
        if (cov.face[t] < 0) continue;
        const TexelGeometry g = texelGeometry(target, atlas.wedgeUv, cov, t);
        mirrored += g.B.dot(g.N.cross(g.T)) < 0;
        const Eigen::Vector3d nt = at(tangent.normals, t);
        largestXY = std::max(largestXY, std::hypot(nt.x(), nt.y()));
        EXPECT_LT(angleDegrees(nt.x() * g.T + nt.y() * g.B + nt.z() * g.N, exact), 1e-3) << t;
        EXPECT_LT(angleDegrees(at(tangent.tangents, t), g.T), 1e-3) << t;
        ++checked;
    }
    EXPECT_GT(mirrored, 1000u);
    EXPECT_GT(checked, 10000u);
    EXPECT_GT(largestXY, 0.3);
}

// A torus layout with shared corners: u = major angle / 2 pi, v = minor angle / 2 pi, per corner,
// a face crossing a seam taking u + 1 (or v + 1) at its corners below the seam, all scaled into
// [0.02, 0.98] so the layout stays inside the texture.
std::vector<float> torusUv(const rad::TriangleMesh& m, double R) {
    std::vector<float> uv(6 * m.faceCount());
    for (std::size_t f = 0; f < m.faceCount(); ++f) {
        double u[3], v[3];
        for (int k = 0; k < 3; ++k) {
            const Eigen::Vector3d p = at(m.positions, m.faces[3 * f + k]);
            u[k] = std::atan2(p.y(), p.x()) / (2 * kPi);
            if (u[k] < 0) u[k] += 1;
            v[k] = std::atan2(p.z(), std::hypot(p.x(), p.y()) - R) / (2 * kPi);
            if (v[k] < 0) v[k] += 1;
        }
        for (double* w : {u, v}) {
            const double hi = std::max({w[0], w[1], w[2]});
            for (int k = 0; k < 3; ++k)
                if (hi - w[k] > 0.5) w[k] += 1;  // the face crosses the seam: unwrap its low corners
        }
        for (int k = 0; k < 3; ++k) {
            // Faces that crossed the seam end beyond 1: they are drawn at the high end of the
            // layout, which is where the seam's other side is; shrink everything to fit.
            uv[6 * f + 2 * k] = float(0.02 + 0.96 * u[k] / (1.0 + 1.0 / 24));
            uv[6 * f + 2 * k + 1] = float(0.02 + 0.96 * v[k] / (1.0 + 1.0 / 12));
        }
    }
    return uv;
}

// Decodes a tangent-space texel the way a MikkTSpace renderer does.
Eigen::Vector3d decodeMikkTSpace(const rad::TriangleMesh& m, const std::vector<float>& cornerTangents,
                                 const rad::TexelCoverage& c, std::size_t t, const Eigen::Vector3d& tangentNormal) {
    const std::size_t f = std::size_t(c.face[t]);
    const double b1 = c.barycentric[2 * t], b2 = c.barycentric[2 * t + 1], w[3] = {1 - b1 - b2, b1, b2};
    Eigen::Vector3d T = Eigen::Vector3d::Zero(), N = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
        const float* ct = cornerTangents.data() + 4 * (3 * f + k);
        T += w[k] * Eigen::Vector3d(ct[0], ct[1], ct[2]);
        N += w[k] * at(m.normals, m.faces[3 * f + k]);
    }
    const double sign = cornerTangents[4 * 3 * f + 3];
    const Eigen::Vector3d B = sign * N.cross(T);
    return (tangentNormal.x() * T + tangentNormal.y() * B + tangentNormal.z() * N).normalized();
}

TEST(NormalBaker, MikkTSpaceBakeOfATorusWithSharedUvsDecodesToTheAnalyticNormal) {
    // The default tangent frame. A MikkTSpace renderer (decoder above) gets the analytic normal
    // back from our map; the same renderer given a map baked in the old per-face frame does not.
    const double R = 1.0, r = 0.35;
    const rad::TriangleMesh source = rad::makeTorus(float(R), float(r), 256, 128), target = rad::makeTorus(float(R), float(r), 24, 12);
    const std::vector<float> uv = torusUv(target, R);
    const int size = 512;
    ASSERT_EQ(rad::checkUvLayout(uv.data(), target.faceCount(), size).problem(), "");
    rad::TangentSpaceInput in;
    in.positions = target.positions.data();
    in.vertexCount = target.vertexCount();
    in.faces = target.faces.data();
    in.faceCount = target.faceCount();
    in.normals = target.normals.data();
    in.uv = uv.data();
    const rad::CornerTangents frames = rad::computeMikkTSpaceTangents(in);
    ASSERT_EQ(frames.defaultFrameCorners + frames.zeroTangentCorners, 0u);

    rad::NormalBakeOptions options;
    options.width = options.height = size;
    options.space = rad::NormalSpace::Tangent;
    ASSERT_EQ(options.tangentFrame, rad::TangentFrame::MikkTSpace);  // the default
    const rad::NormalBakeResult mikk = rad::bakeNormalMap(target, uv.data(), source, nullptr, options);
    options.tangentFrame = rad::TangentFrame::PerFaceUvDerivative;
    const rad::NormalBakeResult perFace = rad::bakeNormalMap(target, uv.data(), source, nullptr, options);
    const rad::TexelCoverage cov = rad::rasterizeTexelCoverage(uv.data(), target.faceCount(), size, size);
    const AnalyticNormal exact = torusNormal(R, r);
    double mikkMean = 0, mikkMax = 0, perFaceMean = 0;
    std::size_t texels = 0;
    for (std::size_t t = 0; t < cov.face.size(); ++t) {
        if (cov.face[t] < 0) continue;
        ASSERT_EQ(mikk.valid[t], 1);
        const TexelGeometry g = texelGeometry(target, uv, cov, t);
        const Eigen::Vector3d truth = exact(g.p, g.N);
        const double e = angleDegrees(decodeMikkTSpace(target, frames.tangents, cov, t, at(mikk.normals, t)), truth);
        EXPECT_NEAR(at(mikk.normals, t).norm(), 1.0, 1e-5);
        mikkMean += e;
        mikkMax = std::max(mikkMax, e);
        perFaceMean += angleDegrees(decodeMikkTSpace(target, frames.tangents, cov, t, at(perFace.normals, t)), truth);
        ++texels;
    }
    ASSERT_GT(texels, 50000u);
    mikkMean /= double(texels);
    perFaceMean /= double(texels);
    // Measured: 0.0066 mean, 0.022 max (the source's own facets); the per-face map 0.034.
    EXPECT_LT(mikkMean, 0.02);
    EXPECT_LT(mikkMax, 0.1);
    EXPECT_GT(perFaceMean, 3 * mikkMean) << "the old frame should be off in a MikkTSpace renderer";
}

TEST(NormalBaker, MikkTSpaceBakeOnAPerTriangleAtlasDecodesToTheAnalyticNormal) {
    // Every triangle its own chart: each corner's tangent is its face's dP/du projected on the
    // vertex normal's plane, so the frame varies inside a triangle. The sphere's analytic normal
    // comes back through the MikkTSpace decoding.
    const rad::TriangleMesh source = rad::makeIcosphere(6), target = rad::makeIcosphere(2);
    const int size = 256;
    const rad::PerTriangleAtlas atlas = rad::makePerTriangleAtlas(target.faceCount(), size);
    rad::TangentSpaceInput in;
    in.positions = target.positions.data();
    in.vertexCount = target.vertexCount();
    in.faces = target.faces.data();
    in.faceCount = target.faceCount();
    in.normals = target.normals.data();
    in.uv = atlas.wedgeUv.data();
    const rad::CornerTangents frames = rad::computeMikkTSpaceTangents(in);
    rad::NormalBakeOptions options;
    options.width = options.height = size;
    options.space = rad::NormalSpace::Tangent;
    const rad::NormalBakeResult mikk = rad::bakeNormalMap(target, atlas.wedgeUv.data(), source, nullptr, options);
    const rad::TexelCoverage cov = rad::rasterizeTexelCoverage(atlas.wedgeUv.data(), target.faceCount(), size, size);
    double mean = 0;
    std::size_t texels = 0;
    for (std::size_t t = 0; t < cov.face.size(); ++t) {
        if (cov.face[t] < 0) continue;
        const TexelGeometry g = texelGeometry(target, atlas.wedgeUv, cov, t);
        mean += angleDegrees(decodeMikkTSpace(target, frames.tangents, cov, t, at(mikk.normals, t)), sphereNormal(g.p, g.N));
        ++texels;
    }
    ASSERT_GT(texels, 10000u);
    EXPECT_LT(mean / double(texels), 0.5);
}

// Two parallel 2 x 2 squares at heights zUp > 0 and zDown < 0, each with its own constant vertex
// normal; the target is the unit square z = 0 with normal +z, UVs = (x, y) in [0, 1].
void twoSheets(float zUp, const Eigen::Vector3f& nUp, float zDown, const Eigen::Vector3f& nDown,
               rad::TriangleMesh& source, rad::TriangleMesh& target, std::vector<float>& uv) {
    source = rad::TriangleMesh();
    for (const auto& [z, n] : {std::make_pair(zUp, nUp), std::make_pair(zDown, nDown)}) {
        const std::uint32_t base = std::uint32_t(source.vertexCount());
        for (const auto& [x, y] : {std::make_pair(-0.5f, -0.5f), std::make_pair(1.5f, -0.5f), std::make_pair(1.5f, 1.5f),
                                   std::make_pair(-0.5f, 1.5f)}) {
            source.positions.insert(source.positions.end(), {x, y, z});
            source.normals.insert(source.normals.end(), {n.x(), n.y(), n.z()});
        }
        source.faces.insert(source.faces.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
    target = rad::TriangleMesh();
    target.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    target.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    target.faces = {0, 1, 2, 0, 2, 3};
    uv = {0, 0, 1, 0, 1, 1, 0, 0, 1, 1, 0, 1};
}

TEST(NormalBaker, TheNearerOfTheSurfacesAheadAndBehindIsBakedWhicheverSideItIsOn) {
    // The nearer sheet wins, whether it lies ahead of the target (+n) or behind it, and a sheet
    // beyond the ray distance is ignored: the one-ray-per-texel shortcut must not change the rule.
    const Eigen::Vector3f a = Eigen::Vector3f(0.3f, 0.0f, 1.0f).normalized(), b = Eigen::Vector3f(0.0f, -0.4f, 1.0f).normalized();
    struct Case {
        float zUp, zDown, distance;
        Eigen::Vector3f expected;
    };
    for (const Case& c : {Case{0.02f, -0.03f, 0.1f, a}, Case{0.03f, -0.02f, 0.1f, b}, Case{0.05f, -0.2f, 0.1f, a},
                          Case{0.2f, -0.05f, 0.1f, b}}) {
        rad::TriangleMesh source, target;
        std::vector<float> uv;
        twoSheets(c.zUp, a, c.zDown, b, source, target, uv);
        rad::NormalBakeOptions options;
        options.width = options.height = 32;
        options.space = rad::NormalSpace::Object;
        options.maxRayDistance = c.distance;
        const rad::NormalBakeResult r = rad::bakeNormalMap(target, uv.data(), source, nullptr, options);
        ASSERT_GT(r.chartTexels, 900u);
        EXPECT_EQ(r.rayHits, r.chartTexels) << c.zUp << " " << c.zDown;
        for (std::size_t t = 0; t < r.valid.size(); ++t) {
            if (!r.valid[t]) continue;
            EXPECT_LT(angleDegrees(at(r.normals, t), c.expected.cast<double>()), 1e-3) << c.zUp << " " << c.zDown << " " << t;
        }
    }
}

TEST(NormalBaker, WithoutKeptTangentsTheMapIsTheSameAndNoTangentArrayIsMade) {
    // A tangent-space bake without LEAN has no use for the per-texel tangents (normal_map_bake.cpp
    // turns them off): the map must not change with them.
    const double R = 1.0, r = 0.35;
    const rad::TriangleMesh source = rad::makeTorus(float(R), float(r), 128, 64), target = rad::makeTorus(float(R), float(r), 24, 12);
    const std::vector<float> uv = torusUv(target, R);
    rad::NormalBakeOptions options;
    options.width = options.height = 128;
    options.space = rad::NormalSpace::Tangent;
    const rad::NormalBakeResult kept = rad::bakeNormalMap(target, uv.data(), source, nullptr, options);
    options.keepTangents = false;
    const rad::NormalBakeResult dropped = rad::bakeNormalMap(target, uv.data(), source, nullptr, options);
    EXPECT_EQ(kept.tangents.size(), 3u * 128 * 128);
    EXPECT_TRUE(dropped.tangents.empty());
    EXPECT_EQ(kept.normals, dropped.normals);
    EXPECT_EQ(kept.valid, dropped.valid);
    EXPECT_GT(dropped.rayHits, 5000u);
}

TEST(NormalBaker, ClosestPointFallbackWhereTheSourceHasAHole) {
    // Source: a sphere without its cap z > 0.8; rays of at most 0.05 from the target (a coarse
    // sphere) cannot reach anything from the middle of the missing cap.
    rad::TriangleMesh source = rad::makeIcosphere(5);
    std::vector<std::uint32_t> kept;
    for (std::size_t f = 0; f < source.faceCount(); ++f) {
        double z = 0;
        for (int k = 0; k < 3; ++k) z += source.positions[3 * source.faces[3 * f + k] + 2] / 3.0;
        if (z <= 0.8) kept.insert(kept.end(), source.faces.begin() + 3 * f, source.faces.begin() + 3 * f + 3);
    }
    source.faces = kept;
    const rad::TriangleMesh target = rad::makeIcosphere(2);
    const int size = 256;
    const rad::PerTriangleAtlas atlas = rad::makePerTriangleAtlas(target.faceCount(), size);
    const rad::TexelCoverage cov = rad::rasterizeTexelCoverage(atlas.wedgeUv.data(), target.faceCount(), size, size);
    rad::NormalBakeOptions options;
    options.width = options.height = size;
    options.maxRayDistance = 0.05f;
    const rad::NormalBakeResult r = rad::bakeNormalMap(target, atlas.wedgeUv.data(), source, nullptr, options);
    EXPECT_FLOAT_EQ(r.maxRayDistance, 0.05f);
    std::size_t deepInHole = 0, nearHole = 0;
    for (std::size_t t = 0; t < cov.face.size(); ++t) {
        if (cov.face[t] < 0) continue;
        const Eigen::Vector3d p = texelGeometry(target, atlas.wedgeUv, cov, t).p.normalized();
        deepInHole += p.z() > 0.86;
        nearHole += p.z() > 0.74;
        EXPECT_EQ(r.valid[t], 1);
        // Fallback or hit, the normal is the source's near the texel: on the hole's side, the
        // rim's normal, otherwise the sphere's own.
        if (p.z() < 0.74) EXPECT_LT(angleDegrees(at(r.normals, t), p), 1.0);
    }
    EXPECT_GT(deepInHole, 100u);
    EXPECT_GE(r.closestPointFallbacks, deepInHole);
    EXPECT_LE(r.closestPointFallbacks, nearHole);
    EXPECT_EQ(r.rayHits + r.closestPointFallbacks + r.invalidTexels, r.chartTexels);
    EXPECT_EQ(r.invalidTexels, 0u);
}

TEST(NormalBaker, TinyRayDistanceFallsBackToTheClosestPointEverywhereOffTheSurface) {
    const rad::TriangleMesh source = rad::makeIcosphere(5), target = rad::makeIcosphere(2, 0.9f);
    const int size = 256;
    const rad::PerTriangleAtlas atlas = rad::makePerTriangleAtlas(target.faceCount(), size);
    const rad::TexelCoverage cov = rad::rasterizeTexelCoverage(atlas.wedgeUv.data(), target.faceCount(), size, size);
    rad::NormalBakeOptions options;
    options.width = options.height = size;
    options.maxRayDistance = 1e-4f;
    const rad::NormalBakeResult r = rad::bakeNormalMap(target, atlas.wedgeUv.data(), source, nullptr, options);
    EXPECT_EQ(r.rayHits, 0u);
    EXPECT_EQ(r.closestPointFallbacks, r.chartTexels);
    for (std::size_t t = 0; t < cov.face.size(); ++t) {
        if (cov.face[t] < 0) continue;
        // The closest point of a (fine) sphere to an inner point is along the radius.
        const Eigen::Vector3d p = texelGeometry(target, atlas.wedgeUv, cov, t).p;
        EXPECT_LT(angleDegrees(at(r.normals, t), p), 1.0);
    }
}

TEST(NormalBaker, ColoursAreTheSourceColourAtTheHitPoint) {
    // Colour = A x + b, linear in position, so its barycentric interpolation on a source triangle
    // is exact: the baked colour, mapped back through A, must be a point of the texel's ray that
    // lies on the source.
    const rad::TriangleMesh source = rad::makeIcosphere(5), target = rad::makeIcosphere(2);
    Eigen::Matrix3d A;
    A << 0.5, 0.1, 0.0, -0.2, 0.4, 0.1, 0.0, 0.3, 0.6;
    const Eigen::Vector3d b(0.5, 0.4, 0.3);
    std::vector<float> colors(3 * source.vertexCount());
    for (std::size_t v = 0; v < source.vertexCount(); ++v) {
        const Eigen::Vector3d c = A * at(source.positions, v) + b;
        for (int k = 0; k < 3; ++k) colors[3 * v + k] = float(c[k]);
    }
    const int size = 256;
    const rad::PerTriangleAtlas atlas = rad::makePerTriangleAtlas(target.faceCount(), size);
    const rad::TexelCoverage cov = rad::rasterizeTexelCoverage(atlas.wedgeUv.data(), target.faceCount(), size, size);
    rad::NormalBakeOptions options;
    options.width = options.height = size;
    options.bakeColor = true;
    const rad::NormalBakeResult r = rad::bakeNormalMap(target, atlas.wedgeUv.data(), source, colors.data(), options);
    ASSERT_EQ(r.colors.size(), 3 * cov.face.size());
    const double innerRadius = std::cos(0.05);  // the fine icosphere's faces are within this of the centre
    std::size_t checked = 0;
    for (std::size_t t = 0; t < cov.face.size(); ++t) {
        if (cov.face[t] < 0) {
            EXPECT_EQ(at(r.colors, t).norm(), 0.0);
            continue;
        }
        const TexelGeometry g = texelGeometry(target, atlas.wedgeUv, cov, t);
        const Eigen::Vector3d q = A.inverse() * (at(r.colors, t) - b);
        const Eigen::Vector3d offset = q - g.p;
        EXPECT_LT((offset - offset.dot(g.N) * g.N).norm(), 1e-4) << "not on the ray";
        EXPECT_LE(q.norm(), 1.0 + 1e-5);
        EXPECT_GE(q.norm(), innerRadius);
        ++checked;
    }
    EXPECT_GT(checked, 1000u);
}

TEST(NormalBaker, AutomaticRayDistanceIsTwiceTheLargestGapAndAtLeastAFractionOfTheDiagonal) {
    const rad::TriangleMesh source = rad::makeIcosphere(6), target = rad::makeIcosphere(1);
    // The gap is largest at the face centroids of the coarse sphere: 1 - |centroid|, up to the
    // fine sphere's own sagitta (< 1 - cos(0.02)).
    double gap = 0;
    for (std::size_t f = 0; f < target.faceCount(); ++f) {
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        for (int k = 0; k < 3; ++k) c += at(target.positions, target.faces[3 * f + k]) / 3.0;
        gap = std::max(gap, 1.0 - c.norm());
    }
    EXPECT_NEAR(rad::automaticRayDistance(target, source), 2 * gap, 2 * (1 - std::cos(0.02)) + 1e-5);
    // Identical meshes: the floor, 0.5 % of the bounding-box diagonal (2 sqrt(3) for the unit sphere,
    // whose icosahedral vertices do not reach the box corners: computed here from the vertices).
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
    for (std::size_t v = 0; v < source.vertexCount(); ++v) {
        lo = lo.cwiseMin(at(source.positions, v));
        hi = hi.cwiseMax(at(source.positions, v));
    }
    EXPECT_NEAR(rad::automaticRayDistance(source, source), 0.005 * (hi - lo).norm(), 1e-5);
}

TEST(NormalBaker, RefusesBadInputs) {
    const rad::TriangleMesh good = rad::makeIcosphere(1);
    const rad::PerTriangleAtlas atlas = rad::makePerTriangleAtlas(good.faceCount(), 128);
    rad::NormalBakeOptions options;
    options.width = options.height = 128;
    const float* uv = atlas.wedgeUv.data();
    rad::TriangleMesh empty;
    EXPECT_THROW(rad::bakeNormalMap(empty, uv, good, nullptr, options), rad::BakeInputError);
    EXPECT_THROW(rad::bakeNormalMap(good, uv, empty, nullptr, options), rad::BakeInputError);
    rad::TriangleMesh noNormals = good;
    noNormals.normals.clear();
    EXPECT_THROW(rad::bakeNormalMap(noNormals, uv, good, nullptr, options), rad::BakeInputError);
    EXPECT_NO_THROW(rad::bakeNormalMap(good, uv, noNormals, nullptr, options));  // source normals are computed
    rad::TriangleMesh nan = good;
    nan.positions[4] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(rad::bakeNormalMap(nan, uv, good, nullptr, options), rad::BakeInputError);
    EXPECT_THROW(rad::bakeNormalMap(good, uv, nan, nullptr, options), rad::BakeInputError);
    rad::TriangleMesh mismatched = good;
    mismatched.normals.pop_back();
    EXPECT_THROW(rad::bakeNormalMap(mismatched, uv, good, nullptr, options), rad::BakeInputError);
    rad::TriangleMesh zeroNormal = good;
    zeroNormal.normals[0] = zeroNormal.normals[1] = zeroNormal.normals[2] = 0.0f;
    EXPECT_THROW(rad::bakeNormalMap(zeroNormal, uv, good, nullptr, options), rad::BakeInputError);
    EXPECT_THROW(rad::bakeNormalMap(good, nullptr, good, nullptr, options), rad::BakeInputError);
    rad::NormalBakeOptions colour = options;
    colour.bakeColor = true;
    EXPECT_THROW(rad::bakeNormalMap(good, uv, good, nullptr, colour), rad::BakeInputError);
    rad::NormalBakeOptions zeroSize = options;
    zeroSize.width = 0;
    EXPECT_THROW(rad::bakeNormalMap(good, uv, good, nullptr, zeroSize), rad::BakeInputError);
}

TEST(NormalBaker, ProgressIsReportedAndReturningFalseCancels) {
    const rad::TriangleMesh source = rad::makeIcosphere(4), target = rad::makeIcosphere(2);
    const rad::PerTriangleAtlas atlas = rad::makePerTriangleAtlas(target.faceCount(), 256);
    rad::NormalBakeOptions options;
    options.width = options.height = 256;
    std::vector<double> seen;
    options.progress = [&](double fraction, const char*) {
        seen.push_back(fraction);
        return true;
    };
    rad::bakeNormalMap(target, atlas.wedgeUv.data(), source, nullptr, options);
    ASSERT_FALSE(seen.empty());
    EXPECT_DOUBLE_EQ(seen.back(), 1.0);
    for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_GT(seen[i], seen[i - 1]);
    int calls = 0;
    options.progress = [&](double, const char*) {
        ++calls;
        return false;
    };
    EXPECT_THROW(rad::bakeNormalMap(target, atlas.wedgeUv.data(), source, nullptr, options), rad::OperationCancelled);
    EXPECT_EQ(calls, 1);
}

TEST(NormalBaker, EncodingMapsMinusOneToOneOntoTheCodeRangeAndBack) {
    EXPECT_EQ(rad::encodeNormal8(-1.0f), 0);
    EXPECT_EQ(rad::encodeNormal8(1.0f), 255);
    EXPECT_EQ(rad::encodeNormal8(0.0f), 128);  // round(127.5)
    EXPECT_EQ(rad::encodeNormal16(-1.0f), 0);
    EXPECT_EQ(rad::encodeNormal16(1.0f), 65535);
    EXPECT_EQ(rad::encodeNormal16(0.0f), 32768);
    EXPECT_EQ(rad::encodeNormal8(2.0f), 255);  // clamped
    EXPECT_EQ(rad::encodeNormal16(-3.0f), 0);
    for (int i = -1000; i <= 1000; ++i) {
        const float x = i / 1000.0f;
        EXPECT_LE(std::fabs(rad::decodeNormal8(rad::encodeNormal8(x)) - x), 1.0f / 255.0f + 1e-6f);
        EXPECT_LE(std::fabs(rad::decodeNormal16(rad::encodeNormal16(x)) - x), 1.0f / 65535.0f + 1e-6f);
    }
    // Round to nearest with halves up, as std::lround of the scaled value, also right at and next
    // to every half code (where a cheaper rounding could slip by one).
    for (int k = 0; k < 255; ++k) {
        const float half = float((k + 0.5) / 255.0 * 2.0 - 1.0);
        for (const float x : {std::nextafter(half, -2.0f), half, std::nextafter(half, 2.0f)})
            EXPECT_EQ(rad::encodeNormal8(x), std::lround((x + 1.0f) * 0.5f * 255.0f)) << x;
    }
    for (int k = 0; k < 65535; k += 3) {
        const float half = float((k + 0.5) / 65535.0 * 2.0 - 1.0);
        for (const float x : {std::nextafter(half, -2.0f), half, std::nextafter(half, 2.0f)})
            EXPECT_EQ(rad::encodeNormal16(x), std::lround((double(x) + 1.0) * 0.5 * 65535.0)) << x;
    }
    EXPECT_EQ(rad::encodeNormal8(std::nanf("")), 128);
    EXPECT_EQ(rad::encodeNormal16(std::numeric_limits<float>::infinity()), 32768);
    for (int c = 0; c < 256; ++c) EXPECT_EQ(rad::encodeNormal8(rad::decodeNormal8(std::uint8_t(c))), c);
    for (int c = 0; c < 65536; c += 7) EXPECT_EQ(rad::encodeNormal16(rad::decodeNormal16(std::uint16_t(c))), c);
}

}  // namespace
