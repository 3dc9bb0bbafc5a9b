// repairVertexNormals (geometry/normal_repair.h): the defects of real scans get a usable normal.
#include "geometry/normal_repair.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace {

void expectNormal(const std::vector<float>& normals, std::size_t v, double x, double y, double z, double tol = 1e-6) {
    EXPECT_NEAR(normals[3 * v], x, tol) << "vertex " << v;
    EXPECT_NEAR(normals[3 * v + 1], y, tol) << "vertex " << v;
    EXPECT_NEAR(normals[3 * v + 2], z, tol) << "vertex " << v;
}

TEST(NormalRepair, ShortFiniteNormalsAreKeptAndNormalised) {
    // MeshLab stores unnormalised area-weighted sums: a sliver's vertex has a normal 1e-10 long.
    const std::vector<float> positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const std::vector<std::uint32_t> faces = {0, 1, 2};
    std::vector<float> normals = {0, 0, 1e-10f, 0, 3e-20f, 4e-20f, 2, 0, 0};
    const rad::NormalRepairCounts c = rad::repairVertexNormals(positions, faces, normals);
    EXPECT_EQ(c.kept, 3u);
    EXPECT_EQ(c.repaired(), 0u);
    EXPECT_TRUE(c.describe().empty());
    expectNormal(normals, 0, 0, 0, 1);
    expectNormal(normals, 1, 0, 0.6, 0.8);  // direction kept, not replaced by the face's
    expectNormal(normals, 2, 1, 0, 0);
}

TEST(NormalRepair, ZeroOrNanNormalOfASliverComesFromItsPlane) {
    // A sliver of area 5e-11 in the plane x + y + z = 0 ... tilted: its unit normal is known exactly.
    const double s = 1e-5;
    const std::vector<float> positions = {0, 0, 0, float(s), float(-s), 0, 0, float(s), float(-s)};
    const std::vector<std::uint32_t> faces = {0, 1, 2};
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::vector<float> normals = {0, 0, 0, nan, 0, 0, 0, 0, 0};
    const rad::NormalRepairCounts c = rad::repairVertexNormals(positions, faces, normals);
    EXPECT_EQ(c.fromFaces, 3u);
    const double k = 1.0 / std::sqrt(3.0);  // (s, -s, 0) x (0, s, -s) = s^2 (1, 1, 1)
    for (std::size_t v = 0; v < 3; ++v) expectNormal(normals, v, k, k, k, 1e-5);
}

TEST(NormalRepair, FaceNormalsAreAngleWeightedNotAreaWeighted) {
    // Two faces at the origin, both with a right angle there: a small one facing +Z and a large one
    // facing +X (25 times the area). Angle weighting gives the bisector; area weighting would not.
    const std::vector<float> positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 5, 0, 0, 0, 5};
    const std::vector<std::uint32_t> faces = {0, 1, 2, 0, 3, 4};
    std::vector<float> normals(15, 0.0f);
    for (int v = 1; v < 5; ++v) normals[3 * v + 2] = 1.0f;  // the others are known
    const rad::NormalRepairCounts c = rad::repairVertexNormals(positions, faces, normals);
    EXPECT_EQ(c.kept, 4u);
    EXPECT_EQ(c.fromFaces, 1u);
    const double k = 1.0 / std::sqrt(2.0);
    expectNormal(normals, 0, k, 0, k);
}

TEST(NormalRepair, VertexOnlyInDegenerateFacesTakesItsNeighboursRingByRing) {
    // A flat strip, plus vertex 4 on the segment 0-1 (its only faces have zero area), and vertices 5
    // and 6 further on that line in a face with 4 only (zero area too). Round 1: 4 gets the average
    // of 0 and 1. Round 2: 5 and 6 see only 4 as known (each other not: a round reads the normals
    // known before it), so both get 4's normal, whatever the order.
    const std::vector<float> positions = {0, 0, 0, 2, 0, 0, 0, 1, 0, 2, 1, 0, 1, 0, 0, 1.25f, 0, 0, 1.5f, 0, 0};
    const std::vector<std::uint32_t> faces = {0, 1, 2, 1, 3, 2, 0, 4, 1, 4, 5, 6};
    std::vector<float> normals(21, 0.0f);
    normals[2] = 1.0f;   // vertex 0: +Z
    normals[3] = 1.0f;   // vertex 1: +X (an odd scan normal, so that the average is recognisable)
    normals[8] = 1.0f;   // vertex 2: +Z
    normals[11] = 1.0f;  // vertex 3: +Z
    const rad::NormalRepairCounts c = rad::repairVertexNormals(positions, faces, normals);
    EXPECT_EQ(c.kept, 4u);
    EXPECT_EQ(c.fromFaces, 0u);
    EXPECT_EQ(c.fromNeighbours, 3u);
    const double k = 1.0 / std::sqrt(2.0);
    for (std::size_t v : {4u, 5u, 6u}) expectNormal(normals, v, k, 0, k);  // (0,0,1) + (1,0,0)
    EXPECT_EQ(c.describe(), "3 vertex normals repaired (3 from their neighbours)");
}

TEST(NormalRepair, IsolatedVerticesAreDefaultedAndCounted) {
    const std::vector<float> positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 7, 7, 7};
    const std::vector<std::uint32_t> faces = {0, 1, 2};
    std::vector<float> normals;  // none at all: every vertex is repaired
    const rad::NormalRepairCounts c = rad::repairVertexNormals(positions, faces, normals);
    ASSERT_EQ(normals.size(), 12u);
    EXPECT_EQ(c.kept, 0u);
    EXPECT_EQ(c.fromFaces, 3u);
    EXPECT_EQ(c.defaulted, 1u);
    for (std::size_t v = 0; v < 4; ++v) expectNormal(normals, v, 0, 0, 1);
    EXPECT_EQ(c.describe(), "4 vertex normals repaired (3 from their faces, 1 isolated, given +Z)");
}

}  // namespace
