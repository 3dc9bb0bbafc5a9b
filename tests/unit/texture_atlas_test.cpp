// Tests of bake/texture_atlas.h. Oracles independent of the rasteriser under test: texels touched
// by a face are found by clipping the (closed) texel square against the triangle
// (Sutherland-Hodgman, a non-empty result even for a corner contact); texel centres inside faces
// are counted with plain barycentric coordinates; the largest cell is recomputed by trying the
// next larger one.
#include "bake/texel_coverage.h"
#include "bake/texture_atlas.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace {

struct P2 {
    double x, y;
};

// Texel-space triangle (x = u W, y = (1 - v) H) of face f.
void texelTriangle(const std::vector<float>& uv, std::size_t f, int size, P2 out[3]) {
    for (int k = 0; k < 3; ++k) out[k] = {uv[6 * f + 2 * k] * double(size), (1.0 - uv[6 * f + 2 * k + 1]) * size};
}

// Whether the closed square [x0, x0 + 1] x [y0, y0 + 1] meets the closed triangle: clip the
// triangle by the square's four half planes (with a tiny tolerance outwards).
bool squareMeetsTriangle(double x0, double y0, const P2 tri[3]) {
    std::vector<P2> poly(tri, tri + 3);
    const double eps = 1e-9;
    const auto clip = [&](auto inside, auto cut) {
        std::vector<P2> out;
        for (std::size_t i = 0; i < poly.size(); ++i) {
            const P2 a = poly[i], b = poly[(i + 1) % poly.size()];
            const bool ia = inside(a), ib = inside(b);
            if (ia) out.push_back(a);
            if (ia != ib) out.push_back(cut(a, b));
        }
        poly = out;
    };
    const auto cutX = [](double x) {
        return [x](P2 a, P2 b) { const double t = (x - a.x) / (b.x - a.x); return P2{x, a.y + t * (b.y - a.y)}; };
    };
    const auto cutY = [](double y) {
        return [y](P2 a, P2 b) { const double t = (y - a.y) / (b.y - a.y); return P2{a.x + t * (b.x - a.x), y}; };
    };
    clip([&](P2 p) { return p.x >= x0 - eps; }, cutX(x0 - eps));
    if (poly.empty()) return false;
    clip([&](P2 p) { return p.x <= x0 + 1 + eps; }, cutX(x0 + 1 + eps));
    if (poly.empty()) return false;
    clip([&](P2 p) { return p.y >= y0 - eps; }, cutY(y0 - eps));
    if (poly.empty()) return false;
    clip([&](P2 p) { return p.y <= y0 + 1 + eps; }, cutY(y0 + 1 + eps));
    return !poly.empty();
}

// Barycentric inside test with a margin (in texels, along each edge's normal).
bool strictlyInside(double px, double py, const P2 t[3], double margin) {
    for (int k = 0; k < 3; ++k) {
        const P2 a = t[(k + 1) % 3], b = t[(k + 2) % 3], c = t[k];
        const double ex = b.x - a.x, ey = b.y - a.y, length = std::hypot(ex, ey);
        const double side = (ex * (py - a.y) - ey * (px - a.x)) / length;
        const double sideC = ex * (c.y - a.y) - ey * (c.x - a.x);
        if (!(sideC > 0 ? side > margin : -side > margin)) return false;
    }
    return true;
}

std::size_t bruteForceOverlaps(const std::vector<float>& uv, int size) {
    const std::size_t faces = uv.size() / 6;
    std::size_t overlapping = 0;
    for (int r = 0; r < size; ++r)
        for (int c = 0; c < size; ++c) {
            int inside = 0;
            for (std::size_t f = 0; f < faces; ++f) {
                P2 t[3];
                texelTriangle(uv, f, size, t);
                inside += strictlyInside(c + 0.5, r + 0.5, t, 1e-2);
            }
            overlapping += inside >= 2;
        }
    return overlapping;
}

