// Tests of geometry/midpoint_subdivision.h: counts V + E and 4 F per level, no duplicated
// midpoints, watertight and consistently oriented meshes stay so, the shape is unchanged,
// normals recomputed or interpolated, refusals.
#include "geometry/midpoint_subdivision.h"

#include "geometry/mesh_normals.h"
#include "geometry/primitive_meshes.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <tuple>

namespace {

using Eigen::Vector3d;

std::size_t edgeCount(const rad::TriangleMesh& m) {
    std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
    for (std::size_t f = 0; f < m.faceCount(); ++f)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = m.faces[3 * f + k], b = m.faces[3 * f + (k + 1) % 3];
            edges.insert({std::min(a, b), std::max(a, b)});
        }
    return edges.size();
}

// Every directed edge appears once and its reverse once: closed, manifold, consistently oriented.
bool watertightAndOriented(const rad::TriangleMesh& m) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (std::size_t f = 0; f < m.faceCount(); ++f)
        for (int k = 0; k < 3; ++k) ++directed[{m.faces[3 * f + k], m.faces[3 * f + (k + 1) % 3]}];
    for (const auto& [e, n] : directed) {
        if (n != 1) return false;
        const auto rev = directed.find({e.second, e.first});
        if (rev == directed.end() || rev->second != 1) return false;
    }
    return true;
}

Vector3d position(const rad::TriangleMesh& m, std::size_t v) {
    return {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]};
}

double totalArea(const rad::TriangleMesh& m) {
    double a = 0;
    for (std::size_t f = 0; f < m.faceCount(); ++f) a += rad::faceArea(m, f);
    return a;
}

TEST(MidpointSubdivision, CountsAreVPlusEAndFourF) {
    rad::TriangleMesh m = rad::makeIcosphere(1);  // V 42, F 80, E 120
    for (int level = 1; level <= 3; ++level) {
        const std::size_t V = m.vertexCount(), F = m.faceCount(), E = edgeCount(m);
        rad::TriangleMesh s = rad::subdivideMidpoint(m, 1);
        EXPECT_EQ(s.vertexCount(), V + E);
        EXPECT_EQ(s.faceCount(), 4 * F);
        EXPECT_EQ(edgeCount(s), 2 * E + 3 * F);
        EXPECT_TRUE(s.validate().empty()) << s.validate();
        m = std::move(s);
    }
    // Several levels at once give the same mesh as repeated single levels.
    const rad::TriangleMesh direct = rad::subdivideMidpoint(rad::makeIcosphere(1), 3);
    EXPECT_EQ(direct.positions, m.positions);
    EXPECT_EQ(direct.faces, m.faces);
    EXPECT_EQ(direct.vertexCount(), rad::icosphereVertexCount(4));  // same counts as a level-4 icosphere
}

TEST(MidpointSubdivision, NoDuplicatedMidpointsAndStaysWatertight) {
    const rad::TriangleMesh sphere = rad::makeIcosphere(2);
    ASSERT_TRUE(watertightAndOriented(sphere));
    const rad::TriangleMesh s = rad::subdivideMidpoint(sphere, 2);
    std::set<std::array<float, 3>> unique;
    for (std::size_t v = 0; v < s.vertexCount(); ++v)
        unique.insert({s.positions[3 * v], s.positions[3 * v + 1], s.positions[3 * v + 2]});
    EXPECT_EQ(unique.size(), s.vertexCount());
    EXPECT_TRUE(watertightAndOriented(s));
    // Every vertex is used.
    std::vector<int> used(s.vertexCount(), 0);
    for (std::uint32_t i : s.faces) used[i] = 1;
    for (int u : used) ASSERT_EQ(u, 1);
}

