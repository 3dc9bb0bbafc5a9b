// Tests of color_quadric.h: the extended colour QEM of Garland & Heckbert 1998 as a collapse metric.
#include "simplify/color_quadric.h"

#include "simplify/collapse_mesh.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <vector>

namespace {

using Eigen::Vector3d;
using rad::ColorQuadric;
using rad::ColorQuadricMetric;
using rad::Vector6d;

// An n x n grid of vertices in the plane z = 0, spacing 1, two triangles per cell (counter-clockwise
// from +z). Vertex (i, j) has index j * n + i.
struct Grid {
    int n;
    std::vector<float> positions;
    std::vector<std::uint32_t> faces;
    std::uint32_t at(int i, int j) const { return std::uint32_t(j * n + i); }
    explicit Grid(int size) : n(size) {
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) positions.insert(positions.end(), {float(i), float(j), 0.0f});
        for (int j = 0; j + 1 < n; ++j)
            for (int i = 0; i + 1 < n; ++i) {
                faces.insert(faces.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1)});
                faces.insert(faces.end(), {at(i, j), at(i + 1, j + 1), at(i, j + 1)});
            }
    }
    rad::CollapseMesh mesh() const {
        return rad::CollapseMesh(positions.data(), positions.size() / 3, faces.data(), faces.size() / 3);
    }
};

std::vector<float> uniformColors(std::size_t count, const Vector3d& c) {
    std::vector<float> out;
    for (std::size_t v = 0; v < count; ++v) out.insert(out.end(), {float(c.x()), float(c.y()), float(c.z())});
    return out;
}

double halfEdgeCost(const ColorQuadricMetric& metric, const rad::CollapseMesh& mesh, std::uint32_t v0,
                    std::uint32_t v1) {
    std::vector<rad::StarFace> star;
    mesh.star(v0, star);
    rad::HalfEdgeQuery q;
    q.source = v0;
    q.star = star.data();
    q.starSize = int(star.size());
    q.targets = &v1;
    q.targetCount = 1;
    double cost = -1;
    metric.priceHalfEdges(mesh, q, &cost);
    return cost;
}

rad::EdgeQuery fullQuery(const rad::CollapseMesh& mesh, std::uint32_t v0, std::uint32_t v1, double s) {
    rad::EdgeQuery q;
    q.v0 = v0;
    q.v1 = v1;
    q.s = s;
    q.position = (1 - s) * mesh.position(v0) + s * mesh.position(v1);
    return q;
}

// Squared distance from x to the affine plane through p, q, r, by classical Gram-Schmidt on the
// edge vectors taken in the other order (r - p first), written here independently of the unit.
double squaredDistanceToPlane(const Vector6d& p, const Vector6d& q, const Vector6d& r, const Vector6d& x) {
    const Vector6d u1 = (r - p).normalized();
    Vector6d u2 = (q - p) - (q - p).dot(u1) * u1;
    u2.normalize();
    const Vector6d d = x - p;
    return (d - d.dot(u1) * u1 - d.dot(u2) * u2).squaredNorm();
}

Vector6d randomPoint(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1, 1);
    Vector6d v;
    for (int k = 0; k < 6; ++k) v[k] = u(rng);
    return v;
}

TEST(ColorQuadric, FaceQuadricIsTheSquaredDistanceToThe6DPlane) {
    std::mt19937 rng(11);
    for (int trial = 0; trial < 20; ++trial) {
        const Vector6d p = randomPoint(rng), q = randomPoint(rng), r = randomPoint(rng);
        const ColorQuadric Q = ColorQuadric::triangle(p, q, r);
        // On the plane (any affine combination, inside or outside the triangle): zero.
        std::uniform_real_distribution<double> a(-2, 2);
        const double s = a(rng), t = a(rng);
        EXPECT_NEAR(Q.evaluate(Vector6d(p + s * (q - p) + t * (r - p))), 0.0, 1e-12);
        // Off the plane: the squared distance.
        for (int k = 0; k < 5; ++k) {
            const Vector6d x = 2.0 * randomPoint(rng);
            const double expected = squaredDistanceToPlane(p, q, r, x);
            EXPECT_GT(expected, 1e-3);
            EXPECT_NEAR(Q.evaluate(x), expected, 1e-12 * (1 + expected));
        }
    }
}

