#include "simplify/edge_collapse.h"

#include "geometry/primitive_meshes.h"
#include "radiance/radiance_field.h"
#include "radiance/radiance_frame.h"
#include "simplify/radiance_quadric.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <utility>
#include <vector>

namespace {

using rad::CollapseKind;
using rad::CollapseMesh;
using rad::EdgeCollapseOptions;

CollapseMesh toCollapseMesh(const rad::TriangleMesh& m) {
    return CollapseMesh(m.positions.data(), m.vertexCount(), m.faces.data(), m.faceCount());
}

// A regular n x n grid of squares over [0, 1]^2 in z = 0, counter-clockwise seen from +z.
rad::TriangleMesh grid(int n) {
    rad::TriangleMesh m;
    radtest::addGrid(m, n + 1, 0.0f, 1.0f);
    return m;
}

struct Topology {
    std::size_t vertices = 0, edges = 0, faces = 0;
    std::size_t nonManifoldEdges = 0, boundaryEdges = 0, duplicateFaces = 0;
    std::map<std::uint32_t, std::set<std::uint32_t>> neighbours;
};

// Recounted from the compacted arrays, independently of the engine's incidence lists.
Topology topology(const std::vector<std::uint32_t>& faces, std::size_t vertexCount) {
    Topology t;
    t.vertices = vertexCount;
    t.faces = faces.size() / 3;
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> edgeUse;
    std::set<std::vector<std::uint32_t>> seen;
    for (std::size_t f = 0; f < t.faces; ++f) {
        std::vector<std::uint32_t> key(faces.begin() + 3 * f, faces.begin() + 3 * f + 3);
        std::sort(key.begin(), key.end());
        if (!seen.insert(key).second) ++t.duplicateFaces;
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = faces[3 * f + k], b = faces[3 * f + (k + 1) % 3];
            ++edgeUse[{std::min(a, b), std::max(a, b)}];
            t.neighbours[a].insert(b);
            t.neighbours[b].insert(a);
        }
    }
    t.edges = edgeUse.size();
    for (const auto& [edge, count] : edgeUse) {
        if (count > 2) ++t.nonManifoldEdges;
        if (count == 1) ++t.boundaryEdges;
    }
    return t;
}

TEST(EdgeCollapse, GeometryOnlySphereStaysAClosedOrientedManifold) {
    for (CollapseKind kind : {CollapseKind::HalfEdge, CollapseKind::Full}) {
        const rad::TriangleMesh sphere = rad::makeIcosphere(4);  // 5120 faces
        CollapseMesh mesh = toCollapseMesh(sphere);
        EdgeCollapseOptions options;
        options.kind = kind;
        options.targetFaceCount = 500;
        std::size_t steps = 0;
        const rad::EdgeCollapseResult r =
            rad::simplifyByEdgeCollapse(mesh, nullptr, options, [&](const rad::CollapseStep&) { ++steps; });
        EXPECT_EQ(r.stop, rad::StopReason::TargetReached);
        EXPECT_LE(r.finalFaceCount, 500u);
        EXPECT_GE(r.finalFaceCount, 498u);  // each collapse removes exactly two faces of a closed mesh
        EXPECT_EQ(steps, r.collapses);
        std::vector<float> p;
        std::vector<std::uint32_t> f, map;
        mesh.compact(p, f, map);
        const Topology t = topology(f, p.size() / 3);
        EXPECT_EQ(t.nonManifoldEdges, 0u);
        EXPECT_EQ(t.boundaryEdges, 0u);
        EXPECT_EQ(t.duplicateFaces, 0u);
        EXPECT_EQ(static_cast<long>(t.vertices) - static_cast<long>(t.edges) + static_cast<long>(t.faces), 2);
        for (std::size_t i = 0; i < t.faces; ++i) {
            // Every face still faces away from the centre, and vertices stay near the unit sphere.
            Eigen::Vector3d a(p[3 * f[3 * i]], p[3 * f[3 * i] + 1], p[3 * f[3 * i] + 2]);
            Eigen::Vector3d b(p[3 * f[3 * i + 1]], p[3 * f[3 * i + 1] + 1], p[3 * f[3 * i + 1] + 2]);
            Eigen::Vector3d c(p[3 * f[3 * i + 2]], p[3 * f[3 * i + 2] + 1], p[3 * f[3 * i + 2] + 2]);
            EXPECT_GT((b - a).cross(c - a).dot(a + b + c), 0.0);
            EXPECT_NEAR(a.norm(), 1.0, kind == CollapseKind::HalfEdge ? 1e-6 : 0.05);
        }
    }
}

