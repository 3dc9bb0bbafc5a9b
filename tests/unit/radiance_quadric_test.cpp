// Tests of radiance_quadric.h: the accumulating quadric of geometry and radiance coefficients
// (Hoppe 1999) as the simplification's collapse metric.
#include "simplify/radiance_quadric.h"

#include "radiance/radiance_frame.h"
#include "simplify/collapse_mesh.h"
#include "simplify/radiance_simplification.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace {

using Eigen::Vector3d;

// An n x n grid in the plane z = 0 (spacing 1), two triangles per cell, counter-clockwise from +z.
struct Grid {
    int n;
    std::vector<float> positions;
    std::vector<std::uint32_t> faces;
    std::uint32_t at(int i, int j) const { return std::uint32_t(j * n + i); }
    explicit Grid(int size, float spacing = 1.0f) : n(size) {
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) positions.insert(positions.end(), {spacing * i, spacing * j, 0.0f});
        for (int j = 0; j + 1 < n; ++j)
            for (int i = 0; i + 1 < n; ++i) {
                faces.insert(faces.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1)});
                faces.insert(faces.end(), {at(i, j), at(i + 1, j + 1), at(i, j + 1)});
            }
    }
    std::size_t vertices() const { return positions.size() / 3; }
    rad::CollapseMesh mesh() const { return rad::CollapseMesh(positions.data(), vertices(), faces.data(), faces.size() / 3); }
};

// A field whose every coefficient is an affine function of the position (frames facing +z).
rad::RadianceField affineField(const Grid& grid, rad::BasisSpec basis, double scale = 1.0) {
    rad::RadianceField field(basis, grid.vertices());
    const int m = field.coefficientsPerVertex();
    for (std::size_t v = 0; v < grid.vertices(); ++v) {
        const double x = grid.positions[3 * v], y = grid.positions[3 * v + 1];
        for (int j = 0; j < m; ++j)
            field.vertexCoefficients(v)[j] = float(scale * (0.3 + 0.01 * j + 0.05 * (j % 3) * x - 0.02 * (j % 5) * y));
        rad::storeFrame(rad::frameFromNormal(Vector3d::UnitZ()), field.frame(v));
    }
    return field;
}

double halfEdgeCost(const rad::RadianceQuadricMetric& metric, const rad::CollapseMesh& mesh, std::uint32_t v0,
                    std::uint32_t v1) {
    std::vector<rad::StarFace> star;
    mesh.star(v0, star);
    rad::HalfEdgeQuery q;
    q.source = v0;
    q.star = star.data();
    q.starSize = int(star.size());
    q.targets = &v1;
    q.targetCount = 1;
    double cost = -1.0;
    metric.priceHalfEdges(mesh, q, &cost);
    return cost;
}

TEST(RadianceQuadric, AffineRadianceOnAPlaneCostsNothing) {
    const Grid grid(5);
    rad::CollapseMesh mesh = grid.mesh();
    rad::RadianceField field = affineField(grid, {rad::BasisKind::HemisphericalPolynomial, 2});
    const rad::RadianceQuadricMetric metric(mesh, field);
    // Interior vertex into a neighbour: the plane and the attribute planes are met exactly.
    EXPECT_NEAR(halfEdgeCost(metric, mesh, grid.at(2, 2), grid.at(3, 2)), 0.0, 1e-9);
    EXPECT_NEAR(halfEdgeCost(metric, mesh, grid.at(1, 2), grid.at(1, 1)), 0.0, 1e-9);
}

