// Tests of geometry/primitive_meshes.h: topology (Euler characteristic, closed 2-manifold with a
// consistent orientation), counts as functions of the parameters, exact normals, and the shapes of
// the paper scenes (Fig. 6 quad of Vanhoey et al. 2015, column of Křivánek et al. 2004 Fig. 1).
#include "geometry/primitive_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <algorithm>
#include <stdexcept>
#include <utility>

namespace {

constexpr double kPi = 3.14159265358979323846;

using rad::TriangleMesh;

struct Topology {
    std::size_t edges = 0;
    bool everyEdgeTwoFaces = true;      // undirected edge shared by exactly two faces
    bool consistentlyOriented = true;   // each directed edge used once, its reverse once
};

Topology topologyOf(const TriangleMesh& m) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (std::size_t f = 0; f < m.faceCount(); ++f)
        for (int k = 0; k < 3; ++k) ++directed[{m.faces[3 * f + k], m.faces[3 * f + (k + 1) % 3]}];
    Topology t;
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> undirected;
    for (const auto& [e, count] : directed) {
        undirected[{std::min(e.first, e.second), std::max(e.first, e.second)}] += count;
        if (count != 1) t.consistentlyOriented = false;
        auto rev = directed.find({e.second, e.first});
        if (rev == directed.end() || rev->second != 1) t.consistentlyOriented = false;
    }
    t.edges = undirected.size();
    for (const auto& [e, count] : undirected)
        if (count != 2) t.everyEdgeTwoFaces = false;
    return t;
}

long long euler(const TriangleMesh& m) {
    return static_cast<long long>(m.vertexCount()) - static_cast<long long>(topologyOf(m).edges) +
           static_cast<long long>(m.faceCount());
}

double signedVolume(const TriangleMesh& m) {
    double v = 0.0;
    for (std::size_t f = 0; f < m.faceCount(); ++f) {
        const float* a = &m.positions[3 * m.faces[3 * f]];
        const float* b = &m.positions[3 * m.faces[3 * f + 1]];
        const float* c = &m.positions[3 * m.faces[3 * f + 2]];
        v += (double(a[0]) * (double(b[1]) * c[2] - double(b[2]) * c[1]) -
              double(a[1]) * (double(b[0]) * c[2] - double(b[2]) * c[0]) +
              double(a[2]) * (double(b[0]) * c[1] - double(b[1]) * c[0])) / 6.0;
    }
    return v;
}

// Geometric normal of face f (unnormalised) dotted with the mean of its vertex normals: > 0 when
// the winding agrees with the stored normals.
double windingAgreement(const TriangleMesh& m, std::size_t f) {
    const std::uint32_t i[3] = {m.faces[3 * f], m.faces[3 * f + 1], m.faces[3 * f + 2]};
    double e1[3], e2[3], nm[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
        e1[k] = double(m.positions[3 * i[1] + k]) - m.positions[3 * i[0] + k];
        e2[k] = double(m.positions[3 * i[2] + k]) - m.positions[3 * i[0] + k];
        for (int v = 0; v < 3; ++v) nm[k] += m.normals[3 * i[v] + k];
    }
    const double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    return c[0] * nm[0] + c[1] * nm[1] + c[2] * nm[2];
}

void expectUnitNormals(const TriangleMesh& m, double tol = 1e-6) {
    ASSERT_EQ(m.normals.size(), m.positions.size());
    for (std::size_t v = 0; v < m.vertexCount(); ++v) {
        const double len = std::hypot(m.normals[3 * v], m.normals[3 * v + 1], m.normals[3 * v + 2]);
        ASSERT_NEAR(len, 1.0, tol) << "vertex " << v;
    }
}

void expectWindingMatchesNormals(const TriangleMesh& m) {
    for (std::size_t f = 0; f < m.faceCount(); ++f) ASSERT_GT(windingAgreement(m, f), 0.0) << "face " << f;
}

