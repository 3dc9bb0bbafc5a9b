// Tests of lod/pop_buffer.h (Limper et al. 2013). Oracles: triangles whose level is worked out by
// hand in the comments, and an independent level finder that snaps with floor(t * 2^L) in double
// precision at every level (not the bit shifts of the unit) and looks for three distinct cells.
#include "lod/pop_buffer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using rad::TriangleMesh;

// Appends a triangle of three new vertices.
void addTriangle(TriangleMesh& m, std::array<float, 9> p) {
    const auto base = std::uint32_t(m.vertexCount());
    m.positions.insert(m.positions.end(), p.begin(), p.end());
    for (std::uint32_t k = 0; k < 3; ++k) m.faces.push_back(base + k);
}

// Cell of coordinate x of an axis spanning [lo, lo + extent] at level L, by floor in double.
long cellAt(double x, double lo, double extent, int level) {
    const double cells = std::ldexp(1.0, level);
    return std::min(long(std::floor((x - lo) / extent * cells)), long(cells) - 1);
}

// Level of every face by brute force over the levels.
std::vector<int> bruteLevels(const TriangleMesh& m) {
    std::array<double, 3> lo, hi;
    for (int k = 0; k < 3; ++k) lo[k] = hi[k] = m.positions[k];
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        lo[i % 3] = std::min(lo[i % 3], double(m.positions[i]));
        hi[i % 3] = std::max(hi[i % 3], double(m.positions[i]));
    }
    std::vector<int> levels(m.faceCount(), 17);
    for (std::size_t f = 0; f < m.faceCount(); ++f)
        for (int level = 1; level <= 16; ++level) {
            std::array<std::array<long, 3>, 3> c;
            for (int j = 0; j < 3; ++j)
                for (int k = 0; k < 3; ++k)
                    c[j][k] = hi[k] > lo[k] ? cellAt(m.positions[3 * m.faces[3 * f + j] + k], lo[k], hi[k] - lo[k], level) : 0;
            if (c[0] != c[1] && c[1] != c[2] && c[0] != c[2]) {
                levels[f] = level;
                break;
            }
        }
    return levels;
}

// The unit box [0, 1]^3 with triangles of known levels, in a scrambled order.
TriangleMesh handMadeMesh() {
    TriangleMesh m;
    const float g = 0.25f + 1.5f / 65536.0f;  // cell 16384 vs 16385 at level 16, both 8192 at level 15
    addTriangle(m, {0.25f, 0.5f, 0.5f, g, 0.5f, 0.5f, 0.25f, 0.9f, 0.5f});        // G: level 16
    addTriangle(m, {0.3f, 0.3f, 0.3f, 0.3f, 0.3f, 0.3f, 0.8f, 0.8f, 0.8f});        // D: duplicate point: never
    // C: x 0.40 vs 0.45 -> cells 0,0 | 1,1 | 3,3 | 6,7 at levels 1..4: first differ at 4
    addTriangle(m, {0.40f, 0.40f, 0.40f, 0.45f, 0.40f, 0.40f, 0.40f, 0.45f, 0.40f});
    addTriangle(m, {0.1f, 0.1f, 0.0f, 0.9f, 0.1f, 0.0f, 0.1f, 0.9f, 0.0f});        // A: level 1
    addTriangle(m, {0.7f, 0.7f, 0.7f, 0.700001f, 0.7f, 0.7f, 0.7f, 0.2f, 0.7f});   // F: 1e-6 apart: never
    // B: 0.1 vs 0.3: same half (level 1), quarters 0 and 1 (level 2)
    addTriangle(m, {0.1f, 0.1f, 0.1f, 0.3f, 0.1f, 0.1f, 0.1f, 0.3f, 0.1f});
    addTriangle(m, {0.0f, 0.0f, 0.0f, 1.0f, 1.0f, 1.0f, 1.0f, 0.0f, 0.0f});        // H: the box; level 1
    // E: one vertex used twice: never
    const auto base = std::uint32_t(m.vertexCount());
    m.positions.insert(m.positions.end(), {0.2f, 0.6f, 0.6f, 0.9f, 0.6f, 0.6f});
    m.faces.insert(m.faces.end(), {base, base, base + 1});
    return m;
}

TEST(PopBuffer, HandMadeTrianglesGetTheLevelsWorkedOutByHand) {
    const TriangleMesh m = handMadeMesh();
    const rad::PopBuffer pop = rad::buildPopBuffer(m);
    // Input order G D C A F B H E; levels 16 17 4 1 17 2 1 17; sorted stably by level.
    const std::vector<std::uint32_t> order = {3, 6, 5, 2, 0, 1, 4, 7};
    const std::vector<int> levels = {1, 1, 2, 4, 16, 17, 17, 17};
    ASSERT_EQ(pop.faceOrder, order);
    for (std::size_t i = 0; i < levels.size(); ++i) EXPECT_EQ(int(pop.faceLevel[i]), levels[i]) << i;
    const std::array<std::size_t, 18> ends = {0, 2, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 8};
    for (int l = 0; l <= 17; ++l) EXPECT_EQ(pop.levelEnd[l], ends[l]) << "level " << l;
    for (std::size_t i = 0; i < order.size(); ++i)
        for (int k = 0; k < 3; ++k) EXPECT_EQ(pop.faces[3 * i + k], m.faces[3 * order[i] + k]);
    EXPECT_EQ(bruteLevels(m), std::vector<int>({16, 17, 4, 1, 17, 2, 1, 17}));  // the oracle agrees
}

