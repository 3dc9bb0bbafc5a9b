// Tests of lod/texcoord_correction.h (Weber & Stamminger, eq. 1-3 and Alg. 1). Oracles: meshes whose
// texture coordinates are a linear function of the position, chosen here; the derivative of that
// function is known in closed form, and the coordinates of a moved point are the function at the
// point (or at its projection onto the plane, for a tilted plane).
#include "lod/texcoord_correction.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using rad::TriangleMesh;

// A jittered n x n grid of the plane origin + x a + y b, (x, y) in [0, 1]^2, with wedge coordinates
// uv = A (x, y) + o.
struct PlaneGrid {
    TriangleMesh mesh;
    std::vector<float> wedgeUv;
    std::vector<Eigen::Vector2d> xy;  // plane coordinates of every vertex
};

PlaneGrid planeGrid(int n, const Eigen::Vector3d& origin, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                    const Eigen::Matrix2d& A, const Eigen::Vector2d& o, unsigned seed) {
    PlaneGrid g;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> jitter(-0.3, 0.3);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const bool border = i == 0 || j == 0 || i == n - 1 || j == n - 1;
            Eigen::Vector2d q((i + (border ? 0 : jitter(rng))) / (n - 1), (j + (border ? 0 : jitter(rng))) / (n - 1));
            const Eigen::Vector3d p = origin + q.x() * a + q.y() * b;
            for (int k = 0; k < 3; ++k) g.mesh.positions.push_back(float(p[k]));
            g.xy.push_back(q);
        }
    // Plane coordinates of the float positions, so that the oracle is exact for what the mesh holds.
    Eigen::Matrix<double, 3, 2> basis;
    basis << a, b;
    for (std::size_t v = 0; v < g.xy.size(); ++v) {
        const Eigen::Vector3d p(g.mesh.positions[3 * v], g.mesh.positions[3 * v + 1], g.mesh.positions[3 * v + 2]);
        g.xy[v] = basis.colPivHouseholderQr().solve(p - origin);
    }
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            const std::uint32_t v00 = j * n + i, v10 = v00 + 1, v01 = v00 + n, v11 = v01 + 1;
            for (std::uint32_t v : {v00, v10, v11, v00, v11, v01}) g.mesh.faces.push_back(v);
        }
    for (std::uint32_t v : g.mesh.faces) {
        const Eigen::Vector2d uv = A * g.xy[v] + o;
        g.wedgeUv.push_back(float(uv.x()));
        g.wedgeUv.push_back(float(uv.y()));
    }
    return g;
}

TEST(TexCoordCorrection, DerivativeOfALinearMapOnAnAxisPlane) {
    Eigen::Matrix2d A;
    A << 0.3, 0.1, -0.05, 0.25;
    const PlaneGrid g = planeGrid(6, Eigen::Vector3d(1, 2, 0.5), Eigen::Vector3d(2, 0, 0), Eigen::Vector3d(0, 3, 0), A,
                                  Eigen::Vector2d(0.2, 0.1), 1);
    const rad::TexCoordDerivatives d = rad::computeTexCoordDerivatives(g.mesh, g.wedgeUv);
    // u = 0.3 (x - 1) / 2 + 0.1 (y - 2) / 3 + ..., so du/dx = 0.15, du/dy = 0.1 / 3, du/dz = 0.
    const double expected[6] = {0.3 / 2, 0.1 / 3, 0, -0.05 / 2, 0.25 / 3, 0};
    EXPECT_EQ(d.textureVertices, 36u);
    EXPECT_EQ(d.withoutTangentSpace, 0u);
    for (std::size_t c = 0; c < g.mesh.faces.size(); ++c)
        for (int k = 0; k < 6; ++k) ASSERT_NEAR(d.perCorner[6 * c + k], expected[k], 1e-5) << "corner " << c;
}

TEST(TexCoordCorrection, MovedVertexOfATiltedPlaneGetsTheCoordinatesOfItsProjection) {
    // An orthonormal but tilted plane: a moved point p' has the coordinates of its orthogonal
    // projection onto the plane (Alg. 1 moves along T and B, never along N).
    const Eigen::Vector3d a = Eigen::Vector3d(1, 2, 2) / 3, b = Eigen::Vector3d(2, 1, -2) / 3;
    Eigen::Matrix2d A;
    A << 0.5, -0.2, 0.1, 0.7;
    const Eigen::Vector2d o(0.1, 0.05);
    const Eigen::Vector3d origin(-1, 0.5, 2);
    const PlaneGrid g = planeGrid(5, origin, a, b, A, o, 2);
    const rad::TexCoordDerivatives d = rad::computeTexCoordDerivatives(g.mesh, g.wedgeUv);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> move(-0.05, 0.05);
    for (std::size_t c = 0; c < g.mesh.faces.size(); ++c) {
        const std::uint32_t v = g.mesh.faces[c];
        const double original[3] = {g.mesh.positions[3 * v], g.mesh.positions[3 * v + 1], g.mesh.positions[3 * v + 2]};
        const double moved[3] = {original[0] + move(rng), original[1] + move(rng), original[2] + move(rng)};
        double uv[2] = {g.wedgeUv[2 * c], g.wedgeUv[2 * c + 1]};
        rad::correctTexCoord(&d.perCorner[6 * c], original, moved, uv);
        const Eigen::Vector3d rel = Eigen::Vector3d(moved[0], moved[1], moved[2]) - origin;
        const Eigen::Vector2d expected = A * Eigen::Vector2d(rel.dot(a), rel.dot(b)) + o;
        ASSERT_NEAR(uv[0], expected.x(), 2e-6) << "corner " << c;
        ASSERT_NEAR(uv[1], expected.y(), 2e-6) << "corner " << c;
    }
}