TEST(RadianceQuadric, PbFramesTurnedAboutTheNormalDescribeTheSameFunction) {
    // Every vertex holds f(w) = w.x + 0.5 in PB1, each in a frame turned by its own angle about +z:
    // u = cos a x + sin a y, v = -sin a x + cos a y, so f = cos a u - sin a v + 0.5. The same
    // function everywhere: no collapse may cost anything (raw coefficients differ from vertex to vertex).
    const Grid grid(5);
    rad::CollapseMesh mesh = grid.mesh();
    const rad::BasisSpec basis{rad::BasisKind::HemisphericalPolynomial, 1};
    rad::RadianceField field(basis, grid.vertices());
    for (std::size_t v = 0; v < grid.vertices(); ++v) {
        const double a = 0.7 * double(v);
        rad::Frame frame;
        frame.t = Vector3d(std::cos(a), std::sin(a), 0.0);
        frame.b = Vector3d(-std::sin(a), std::cos(a), 0.0);
        frame.n = Vector3d::UnitZ();
        rad::storeFrame(frame, field.frame(v));
        for (int c = 0; c < 3; ++c) {
            float* k = field.channelCoefficients(v, c);
            k[rad::polynomialIndex(0, 0)] = 0.5f;
            k[rad::polynomialIndex(1, 0)] = float(std::cos(a));
            k[rad::polynomialIndex(0, 1)] = float(-std::sin(a));
        }
    }
    const rad::RadianceQuadricMetric metric(mesh, field);
    double largest = 0.0;
    for (std::uint32_t v0 = 0; v0 < grid.vertices(); ++v0) {
        // Not from the border: the boundary planes price moving a corner (BoundaryPlanesPrice... below).
        const int i = int(v0) % grid.n, j = int(v0) / grid.n;
        if (i == 0 || j == 0 || i == grid.n - 1 || j == grid.n - 1) continue;
        std::vector<std::uint32_t> ring;
        mesh.neighbours(v0, ring);
        for (std::uint32_t v1 : ring) largest = std::max(largest, halfEdgeCost(metric, mesh, v0, v1));
    }
    EXPECT_LT(largest, 1e-9);
    // A different function at one vertex does cost.
    rad::RadianceField other = field;
    other.channelCoefficients(grid.at(2, 2), 0)[rad::polynomialIndex(1, 0)] += 0.5f;
    const rad::RadianceQuadricMetric changed(mesh, other);
    EXPECT_GT(halfEdgeCost(changed, mesh, grid.at(2, 2), grid.at(3, 2)), 1e-4);
}

TEST(RadianceQuadric, RadianceChangeCostsAndMatchesTheAreaWeightedSum) {
    // One vertex's radiance differs by delta in every coefficient (in the metric's space): moving
    // that vertex onto a neighbour must cost; the neighbour onto it too.
    const Grid grid(5);
    rad::CollapseMesh mesh = grid.mesh();
    rad::RadianceField field = affineField(grid, {rad::BasisKind::SphericalHarmonics, 1});
    for (int j = 0; j < field.coefficientsPerVertex(); ++j) field.vertexCoefficients(grid.at(2, 2))[j] += 0.5f;
    const rad::RadianceQuadricMetric metric(mesh, field);
    const double away = halfEdgeCost(metric, mesh, grid.at(2, 2), grid.at(3, 2));
    EXPECT_GT(away, 1e-6);
    // A vertex whose faces do not reach the bump keeps costing nothing.
    EXPECT_NEAR(halfEdgeCost(metric, mesh, grid.at(1, 3), grid.at(0, 3)), 0.0, 1e-9);
}

TEST(RadianceQuadric, BoundaryPlanesPriceMovingACornerNotSlidingAlongAStraightSide) {
    // A flat grid with one function everywhere: the faces' planes and the attribute planes cost
    // nothing anywhere in the plane; the boundary planes (Garland & Heckbert 1997) do, off the
    // boundary's line.
    const Grid grid(6);
    rad::CollapseMesh mesh = grid.mesh();
    rad::RadianceField field({rad::BasisKind::HemisphericalPolynomial, 2}, grid.vertices());
    std::fill(field.coefficients.begin(), field.coefficients.end(), 0.4f);
    for (std::size_t v = 0; v < grid.vertices(); ++v) rad::storeFrame(rad::frameFromNormal(Vector3d::UnitZ()), field.frame(v));
    const rad::RadianceQuadricMetric metric(mesh, field);
    const auto fullCost = [&](std::uint32_t v0, std::uint32_t v1, const Vector3d& at) {
        rad::EdgeQuery q;
        q.v0 = v0;
        q.v1 = v1;
        q.position = at;
        q.s = 1.0;
        return metric.priceEdge(mesh, q);
    };
    const std::uint32_t side = grid.at(2, 0), next = grid.at(3, 0), corner = grid.at(0, 0), inside = grid.at(2, 2);
    EXPECT_NEAR(fullCost(side, next, mesh.position(next)), 0.0, 1e-12);    // along a straight side
    EXPECT_NEAR(fullCost(inside, side, mesh.position(side)), 0.0, 1e-12);  // an interior vertex onto the side
    EXPECT_GT(fullCost(corner, grid.at(1, 0), mesh.position(grid.at(1, 0))), 1e-4);  // the corner cut off
    EXPECT_GT(fullCost(side, inside, mesh.position(inside)), 1e-4);                   // the side pulled in
}

