#include "simplify/collapse_mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace {

using rad::CollapseMesh;
using rad::StarFace;

// A hexagonal fan: centre 0, ring 1..6 counter-clockwise in the plane z = 0.
CollapseMesh hexagonFan() {
    std::vector<float> p = {0, 0, 0};
    for (int i = 0; i < 6; ++i) {
        const double a = i * 3.14159265358979 / 3.0;
        p.insert(p.end(), {static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a)), 0.0f});
    }
    std::vector<std::uint32_t> f;
    for (std::uint32_t i = 0; i < 6; ++i) f.insert(f.end(), {0u, 1 + i, 1 + (i + 1) % 6});
    return CollapseMesh(p.data(), 7, f.data(), 6);
}

TEST(CollapseMesh, RefusesOutOfRangeAndRepeatedIndices) {
    const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const std::uint32_t outOfRange[3] = {0, 1, 3};
    const std::uint32_t repeated[3] = {0, 1, 1};
    EXPECT_THROW(CollapseMesh(p, 3, outOfRange, 1), std::invalid_argument);
    EXPECT_THROW(CollapseMesh(p, 3, repeated, 1), std::invalid_argument);
}

TEST(CollapseMesh, StarIsCounterClockwiseWithTheCentreFirst) {
    const CollapseMesh mesh = hexagonFan();
    std::vector<StarFace> star;
    mesh.star(0, star);
    ASSERT_EQ(star.size(), 6u);
    for (const StarFace& f : star) EXPECT_EQ(f.b, 1 + f.a % 6);  // (0, i, i+1)
    mesh.star(3, star);
    ASSERT_EQ(star.size(), 2u);
    // Faces (0, 2, 3) and (0, 3, 4) seen from vertex 3: (3, 0, 2) and (3, 4, 0).
    EXPECT_TRUE((star[0].a == 0 && star[0].b == 2) || (star[0].a == 4 && star[0].b == 0));
}

TEST(CollapseMesh, BoundaryAndEdgeCounts) {
    const CollapseMesh mesh = hexagonFan();
    EXPECT_FALSE(mesh.onBoundary(0));
    EXPECT_TRUE(mesh.onBoundary(1));
    EXPECT_EQ(mesh.edgeFaceCount(0, 1), 2);
    EXPECT_EQ(mesh.edgeFaceCount(1, 2), 1);
    EXPECT_EQ(mesh.edgeFaceCount(1, 4), 0);
    std::vector<std::uint32_t> n;
    mesh.neighbours(0, n);
    std::sort(n.begin(), n.end());
    EXPECT_EQ(n, (std::vector<std::uint32_t>{1, 2, 3, 4, 5, 6}));
}

TEST(CollapseMesh, StarShapeTellsOneOpenFanFromTheRest) {
    using Shape = CollapseMesh::StarShape;
    // Written by hand as (a, b) pairs, not read from a mesh.
    const std::vector<StarFace> closed = {{1, 2}, {2, 3}, {3, 4}, {4, 1}};
    const std::vector<StarFace> open = {{1, 2}, {2, 3}, {3, 4}};
    const std::vector<StarFace> twoFans = {{1, 2}, {2, 3}, {5, 6}, {6, 7}};      // a bowtie
    const std::vector<StarFace> threeOnAnEdge = {{1, 2}, {2, 3}, {3, 1}, {1, 4}};  // 1 is an 'a' twice
    const std::vector<StarFace> flipped = {{1, 2}, {3, 2}, {3, 4}, {4, 1}};       // one face turned over
    EXPECT_EQ(CollapseMesh::starShape(closed), Shape::ClosedFan);
    EXPECT_EQ(CollapseMesh::starShape(open), Shape::OneOpenFan);
    EXPECT_EQ(CollapseMesh::starShape(twoFans), Shape::Other);
    EXPECT_EQ(CollapseMesh::starShape(threeOnAnEdge), Shape::Other);
    EXPECT_EQ(CollapseMesh::starShape(flipped), Shape::Other);
    for (const auto* star : {&closed, &open, &twoFans, &threeOnAnEdge, &flipped})
        EXPECT_EQ(CollapseMesh::isOpenStar(*star), CollapseMesh::starShape(*star) != Shape::ClosedFan);
    // On a mesh: the hexagon's centre and a ring vertex.
    const CollapseMesh mesh = hexagonFan();
    std::vector<StarFace> star;
    mesh.star(0, star);
    EXPECT_EQ(CollapseMesh::starShape(star), Shape::ClosedFan);
    mesh.star(1, star);
    EXPECT_EQ(CollapseMesh::starShape(star), Shape::OneOpenFan);
}

TEST(CollapseMesh, CollapseKillsTheEdgeFacesAndRewiresTheOthers) {
    CollapseMesh mesh = hexagonFan();
    std::vector<std::uint32_t> killed;
    mesh.collapse(0, 1, &killed);  // centre onto ring vertex 1
    std::sort(killed.begin(), killed.end());
    EXPECT_EQ(killed, (std::vector<std::uint32_t>{0, 5}));  // (0,1,2) and (0,6,1)
    EXPECT_EQ(mesh.aliveFaceCount(), 4u);
    EXPECT_EQ(mesh.aliveVertexCount(), 6u);
    EXPECT_FALSE(mesh.vertexAlive(0));
    EXPECT_EQ(mesh.incidentFaces(1).size(), 4u);  // the fan now spans from vertex 1
    EXPECT_EQ(mesh.incidentFaces(2).size(), 1u);
    for (std::uint32_t f = 0; f < 6; ++f) {
        if (!mesh.faceAlive(f)) continue;
        const std::uint32_t* t = mesh.face(f);
        EXPECT_TRUE(t[0] == 1 || t[1] == 1 || t[2] == 1);
        EXPECT_TRUE(t[0] != 0 && t[1] != 0 && t[2] != 0);
    }
    std::vector<float> positions;
    std::vector<std::uint32_t> faces, map;
    mesh.compact(positions, faces, map);
    EXPECT_EQ(positions.size(), 18u);
    EXPECT_EQ(faces.size(), 12u);
    EXPECT_EQ(map[0], UINT32_MAX);
    EXPECT_EQ(map[1], 0u);
    for (std::uint32_t i : faces) EXPECT_LT(i, 6u);
}

}  // namespace