TEST(TexCoordCorrection, ASeamKeepsOneDerivativePerChart) {
    // Two triangles sharing the edge (1,0,0)-(0,1,0) of the plane z = 0; the second chart is mirrored
    // in u and shifted: u = 3 - x, v = y. Its corners on the shared edge are other texture vertices.
    TriangleMesh m;
    m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    m.faces = {0, 1, 2, 1, 3, 2};
    const std::vector<float> uv = {0, 0, 1, 0, 0, 1,   // chart 1: u = x, v = y
                                   2, 0, 2, 1, 3, 1};  // chart 2: u = 3 - x, v = y
    const rad::TexCoordDerivatives d = rad::computeTexCoordDerivatives(m, uv);
    EXPECT_EQ(d.textureVertices, 6u);  // 4 vertices, the two on the seam twice
    EXPECT_EQ(d.withoutTangentSpace, 0u);
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(d.perCorner[6 * c + 0], 1, 1e-6);
        EXPECT_NEAR(d.perCorner[6 * c + 4], 1, 1e-6);
    }
    for (int c = 3; c < 6; ++c) {
        EXPECT_NEAR(d.perCorner[6 * c + 0], -1, 1e-6);
        EXPECT_NEAR(d.perCorner[6 * c + 4], 1, 1e-6);
    }
}

TEST(TexCoordCorrection, SharedTextureVertexAveragesItsTrianglesTangentSpaces) {
    // Vertex 0 at the origin shared by two triangles (same uv (0, 0)) on the edge of a box: the top
    // z = 0 (normal +z) with u = x, v = y, and the side x = 0 (normal -x) with u = z, v = y, so u
    // continues across the edge. Tangent spaces: T = (1,0,0) and (0,0,1), B = (0,1,0), N = (0,0,1)
    // and (-1,0,0). Averaged: T = (.5,0,.5), B = (0,1,0), N = (-.5,0,.5); the rows of its inverse
    // (row_u . T = 1, row_u . B = row_u . N = 0) are u = (1, 0, 1), v = (0, 1, 0).
    TriangleMesh m;
    m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, -1};
    m.faces = {0, 1, 2, 0, 2, 3};
    const std::vector<float> uv = {0, 0, 1, 0, 0, 1, 0, 0, 0, 1, -1, 0};
    const rad::TexCoordDerivatives d = rad::computeTexCoordDerivatives(m, uv);
    const double expected[6] = {1, 0, 1, 0, 1, 0};
    for (int c : {0, 3})
        for (int k = 0; k < 6; ++k) EXPECT_NEAR(d.perCorner[6 * c + k], expected[k], 1e-6) << c << " " << k;
    // Vertex 1 has only the first triangle: u = x exactly.
    EXPECT_NEAR(d.perCorner[6 * 1 + 0], 1, 1e-6);
    EXPECT_NEAR(d.perCorner[6 * 1 + 2], 0, 1e-6);
}

TEST(TexCoordCorrection, DegenerateTextureTrianglesGiveNoCorrection) {
    TriangleMesh m;
    m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    m.faces = {0, 1, 2};
    const std::vector<float> uv = {0, 0, 0.5f, 0.5f, 1, 1};  // collinear in texture space
    const rad::TexCoordDerivatives d = rad::computeTexCoordDerivatives(m, uv);
    EXPECT_EQ(d.textureVertices, 3u);
    EXPECT_EQ(d.withoutTangentSpace, 3u);
    for (float x : d.perCorner) EXPECT_EQ(x, 0.0f);
}

void expectRefusal(const TriangleMesh& m, const std::vector<float>& uv, const std::string& words) {
    try {
        rad::computeTexCoordDerivatives(m, uv);
        ADD_FAILURE() << "accepted input that should be refused (" << words << ")";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
}

TEST(TexCoordCorrection, RefusesMissingOrBrokenCoordinates) {
    TriangleMesh m;
    m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    m.faces = {0, 1, 2};
    expectRefusal(m, {}, "give the mesh texture coordinates");
    expectRefusal(m, {0, 0, 1, 0, 0, std::numeric_limits<float>::quiet_NaN()}, "non-finite texture coordinate");
    expectRefusal(TriangleMesh{}, {}, "no faces");
    TriangleMesh nan = m;
    nan.positions[4] = std::numeric_limits<float>::infinity();
    expectRefusal(nan, {0, 0, 1, 0, 0, 1}, "non-finite coordinate");
}

}  // namespace