TEST(TextureAtlas, EveryCoordinateIsInTheUnitSquareOnATexelCentreAndTheLayoutPassesTheChecks) {
    for (const std::size_t faces : {std::size_t(1), std::size_t(2), std::size_t(7), std::size_t(1001), std::size_t(52000)}) {
        const int size = faces > 10000 ? 4096 : 512;
        const rad::PerTriangleAtlas atlas = rad::makePerTriangleAtlas(faces, size);
        ASSERT_EQ(atlas.wedgeUv.size(), 6 * faces);
        for (const float x : atlas.wedgeUv) {
            ASSERT_GE(x, 0.0f);
            ASSERT_LE(x, 1.0f);
            const double texel = x * size - 0.5;  // on a centre: an integer
            ASSERT_NEAR(texel, std::round(texel), 1e-3) << faces;
        }
        const rad::UvLayoutReport report = rad::checkUvLayout(atlas.wedgeUv.data(), faces, size);
        EXPECT_EQ(report.faceCount, faces);
        EXPECT_EQ(report.overlappingTexels, 0u);
        EXPECT_EQ(report.problem(), "") << faces;
    }
}

TEST(TextureAtlas, TheLargestCellThatFitsIsUsedAndLegsAreAtLeastTwoTexels) {
    for (const std::size_t faces : {std::size_t(1), std::size_t(3), std::size_t(100), std::size_t(999), std::size_t(20000)}) {
        for (const int gutter : {1, 2, 4, 7}) {
            const int size = faces > 10000 ? 4096 : 1024;
            const rad::PerTriangleAtlas atlas = rad::makePerTriangleAtlas(faces, size, gutter);
            const std::size_t cells = (faces + 1) / 2;
            // The cells fit...
            const std::size_t perRow = std::size_t(size / atlas.cellSize);
            EXPECT_EQ(atlas.cellsPerRow, int(perRow));
            EXPECT_GE(perRow * perRow, cells);
            // ... and one texel more per cell would not.
            const std::size_t biggerPerRow = std::size_t(size / (atlas.cellSize + 1));
            EXPECT_LT(biggerPerRow * biggerPerRow, cells) << faces << " faces, gutter " << gutter;
            EXPECT_EQ(atlas.gutterTexels, gutter);
            for (std::size_t f = 0; f < faces; ++f) {
                P2 t[3];
                texelTriangle(atlas.wedgeUv, f, size, t);
                EXPECT_GE(std::hypot(t[1].x - t[0].x, t[1].y - t[0].y), 2.0 - 1e-3);
                EXPECT_GE(std::hypot(t[2].x - t[0].x, t[2].y - t[0].y), 2.0 - 1e-3);
            }
        }
    }
}

// Brute force: every texel a face touches (even at a point) is at least `gutter` texels (index
// distance max(|dc|, |dr|)) from every texel another face touches, i.e. gutter - 1 empty texels
// lie between two charts; including across the texture border (wrapping sampler).
TEST(TextureAtlas, TexelsTouchedByDifferentFacesAreAtLeastTheGutterApart) {
    for (const int gutter : {1, 2, 3, 4, 5}) {
        for (const std::size_t faces : {std::size_t(9), std::size_t(30)}) {
            const int size = 128;
            const rad::PerTriangleAtlas atlas = rad::makePerTriangleAtlas(faces, size, gutter);
            std::vector<int> owner(std::size_t(size) * size, -1);
            std::size_t touched = 0;
            for (std::size_t f = 0; f < faces; ++f) {
                P2 t[3];
                texelTriangle(atlas.wedgeUv, f, size, t);
                for (int r = 0; r < size; ++r)
                    for (int c = 0; c < size; ++c) {
                        if (!squareMeetsTriangle(c, r, t)) continue;
                        int& o = owner[std::size_t(r) * size + c];
                        ASSERT_EQ(o, -1) << "texel (" << c << ", " << r << ") touched by faces " << o << " and " << f;
                        o = int(f);
                        ++touched;
                    }
            }
            ASSERT_GT(touched, faces * 3);
            for (int r = 0; r < size; ++r)
                for (int c = 0; c < size; ++c) {
                    const int a = owner[std::size_t(r) * size + c];
                    if (a < 0) continue;
                    for (int dr = -(gutter - 1); dr <= gutter - 1; ++dr)
                        for (int dc = -(gutter - 1); dc <= gutter - 1; ++dc) {
                            const int rr = (r + dr + size) % size, cc = (c + dc + size) % size;
                            const int b = owner[std::size_t(rr) * size + cc];
                            ASSERT_TRUE(b < 0 || b == a) << "gutter " << gutter << ": texels (" << c << ", " << r
                                                         << ") of face " << a << " and (" << cc << ", " << rr
                                                         << ") of face " << b;
                        }
                }
            // The rasteriser's coverage stays inside the touched texels, owned by the same face.
            const rad::TexelCoverage coverage = rad::rasterizeTexelCoverage(atlas.wedgeUv.data(), faces, size, size);
            for (std::size_t i = 0; i < owner.size(); ++i)
                if (coverage.face[i] >= 0) ASSERT_EQ(coverage.face[i], owner[i]) << i;
        }
    }
}