TEST(Icosphere, CountsFollowTheLevel) {
    for (int level = 0; level <= 5; ++level) {
        const TriangleMesh m = rad::makeIcosphere(level);
        const std::size_t p = std::size_t{1} << (2 * level);  // 4^level
        EXPECT_EQ(m.vertexCount(), 10 * p + 2) << "level " << level;
        EXPECT_EQ(m.faceCount(), 20 * p) << "level " << level;
        EXPECT_EQ(m.vertexCount(), rad::icosphereVertexCount(level));
        EXPECT_EQ(m.faceCount(), rad::icosphereFaceCount(level));
        EXPECT_EQ(topologyOf(m).edges, 30 * p) << "level " << level;
        EXPECT_EQ(m.validate(), "");
    }
}

TEST(Icosphere, IsAClosedOrientedGenusZeroSurface) {
    for (int level = 0; level <= 4; ++level) {
        const TriangleMesh m = rad::makeIcosphere(level);
        const Topology t = topologyOf(m);
        EXPECT_EQ(euler(m), 2) << "level " << level;
        EXPECT_TRUE(t.everyEdgeTwoFaces) << "level " << level;
        EXPECT_TRUE(t.consistentlyOriented) << "level " << level;
        EXPECT_GT(signedVolume(m), 0.0) << "outward orientation, level " << level;
        expectWindingMatchesNormals(m);
    }
}

TEST(Icosphere, NormalsAreUnitAndEqualToTheNormalisedPosition) {
    const float radius = 2.5f;
    const TriangleMesh m = rad::makeIcosphere(3, radius);
    expectUnitNormals(m);
    for (std::size_t v = 0; v < m.vertexCount(); ++v) {
        const double x = m.positions[3 * v], y = m.positions[3 * v + 1], z = m.positions[3 * v + 2];
        const double r = std::sqrt(x * x + y * y + z * z);
        ASSERT_NEAR(r, radius, 1e-5);
        EXPECT_NEAR(m.normals[3 * v], x / r, 1e-6);
        EXPECT_NEAR(m.normals[3 * v + 1], y / r, 1e-6);
        EXPECT_NEAR(m.normals[3 * v + 2], z / r, 1e-6);
    }
}

TEST(Icosphere, VolumeConvergesToTheBall) {
    const double ball = 4.0 / 3.0 * kPi;
    const double v3 = signedVolume(rad::makeIcosphere(3));
    const double v5 = signedVolume(rad::makeIcosphere(5));
    EXPECT_LT(v3, ball);
    EXPECT_LT(v5, ball);
    EXPECT_GT(v5, v3);
    EXPECT_NEAR(v5, ball, 0.01 * ball);
}

TEST(Icosphere, RefusesBadParameters) {
    EXPECT_THROW(rad::makeIcosphere(-1), std::invalid_argument);
    EXPECT_THROW(rad::makeIcosphere(10), std::invalid_argument);
    EXPECT_THROW(rad::makeIcosphere(2, 0.0f), std::invalid_argument);
}

TEST(UvSphere, ClosedOrientedWithExactNormals) {
    for (auto [stacks, slices] : {std::pair{2, 3}, std::pair{8, 16}, std::pair{17, 31}}) {
        const TriangleMesh m = rad::makeUvSphere(stacks, slices, 1.5f);
        EXPECT_EQ(m.vertexCount(), std::size_t(stacks - 1) * slices + 2);
        EXPECT_EQ(m.faceCount(), std::size_t(2 * slices * (stacks - 1)));
        const Topology t = topologyOf(m);
        EXPECT_EQ(euler(m), 2);
        EXPECT_TRUE(t.everyEdgeTwoFaces);
        EXPECT_TRUE(t.consistentlyOriented);
        EXPECT_GT(signedVolume(m), 0.0);
        expectUnitNormals(m);
        expectWindingMatchesNormals(m);
        for (std::size_t v = 0; v < m.vertexCount(); ++v)
            for (int k = 0; k < 3; ++k) ASSERT_NEAR(m.normals[3 * v + k], m.positions[3 * v + k] / 1.5, 1e-6);
    }
    EXPECT_THROW(rad::makeUvSphere(1, 8), std::invalid_argument);
    EXPECT_THROW(rad::makeUvSphere(4, 2), std::invalid_argument);
}

