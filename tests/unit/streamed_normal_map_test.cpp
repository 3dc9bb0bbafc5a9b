// The normal map made by streaming the original points (outofcore/streamed_normal_map.h).
#include "outofcore/streamed_normal_map.h"

#include "bake/texel_coverage.h"
#include "bake/texture_atlas.h"
#include "geometry/primitive_meshes.h"
#include "outofcore/vertex_clustering.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace {

constexpr double kDegrees = 180.0 / 3.14159265358979323846;

// A finely tessellated unit sphere simplified; the map's normal at every chart texel is compared
// with the analytic normal of the sphere at the texel's point (its direction from the centre).
TEST(StreamedNormalMap, SphereMapMatchesTheAnalyticNormal) {
    const rad::TriangleMesh sphere = rad::makeIcosphere(6);  // 40,962 points
    std::vector<float> normals(sphere.positions.size());
    for (std::size_t v = 0; v < sphere.vertexCount(); ++v) {
        const float* p = &sphere.positions[3 * v];
        const float length = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        for (int k = 0; k < 3; ++k) normals[3 * v + k] = p[k] / length;
    }
    rad::ClusteringOptions options;
    options.targetTriangles = 600;
    const rad::TriangleMesh simplified = rad::clusterVertices(sphere, options);
    ASSERT_GT(simplified.faceCount(), 300u);
    const int size = 512;
    const rad::PerTriangleAtlas atlas = rad::makePerTriangleAtlas(simplified.faceCount(), size, 5);
    rad::NormalSplatter splatter(simplified, atlas.wedgeUv, size);
    // In two chunks, as a stream would come.
    const std::size_t half = sphere.vertexCount() / 2;
    splatter.splat(sphere.positions.data(), normals.data(), half);
    splatter.splat(&sphere.positions[3 * half], &normals[3 * half], sphere.vertexCount() - half);
    const rad::StreamedNormalMap map = splatter.finish(4);
    EXPECT_EQ(map.pointsSplatted, sphere.vertexCount());
    EXPECT_GT(map.texelsWithPoints, map.chartTexels / 4);

    const rad::TexelCoverage coverage = rad::rasterizeTexelCoverage(atlas.wedgeUv.data(), simplified.faceCount(), size, size);
    double sum = 0.0, worst = 0.0;
    std::size_t count = 0;
    std::vector<double> angles;
    for (std::size_t t = 0; t < coverage.face.size(); ++t) {
        if (coverage.face[t] < 0 || !coverage.interior[t]) continue;
        const std::uint32_t* f = &simplified.faces[3 * std::size_t(coverage.face[t])];
        const float b1 = coverage.barycentric[2 * t], b2 = coverage.barycentric[2 * t + 1];
        double p[3], length = 0;
        for (int k = 0; k < 3; ++k) {
            p[k] = (1 - b1 - b2) * simplified.positions[3 * f[0] + k] + b1 * simplified.positions[3 * f[1] + k] +
                   b2 * simplified.positions[3 * f[2] + k];
            length += p[k] * p[k];
        }
        length = std::sqrt(length);
        double dot = 0;
        for (int k = 0; k < 3; ++k) dot += p[k] / length * map.normals[3 * t + k];
        const double angle = std::acos(std::clamp(dot, -1.0, 1.0)) * kDegrees;
        sum += angle;
        angles.push_back(angle);
        worst = std::max(worst, angle);
        ++count;
    }
    ASSERT_GT(count, 10000u);
    std::sort(angles.begin(), angles.end());
    const double p99 = angles[angles.size() * 99 / 100];
    std::printf("sphere: %zu interior texels, %zu with points, mean %.3f, p99 %.3f, max %.3f degrees\n", count,
                map.texelsWithPoints, sum / double(count), p99, worst);
    // The map's texels average the normals of the points nearest to them: their angular spread is
    // about a point spacing (0.94 degrees at level 6) and a texel (~0.2 degrees). Texels no point
    // reached are filled from their own triangle, whose extent (~12 degrees for 600 triangles) bounds the worst case.
    EXPECT_LT(sum / double(count), 1.0);
    EXPECT_LT(p99, 3.0);
    EXPECT_LT(worst, 10.0);
    // Every texel filled with a unit vector.
    for (std::size_t t = 0; t < map.normals.size() / 3; t += 97) {
        const float* n = &map.normals[3 * t];
        EXPECT_NEAR(n[0] * n[0] + n[1] * n[1] + n[2] * n[2], 1.0f, 1e-4f);
    }
}

TEST(StreamedNormalMap, ZeroNormalsAreSkipped) {
    const rad::TriangleMesh target = rad::makeIcosphere(1);
    const rad::PerTriangleAtlas atlas = rad::makePerTriangleAtlas(target.faceCount(), 64, 2);
    rad::NormalSplatter splatter(target, atlas.wedgeUv, 64);
    const float points[6] = {1, 0, 0, 0, 1, 0};
    const float normals[6] = {0, 0, 0, 0, 1, 0};
    splatter.splat(points, normals, 2);
    const rad::StreamedNormalMap map = splatter.finish(2);
    EXPECT_EQ(map.pointsSplatted, 1u);
    EXPECT_EQ(map.pointsWithoutNormal, 1u);
    EXPECT_EQ(map.texelsWithPoints, 1u);
}

TEST(StreamedNormalMap, MismatchedInputsAreRefused) {
    const rad::TriangleMesh target = rad::makeIcosphere(0);
    std::vector<float> uv(5, 0.0f);
    EXPECT_THROW(rad::NormalSplatter(target, uv, 64), std::invalid_argument);
    EXPECT_THROW(rad::NormalSplatter(rad::TriangleMesh{}, uv, 64), std::invalid_argument);
}

}  // namespace