TEST(TextureAtlas, CellsDoNotOverlapByTheCheckAndByBruteForce) {
    const std::size_t faces = 25;
    const int size = 64;
    const rad::PerTriangleAtlas atlas = rad::makePerTriangleAtlas(faces, size, 2);
    EXPECT_EQ(rad::checkUvLayout(atlas.wedgeUv.data(), faces, size).overlappingTexels, 0u);
    EXPECT_EQ(bruteForceOverlaps(atlas.wedgeUv, size), 0u);
}

TEST(TextureAtlas, RefusesNoFacesTooSmallTexturesAndBadSizes) {
    EXPECT_THROW(rad::makePerTriangleAtlas(0, 1024), rad::BakeInputError);
    for (const int bad : {0, -4, 8, 1000, 1 << 15, 1 << 20})
        EXPECT_THROW(rad::makePerTriangleAtlas(10, bad), rad::BakeInputError) << bad;
    EXPECT_THROW(rad::makePerTriangleAtlas(10, 1024, 0), rad::BakeInputError);
    // 100000 faces need 224 cells per side of >= 11 texels (gutter 4): 2464 -> 4096.
    try {
        rad::makePerTriangleAtlas(100000, 1024);
        FAIL() << "no refusal";
    } catch (const rad::BakeInputError& e) {
        EXPECT_NE(std::string(e.what()).find("4096"), std::string::npos) << e.what();
    }
    EXPECT_THROW(rad::makePerTriangleAtlas(100000, 2048), rad::BakeInputError);
    EXPECT_NO_THROW(rad::makePerTriangleAtlas(100000, 4096));
    // Beyond 16384: the message says so.
    try {
        rad::makePerTriangleAtlas(std::size_t(10) * 1000 * 1000, 16384);
        FAIL() << "no refusal";
    } catch (const rad::BakeInputError& e) {
        EXPECT_NE(std::string(e.what()).find("16384"), std::string::npos) << e.what();
    }
}

TEST(TextureAtlas, TextureSizeProblemAcceptsPowersOfTwoInRange) {
    EXPECT_EQ(rad::textureSizeProblem(16), "");
    EXPECT_EQ(rad::textureSizeProblem(4096), "");
    EXPECT_EQ(rad::textureSizeProblem(16384), "");
    EXPECT_NE(rad::textureSizeProblem(8), "");
    EXPECT_NE(rad::textureSizeProblem(1000), "");
    EXPECT_NE(rad::textureSizeProblem(32768), "");
    EXPECT_NE(rad::textureSizeProblem(0), "");
    EXPECT_NE(rad::textureSizeProblem(-16), "");
    EXPECT_EQ(rad::textureSizeProblem(64, 64, 64), "");
    EXPECT_NE(rad::textureSizeProblem(128, 64, 64), "");
}

TEST(TextureAtlas, AnOverlappingHandMadeLayoutIsReportedButSharedEdgesAreNot) {
    const int size = 32;
    // A unit square split along its diagonal: the two faces share an edge, no overlap.
    const std::vector<float> split = {0.1f, 0.1f, 0.9f, 0.1f, 0.9f, 0.9f, 0.1f, 0.1f, 0.9f, 0.9f, 0.1f, 0.9f};
    const rad::UvLayoutReport ok = rad::checkUvLayout(split.data(), 2, size);
    EXPECT_EQ(ok.overlappingTexels, 0u);
    EXPECT_EQ(ok.problem(), "");
    // The same square plus a triangle across its middle.
    std::vector<float> overlapping = split;
    overlapping.insert(overlapping.end(), {0.2f, 0.3f, 0.8f, 0.3f, 0.5f, 0.7f});
    const rad::UvLayoutReport bad = rad::checkUvLayout(overlapping.data(), 3, size);
    const std::size_t expected = bruteForceOverlaps(overlapping, size);
    EXPECT_GT(expected, 20u);
    EXPECT_EQ(bad.overlappingTexels, expected);
    EXPECT_NE(bad.problem().find("overlap"), std::string::npos) << bad.problem();
    EXPECT_NE(bad.problem().find("Trivial Per-Triangle"), std::string::npos);
}