TEST(EdgeCollapse, PlanarGridKeepsItsBoundaryAndCollapsesForFree) {
    const rad::TriangleMesh g = grid(12);
    CollapseMesh mesh = toCollapseMesh(g);
    EdgeCollapseOptions options;
    options.targetFaceCount = 60;
    const rad::EdgeCollapseResult r = rad::simplifyByEdgeCollapse(mesh, nullptr, options);
    EXPECT_LE(r.finalFaceCount, 60u);
    EXPECT_NEAR(r.maxCost, 0.0, 1e-20);  // every face stays in the plane
    for (std::uint32_t v = 0; v < g.vertexCount(); ++v) {
        const float x = g.positions[3 * v], y = g.positions[3 * v + 1];
        const bool boundary = x == 0.0f || y == 0.0f || x == 1.0f || y == 1.0f;
        if (boundary) EXPECT_TRUE(mesh.vertexAlive(v)) << v;
    }
    std::vector<float> p;
    std::vector<std::uint32_t> f, map;
    mesh.compact(p, f, map);
    double area = 0.0;
    for (std::size_t i = 0; i < f.size() / 3; ++i) {
        const float* a = &p[3 * f[3 * i]];
        const float* b = &p[3 * f[3 * i + 1]];
        const float* c = &p[3 * f[3 * i + 2]];
        const double z = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        EXPECT_GT(z, 0.0);  // no flip
        area += 0.5 * z;
    }
    EXPECT_NEAR(area, 1.0, 1e-6);  // the square is still covered exactly once
}

TEST(EdgeCollapse, BoundaryMayMoveWhenNotPreservedButNeverPinches) {
    CollapseMesh mesh = toCollapseMesh(grid(10));
    EdgeCollapseOptions options;
    options.preserveBoundary = false;
    options.targetFaceCount = 20;
    rad::simplifyByEdgeCollapse(mesh, nullptr, options);
    std::vector<float> p;
    std::vector<std::uint32_t> f, map;
    mesh.compact(p, f, map);
    const Topology t = topology(f, p.size() / 3);
    EXPECT_LE(t.faces, 20u);
    EXPECT_EQ(t.nonManifoldEdges, 0u);
    EXPECT_EQ(static_cast<long>(t.vertices) - static_cast<long>(t.edges) + static_cast<long>(t.faces), 1);  // a disc
}

TEST(EdgeCollapse, TetrahedronCannotCollapse) {
    const float p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    const std::uint32_t f[] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    CollapseMesh mesh(p, 4, f, 4);
    EdgeCollapseOptions options;
    options.targetFaceCount = 0;
    const rad::EdgeCollapseResult r = rad::simplifyByEdgeCollapse(mesh, nullptr, options);
    EXPECT_EQ(r.stop, rad::StopReason::NoValidCollapse);
    EXPECT_EQ(r.collapses, 0u);
    EXPECT_EQ(mesh.aliveFaceCount(), 4u);
}

TEST(EdgeCollapse, ValenceBoundsHold) {
    CollapseMesh mesh = toCollapseMesh(rad::makeIcosphere(3));
    EdgeCollapseOptions options;
    options.minValence = 4;
    options.maxValence = 11;
    options.targetFaceCount = 200;
    rad::simplifyByEdgeCollapse(mesh, nullptr, options);
    std::vector<float> p;
    std::vector<std::uint32_t> f, map;
    mesh.compact(p, f, map);
    const Topology t = topology(f, p.size() / 3);
    for (const auto& [v, n] : t.neighbours) {
        EXPECT_GE(n.size(), 4u);
        EXPECT_LE(n.size(), 11u);
    }
}