TEST(RadianceQuadric, CostsDoNotDependOnTheScansSizeOrTheRadianceRange) {
    const Grid small(6, 1.0f), large(6, 1000.0f);
    rad::CollapseMesh meshSmall = small.mesh(), meshLarge = large.mesh();
    rad::RadianceField fieldSmall = affineField(small, {rad::BasisKind::HemisphericalPolynomial, 2}, 1.0);
    rad::RadianceField fieldLarge = fieldSmall;  // same functions per vertex, radiance 40 times larger
    for (float& c : fieldLarge.coefficients) c *= 40.0f;
    // A bump so that the costs are not all zero, and a lifted vertex for geometry.
    for (rad::RadianceField* f : {&fieldSmall, &fieldLarge})
        for (int j = 0; j < f->coefficientsPerVertex(); ++j) f->vertexCoefficients(small.at(2, 3))[j] *= 1.7f;
    meshSmall.setPosition(small.at(3, 2), Vector3d(3.0, 2.0, 0.4));
    meshLarge.setPosition(large.at(3, 2), Vector3d(3000.0, 2000.0, 400.0));
    const rad::RadianceQuadricMetric a(meshSmall, fieldSmall), b(meshLarge, fieldLarge);
    struct Pair {
        std::uint32_t v0, v1;
        double ca, cb;
    };
    std::vector<Pair> pairs;
    double largest = 0.0;
    for (std::uint32_t v0 = 0; v0 < small.vertices(); ++v0) {
        std::vector<std::uint32_t> ring;
        meshSmall.neighbours(v0, ring);
        for (std::uint32_t v1 : ring) {
            pairs.push_back({v0, v1, halfEdgeCost(a, meshSmall, v0, v1), halfEdgeCost(b, meshLarge, v0, v1)});
            largest = std::max(largest, pairs.back().ca);
        }
    }
    ASSERT_GT(largest, 1e-3);
    // Equal to 1e-6 of each cost, and collapses that cost nothing to 1e-8 of the largest cost (the
    // planes are stored in floats, rounded differently at each scale).
    for (const Pair& p : pairs)
        EXPECT_NEAR(p.ca, p.cb, 1e-6 * std::abs(p.ca) + 1e-8 * largest) << p.v0 << " -> " << p.v1;
}

TEST(RadianceQuadric, FullCollapseRecoversAffineRadianceAtTheNewPosition) {
    const Grid grid(5);
    rad::CollapseMesh mesh = grid.mesh();
    const rad::BasisSpec basis{rad::BasisKind::SphericalHarmonics, 2};
    rad::RadianceField field = affineField(grid, basis);
    const rad::RadianceField truth = field;
    rad::RadianceQuadricMetric metric(mesh, field);
    const std::uint32_t v0 = grid.at(2, 2), v1 = grid.at(3, 2);
    Vector3d position;
    ASSERT_TRUE(metric.placeEdge(mesh, v0, v1, position));
    EXPECT_NEAR(position.z(), 0.0, 1e-9);  // stays in the plane
    rad::EdgeQuery q;
    q.v0 = v0;
    q.v1 = v1;
    q.position = position;
    q.s = std::clamp((position.x() - 2.0) / 1.0, 0.0, 1.0);
    EXPECT_NEAR(metric.priceEdge(mesh, q), 0.0, 1e-9);
    mesh.setPosition(v1, position);
    mesh.collapse(v0, v1);
    metric.onCollapse(mesh, q);
    // The survivor's coefficients are the affine field at its new position.
    const int m = field.coefficientsPerVertex();
    for (int j = 0; j < m; ++j) {
        const double expected = 0.3 + 0.01 * j + 0.05 * (j % 3) * position.x() - 0.02 * (j % 5) * position.y();
        EXPECT_NEAR(field.vertexCoefficients(v1)[j], expected, 1e-4) << j;
    }
    (void)truth;
}