TEST(DivergingQuad, FourVerticesTwoTrianglesNormalsTiltedOutwards) {
    const double tilt = 20.0 * kPi / 180.0;
    const TriangleMesh m = rad::makeDivergingQuad(static_cast<float>(tilt), 0.5f);
    ASSERT_EQ(m.vertexCount(), 4u);
    ASSERT_EQ(m.faceCount(), 2u);
    EXPECT_EQ(m.validate(), "");
    expectUnitNormals(m);
    expectWindingMatchesNormals(m);
    const Topology t = topologyOf(m);
    EXPECT_EQ(t.edges, 5u);  // 4 border edges + the diagonal
    EXPECT_EQ(euler(m), 1);  // a disc
    for (std::size_t v = 0; v < 4; ++v) {
        const double px = m.positions[3 * v], py = m.positions[3 * v + 1];
        EXPECT_FLOAT_EQ(m.positions[3 * v + 2], 0.0f);
        EXPECT_NEAR(std::fabs(px), 0.5, 1e-7);
        EXPECT_NEAR(std::fabs(py), 0.5, 1e-7);
        const double nx = m.normals[3 * v], ny = m.normals[3 * v + 1], nz = m.normals[3 * v + 2];
        // Angle to +z is the tilt, and the horizontal part points towards the corner (outwards).
        EXPECT_NEAR(std::acos(nz), tilt, 1e-6);
        const double radialX = px / std::hypot(px, py), radialY = py / std::hypot(px, py);
        EXPECT_NEAR(nx, std::sin(tilt) * radialX, 1e-6);
        EXPECT_NEAR(ny, std::sin(tilt) * radialY, 1e-6);
    }
    // Opposite corners diverge by twice the tilt.
    const double dot02 = m.normals[0] * m.normals[6] + m.normals[1] * m.normals[7] + m.normals[2] * m.normals[8];
    EXPECT_NEAR(std::acos(dot02), 2.0 * tilt, 1e-5);
}

TEST(DivergingQuad, ZeroTiltIsFlatAndNegativeTiltConverges) {
    const TriangleMesh flat = rad::makeDivergingQuad(0.0f);
    for (std::size_t v = 0; v < 4; ++v) EXPECT_FLOAT_EQ(flat.normals[3 * v + 2], 1.0f);
    const TriangleMesh inwards = rad::makeDivergingQuad(-0.3f);
    for (std::size_t v = 0; v < 4; ++v)
        EXPECT_LT(inwards.normals[3 * v] * inwards.positions[3 * v], 0.0f) << "normal leans to the centre";
    EXPECT_THROW(rad::makeDivergingQuad(static_cast<float>(kPi / 2)), std::invalid_argument);
}

TEST(ColumnOnPlane, DefaultCountsAreThoseOfThePaperScene) {
    const rad::ColumnSceneOptions o;
    const TriangleMesh m = rad::makeColumnOnPlane(o);
    EXPECT_EQ(m.validate(), "");
    EXPECT_EQ(m.vertexCount(), 195u);
    EXPECT_EQ(m.faceCount(), 288u);
    EXPECT_EQ(m.vertexCount(), rad::columnOnPlaneVertexCount(o));
    EXPECT_EQ(m.faceCount(), rad::columnOnPlaneFaceCount(o));
    // Křivánek et al. 2004 Fig. 1: 200 vertices, 246 triangles; ours is of the same size.
    EXPECT_NEAR(double(m.vertexCount()), 200.0, 10.0);
    expectUnitNormals(m);
    expectWindingMatchesNormals(m);
}