// A metric that forbids removing the vertices of a chosen set and counts its calls.
class ProtectingMetric : public rad::CollapseMetric {
public:
    explicit ProtectingMetric(std::set<std::uint32_t> p) : protectedVertices(std::move(p)) {}
    std::string name() const override { return "protecting"; }
    void priceHalfEdges(const CollapseMesh&, const rad::HalfEdgeQuery& q, double* costs) const override {
        for (int i = 0; i < q.targetCount; ++i)
            costs[i] = protectedVertices.count(q.source) ? std::numeric_limits<double>::infinity() : 1.0 + q.targets[i];
    }
    void onCollapse(const CollapseMesh& mesh, const rad::EdgeQuery& q) override {
        ++collapses;
        EXPECT_FALSE(mesh.vertexAlive(q.v0));
        EXPECT_TRUE(mesh.vertexAlive(q.v1));
        EXPECT_EQ(q.s, 1.0);
        EXPECT_TRUE(q.halfEdge);
    }
    std::set<std::uint32_t> protectedVertices;
    std::size_t collapses = 0;
};

TEST(EdgeCollapse, MetricCanForbidAndIsToldOfEveryCollapse) {
    CollapseMesh mesh = toCollapseMesh(rad::makeIcosphere(3));
    std::set<std::uint32_t> keep;
    for (std::uint32_t v = 0; v < 40; ++v) keep.insert(v);
    ProtectingMetric metric(keep);
    EdgeCollapseOptions options;
    options.targetFaceCount = 100;
    options.geometryWeight = 0.0;
    options.attributeWeight = 1.0;
    const rad::EdgeCollapseResult r = rad::simplifyByEdgeCollapse(mesh, &metric, options);
    EXPECT_EQ(metric.collapses, r.collapses);
    for (std::uint32_t v : keep) EXPECT_TRUE(mesh.vertexAlive(v)) << v;
    EXPECT_GT(r.collapses, 100u);
}

TEST(EdgeCollapse, MaxErrorStopsBeforeTheTarget) {
    CollapseMesh mesh = toCollapseMesh(rad::makeIcosphere(3));
    EdgeCollapseOptions options;
    options.targetFaceCount = 10;
    options.maxError = 1e-5;
    const rad::EdgeCollapseResult r = rad::simplifyByEdgeCollapse(mesh, nullptr, options);
    EXPECT_EQ(r.stop, rad::StopReason::MaxErrorReached);
    EXPECT_LE(r.maxCost, 1e-5);
    EXPECT_GT(r.finalFaceCount, 10u);
}

TEST(EdgeCollapse, ProgressCanCancel) {
    CollapseMesh mesh = toCollapseMesh(rad::makeIcosphere(3));
    EdgeCollapseOptions options;
    options.targetFaceCount = 100;
    int calls = 0;
    options.progress = [&](double fraction, const char* stage) {
        EXPECT_GE(fraction, 0.0);
        EXPECT_LE(fraction, 1.0);
        EXPECT_NE(stage, nullptr);
        return ++calls < 5;
    };
    EXPECT_THROW(rad::simplifyByEdgeCollapse(mesh, nullptr, options), rad::OperationCancelled);
    EXPECT_EQ(calls, 5);
}

// An icosphere with an SH(2) field that varies smoothly over it, simplified to a tenth of its faces
// under the accumulating radiance quadric (full collapses, costs of the two ends only).
struct QuadricRun {
    rad::EdgeCollapseResult result;
    std::vector<float> positions;
    std::vector<std::uint32_t> faces;
    std::vector<float> costs;  // of each collapse, in order
};
// The radiance quadric with its updates made at each collapse, not at the end of each pass.
class ImmediateRadianceQuadric : public rad::RadianceQuadricMetric {
public:
    using rad::RadianceQuadricMetric::RadianceQuadricMetric;
    bool updatesCanBeDeferred() const override { return false; }
};

