#include "simplify/quadric_error.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <random>

namespace {

using Eigen::Vector3d;

TEST(QuadricError, TrianglePlaneGivesTheSquaredDistanceToThePlane) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    for (int trial = 0; trial < 20; ++trial) {
        const Vector3d a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
        rad::Quadric q;
        q.addTrianglePlane(a, b, c);
        const Vector3d x(u(rng), u(rng), u(rng));
        // Distance to the plane through a, b, c by the triple product (independent formula).
        const double volume = (b - a).cross(c - a).dot(x - a);
        const double distance = volume / (b - a).cross(c - a).norm();
        EXPECT_NEAR(q.evaluate(x), distance * distance, 1e-9 * (1.0 + distance * distance));
    }
}

TEST(QuadricError, DegenerateTriangleAddsNothing) {
    rad::Quadric q;
    q.addTrianglePlane(Vector3d(0, 0, 0), Vector3d(1, 1, 1), Vector3d(2, 2, 2));
    EXPECT_EQ(q.evaluate(Vector3d(5, -3, 2)), 0.0);
}

TEST(QuadricError, OptimalPositionIsTheCornerOfThreePlanes) {
    // Three coordinate-aligned faces meeting at (0.2, 0.1, 0.3) (a corner slightly off the edge).
    const Vector3d corner(0.2, 0.1, 0.3);
    rad::Quadric q;
    q.addTrianglePlane(corner, corner + Vector3d(1, 0, 0), corner + Vector3d(0, 1, 0));
    q.addTrianglePlane(corner, corner + Vector3d(0, 1, 0), corner + Vector3d(0, 0, 1));
    q.addTrianglePlane(corner, corner + Vector3d(0, 0, 1), corner + Vector3d(1, 0, 0));
    const Vector3d x = rad::optimalPosition(q, Vector3d(0, 0, 0), Vector3d(0.5, 0.3, 0.4));
    EXPECT_NEAR((x - corner).norm(), 0.0, 1e-9);
}

TEST(QuadricError, FlatNeighbourhoodFallsBackToTheBestCandidate) {
    // Coplanar faces: A has rank 1, every point of the plane is optimal; the fallback returns one
    // of the candidates and it lies in the plane.
    rad::Quadric q;
    q.addTrianglePlane(Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(0, 1, 0));
    q.addTrianglePlane(Vector3d(1, 0, 0), Vector3d(1, 1, 0), Vector3d(0, 1, 0));
    const Vector3d p0(0.2, 0.2, 0.0), p1(0.6, 0.5, 0.0);
    const Vector3d x = rad::optimalPosition(q, p0, p1);
    EXPECT_TRUE((x - p0).norm() < 1e-12 || (x - p1).norm() < 1e-12 || (x - 0.5 * (p0 + p1)).norm() < 1e-12);
    EXPECT_NEAR(q.evaluate(x), 0.0, 1e-15);
}

TEST(QuadricError, VertexQuadricSumsTheFacesAroundTheVertex) {
    const float p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    const std::uint32_t f[] = {0, 2, 1, 0, 1, 3, 0, 3, 2};  // three faces at the origin
    const rad::CollapseMesh mesh(p, 4, f, 3);
    const rad::Quadric q = rad::vertexQuadric(mesh, 0);
    const Vector3d x(0.3, -0.2, 0.5);
    EXPECT_NEAR(q.evaluate(x), 0.09 + 0.04 + 0.25, 1e-12);  // squared distances to x=0, y=0, z=0
}

}  // namespace