TEST(RadianceQuadric, FullCollapseTurnsTheSurvivorsNormalWithIt) {
    // Eq. 8 reflects about the interpolated normals: a survivor placed between two vertices whose
    // normals differ takes the normal between them (slerped by where it was placed), not v1's.
    const Grid grid(5);
    rad::CollapseMesh mesh = grid.mesh();
    for (const rad::BasisSpec basis : {rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, 2},
                                       rad::BasisSpec{rad::BasisKind::SphericalHarmonics, 2}}) {
        rad::RadianceField field = affineField(grid, basis);
        const std::uint32_t v0 = grid.at(2, 2), v1 = grid.at(3, 2);
        const Vector3d n0 = Vector3d(0.5, 0.0, 1.0).normalized(), n1 = Vector3d(-0.5, 0.0, 1.0).normalized();
        rad::storeFrame(rad::frameFromNormal(n0), field.frame(v0));
        rad::storeFrame(rad::frameFromNormal(n1), field.frame(v1));
        for (const double s : {0.5, 0.25}) {
            rad::CollapseMesh copy = mesh;
            rad::RadianceField written = field;
            rad::RadianceQuadricMetric fresh(copy, written);
            rad::EdgeQuery q;
            q.v0 = v0;
            q.v1 = v1;
            q.position = (1.0 - s) * copy.position(v0) + s * copy.position(v1);
            q.s = s;
            copy.setPosition(v1, q.position);
            copy.collapse(v0, v1);
            fresh.onCollapse(copy, q);
            const rad::Frame frame = rad::frameFromStored(written.frame(v1));
            // The normals are 2 x 26.57 degrees apart; the survivor's lies s of the way from n0.
            const double apart = std::acos(n0.dot(n1));
            EXPECT_NEAR(std::acos(std::clamp(frame.n.dot(n0), -1.0, 1.0)), s * apart, 1e-5) << basis.name() << " s " << s;
            EXPECT_NEAR(std::acos(std::clamp(frame.n.dot(n1), -1.0, 1.0)), (1.0 - s) * apart, 1e-5) << basis.name() << " s " << s;
            EXPECT_NEAR(frame.t.dot(frame.n), 0.0, 1e-6);
        }
    }
}

TEST(RadianceQuadric, FlatCollapsesLandOnAnEnd) {
    // On a plane the planes' optimum is undefined, so the survivor sits on one of the ends, whose
    // faces' attribute planes all pass through its own function: never at the midpoint, where s*
    // would average the two ends' radiance whatever the field.
    const Grid grid(6);
    std::mt19937 random(3);
    std::uniform_real_distribution<float> value(0.0f, 1.0f);
    int placed = 0;
    for (int trial = 0; trial < 20; ++trial) {
        rad::CollapseMesh mesh = grid.mesh();
        rad::RadianceField field(rad::BasisSpec{rad::BasisKind::SphericalHarmonics, 1}, grid.vertices());
        for (float& c : field.coefficients) c = value(random);
        for (std::size_t v = 0; v < grid.vertices(); ++v) rad::storeFrame(rad::frameFromNormal(Vector3d::UnitZ()), field.frame(v));
        const rad::RadianceQuadricMetric metric(mesh, field);
        for (int i = 1; i + 2 < grid.n; ++i) {
            const std::uint32_t v0 = grid.at(i, 2), v1 = grid.at(i + 1, 2 + trial % 2);  // straight and diagonal edges
            Vector3d position;
            ASSERT_TRUE(metric.placeEdge(mesh, v0, v1, position));
            const bool atAnEnd = (position - mesh.position(v0)).norm() < 1e-9 || (position - mesh.position(v1)).norm() < 1e-9;
            EXPECT_TRUE(atAnEnd) << "trial " << trial << " edge " << v0 << "-" << v1 << " placed at " << position.transpose();
            ++placed;
        }
    }
    EXPECT_EQ(placed, 60);
}

TEST(RadianceQuadric, QuadricsAccumulateOverCollapses) {
    // After v0 -> v1 (half-edge), v1's quadric is the sum: the error of keeping v1's radiance now
    // includes v0's faces, so a collapse that was free is no longer free when v0 differed.
    const Grid grid(5);
    rad::CollapseMesh mesh = grid.mesh();
    rad::RadianceField field = affineField(grid, {rad::BasisKind::HemisphericalPolynomial, 1});
    for (int j = 0; j < field.coefficientsPerVertex(); ++j) field.vertexCoefficients(grid.at(1, 2))[j] += 0.8f;
    rad::RadianceQuadricMetric metric(mesh, field);
    const std::uint32_t v0 = grid.at(1, 2), v1 = grid.at(2, 2), next = grid.at(3, 2);
    std::vector<double> s(metric.attributeCount());
    metric.attributes(v1, s.data());
    const double before = metric.evaluate(v1, mesh.position(v1), s.data());
    EXPECT_NEAR(before, 0.0, 1e-9);  // v1's own faces carry the bump only at one corner... v1 itself is affine
    const double expectedAdded = metric.evaluate(v0, mesh.position(v1), s.data());
    EXPECT_GT(expectedAdded, 0.0);
    rad::EdgeQuery q;
    q.v0 = v0;
    q.v1 = v1;
    q.position = mesh.position(v1);
    q.s = 1.0;
    q.halfEdge = true;
    mesh.collapse(v0, v1);
    metric.onCollapse(mesh, q);
    const double after = metric.evaluate(v1, mesh.position(v1), s.data());
    EXPECT_NEAR(after, before + expectedAdded, 1e-9 + 1e-6 * expectedAdded);
    EXPECT_GT(halfEdgeCost(metric, mesh, v1, next), 0.0);
}