QuadricRun simplifyShSphere(double passFraction, int threads, double maxError = INFINITY, bool deferred = true,
                            rad::BasisSpec basis = {rad::BasisKind::SphericalHarmonics, 2},
                            std::vector<float>* rows = nullptr, std::vector<std::uint32_t>* facesAfter = nullptr) {
    const rad::TriangleMesh sphere = rad::makeIcosphere(4);  // 5120 faces
    rad::RadianceField field(basis, sphere.vertexCount());
    for (std::size_t v = 0; v < sphere.vertexCount(); ++v) {
        const float* p = sphere.positions.data() + 3 * v;
        for (int j = 0; j < field.coefficientsPerVertex(); ++j)
            field.vertexCoefficients(v)[j] = 0.5f + 0.3f * std::sin(3.0f * p[0] + 2.0f * p[1] * p[2] + 0.7f * j);
        rad::storeFrame(rad::frameFromNormal(Eigen::Vector3d(p[0], p[1], p[2]).normalized()), field.frame(v));
    }
    CollapseMesh mesh = toCollapseMesh(sphere);
    std::unique_ptr<rad::RadianceQuadricMetric> metric =
        deferred ? std::make_unique<rad::RadianceQuadricMetric>(mesh, field)
                 : std::make_unique<ImmediateRadianceQuadric>(mesh, field);
    EdgeCollapseOptions options;
    options.kind = CollapseKind::Full;
    options.targetFaceCount = 512;
    options.maxError = maxError;
    options.passFraction = passFraction;
    options.threads = threads;
    QuadricRun run;
    run.result = rad::simplifyByEdgeCollapse(mesh, metric.get(), options, [&](const rad::CollapseStep& s) {
        run.costs.push_back(s.cost);
        // What a recorder copies when the step is reported: the survivor's row of the field.
        if (rows) rows->insert(rows->end(), field.vertexCoefficients(s.survivor),
                               field.vertexCoefficients(s.survivor) + field.coefficientsPerVertex());
        if (facesAfter) facesAfter->push_back(s.facesAfter);
    });
    std::vector<std::uint32_t> map;
    mesh.compact(run.positions, run.faces, map);
    return run;
}

TEST(EdgeCollapse, PassesReachTheTargetAsAClosedManifoldAtTheQueuesCost) {
    const QuadricRun queue = simplifyShSphere(0.0, 1), passes = simplifyShSphere(0.15, 1);
    EXPECT_EQ(passes.result.stop, rad::StopReason::TargetReached);
    EXPECT_EQ(passes.result.finalFaceCount, queue.result.finalFaceCount);
    const Topology t = topology(passes.faces, passes.positions.size() / 3);
    EXPECT_EQ(t.nonManifoldEdges, 0u);
    EXPECT_EQ(t.boundaryEdges, 0u);
    EXPECT_EQ(t.duplicateFaces, 0u);
    EXPECT_EQ(static_cast<long>(t.vertices) - static_cast<long>(t.edges) + static_cast<long>(t.faces), 2);
    // Passes take the cheapest edges in order, as the queue does: the sum of the costs paid stays
    // close to the queue's (an order that ignored the costs pays many times more).
    double queueSum = 0.0, passSum = 0.0;
    for (float c : queue.costs) queueSum += c;
    for (float c : passes.costs) passSum += c;
    EXPECT_GT(queueSum, 0.0);
    EXPECT_LT(passSum, 1.1 * queueSum);
    EXPECT_LT(passes.result.maxCost, 1.5 * queue.result.maxCost);
    // And they leave few stale entries: each pass drops them before sorting.
    EXPECT_LT(passes.result.staleEntries, queue.result.staleEntries);
}

TEST(EdgeCollapse, PassesGiveTheSameMeshOnOneAndTwoThreads) {
    const QuadricRun one = simplifyShSphere(0.15, 1), two = simplifyShSphere(0.15, 2);
    EXPECT_EQ(one.faces, two.faces);
    EXPECT_EQ(one.positions, two.positions);
    EXPECT_EQ(one.costs, two.costs);
}

TEST(EdgeCollapse, DeferredUpdatesGiveTheSameStepsAsImmediateOnes) {
    // PB, so that each update also turns the survivor's frame and projects s* back onto it.
    const rad::BasisSpec pb{rad::BasisKind::HemisphericalPolynomial, 3};
    for (int threads : {1, 2}) {
        std::vector<float> rowsDeferred, rowsImmediate;
        std::vector<std::uint32_t> facesDeferred, facesImmediate;
        const QuadricRun deferred = simplifyShSphere(0.3, threads, INFINITY, true, pb, &rowsDeferred, &facesDeferred);
        const QuadricRun immediate =
            simplifyShSphere(0.3, threads, INFINITY, false, pb, &rowsImmediate, &facesImmediate);
        EXPECT_EQ(deferred.faces, immediate.faces);
        EXPECT_EQ(deferred.positions, immediate.positions);
        EXPECT_EQ(deferred.costs, immediate.costs);
        EXPECT_EQ(rowsDeferred, rowsImmediate);  // each row as it was right after its step
        EXPECT_EQ(facesDeferred, facesImmediate);
        ASSERT_FALSE(facesDeferred.empty());
        EXPECT_TRUE(std::is_sorted(facesDeferred.rbegin(), facesDeferred.rend()));
        EXPECT_EQ(facesDeferred.back(), deferred.result.finalFaceCount);
    }
}

