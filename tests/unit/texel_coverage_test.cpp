// Tests of bake/texel_coverage.h against brute force on random layouts (small triangles of both
// orientations, some overlapping, in a non-square texture so that width and height cannot be
// swapped unnoticed). Oracles written here: barycentric point-in-triangle with a margin, the
// distance from a point to a triangle by its three edges (segment distances) and a containment
// test, dense sampling of texel squares.
#include "bake/texel_coverage.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace {

constexpr double kReach = rad::TexelCoverage::kBilinearReach;

struct P2 {
    double x, y;
};

constexpr int kWidth = 96, kHeight = 64;

void texelTriangle(const std::vector<float>& uv, std::size_t f, P2 out[3]) {
    for (int k = 0; k < 3; ++k) out[k] = {uv[6 * f + 2 * k] * double(kWidth), (1.0 - uv[6 * f + 2 * k + 1]) * kHeight};
}

double cross(P2 o, P2 a, P2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

// Signed distances to the three edges, positive inside: min of them.
double insideMargin(P2 p, const P2 t[3]) {
    const double orientation = cross(t[0], t[1], t[2]) > 0 ? 1.0 : -1.0;
    double m = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
        const P2 a = t[k], b = t[(k + 1) % 3];
        m = std::min(m, orientation * cross(a, b, p) / std::hypot(b.x - a.x, b.y - a.y));
    }
    return m;
}

double segmentDistance(P2 p, P2 a, P2 b) {
    const double dx = b.x - a.x, dy = b.y - a.y;
    const double s = std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / (dx * dx + dy * dy), 0.0, 1.0);
    return std::hypot(p.x - (a.x + s * dx), p.y - (a.y + s * dy));
}

double distanceToTriangle(P2 p, const P2 t[3]) {
    if (insideMargin(p, t) >= 0) return 0.0;
    return std::min({segmentDistance(p, t[0], t[1]), segmentDistance(p, t[1], t[2]), segmentDistance(p, t[2], t[0])});
}

std::vector<float> randomLayout(std::mt19937& rng, std::size_t faces) {
    std::uniform_real_distribution<float> centre(0.05f, 0.95f), offset(-0.06f, 0.06f);
    std::vector<float> uv;
    while (uv.size() < 6 * faces) {
        const float cu = centre(rng), cv = centre(rng);
        float t[6];
        for (int k = 0; k < 3; ++k) {
            t[2 * k] = std::clamp(cu + offset(rng), 0.0f, 1.0f);
            t[2 * k + 1] = std::clamp(cv + offset(rng), 0.0f, 1.0f);
        }
        const double area = std::fabs((t[2] - t[0]) * (t[5] - t[1]) - (t[3] - t[1]) * (t[4] - t[0])) * kWidth * kHeight;
        if (area < 2.0) continue;  // keep slivers out: the checks divide by edge lengths
        uv.insert(uv.end(), t, t + 6);
    }
    return uv;
}

P2 pointFromBarycentrics(const P2 t[3], double b1, double b2) {
    const double b0 = 1 - b1 - b2;
    return {b0 * t[0].x + b1 * t[1].x + b2 * t[2].x, b0 * t[0].y + b1 * t[1].y + b2 * t[2].y};
}

TEST(TexelCoverage, InteriorTouchedAndEmptyTexelsAgreeWithBruteForce) {
    std::mt19937 rng(5);
    for (int trial = 0; trial < 4; ++trial) {
        const std::size_t faces = 40;
        const std::vector<float> uv = randomLayout(rng, faces);
        const rad::TexelCoverage cov = rad::rasterizeTexelCoverage(uv.data(), faces, kWidth, kHeight);
        ASSERT_EQ(cov.width, kWidth);
        ASSERT_EQ(cov.height, kHeight);
        ASSERT_EQ(cov.face.size(), std::size_t(kWidth) * kHeight);
        std::vector<P2> tris(3 * faces);
        for (std::size_t f = 0; f < faces; ++f) texelTriangle(uv, f, &tris[3 * f]);
        std::size_t interiorCount = 0, touchedCount = 0, covered = 0;
        for (int r = 0; r < kHeight; ++r)
            for (int c = 0; c < kWidth; ++c) {
                const P2 centre{c + 0.5, r + 0.5};
                const std::size_t i = cov.texelIndex(c, r);
                const int f = cov.face[i];
                double nearest = std::numeric_limits<double>::infinity();
                bool centreInsideSome = false;
                for (std::size_t g = 0; g < faces; ++g) {
                    nearest = std::min(nearest, distanceToTriangle(centre, &tris[3 * g]));
                    centreInsideSome = centreInsideSome || insideMargin(centre, &tris[3 * g]) > 1e-6;
                }
                // No texel farther than the reach square's half-diagonal from every triangle is
                // covered.
                if (nearest > kReach * std::sqrt(2.0) + 1e-6) EXPECT_LT(f, 0) << c << ", " << r;
                if (f < 0) {
                    // An empty texel: the square of half-size kReach around its centre (what a
                    // bilinear lookup may read it from) meets no triangle (sampled densely inside).
                    EXPECT_FALSE(centreInsideSome) << c << ", " << r;
                    for (int a = 1; a < 16; ++a)
                        for (int b = 1; b < 16; ++b) {
                            const P2 q{centre.x - kReach + 2 * kReach * a / 16.0, centre.y - kReach + 2 * kReach * b / 16.0};
                            for (std::size_t g = 0; g < faces; ++g)
                                ASSERT_LT(insideMargin(q, &tris[3 * g]), 1e-6) << c << ", " << r << " face " << g;
                        }
                    continue;
                }
                ++covered;
                const P2* t = &tris[3 * std::size_t(f)];
                const double b1 = cov.barycentric[2 * i], b2 = cov.barycentric[2 * i + 1];
                const P2 q = pointFromBarycentrics(t, b1, b2);
                // The point is on the triangle.
                EXPECT_GE(b1, -1e-5);
                EXPECT_GE(b2, -1e-5);
                EXPECT_LE(b1 + b2, 1 + 1e-5);
                if (centreInsideSome) {
                    // Every centre inside a triangle belongs to a triangle that contains it, and its
                    // barycentrics give the centre back.
                    ++interiorCount;
                    EXPECT_EQ(cov.interior[i], 1) << c << ", " << r;
                    EXPECT_GT(insideMargin(centre, t), -1e-5) << c << ", " << r;
                    EXPECT_NEAR(q.x, centre.x, 1e-3);
                    EXPECT_NEAR(q.y, centre.y, 1e-3);
                } else {
                    // Reached only: the nearest point of the nearest triangle, within the reach
                    // square's half-diagonal of the centre.
                    ++touchedCount;
                    EXPECT_EQ(cov.interior[i], 0) << c << ", " << r;
                    const double d = std::hypot(q.x - centre.x, q.y - centre.y);
                    EXPECT_LE(d, kReach * std::sqrt(2.0) + 1e-5) << c << ", " << r;
                    EXPECT_NEAR(d, distanceToTriangle(centre, t), 1e-4);
                    // A triangle within kReach of the centre overlaps the reach square, so it
                    // competed: the chosen one is the nearest of all.
                    if (nearest < kReach) EXPECT_NEAR(d, nearest, 1e-4) << "not the nearest triangle at " << c << ", " << r;
                }
            }
        EXPECT_GT(interiorCount, 100u);
        EXPECT_GT(touchedCount, 100u);
        EXPECT_EQ(cov.coveredCount(), covered);
    }
}