TEST(ColorQuadric, DegenerateTriangleGivesTheZeroQuadric) {
    std::mt19937 rng(12);
    const Vector6d p = randomPoint(rng), q = randomPoint(rng);
    const ColorQuadric Q = ColorQuadric::triangle(p, q, Vector6d(p + 0.5 * (q - p)));
    EXPECT_EQ(Q.A.norm(), 0.0);
    EXPECT_EQ(Q.c, 0.0);
    EXPECT_EQ(ColorQuadric::triangle(p, p, q).A.norm(), 0.0);
}

TEST(ColorQuadricMetric, FlatConstantColourPatchPricesZero) {
    const Grid grid(4);
    const rad::CollapseMesh mesh = grid.mesh();
    const ColorQuadricMetric metric(mesh, uniformColors(mesh.vertexCount(), Vector3d(0.2, 0.5, 0.9)));
    std::string why;
    EXPECT_TRUE(metric.supportsFullCollapse(why)) << why;
    const std::uint32_t v0 = grid.at(1, 1);
    for (std::uint32_t v1 : {grid.at(2, 1), grid.at(1, 2), grid.at(2, 2), grid.at(0, 0)}) {
        EXPECT_NEAR(halfEdgeCost(metric, mesh, v0, v1), 0.0, 1e-13);
        for (double s : {0.0, 0.3, 0.5}) {
            // Planar collapse: the new position stays in the plane, and c* is the patch's colour.
            EXPECT_NEAR(metric.priceEdge(mesh, fullQuery(mesh, v0, v1, s)), 0.0, 1e-13);
        }
    }
}

// Two columns of colours: vertices with i <= 1 have colour a, the others b.
ColorQuadricMetric stepMetric(const Grid& grid, const rad::CollapseMesh& mesh, const Vector3d& a, const Vector3d& b) {
    std::vector<float> colors;
    for (int j = 0; j < grid.n; ++j)
        for (int i = 0; i < grid.n; ++i) {
            const Vector3d& c = i <= 1 ? a : b;
            colors.insert(colors.end(), {float(c.x()), float(c.y()), float(c.z())});
        }
    return ColorQuadricMetric(mesh, colors);
}

TEST(ColorQuadricMetric, ColourStepPricesGrowWithTheColourDifference) {
    const Grid grid(4);
    const rad::CollapseMesh mesh = grid.mesh();
    const Vector3d a(0.2, 0.3, 0.4);
    // The edge (1, 1) -> (2, 1) crosses the step; an edge inside the a-side does not.
    const std::uint32_t v0 = grid.at(1, 1), across = grid.at(2, 1), inside = grid.at(1, 2);
    double previousHalf = 0, previousFull = 0;
    for (double step : {0.05, 0.1, 0.2, 0.4}) {
        const ColorQuadricMetric metric = stepMetric(grid, mesh, a, a + Vector3d(step, -step, step));
        const double half = halfEdgeCost(metric, mesh, v0, across);
        const double full = metric.priceEdge(mesh, fullQuery(mesh, v0, across, 0.5));
        EXPECT_GT(half, 1e-6) << step;
        EXPECT_GT(full, 1e-6) << step;
        EXPECT_GT(half, 1.5 * previousHalf) << step;  // ~ quadratic in the step
        EXPECT_GT(full, 1.5 * previousFull) << step;
        // Moving along the step (colour constant on the collapsed edge) costs less than across it.
        EXPECT_LT(halfEdgeCost(metric, mesh, v0, inside), half) << step;
        previousHalf = half;
        previousFull = full;
    }
}

TEST(ColorQuadricMetric, GeometryIsNormalisedByTheBoundingBoxDiagonal) {
    const Grid grid(3);
    const rad::CollapseMesh mesh = grid.mesh();
    const ColorQuadricMetric metric(mesh, uniformColors(mesh.vertexCount(), Vector3d(0.5, 0.5, 0.5)));
    EXPECT_NEAR(metric.geometryScale(), 1.0 / std::sqrt(8.0), 1e-15);
    EXPECT_TRUE(metric.centre().isApprox(Vector3d(1, 1, 0)));
    rad::ColorQuadricOptions options;
    options.geometryScale = 3.0;
    EXPECT_EQ(ColorQuadricMetric(mesh, uniformColors(mesh.vertexCount(), Vector3d::Zero()), options).geometryScale(),
              3.0);
    EXPECT_THROW(ColorQuadricMetric(mesh, std::vector<float>(5, 0.0f)), std::invalid_argument);
    options.geometryScale = -1;
    EXPECT_THROW(ColorQuadricMetric(mesh, uniformColors(mesh.vertexCount(), Vector3d::Zero()), options),
                 std::invalid_argument);
}