TEST(EdgeCollapse, PassesStopAtTheLargestError) {
    const QuadricRun full = simplifyShSphere(0.15, 1);
    const double limit = full.result.maxCost / 10.0;
    const QuadricRun bounded = simplifyShSphere(0.15, 1, limit);
    EXPECT_EQ(bounded.result.stop, rad::StopReason::MaxErrorReached);
    EXPECT_LE(bounded.result.maxCost, limit);
    EXPECT_GT(bounded.result.finalFaceCount, full.result.finalFaceCount);
}

// A flat mesh with one constant PB(2) function everywhere, simplified under the radiance quadric
// with full collapses: every collapse that keeps the outline costs nothing.
struct FlatRun {
    rad::EdgeCollapseResult result;
    std::vector<float> positions;
    std::vector<std::uint32_t> faces;
    std::vector<std::uint8_t> alive;  // of the input's vertices
    std::vector<float> finalPositions;  // of the input's vertices, where alive
};
FlatRun simplifyFlat(const rad::TriangleMesh& flat, bool alongBoundary, std::size_t targetFaces) {
    rad::RadianceField field(rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, 2}, flat.vertexCount());
    std::fill(field.coefficients.begin(), field.coefficients.end(), 0.5f);
    for (std::size_t v = 0; v < flat.vertexCount(); ++v) rad::storeFrame(rad::frameFromNormal(Eigen::Vector3d::UnitZ()), field.frame(v));
    CollapseMesh mesh = toCollapseMesh(flat);
    rad::RadianceQuadricMetric metric(mesh, field);
    EdgeCollapseOptions options;
    options.kind = CollapseKind::Full;
    options.targetFaceCount = targetFaces;
    options.collapseAlongBoundary = alongBoundary;
    FlatRun run;
    run.result = rad::simplifyByEdgeCollapse(mesh, &metric, options);
    for (std::uint32_t v = 0; v < flat.vertexCount(); ++v) {
        run.alive.push_back(mesh.vertexAlive(v));
        const Eigen::Vector3d p = mesh.position(v);
        run.finalPositions.insert(run.finalPositions.end(), {float(p.x()), float(p.y()), float(p.z())});
    }
    std::vector<std::uint32_t> map;
    mesh.compact(run.positions, run.faces, map);
    return run;
}

// The vertices of the compacted mesh that lie on a boundary edge.
std::set<std::uint32_t> boundaryVertices(const std::vector<std::uint32_t>& faces) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> use;
    for (std::size_t f = 0; f < faces.size() / 3; ++f)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = faces[3 * f + k], b = faces[3 * f + (k + 1) % 3];
            ++use[{std::min(a, b), std::max(a, b)}];
        }
    std::set<std::uint32_t> out;
    for (const auto& [edge, count] : use)
        if (count == 1) out.insert({edge.first, edge.second});
    return out;
}