TEST(RadianceQuadric, QuadricsAreTheSameOnOneAndTwoThreads) {
    // Vertices numbered at random, so that the corners of most faces are far apart: each vertex's
    // quadric must still sum its faces in one order, whatever the threads.
    const Grid grid(40);
    std::vector<float> positions = grid.positions;
    std::vector<std::uint32_t> faces = grid.faces;
    radtest::renumberVerticesAtRandom(positions, faces, 5);
    const std::size_t n = grid.vertices();
    for (std::size_t v = 0; v < n; ++v) positions[3 * v + 2] = 0.1f * std::sin(0.7f * positions[3 * v]);
    const rad::CollapseMesh mesh(positions.data(), n, faces.data(), faces.size() / 3);
    rad::RadianceField field({rad::BasisKind::HemisphericalPolynomial, 2}, n);
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> value(0.0f, 1.0f);
    for (std::size_t v = 0; v < n; ++v) {
        for (int j = 0; j < field.coefficientsPerVertex(); ++j) field.vertexCoefficients(v)[j] = value(rng);
        rad::storeFrame(rad::frameFromNormal(Vector3d(0.1 * value(rng), 0.1 * value(rng), 1.0).normalized()), field.frame(v));
    }
    rad::RadianceQuadricOptions one, two;
    one.threads = 1;
    two.threads = 2;
    one.perceptualExponent = two.perceptualExponent = 0.5;
    rad::RadianceField fieldOne = field, fieldTwo = field;
    const rad::RadianceQuadricMetric a(mesh, fieldOne, one), b(mesh, fieldTwo, two);
    ASSERT_EQ(a.attributeScale(), b.attributeScale());
    std::vector<double> s(a.attributeCount());
    for (std::uint32_t v = 0; v < n; v += 7) {
        a.attributes(v, s.data());
        const Vector3d p = mesh.position(v) + Vector3d(0.01, -0.02, 0.03);
        EXPECT_EQ(a.evaluate(v, p, s.data()), b.evaluate(v, p, s.data())) << "vertex " << v;
    }
}

TEST(RadianceQuadric, IsTheDefaultAndSimplifiesBothCollapseKinds) {
    EXPECT_EQ(rad::RadianceSimplificationOptions().metric, rad::SimplificationMetric::RadianceQuadric);
    const Grid grid(12);
    for (rad::CollapseKind kind : {rad::CollapseKind::HalfEdge, rad::CollapseKind::Full}) {
        rad::RadianceMesh mesh;
        mesh.positions = grid.positions;
        for (std::size_t v = 0; v < grid.vertices(); ++v)  // a dome, so that geometry matters
            mesh.positions[3 * v + 2] = 0.05f * (mesh.positions[3 * v] - 5.5f) * (mesh.positions[3 * v + 1] - 5.5f);
        mesh.faces = grid.faces;
        mesh.radiance = affineField(grid, {rad::BasisKind::HemisphericalPolynomial, 3});
        rad::RadianceSimplificationOptions options;
        options.collapse.kind = kind;
        options.collapse.preserveBoundary = true;
        options.collapse.targetFaceCount = mesh.faceCount() / 4;
        const rad::RadianceSimplificationResult r = rad::simplifyRadianceMesh(mesh, options);
        EXPECT_LE(r.collapse.finalFaceCount, mesh.faceCount() / 4);
        const rad::RadianceMesh coarse = r.progressive.extract(r.progressive.steps.size());
        ASSERT_TRUE(coarse.radiance.has_value());
        EXPECT_EQ(coarse.radiance->validate(), "");
        // Affine radiance stays affine through full collapses (the optimum reproduces it), and
        // half-edge collapses keep original rows: either way every coefficient is the affine
        // function of its vertex's original (x, y) up to the dome's small z.
        const int m = coarse.radiance->coefficientsPerVertex();
        for (std::size_t v = 0; v < coarse.vertexCount(); ++v) {
            const double x = coarse.positions[3 * v], y = coarse.positions[3 * v + 1];
            for (int j = 0; j < m; ++j) {
                const double expected = 0.3 + 0.01 * j + 0.05 * (j % 3) * x - 0.02 * (j % 5) * y;
                EXPECT_NEAR(coarse.radiance->vertexCoefficients(v)[j], expected, 0.02) << "vertex " << v << " coefficient " << j;
            }
        }
    }
}

}  // namespace