TEST(ColorQuadricMetric, VertexQuadricIsTheAreaWeightedSumOfItsFaces) {
    const Grid grid(3);
    const rad::CollapseMesh mesh = grid.mesh();
    std::mt19937 rng(13);
    std::uniform_real_distribution<float> u(0, 1);
    std::vector<float> colors(3 * mesh.vertexCount());
    for (float& c : colors) c = u(rng);
    const ColorQuadricMetric metric(mesh, colors);
    const std::uint32_t v = grid.at(1, 1);
    ColorQuadric expected;
    for (std::uint32_t f : mesh.incidentFaces(v)) {
        Vector6d p[3];
        for (int k = 0; k < 3; ++k)
            p[k] << metric.normalizedPosition(mesh.position(mesh.face(f)[k])), metric.color(mesh.face(f)[k]);
        ColorQuadric q = ColorQuadric::triangle(p[0], p[1], p[2]);
        q *= 0.5 * (p[1] - p[0]).head<3>().cross((p[2] - p[0]).head<3>()).norm();
        expected += q;
    }
    EXPECT_LT((metric.quadric(v).A - expected.A).norm(), 1e-14);
    EXPECT_LT((metric.quadric(v).b - expected.b).norm(), 1e-14);
    EXPECT_NEAR(metric.quadric(v).c, expected.c, 1e-14);
}

TEST(ColorQuadricMetric, OnCollapseAccumulatesQuadricsAndSetsTheSurvivorColour) {
    const Grid grid(4);
    std::mt19937 rng(14);
    std::uniform_real_distribution<float> u(0, 1);
    std::vector<float> colors(3 * grid.n * grid.n);
    for (float& c : colors) c = u(rng);

    // Half-edge: Q1 += Q0, v1 keeps its colour.
    {
        rad::CollapseMesh mesh = grid.mesh();
        ColorQuadricMetric metric(mesh, colors);
        const std::uint32_t v0 = grid.at(1, 1), v1 = grid.at(2, 1);
        ColorQuadric expected = metric.quadric(v0);
        expected += metric.quadric(v1);
        const Vector3d c1 = metric.color(v1);
        rad::EdgeQuery query = fullQuery(mesh, v0, v1, 1.0);
        query.halfEdge = true;
        EXPECT_EQ(metric.priceEdge(mesh, query), halfEdgeCost(metric, mesh, v0, v1));
        mesh.collapse(v0, v1);
        metric.onCollapse(mesh, query);
        EXPECT_LT((metric.quadric(v1).A - expected.A).norm(), 1e-15);
        EXPECT_LT((metric.quadric(v1).b - expected.b).norm(), 1e-15);
        EXPECT_NEAR(metric.quadric(v1).c, expected.c, 1e-15);
        EXPECT_EQ(metric.color(v1), c1);
        // The accumulated quadric keeps pricing v0's faces: collapsing v1 further onto a vertex of
        // v0's old star costs at least what the faces of v0 alone charge there.
        const std::uint32_t next = grid.at(1, 2);
        const Vector3d x = metric.normalizedPosition(mesh.position(next));
        const rad::CollapseMesh original = grid.mesh();
        ColorQuadric oldFaces;
        for (std::uint32_t f : original.incidentFaces(v0)) {
            Vector6d p[3];
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t w = original.face(f)[k];
                p[k] << metric.normalizedPosition(original.position(w)),
                    Vector3d(colors[3 * w], colors[3 * w + 1], colors[3 * w + 2]);
            }
            ColorQuadric q = ColorQuadric::triangle(p[0], p[1], p[2]);
            q *= 0.5 * (p[1] - p[0]).head<3>().cross((p[2] - p[0]).head<3>()).norm();
            oldFaces += q;
        }
        EXPECT_GE(halfEdgeCost(metric, mesh, v1, next) + 1e-15, oldFaces.evaluate(x, metric.color(next)));
    }
    // Full: Q1 += Q0 and v1's colour becomes c*, the price's colour.
    {
        rad::CollapseMesh mesh = grid.mesh();
        ColorQuadricMetric metric(mesh, colors);
        const std::uint32_t v0 = grid.at(1, 1), v1 = grid.at(2, 2);
        const rad::EdgeQuery query = fullQuery(mesh, v0, v1, 0.4);
        ColorQuadric sum = metric.quadric(v0);
        sum += metric.quadric(v1);
        const Vector3d x = metric.normalizedPosition(query.position);
        const Vector3d cStar = sum.optimalColor(x, Vector3d::Zero());
        const double price = metric.priceEdge(mesh, query);
        EXPECT_NEAR(price, sum.evaluate(x, cStar), 1e-14);
        mesh.setPosition(v1, query.position);
        mesh.collapse(v0, v1);
        metric.onCollapse(mesh, query);
        EXPECT_LT((metric.color(v1) - cStar).norm(), 1e-12);
        EXPECT_LT((metric.quadric(v1).A - sum.A).norm(), 1e-15);
        EXPECT_NEAR(metric.quadric(v1).c, sum.c, 1e-15);
        EXPECT_EQ(metric.colors().size(), 3 * mesh.vertexCount());
    }
}