TEST(EdgeCollapse, TheRadianceQuadricCollapsesAlongTheBoundaryAndKeepsTheOutline) {
    const rad::TriangleMesh g = grid(12);  // 13 x 13 vertices, 48 on the boundary, 288 faces
    const FlatRun along = simplifyFlat(g, true, 8);
    EXPECT_LE(along.result.finalFaceCount, 8u);
    const Topology t = topology(along.faces, along.positions.size() / 3);
    EXPECT_EQ(t.nonManifoldEdges, 0u);
    EXPECT_EQ(static_cast<long>(t.vertices) - static_cast<long>(t.edges) + static_cast<long>(t.faces), 1);  // a disc
    double area = 0.0;
    for (std::size_t i = 0; i < along.faces.size() / 3; ++i) {
        const float* a = &along.positions[3 * along.faces[3 * i]];
        const float* b = &along.positions[3 * along.faces[3 * i + 1]];
        const float* c = &along.positions[3 * along.faces[3 * i + 2]];
        const double z = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        EXPECT_GT(z, 0.0);  // no flip
        area += 0.5 * z;
    }
    // The boundary planes make moving a corner cost, sliding along a straight side not: the square
    // is whole, and its boundary vertices are original ones on its sides.
    EXPECT_NEAR(area, 1.0, 1e-6);
    const std::set<std::uint32_t> boundary = boundaryVertices(along.faces);
    EXPECT_LT(boundary.size(), 12u);
    std::set<std::pair<float, float>> corners;
    for (std::uint32_t v : boundary) {
        const float x = along.positions[3 * v], y = along.positions[3 * v + 1];
        EXPECT_TRUE(x == 0.0f || y == 0.0f || x == 1.0f || y == 1.0f) << x << " " << y;
        if ((x == 0.0f || x == 1.0f) && (y == 0.0f || y == 1.0f)) corners.insert({x, y});
    }
    EXPECT_EQ(corners.size(), 4u);

    // Without it the 48 boundary vertices stay: a polygon of 48 vertices needs 46 triangles.
    const FlatRun locked = simplifyFlat(g, false, 8);
    EXPECT_GE(locked.result.finalFaceCount, 46u);
    for (std::uint32_t v = 0; v < g.vertexCount(); ++v) {
        const float x = g.positions[3 * v], y = g.positions[3 * v + 1];
        if (x == 0.0f || y == 0.0f || x == 1.0f || y == 1.0f) EXPECT_TRUE(locked.alive[v]) << v;
    }
}

TEST(EdgeCollapse, AVertexJoiningTwoFansNeverMovesWhenCollapsingAlongTheBoundary) {
    // Two squares touching at one corner (a non-manifold vertex): it has two open fans.
    rad::TriangleMesh m = grid(6);
    const rad::TriangleMesh second = grid(6);
    const std::uint32_t shared = 6 * 7 + 6;  // (1, 1) of the first square
    const auto base = static_cast<std::uint32_t>(m.vertexCount());
    for (std::size_t v = 0; v < second.vertexCount(); ++v)
        m.positions.insert(m.positions.end(), {second.positions[3 * v] + 1.0f, second.positions[3 * v + 1] + 1.0f, 0.0f});
    for (std::uint32_t i : second.faces) m.faces.push_back(i == 0 ? shared : base + i);  // its (0, 0) is (1, 1)
    ASSERT_EQ(m.positions[3 * shared], 1.0f);
    ASSERT_EQ(m.positions[3 * shared + 1], 1.0f);
    const FlatRun run = simplifyFlat(m, true, 10);
    EXPECT_TRUE(run.alive[shared]);
    EXPECT_EQ(run.finalPositions[3 * shared], 1.0f);
    EXPECT_EQ(run.finalPositions[3 * shared + 1], 1.0f);
    const Topology t = topology(run.faces, run.positions.size() / 3);
    EXPECT_EQ(t.nonManifoldEdges, 0u);
    EXPECT_LT(run.result.finalFaceCount, 40u);  // both squares did simplify
}

TEST(EdgeCollapse, RefusesInconsistentOptions) {
    CollapseMesh mesh = toCollapseMesh(rad::makeIcosphere(1));
    ProtectingMetric metric({});
    EdgeCollapseOptions options;
    options.kind = CollapseKind::Full;
    EXPECT_THROW(rad::simplifyByEdgeCollapse(mesh, &metric, options), std::invalid_argument);
    options.kind = CollapseKind::HalfEdge;
    options.minValence = 8;
    options.maxValence = 4;
    EXPECT_THROW(rad::simplifyByEdgeCollapse(mesh, &metric, options), std::invalid_argument);
    options.minValence = options.maxValence = 0;
    for (double fraction : {-0.1, 1.5, double(NAN)}) {
        options.passFraction = fraction;
        EXPECT_THROW(rad::simplifyByEdgeCollapse(mesh, &metric, options), std::invalid_argument) << fraction;
    }
}

}  // namespace