TEST(PopBuffer, SnappedCoordinatesAreCellCentresAndFlatAxesStay) {
    const TriangleMesh m = handMadeMesh();
    const rad::PopBuffer pop = rad::buildPopBuffer(m);
    // Vertex 6 is x = 0.40 (triangle C): cell 6 of 16 at level 4, centre 6.5 / 16.
    EXPECT_DOUBLE_EQ(pop.quantizedCoordinate(6, 0, 4), 6.5 / 16);
    EXPECT_DOUBLE_EQ(pop.quantizedCoordinate(6, 0, 1), 0.25);   // first half, centre 0.25
    EXPECT_DOUBLE_EQ(pop.quantizedCoordinate(19, 0, 1), 0.75);  // x = 1 (the box's max) is in the last cell

    TriangleMesh flat;  // the plane z = 2
    addTriangle(flat, {0, 0, 2, 1, 0, 2, 0, 1, 2});
    const rad::PopBuffer flatPop = rad::buildPopBuffer(flat);
    for (int level = 1; level <= 16; ++level) EXPECT_EQ(flatPop.quantizedCoordinate(1, 2, level), 2.0);
    EXPECT_EQ(flatPop.levelEnd[1], 1u);
}

TEST(PopBuffer, EveryLevelIsThePrefixOfItsNonDegenerateTriangles) {
    std::mt19937 rng(19);
    std::uniform_real_distribution<float> coord(-3.0f, 5.0f), jitter(-0.01f, 0.01f);
    TriangleMesh m;
    // Triangles of every size, from the box's size down to below a level-16 cell.
    for (int i = 0; i < 3000; ++i) {
        const float s = std::pow(10.0f, -float(i % 7));
        const float x = coord(rng), y = coord(rng), z = coord(rng);
        addTriangle(m, {x, y, z, x + s * jitter(rng) * 100, y + s * jitter(rng) * 100, z, x, y + s * jitter(rng) * 100,
                        z + s * jitter(rng) * 100});
    }
    const rad::PopBuffer pop = rad::buildPopBuffer(m);
    const std::vector<int> levels = bruteLevels(m);
    std::vector<std::uint32_t> sorted = pop.faceOrder;
    std::sort(sorted.begin(), sorted.end());
    for (std::uint32_t f = 0; f < sorted.size(); ++f) ASSERT_EQ(sorted[f], f);  // a permutation
    for (int level = 1; level <= 16; ++level) {
        std::vector<std::uint32_t> prefix(pop.faceOrder.begin(), pop.faceOrder.begin() + pop.levelEnd[level]);
        std::vector<std::uint32_t> expected;
        for (std::uint32_t f = 0; f < levels.size(); ++f)
            if (levels[f] <= level) expected.push_back(f);
        std::sort(prefix.begin(), prefix.end());
        EXPECT_EQ(prefix, expected) << "level " << level;
    }
    EXPECT_GT(pop.levelEnd[16] - pop.levelEnd[8], 0u);
    EXPECT_GT(pop.levelEnd[17] - pop.levelEnd[16], 0u);  // the smallest triangles never appear
}

TEST(PopBuffer, LevelForScreenSize) {
    // Largest move at level L: box / 2^(L + 1) pixels.
    EXPECT_EQ(rad::popLevelForScreenSize(1024, 1), 9);   // 1024 / 1024 = 1
    EXPECT_EQ(rad::popLevelForScreenSize(1025, 1), 10);
    EXPECT_EQ(rad::popLevelForScreenSize(1000, 2), 8);   // 1000 / 512 < 2, 1000 / 256 > 2
    EXPECT_EQ(rad::popLevelForScreenSize(1, 1), 1);
    EXPECT_EQ(rad::popLevelForScreenSize(1e9, 0.5), 16);
    EXPECT_THROW(rad::popLevelForScreenSize(100, 0), std::invalid_argument);
}

void expectRefusal(const TriangleMesh& m, const std::string& words) {
    try {
        rad::buildPopBuffer(m);
        ADD_FAILURE() << "accepted a mesh that should be refused (" << words << ")";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
}

TEST(PopBuffer, RefusesEmptyAndBrokenMeshes) {
    expectRefusal(TriangleMesh{}, "no vertices");
    TriangleMesh noFaces;
    noFaces.positions = {0, 0, 0, 1, 1, 1};
    expectRefusal(noFaces, "no faces");
    TriangleMesh nan;
    addTriangle(nan, {0, 0, 0, 1, 0, 0, 0, std::numeric_limits<float>::quiet_NaN(), 0});
    expectRefusal(nan, "non-finite");
    TriangleMesh inf;
    addTriangle(inf, {0, 0, 0, 1, 0, 0, 0, std::numeric_limits<float>::infinity(), 0});
    expectRefusal(inf, "non-finite");
    TriangleMesh outOfRange;
    addTriangle(outOfRange, {0, 0, 0, 1, 0, 0, 0, 1, 0});
    outOfRange.faces[2] = 7;
    expectRefusal(outOfRange, "refers to vertex 7");
}

}  // namespace