TEST(TexelCoverage, EveryTexelWhoseReachSquareOverlapsATriangleIsCovered) {
    std::mt19937 rng(6);
    const std::size_t faces = 30;
    const std::vector<float> uv = randomLayout(rng, faces);
    const rad::TexelCoverage cov = rad::rasterizeTexelCoverage(uv.data(), faces, kWidth, kHeight);
    std::size_t checked = 0;
    for (std::size_t f = 0; f < faces; ++f) {
        P2 t[3];
        texelTriangle(uv, f, t);
        for (int r = 0; r < kHeight; ++r)
            for (int c = 0; c < kWidth; ++c) {
                bool overlaps = false;
                for (int a = 1; a < 8 && !overlaps; ++a)
                    for (int b = 1; b < 8 && !overlaps; ++b)
                        overlaps = insideMargin({c + 0.5 - kReach + 2 * kReach * a / 8.0,
                                                 r + 0.5 - kReach + 2 * kReach * b / 8.0}, t) > 1e-6;
                if (!overlaps) continue;
                ++checked;
                EXPECT_GE(cov.face[cov.texelIndex(c, r)], 0) << "face " << f << " texel " << c << ", " << r;
            }
    }
    EXPECT_GT(checked, 400u);
}

TEST(TexelCoverage, CountsTexelCentresStrictlyInsideTwoFaces) {
    // Two copies of one triangle, and a third face sharing an edge with the first: only the
    // copies' common interior counts.
    const std::vector<float> uv = {0.1f, 0.1f, 0.6f, 0.1f, 0.1f, 0.6f, 0.1f, 0.1f, 0.6f,
                                   0.1f, 0.1f, 0.6f, 0.6f, 0.1f, 0.6f, 0.6f, 0.1f, 0.6f};
    const rad::TexelCoverage cov = rad::rasterizeTexelCoverage(uv.data(), 3, kWidth, kHeight);
    P2 t[3];
    texelTriangle(uv, 0, t);
    std::size_t expected = 0;
    for (int r = 0; r < kHeight; ++r)
        for (int c = 0; c < kWidth; ++c) expected += insideMargin({c + 0.5, r + 0.5}, t) > 1e-2;
    EXPECT_GT(expected, 100u);
    EXPECT_EQ(cov.overlappingTexels, expected);
    // Ties between the identical faces keep the lower index.
    for (const int f : cov.face) EXPECT_NE(f, 1);
}

TEST(TexelCoverage, NonFiniteAndDegenerateFacesCoverNothing) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::vector<float> uv = {0.1f, 0.1f, 0.5f, 0.1f, nan, 0.5f,        // NaN
                                   0.1f, 0.1f, 0.5f, 0.5f, 0.9f, 0.9f,       // collinear
                                   0.2f, 0.2f, 0.2f, 0.2f, 0.2f, 0.2f};      // a point
    const rad::TexelCoverage cov = rad::rasterizeTexelCoverage(uv.data(), 3, kWidth, kHeight);
    EXPECT_EQ(cov.coveredCount(), 0u);
    EXPECT_EQ(cov.overlappingTexels, 0u);
    const rad::TexelCoverage none = rad::rasterizeTexelCoverage(nullptr, 0, 16, 8);
    EXPECT_EQ(none.face.size(), 128u);
    EXPECT_EQ(none.coveredCount(), 0u);
}

TEST(TexelCoverage, RowsRunTopToBottomWithVUp) {
    // A triangle near v = 1 (the top of the texture) covers row 0, not the last row.
    const std::vector<float> uv = {0.0f, 0.9f, 0.3f, 0.9f, 0.0f, 1.0f};
    const rad::TexelCoverage cov = rad::rasterizeTexelCoverage(uv.data(), 1, kWidth, kHeight);
    EXPECT_EQ(cov.face[cov.texelIndex(0, 0)], 0);
    EXPECT_EQ(cov.face[cov.texelIndex(0, kHeight - 1)], -1);
}

}  // namespace