TEST(MidpointSubdivision, ShapeIsUnchanged) {
    const rad::TriangleMesh torus = rad::makeTorus(1.0f, 0.35f, 12, 8);
    const rad::TriangleMesh s = rad::subdivideMidpoint(torus, 2);
    // The original vertices keep their indices and positions.
    for (std::size_t i = 0; i < torus.positions.size(); ++i) ASSERT_EQ(s.positions[i], torus.positions[i]);
    // Same total area (each triangle is split into four coplanar quarters).
    EXPECT_NEAR(totalArea(s), totalArea(torus), 1e-5 * totalArea(torus));
    // A single triangle: the new vertices lie in it, at the midpoints of its edges (level 1).
    rad::TriangleMesh tri;
    tri.positions = {0, 0, 0, 4, 0, 0, 0, 2, 0};
    tri.faces = {0, 1, 2};
    const rad::TriangleMesh t = rad::subdivideMidpoint(tri, 1);
    ASSERT_EQ(t.vertexCount(), 6u);
    std::set<std::tuple<float, float, float>> mids;
    for (std::size_t v = 3; v < 6; ++v) mids.insert({t.positions[3 * v], t.positions[3 * v + 1], t.positions[3 * v + 2]});
    EXPECT_EQ(mids, (std::set<std::tuple<float, float, float>>{{2.0f, 0.0f, 0.0f}, {2.0f, 1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}}));
    // Orientation kept: every sub-triangle's normal is the original's (+z).
    for (std::size_t f = 0; f < t.faceCount(); ++f) {
        float n[3];
        rad::faceNormal(t, f, n);
        EXPECT_NEAR(n[2], 1.0f, 1e-6);
    }
}

TEST(MidpointSubdivision, NormalsRecomputedOrInterpolated) {
    const rad::TriangleMesh sphere = rad::makeIcosphere(1);
    const rad::TriangleMesh s = rad::subdivideMidpoint(sphere, 1);
    std::vector<float> expected;
    rad::computeAreaWeightedNormals(s.positions, s.faces, expected);
    EXPECT_EQ(s.normals, expected);

    const rad::TriangleMesh si = rad::subdivideMidpoint(sphere, 1, rad::SubdivisionNormals::Interpolate);
    for (std::size_t i = 0; i < sphere.normals.size(); ++i) ASSERT_EQ(si.normals[i], sphere.normals[i]);
    // A midpoint's normal is normalize(n_a + n_b) of its edge: find the edge from the positions.
    for (std::size_t v = sphere.vertexCount(); v < si.vertexCount(); ++v) {
        const Vector3d p = position(si, v);
        bool found = false;
        for (std::size_t f = 0; f < sphere.faceCount() && !found; ++f)
            for (int k = 0; k < 3 && !found; ++k) {
                const std::uint32_t a = sphere.faces[3 * f + k], b = sphere.faces[3 * f + (k + 1) % 3];
                if ((0.5 * (position(sphere, a) + position(sphere, b)) - p).norm() > 1e-6) continue;
                found = true;
                const Vector3d na(sphere.normals[3 * a], sphere.normals[3 * a + 1], sphere.normals[3 * a + 2]);
                const Vector3d nb(sphere.normals[3 * b], sphere.normals[3 * b + 1], sphere.normals[3 * b + 2]);
                const Vector3d want = (na + nb).normalized();
                for (int c = 0; c < 3; ++c) EXPECT_NEAR(si.normals[3 * v + c], want[c], 1e-6);
            }
        EXPECT_TRUE(found) << "vertex " << v << " is not an edge midpoint";
    }
}

TEST(MidpointSubdivision, LevelZeroAndRefusals) {
    const rad::TriangleMesh sphere = rad::makeIcosphere(1);
    const rad::TriangleMesh same = rad::subdivideMidpoint(sphere, 0, rad::SubdivisionNormals::Interpolate);
    EXPECT_EQ(same.positions, sphere.positions);
    EXPECT_EQ(same.normals, sphere.normals);
    EXPECT_EQ(same.faces, sphere.faces);
    EXPECT_THROW(rad::subdivideMidpoint(sphere, -1), std::invalid_argument);
    rad::TriangleMesh noNormals = sphere;
    noNormals.normals.clear();
    EXPECT_THROW(rad::subdivideMidpoint(noNormals, 1, rad::SubdivisionNormals::Interpolate), std::invalid_argument);
    rad::TriangleMesh bad = sphere;
    bad.faces[0] = 1000;
    EXPECT_THROW(rad::subdivideMidpoint(bad, 1), std::invalid_argument);
}

}  // namespace