TEST(TextureAtlas, OutOfRangeNonFiniteAndDegenerateCoordinatesAreReported) {
    const int size = 64;
    std::vector<float> uv = {0.1f, 0.1f, 0.4f, 0.1f, 0.1f, 0.4f,    // fine
                             0.5f, 0.5f, 1.5f, 0.5f, 0.5f, 0.9f,    // out of range
                             0.6f, 0.1f, 0.9f, 0.1f, 0.6f, 0.4f};   // fine
    rad::UvLayoutReport r = rad::checkUvLayout(uv.data(), 3, size);
    EXPECT_EQ(r.outOfRangeFaces, 1u);
    EXPECT_EQ(r.nonFiniteFaces, 0u);
    EXPECT_NE(r.problem().find("outside [0, 1]"), std::string::npos) << r.problem();
    uv[9] = -0.01f;
    uv[8] = 0.9f;
    r = rad::checkUvLayout(uv.data(), 3, size);
    EXPECT_EQ(r.outOfRangeFaces, 1u);
    // Rounding of another tool's unwrap (Blender's torus has u = -4.4e-16 and 1 + 1e-7) is not out of range.
    uv[9] = -4.4e-16f;
    uv[8] = 1.0f + 1e-7f;
    EXPECT_EQ(rad::checkUvLayout(uv.data(), 3, size).outOfRangeFaces, 0u);
    uv[9] = -1e-4f;
    EXPECT_EQ(rad::checkUvLayout(uv.data(), 3, size).outOfRangeFaces, 1u);
    uv[8] = 0.9f;
    uv[9] = std::numeric_limits<float>::quiet_NaN();
    r = rad::checkUvLayout(uv.data(), 3, size);
    EXPECT_EQ(r.nonFiniteFaces, 1u);
    EXPECT_NE(r.problem().find("NaN"), std::string::npos) << r.problem();
    uv[9] = std::numeric_limits<float>::infinity();
    EXPECT_EQ(rad::checkUvLayout(uv.data(), 3, size).nonFiniteFaces, 1u);
    // Degenerate: collinear corners.
    uv[9] = 0.5f;
    uv[10] = 0.7f;
    uv[11] = 0.5f;
    r = rad::checkUvLayout(uv.data(), 3, size);
    EXPECT_EQ(r.nonFiniteFaces, 0u);
    EXPECT_EQ(r.outOfRangeFaces, 0u);
    EXPECT_EQ(r.degenerateFaces, 1u);
    EXPECT_NE(r.problem(), "");
    EXPECT_EQ(rad::checkUvLayout(uv.data(), 0, size).problem().empty(), false);
}

}  // namespace

// perTriangleAtlasCapacity is exactly the largest face count makePerTriangleAtlas accepts; and at
// 4096^2 with the smallest gutter it is 2 x 819^2 (cells of 2 + 1 + 2 = 5 texels).
TEST(TextureAtlas, CapacityIsTheLargestFaceCountThatIsLaidOut) {
    EXPECT_EQ(rad::perTriangleAtlasCapacity(4096, 1), 2u * 819u * 819u);
    EXPECT_EQ(rad::perTriangleAtlasCapacity(4096, 0), 0u);
    for (const int size : {16, 64, 256, 1024}) {
        for (const int gutter : {1, 2, 3, 5}) {
            const std::size_t capacity = rad::perTriangleAtlasCapacity(size, gutter);
            if (capacity == 0) {
                EXPECT_THROW(rad::makePerTriangleAtlas(1, size, gutter), rad::BakeInputError);
                continue;
            }
            EXPECT_NO_THROW(rad::makePerTriangleAtlas(capacity, size, gutter)) << size << " " << gutter;
            EXPECT_THROW(rad::makePerTriangleAtlas(capacity + 1, size, gutter), rad::BakeInputError)
                << size << " " << gutter;
        }
    }
}