TEST(ColorQuadricMetric, OptimalColourMinimisesTheQuadricAtTheFixedPosition) {
    const Grid grid(4);
    rad::CollapseMesh mesh = grid.mesh();
    std::mt19937 rng(15);
    std::uniform_real_distribution<float> u(0, 1);
    std::vector<float> colors(3 * mesh.vertexCount());
    for (float& c : colors) c = u(rng);
    // A bumpy patch, so that geometry and colour both matter.
    for (std::uint32_t v = 0; v < mesh.vertexCount(); ++v)
        mesh.setPosition(v, mesh.position(v) + Vector3d(0, 0, 0.3 * u(rng)));
    const ColorQuadricMetric metric(mesh, colors);
    std::normal_distribution<double> g;
    for (std::uint32_t v1 : {grid.at(2, 1), grid.at(2, 2), grid.at(1, 2)}) {
        const std::uint32_t v0 = grid.at(1, 1);
        for (double s : {0.0, 0.25, 0.5, 0.9}) {
            const rad::EdgeQuery query = fullQuery(mesh, v0, v1, s);
            ColorQuadric sum = metric.quadric(v0);
            sum += metric.quadric(v1);
            const Vector3d x = metric.normalizedPosition(query.position);
            const Vector3d cStar = sum.optimalColor(x, Vector3d(0.5, 0.5, 0.5));
            const double best = sum.evaluate(x, cStar);
            EXPECT_NEAR(metric.priceEdge(mesh, query), best, 1e-14);
            for (int k = 0; k < 10; ++k) {
                const Vector3d delta = 1e-3 * Vector3d(g(rng), g(rng), g(rng));
                EXPECT_GT(sum.evaluate(x, cStar + delta), best);
            }
            // And it beats both endpoint colours.
            EXPECT_LE(best, sum.evaluate(x, metric.color(v0)) + 1e-15);
            EXPECT_LE(best, sum.evaluate(x, metric.color(v1)) + 1e-15);
        }
    }
}

TEST(ColorQuadric, OptimalColourKeepsTheFallbackWhereTheQuadricIsFlat) {
    const ColorQuadric zero;
    EXPECT_EQ(zero.optimalColor(Vector3d(1, 2, 3), Vector3d(0.1, 0.2, 0.3)), Vector3d(0.1, 0.2, 0.3));
    // Curvature only along red: green and blue stay at the fallback.
    ColorQuadric q;
    q.A(3, 3) = 2.0;
    q.b[3] = -1.0;  // Q = 2 r^2 - 2 r + c: minimum at r = 0.5
    const Vector3d c = q.optimalColor(Vector3d::Zero(), Vector3d(0.9, 0.2, 0.3));
    EXPECT_NEAR(c.x(), 0.5, 1e-15);
    EXPECT_EQ(c.y(), 0.2);
    EXPECT_EQ(c.z(), 0.3);
}

}  // namespace