TEST(ColumnOnPlane, CountsFollowTheOptions) {
    rad::ColumnSceneOptions o;
    o.segments = 7;
    o.heightRings = 3;
    o.groundResolution = 5;
    const TriangleMesh m = rad::makeColumnOnPlane(o);
    EXPECT_EQ(m.vertexCount(), std::size_t(7 * 4 + 2 * 8 + 36));
    EXPECT_EQ(m.faceCount(), std::size_t(2 * 7 * 3 + 2 * 7 + 2 * 25));
    EXPECT_EQ(m.vertexCount(), rad::columnOnPlaneVertexCount(o));
    EXPECT_EQ(m.faceCount(), rad::columnOnPlaneFaceCount(o));
    o.segments = 2;
    EXPECT_THROW(rad::makeColumnOnPlane(o), std::invalid_argument);
}

TEST(ColumnOnPlane, ColumnIsClosedAndStandsOnTheGround) {
    const rad::ColumnSceneOptions o;
    const TriangleMesh m = rad::makeColumnOnPlane(o);
    const std::size_t columnVertices = m.vertexCount() - 81;
    const std::size_t columnFaces = m.faceCount() - 128;
    // The column alone (side + caps): positions welded at the rims, it is a closed genus-0 solid
    // of volume ~ pi r^2 h (a 16-gon prism).
    TriangleMesh column;
    column.positions.assign(m.positions.begin(), m.positions.begin() + 3 * columnVertices);
    column.normals.assign(m.normals.begin(), m.normals.begin() + 3 * columnVertices);
    column.faces.assign(m.faces.begin(), m.faces.begin() + 3 * columnFaces);
    const double prism = 0.5 * o.segments * o.radius * o.radius * std::sin(2 * kPi / o.segments) * o.height;
    EXPECT_NEAR(signedVolume(column), prism, 1e-6);
    // Topologically the rims are duplicated (sharp normals), so the side is a tube with two
    // boundaries and each cap a disc: Euler 0 + 1 + 1.
    EXPECT_EQ(euler(column), 2);

    double minZ = 1e9, maxZ = -1e9;
    for (std::size_t v = 0; v < columnVertices; ++v) {
        minZ = std::min<double>(minZ, m.positions[3 * v + 2]);
        maxZ = std::max<double>(maxZ, m.positions[3 * v + 2]);
    }
    EXPECT_DOUBLE_EQ(minZ, 0.0);
    EXPECT_NEAR(maxZ, o.height, 1e-7);
    for (std::size_t v = columnVertices; v < m.vertexCount(); ++v) {
        EXPECT_FLOAT_EQ(m.positions[3 * v + 2], 0.0f);
        EXPECT_FLOAT_EQ(m.normals[3 * v + 2], 1.0f);
        EXPECT_LE(std::fabs(m.positions[3 * v]), o.groundHalfSize + 1e-6);
    }
}

TEST(Torus, ClosedGenusOneWithExactNormals) {
    const float R = 1.0f, r = 0.3f;
    const TriangleMesh m = rad::makeTorus(R, r, 24, 12);
    EXPECT_EQ(m.vertexCount(), 24u * 12u);
    EXPECT_EQ(m.faceCount(), 2u * 24u * 12u);
    const Topology t = topologyOf(m);
    EXPECT_EQ(euler(m), 0);
    EXPECT_TRUE(t.everyEdgeTwoFaces);
    EXPECT_TRUE(t.consistentlyOriented);
    EXPECT_GT(signedVolume(m), 0.0);
    EXPECT_NEAR(signedVolume(rad::makeTorus(R, r, 256, 128)), 2 * kPi * kPi * R * r * r, 1e-3);
    expectUnitNormals(m);
    expectWindingMatchesNormals(m);
    for (std::size_t v = 0; v < m.vertexCount(); ++v) {
        // p - r n lies on the core circle.
        const double cx = m.positions[3 * v] - r * m.normals[3 * v];
        const double cy = m.positions[3 * v + 1] - r * m.normals[3 * v + 1];
        const double cz = m.positions[3 * v + 2] - r * m.normals[3 * v + 2];
        ASSERT_NEAR(std::hypot(cx, cy), R, 1e-6);
        ASSERT_NEAR(cz, 0.0, 1e-6);
    }
    EXPECT_THROW(rad::makeTorus(0.3f, 0.5f), std::invalid_argument);
}

}  // namespace
