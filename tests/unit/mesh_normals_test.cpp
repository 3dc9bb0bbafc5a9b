// Tests of geometry/mesh_normals.h: exact cases worked by hand (area weighting, flat grids,
// orientation), convergence to the analytic normals of generated spheres and tori, and the
// treatment of vertices whose normal is undetermined.
#include "geometry/mesh_normals.h"
#include "geometry/primitive_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace {

double angleBetween(const float* a, const float* b) {
    const double d = double(a[0]) * b[0] + double(a[1]) * b[1] + double(a[2]) * b[2];
    const double la = std::sqrt(double(a[0]) * a[0] + double(a[1]) * a[1] + double(a[2]) * a[2]);
    const double lb = std::sqrt(double(b[0]) * b[0] + double(b[1]) * b[1] + double(b[2]) * b[2]);
    return std::acos(std::max(-1.0, std::min(1.0, d / (la * lb))));
}

TEST(MeshNormals, WeightsFacesByArea) {
    // Vertex 0 at the origin shared by a triangle of area 1 in the xy plane (normal +z) and one of
    // area 3 in the zx plane (normal +y): the area-weighted normal is (0, 3, 1) / sqrt(10), not
    // the unweighted (0, 1, 1) / sqrt(2).
    rad::TriangleMesh m;
    m.positions = {0, 0, 0, 2, 0, 0, 0, 1, 0, 0, 0, 3};
    m.faces = {0, 1, 2,   // (2,0,0) x (0,1,0) = (0,0,2): area 1, +z
               0, 3, 1};  // (0,0,3) x (2,0,0) = (0,6,0): area 3, +y
    EXPECT_EQ(rad::computeAreaWeightedNormals(m), 0u);
    ASSERT_EQ(m.normals.size(), 12u);
    EXPECT_NEAR(m.normals[0], 0.0, 1e-7);
    EXPECT_NEAR(m.normals[1], 3.0 / std::sqrt(10.0), 1e-7);
    EXPECT_NEAR(m.normals[2], 1.0 / std::sqrt(10.0), 1e-7);
    // Vertex 2 belongs to the first face only, vertex 3 to the second only.
    EXPECT_FLOAT_EQ(m.normals[8], 1.0f);
    EXPECT_FLOAT_EQ(m.normals[10], 1.0f);
    // Vertex 1 belongs to both: same weighting.
    EXPECT_NEAR(m.normals[4], 3.0 / std::sqrt(10.0), 1e-7);

    float n[3];
    rad::faceNormal(m, 1, n);
    EXPECT_FLOAT_EQ(n[1], 1.0f);
    EXPECT_DOUBLE_EQ(rad::faceArea(m, 0), 1.0);
    EXPECT_DOUBLE_EQ(rad::faceArea(m, 1), 3.0);
}

TEST(MeshNormals, FlatGroundIsUpAndReversedWindingFlips) {
    rad::ColumnSceneOptions o;
    rad::TriangleMesh scene = rad::makeColumnOnPlane(o);
    const std::vector<float> exact = scene.normals;
    EXPECT_EQ(rad::computeAreaWeightedNormals(scene), 0u);
    const std::size_t groundFirst = scene.vertexCount() - 81;
    for (std::size_t v = groundFirst; v < scene.vertexCount(); ++v) {
        EXPECT_FLOAT_EQ(scene.normals[3 * v + 2], 1.0f) << v;
        EXPECT_FLOAT_EQ(scene.normals[3 * v], 0.0f) << v;
    }
    // Cap vertices (flat discs) get the cap normal exactly.
    for (std::size_t v = 80; v < groundFirst; ++v) EXPECT_FLOAT_EQ(scene.normals[3 * v + 2], exact[3 * v + 2]) << v;

    for (std::size_t f = 0; f < scene.faceCount(); ++f) std::swap(scene.faces[3 * f + 1], scene.faces[3 * f + 2]);
    rad::computeAreaWeightedNormals(scene);
    for (std::size_t v = groundFirst; v < scene.vertexCount(); ++v) EXPECT_FLOAT_EQ(scene.normals[3 * v + 2], -1.0f);
}

TEST(MeshNormals, ConvergeToTheAnalyticNormals) {
    // Level 1 is exact by symmetry (every vertex sees congruent faces); from level 2 on the error
    // shrinks with the edge length.
    double previous = 1e9;
    for (int level = 1; level <= 5; ++level) {
        rad::TriangleMesh m = rad::makeIcosphere(level);
        const std::vector<float> exact = m.normals;
        ASSERT_EQ(rad::computeAreaWeightedNormals(m), 0u);
        double worst = 0.0;
        for (std::size_t v = 0; v < m.vertexCount(); ++v) {
            const double len = std::hypot(m.normals[3 * v], m.normals[3 * v + 1], m.normals[3 * v + 2]);
            ASSERT_NEAR(len, 1.0, 1e-6);
            worst = std::max(worst, angleBetween(&m.normals[3 * v], &exact[3 * v]));
        }
        if (level == 1) {
            EXPECT_LT(worst, 1e-6);
        } else {
            EXPECT_LT(worst, previous) << "level " << level;
            previous = worst;
        }
    }
    EXPECT_LT(previous, 0.2 * 3.14159265 / 180.0);  // level 5: within 0.2 degree

    // UV sphere and torus: exact by symmetry up to the stacks' uneven areas; within a degree or so.
    for (rad::TriangleMesh m : {rad::makeUvSphere(64, 128), rad::makeTorus(1.0f, 0.35f, 128, 64)}) {
        const std::vector<float> exact = m.normals;
        rad::computeAreaWeightedNormals(m);
        for (std::size_t v = 0; v < m.vertexCount(); ++v)
            ASSERT_LT(angleBetween(&m.normals[3 * v], &exact[3 * v]), 1.5 * 3.14159265 / 180.0) << v;
    }
}

TEST(MeshNormals, UndeterminedVerticesAreZeroAndCounted) {
    rad::TriangleMesh m;
    // Vertex 3 is used by no face; face 1 is degenerate (collinear), so vertex 4 only has zero area.
    m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 5, 5, 2, 0, 0};
    m.faces = {0, 1, 2, 0, 1, 4};
    EXPECT_EQ(rad::computeAreaWeightedNormals(m), 2u);
    for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(m.normals[9 + k], 0.0f);
        EXPECT_EQ(m.normals[12 + k], 0.0f);
    }
    EXPECT_FLOAT_EQ(m.normals[2], 1.0f);  // vertex 0 unaffected by the degenerate face
    float n[3];
    rad::faceNormal(m, 1, n);
    EXPECT_EQ(n[0], 0.0f);
    EXPECT_EQ(n[2], 0.0f);
    EXPECT_EQ(rad::faceArea(m, 1), 0.0);

    // Two opposite copies of a triangle cancel out.
    rad::TriangleMesh flat;
    flat.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    flat.faces = {0, 1, 2, 0, 2, 1};
    EXPECT_EQ(rad::computeAreaWeightedNormals(flat), 3u);
}

}  // namespace
