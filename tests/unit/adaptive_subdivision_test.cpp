// Tests of prt/adaptive_subdivision.h (Křivánek et al. 2004 sec. 3.2, Fig. 2-3), all checked on the output
// geometry with code independent of the refiner:
//   - conforming output: every interior position-edge used by exactly two faces in opposite
//     directions, one-face edges only on the input boundary, no vertex strictly inside any edge
//     (a geometric search), hence no T-junction, also across an attribute seam;
//   - every output face lies inside its origin face with its orientation, the areas of the faces of
//     each input face add up to its area;
//   - the oracle is asked exactly once per new vertex and never for an input vertex, one call per
//     operation; with an analytic oracle every vertex's transfer is the function at its position
//     (nothing interpolated);
//   - the budget (faces after T-vertex removal) is never exceeded and the loop is greedy: raising
//     the budget by one either changes nothing or lets exactly the next operation in, ending at the
//     new budget; the threshold stops refinement; refinement concentrates along a steep step;
//   - Fig. 3b cases (shorter diagonal), uniform level count and V/F counts, refusals, cancellation.
#include "prt/adaptive_subdivision.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

namespace {

using Eigen::Vector3d;
using rad::PrtMesh;
using rad::SubdivisionResult;

// Transfer as a function of a vertex's position and normal, width floats.
using Field = std::function<void(const float* p, const float* n, float* out)>;

Vector3d position(const PrtMesh& m, std::size_t v) {
    return {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]};
}
Vector3d corner(const PrtMesh& m, std::size_t f, int k) { return position(m, m.faces[3 * f + k]); }
Vector3d areaVector(const PrtMesh& m, std::size_t f) {
    return 0.5 * (corner(m, f, 1) - corner(m, f, 0)).cross(corner(m, f, 2) - corner(m, f, 0));
}

PrtMesh makePrtMesh(const rad::TriangleMesh& tm, int width, const Field& field) {
    PrtMesh m;
    m.positions = tm.positions;
    m.normals = tm.normals;
    m.faces = tm.faces;
    m.width = width;
    m.transfer.resize(m.vertexCount() * width);
    for (std::size_t v = 0; v < m.vertexCount(); ++v)
        field(&m.positions[3 * v], &m.normals[3 * v], &m.transfer[v * width]);
    return m;
}

PrtMesh gridMesh(int n, int width, const Field& field) {
    rad::TriangleMesh tm;
    radtest::addGrid(tm, n);
    return makePrtMesh(tm, width, field);
}

// A "roof": two planes z = 0.5 |x| over [-1, 1]^2 meeting along x = 0, each an n x n grid with its
// own flat normal, so the crease vertices are duplicated with different normals (an attribute seam).
PrtMesh roofMesh(int n, int width, const Field& field) {
    rad::TriangleMesh tm;
    for (int sideIndex = 0; sideIndex < 2; ++sideIndex) {
        const float lo = sideIndex == 0 ? -1.0f : 0.0f, hi = sideIndex == 0 ? 0.0f : 1.0f;
        const Vector3d normal = Vector3d(sideIndex == 0 ? 0.5 : -0.5, 0.0, 1.0).normalized();
        const auto base = static_cast<std::uint32_t>(tm.vertexCount());
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const float x = lo + (hi - lo) * i / (n - 1), y = -1.0f + 2.0f * j / (n - 1);
                tm.positions.insert(tm.positions.end(), {x, y, 0.5f * std::fabs(x)});
                tm.normals.insert(tm.normals.end(), {float(normal.x()), float(normal.y()), float(normal.z())});
            }
        for (int j = 0; j + 1 < n; ++j)
            for (int i = 0; i + 1 < n; ++i) {
                const std::uint32_t a = base + j * n + i, b = a + 1, c = a + n + 1, d = a + n;
                tm.faces.insert(tm.faces.end(), {a, b, c, a, c, d});
            }
    }
    return makePrtMesh(tm, width, field);
}

// Records what the subdivision asks: calls, and every (position, normal) queried.
struct RecordingOracle {
    Field field;
    int width = 1;
    std::size_t calls = 0;
    std::vector<std::array<float, 6>> asked;

    rad::TransferOracle oracle() {
        return [this](const float* p, const float* n, std::size_t count, float* out) {
            ++calls;
            for (std::size_t i = 0; i < count; ++i) {
                asked.push_back({p[3 * i], p[3 * i + 1], p[3 * i + 2], n[3 * i], n[3 * i + 1], n[3 * i + 2]});
                field(p + 3 * i, n + 3 * i, out + width * i);
            }
        };
    }
};

// Steep tanh step across the line x = x0 (plus a gentle slope so that no triangle has zero error),
// two channels.
Field stepField(double x0, double widthOfStep) {
    return [=](const float* p, const float*, float* out) {
        out[0] = static_cast<float>(std::tanh((p[0] - x0) / widthOfStep));
        out[1] = static_cast<float>(0.05 * p[1]);
    };
}

rad::AdaptiveSubdivisionOptions differenceOptions(std::size_t budget, double threshold = 0.0) {
    rad::AdaptiveSubdivisionOptions o;
    o.measure = rad::TransferErrorMeasure::Difference;
    o.triangleBudget = budget;
    o.threshold = threshold;
    return o;
}

using PositionKey = std::array<float, 3>;
PositionKey keyOf(const PrtMesh& m, std::size_t v) {
    return {m.positions[3 * v] + 0.0f, m.positions[3 * v + 1] + 0.0f, m.positions[3 * v + 2] + 0.0f};
}

bool onSegment(const Vector3d& p, const Vector3d& a, const Vector3d& b, bool strictlyInside) {
    const Vector3d d = b - a;
    const double t = (p - a).dot(d) / d.squaredNorm();
    const double eps = strictlyInside ? 1e-6 : -1e-9;
    if (t < eps || t > 1.0 - eps) return false;
    return (a + t * d - p).norm() <= 1e-6 * d.norm();
}

// Empty when every undirected position-edge of `out` is used by two faces in opposite directions,
// or by one face and lies on a boundary edge of `in`; otherwise the first problem found.
std::string conformityProblem(const PrtMesh& in, const PrtMesh& out) {
    const auto edgeUses = [](const PrtMesh& m) {
        std::map<std::pair<PositionKey, PositionKey>, std::array<int, 2>> uses;  // [low->high, high->low]
        for (std::size_t f = 0; f < m.faceCount(); ++f)
            for (int k = 0; k < 3; ++k) {
                const PositionKey a = keyOf(m, m.faces[3 * f + k]), b = keyOf(m, m.faces[3 * f + (k + 1) % 3]);
                if (a < b)
                    ++uses[{a, b}][0];
                else
                    ++uses[{b, a}][1];
            }
        return uses;
    };
    std::vector<std::pair<Vector3d, Vector3d>> inputBoundary;
    for (const auto& [edge, use] : edgeUses(in))
        if (use[0] + use[1] == 1)
            inputBoundary.push_back({Vector3d(edge.first[0], edge.first[1], edge.first[2]),
                                     Vector3d(edge.second[0], edge.second[1], edge.second[2])});
    for (const auto& [edge, use] : edgeUses(out)) {
        const Vector3d a(edge.first[0], edge.first[1], edge.first[2]), b(edge.second[0], edge.second[1], edge.second[2]);
        if (use[0] == 1 && use[1] == 1) continue;
        if (use[0] + use[1] == 1) {
            const bool onInputBoundary = std::any_of(inputBoundary.begin(), inputBoundary.end(), [&](const auto& s) {
                return onSegment(a, s.first, s.second, false) && onSegment(b, s.first, s.second, false);
            });
            if (onInputBoundary) continue;
        }
        std::ostringstream why;
        why << "edge (" << a.transpose() << ") - (" << b.transpose() << ") used " << use[0] << " + " << use[1]
            << " times";
        return why.str();
    }
    return {};
}

// Number of (vertex, edge) pairs where the vertex lies strictly inside the edge: a geometric search
// (uniform grid of cells, each edge tested against the vertices in the cells its box overlaps).
std::size_t verticesInsideEdges(const PrtMesh& m) {
    Vector3d lo = position(m, 0), hi = lo;
    for (std::size_t v = 1; v < m.vertexCount(); ++v) {
        lo = lo.cwiseMin(position(m, v));
        hi = hi.cwiseMax(position(m, v));
    }
    const double cell = std::max((hi - lo).maxCoeff() / 64.0, 1e-9);
    const auto cellOf = [&](const Vector3d& p) {
        return Eigen::Vector3i(int(std::floor((p.x() - lo.x()) / cell)), int(std::floor((p.y() - lo.y()) / cell)),
                               int(std::floor((p.z() - lo.z()) / cell)));
    };
    const auto cellKey = [](int x, int y, int z) { return (std::int64_t(x) * 4096 + y) * 4096 + z; };
    std::unordered_map<std::int64_t, std::vector<Vector3d>> cells;
    std::set<PositionKey> seen;
    for (std::size_t v = 0; v < m.vertexCount(); ++v)
        if (seen.insert(keyOf(m, v)).second) {
            const Eigen::Vector3i c = cellOf(position(m, v));
            cells[cellKey(c.x(), c.y(), c.z())].push_back(position(m, v));
        }
    std::size_t found = 0;
    std::set<std::pair<PositionKey, PositionKey>> edgesDone;
    for (std::size_t f = 0; f < m.faceCount(); ++f)
        for (int k = 0; k < 3; ++k) {
            PositionKey ka = keyOf(m, m.faces[3 * f + k]), kb = keyOf(m, m.faces[3 * f + (k + 1) % 3]);
            if (kb < ka) std::swap(ka, kb);
            if (!edgesDone.insert({ka, kb}).second) continue;
            const Vector3d a(ka[0], ka[1], ka[2]), b(kb[0], kb[1], kb[2]);
            const Eigen::Vector3i c0 = cellOf(a.cwiseMin(b) - Vector3d::Constant(1e-7));
            const Eigen::Vector3i c1 = cellOf(a.cwiseMax(b) + Vector3d::Constant(1e-7));
            for (int x = c0.x(); x <= c1.x(); ++x)
                for (int y = c0.y(); y <= c1.y(); ++y)
                    for (int z = c0.z(); z <= c1.z(); ++z) {
                        const auto it = cells.find(cellKey(x, y, z));
                        if (it == cells.end()) continue;
                        for (const Vector3d& p : it->second) found += onSegment(p, a, b, true);
                    }
        }
    return found;
}

// The checks every refinement must pass, whatever the field, budget and threshold.
void expectValidRefinement(const PrtMesh& in, const SubdivisionResult& r, bool inputConformingAndOriented = true) {
    const PrtMesh& out = r.mesh;
    const std::size_t F = out.faceCount();
    ASSERT_EQ(r.originFace.size(), F);
    ASSERT_EQ(r.faceError.size(), F);
    ASSERT_EQ(out.width, in.width);
    ASSERT_EQ(out.normals.size(), out.positions.size());
    ASSERT_EQ(out.transfer.size(), out.vertexCount() * std::size_t(out.width));
    EXPECT_EQ(r.newVertices, out.vertexCount() - in.vertexCount());
    for (std::uint32_t i : out.faces) ASSERT_LT(i, out.vertexCount());
    // Input vertices are kept as they are, in front.
    for (std::size_t i = 0; i < in.positions.size(); ++i) ASSERT_EQ(out.positions[i], in.positions[i]);
    for (std::size_t i = 0; i < in.normals.size(); ++i) ASSERT_EQ(out.normals[i], in.normals[i]);
    for (std::size_t i = 0; i < in.transfer.size(); ++i) ASSERT_EQ(out.transfer[i], in.transfer[i]);
    for (std::size_t v = 0; v < out.vertexCount(); ++v)
        ASSERT_NEAR(Vector3d(out.normals[3 * v], out.normals[3 * v + 1], out.normals[3 * v + 2]).norm(), 1.0, 1e-5);

    // Inside the origin face, same orientation, areas add up per origin face.
    std::vector<double> areaPerOrigin(in.faceCount(), 0.0);
    for (std::size_t f = 0; f < F; ++f) {
        const std::uint32_t o = r.originFace[f];
        ASSERT_LT(o, in.faceCount());
        const Vector3d a = corner(in, o, 0), b = corner(in, o, 1), c = corner(in, o, 2);
        const Vector3d n = (b - a).cross(c - a);
        const double scale = std::max({(b - a).norm(), (c - a).norm(), (c - b).norm()});
        for (int k = 0; k < 3; ++k) {
            const Vector3d p = corner(out, f, k);
            ASSERT_LE(std::abs((p - a).dot(n.normalized())), 1e-6 * scale) << "face " << f << " leaves the origin plane";
            const double wa = (b - p).cross(c - p).dot(n) / n.squaredNorm();
            const double wb = (c - p).cross(a - p).dot(n) / n.squaredNorm();
            const double wc = 1.0 - wa - wb;
            ASSERT_GE(std::min({wa, wb, wc}), -1e-6) << "face " << f << " leaves its origin face " << o;
        }
        const Vector3d areaVec = areaVector(out, f);
        ASSERT_GT(areaVec.dot(n), 0.0) << "face " << f << " is flipped or degenerate";
        areaPerOrigin[o] += areaVec.norm();
    }
    for (std::size_t o = 0; o < in.faceCount(); ++o)
        ASSERT_NEAR(areaPerOrigin[o], areaVector(in, o).norm(), 1e-5 * areaVector(in, o).norm()) << "input face " << o;

    if (inputConformingAndOriented) EXPECT_EQ(conformityProblem(in, out), "");
    EXPECT_EQ(verticesInsideEdges(out), 0u) << "T-junctions in the output";
}

// Every vertex's transfer is exactly what the field gives at its position and normal.
void expectTransferIsTheField(const PrtMesh& m, const Field& field) {
    std::vector<float> expected(m.width);
    for (std::size_t v = 0; v < m.vertexCount(); ++v) {
        field(&m.positions[3 * v], &m.normals[3 * v], expected.data());
        for (int c = 0; c < m.width; ++c) ASSERT_EQ(m.transfer[v * m.width + c], expected[c]) << "vertex " << v;
    }
}

// Depth of refinement of an output face relative to its origin (areas shrink by 4 per level).
double depthOf(const PrtMesh& in, const SubdivisionResult& r, std::size_t f) {
    return std::log(areaVector(in, r.originFace[f]).norm() / areaVector(r.mesh, f).norm()) / std::log(4.0);
}

TEST(AdaptiveSubdivision, OracleIsAskedExactlyOncePerNewVertexAndNothingIsInterpolated) {
    const Field field = stepField(0.3, 0.05);
    const PrtMesh in = gridMesh(9, 2, field);
    RecordingOracle oracle{field, 2};
    const SubdivisionResult r = rad::subdivideAdaptively(in, oracle.oracle(), differenceOptions(2000));
    ASSERT_GT(r.newVertices, 0u);
    expectValidRefinement(in, r);
    expectTransferIsTheField(r.mesh, field);

    // The multiset of queried (position, normal) is the multiset of new vertices.
    std::vector<std::array<float, 6>> created;
    for (std::size_t v = in.vertexCount(); v < r.mesh.vertexCount(); ++v) {
        const float* p = &r.mesh.positions[3 * v];
        const float* n = &r.mesh.normals[3 * v];
        created.push_back({p[0], p[1], p[2], n[0], n[1], n[2]});
    }
    std::vector<std::array<float, 6>> asked = oracle.asked;
    std::sort(created.begin(), created.end());
    std::sort(asked.begin(), asked.end());
    EXPECT_EQ(asked, created);
    // No position (all normals are +z here) is created twice.
    EXPECT_EQ(std::adjacent_find(created.begin(), created.end()), created.end());
    // One call per operation at most (an operation is a split with its forced splits).
    EXPECT_GE(oracle.calls, 1u);
    EXPECT_LE(oracle.calls, r.regularSplits - r.forcedSplits);
}

TEST(AdaptiveSubdivision, ForcedSplitsKeepTheOutputConforming) {
    // A sharp bump at a point drives deep refinement next to coarse triangles.
    const Field bump = [](const float* p, const float*, float* out) {
        const double d2 = (p[0] - 0.13) * (p[0] - 0.13) + (p[1] + 0.21) * (p[1] + 0.21);
        out[0] = static_cast<float>(std::exp(-d2 / 1e-4) + 0.01 * p[0]);
    };
    const PrtMesh in = gridMesh(6, 1, bump);
    RecordingOracle oracle{bump, 1};
    const SubdivisionResult r = rad::subdivideAdaptively(in, oracle.oracle(), differenceOptions(3000));
    expectValidRefinement(in, r);
    expectTransferIsTheField(r.mesh, bump);
    EXPECT_GT(r.forcedSplits, 0u);
    EXPECT_GT(r.tVertexFixes, 0u);
    // A forced split is batched with the split that needed it: fewer calls than splits.
    EXPECT_LE(oracle.calls, r.regularSplits - r.forcedSplits);
    double deepest = 0.0;
    for (std::size_t f = 0; f < r.mesh.faceCount(); ++f) deepest = std::max(deepest, depthOf(in, r, f));
    EXPECT_GE(deepest, 5.0);
}

TEST(AdaptiveSubdivision, BudgetIsNeverExceededAndTheLoopIsGreedy) {
    // Faces(B) <= B, and raising the budget by one either changes nothing or lets the next operation
    // in, which then ends exactly at the new budget: the loop stops at the first operation that does
    // not fit and counts faces after T-vertex removal exactly.
    const Field field = stepField(-0.1, 0.1);
    const PrtMesh in = gridMesh(5, 2, field);  // 32 faces
    std::size_t previous = 0;
    for (std::size_t budget = 32; budget <= 140; ++budget) {
        RecordingOracle oracle{field, 2};
        const SubdivisionResult r = rad::subdivideAdaptively(in, oracle.oracle(), differenceOptions(budget));
        const std::size_t faces = r.mesh.faceCount();
        ASSERT_LE(faces, budget);
        if (budget > 32) ASSERT_TRUE(faces == previous || faces == budget) << "budget " << budget;
        ASSERT_EQ(r.stop, rad::SubdivisionStop::BudgetReached);
        ASSERT_GT(r.largestRemainingError, 0.0);
        previous = faces;
    }
}

TEST(AdaptiveSubdivision, BudgetIsReachedWithinOneOperation) {
    const Field field = stepField(0.3, 0.05);
    const PrtMesh in = gridMesh(9, 2, field);
    for (const std::size_t budget : {500u, 1001u, 4321u}) {
        RecordingOracle oracle{field, 2};
        const SubdivisionResult r = rad::subdivideAdaptively(in, oracle.oracle(), differenceOptions(budget));
        expectValidRefinement(in, r);
        ASSERT_LE(r.mesh.faceCount(), budget);
        // One split changes the face count by at most 6 (4 children and 2 new hanging midpoints for
        // its neighbours, minus itself); an operation is a split and the coarser splits it forces,
        // at most one per level of depth along a chain of neighbours.
        double deepest = 0.0;
        for (std::size_t f = 0; f < r.mesh.faceCount(); ++f) deepest = std::max(deepest, depthOf(in, r, f));
        EXPECT_LE(budget - r.mesh.faceCount(), 6 * std::size_t(std::ceil(deepest) + 1)) << "budget " << budget;
        EXPECT_EQ(r.stop, rad::SubdivisionStop::BudgetReached);
    }
}

TEST(AdaptiveSubdivision, ThresholdStopsRefinement) {
    // A linear field and eq. 3: a sub-triangle's error never exceeds its ancestor's (its transfer
    // triangle lies inside the ancestor's), so after refinement every output face is at or below
    // the threshold, and a lower threshold gives more faces.
    const Field linear = [](const float* p, const float*, float* out) {
        out[0] = 2.0f * p[0] + 0.5f * p[1];
        out[1] = -p[1];
    };
    const PrtMesh in = gridMesh(5, 2, linear);
    std::size_t previousFaces = 0;
    for (const double threshold : {1.0, 0.5, 0.2}) {
        RecordingOracle oracle{linear, 2};
        const SubdivisionResult r = rad::subdivideAdaptively(in, oracle.oracle(), differenceOptions(100000, threshold));
        expectValidRefinement(in, r);
        EXPECT_EQ(r.stop, rad::SubdivisionStop::QueueEmpty);
        EXPECT_EQ(r.largestRemainingError, 0.0);
        for (std::size_t f = 0; f < r.mesh.faceCount(); ++f) ASSERT_LE(r.faceError[f], threshold * (1 + 1e-6));
        EXPECT_GT(r.mesh.faceCount(), previousFaces);
        previousFaces = r.mesh.faceCount();
    }
    // A threshold above every input error: nothing happens, the oracle is never called.
    RecordingOracle oracle{linear, 2};
    const SubdivisionResult r = rad::subdivideAdaptively(in, oracle.oracle(), differenceOptions(100000, 100.0));
    EXPECT_EQ(r.mesh.faces, in.faces);
    EXPECT_EQ(oracle.calls, 0u);
    EXPECT_EQ(r.regularSplits, 0u);
}

TEST(AdaptiveSubdivision, FaceErrorIsTheMeasureOnEachOutputFace) {
    const Field field = stepField(0.3, 0.05);
    const PrtMesh in = gridMesh(9, 2, field);
    RecordingOracle oracle{field, 2};
    const SubdivisionResult r = rad::subdivideAdaptively(in, oracle.oracle(), differenceOptions(1500));
    const PrtMesh& m = r.mesh;
    for (std::size_t f = 0; f < m.faceCount(); ++f) {
        double sum = 0.0;
        for (int k = 0; k < 3; ++k) {
            const std::size_t a = m.faces[3 * f + k], b = m.faces[3 * f + (k + 1) % 3];
            const Eigen::Vector2d ta(m.transfer[2 * a], m.transfer[2 * a + 1]), tb(m.transfer[2 * b], m.transfer[2 * b + 1]);
            sum += (ta - tb).norm();
        }
        ASSERT_NEAR(r.faceError[f], sum, 1e-5 * (1.0 + sum));
    }
}

TEST(AdaptiveSubdivision, ProbedMeasureAsksEachPointOnceAndItsProbesBecomeTheVertices) {
    const Field field = stepField(0.3, 0.05);
    const PrtMesh in = gridMesh(9, 2, field);
    RecordingOracle oracle{field, 2};
    rad::AdaptiveSubdivisionOptions options;
    options.measure = rad::TransferErrorMeasure::ProbedRelative;
    options.triangleBudget = 2000;
    const SubdivisionResult r = rad::subdivideAdaptively(in, oracle.oracle(), options);
    ASSERT_GT(r.newVertices, 0u);
    expectValidRefinement(in, r);
    // Every vertex holds the field at its own point: a probe reused as a vertex was cast there.
    expectTransferIsTheField(r.mesh, field);
    // No point asked twice (flat grid: one normal), every new vertex asked once, and the rest of the
    // asked points are the probes of edges that were never split.
    std::vector<std::array<float, 6>> asked = oracle.asked;
    std::sort(asked.begin(), asked.end());
    EXPECT_EQ(std::adjacent_find(asked.begin(), asked.end()), asked.end());
    for (std::size_t v = in.vertexCount(); v < r.mesh.vertexCount(); ++v) {
        const float* p = &r.mesh.positions[3 * v];
        const float* n = &r.mesh.normals[3 * v];
        const std::array<float, 6> key{p[0], p[1], p[2], n[0], n[1], n[2]};
        EXPECT_TRUE(std::binary_search(asked.begin(), asked.end(), key)) << "vertex " << v << " never asked";
    }
    EXPECT_GT(r.probes, r.newVertices);  // the unsplit edges' midpoints were probed too
    // Without reuse every new vertex would be asked again after its probe: strictly fewer points.
    EXPECT_LT(asked.size(), r.probes + r.newVertices);
    EXPECT_GE(asked.size(), r.probes);
}

TEST(AdaptiveSubdivision, ProbedMeasureSplitsNothingOnALinearField) {
    // Linear interpolation is exact: every probe matches, no triangle enters the queue. Each edge of
    // the 9 x 9 grid is probed once: 2 * 9 * 8 sides of cells and 8 * 8 diagonals.
    const Field linear = [](const float* p, const float*, float* out) {
        out[0] = 0.5f + 0.25f * p[0];
        out[1] = 1.0f - 0.125f * p[1];
    };
    const PrtMesh in = gridMesh(9, 2, linear);
    RecordingOracle oracle{linear, 2};
    rad::AdaptiveSubdivisionOptions options;
    options.measure = rad::TransferErrorMeasure::ProbedRelative;
    options.triangleBudget = 2000;
    options.threshold = 1e-6;
    const SubdivisionResult r = rad::subdivideAdaptively(in, oracle.oracle(), options);
    EXPECT_EQ(r.mesh.faceCount(), in.faceCount());
    EXPECT_EQ(r.stop, rad::SubdivisionStop::QueueEmpty);
    EXPECT_EQ(r.probes, 2u * 9u * 8u + 8u * 8u);
    EXPECT_EQ(oracle.asked.size(), r.probes);
}

TEST(AdaptiveSubdivision, ProbedMeasureSeesVariationThatTheCornersHide) {
    // A field that is zero at every grid vertex and +-1 halfway between them (x = (k + 1/2) h): the
    // paper's estimates compare corners and see nothing; the probes see the whole error.
    const int n = 9;
    const double h = 2.0 / (n - 1);
    const Field hidden = [h](const float* p, const float*, float* out) {
        out[0] = static_cast<float>(std::sin(3.14159265358979323846 * (double(p[0]) + 1.0) / h));
    };
    const PrtMesh in = gridMesh(n, 1, hidden);
    for (const rad::TransferErrorMeasure measure :
         {rad::TransferErrorMeasure::Difference, rad::TransferErrorMeasure::NormalDivergence,
          rad::TransferErrorMeasure::ProbedRelative, rad::TransferErrorMeasure::ProbedAbsolute}) {
        RecordingOracle oracle{hidden, 1};
        rad::AdaptiveSubdivisionOptions options;
        options.measure = measure;
        options.triangleBudget = 1000;
        options.threshold = 1e-3;
        const SubdivisionResult r = rad::subdivideAdaptively(in, oracle.oracle(), options);
        if (rad::isProbed(measure)) {
            EXPECT_GT(r.regularSplits, 8u);
        } else {
            EXPECT_EQ(r.regularSplits, 0u);
            EXPECT_EQ(r.mesh.faceCount(), in.faceCount());
        }
    }
}

TEST(AdaptiveSubdivision, RefinementConcentratesAlongASteepStep) {
    const Field field = stepField(0.3, 0.02);
    const PrtMesh in = gridMesh(11, 2, field);  // 200 faces
    RecordingOracle oracle{field, 2};
    rad::AdaptiveSubdivisionOptions options;  // the default measure (probed, relative)
    options.triangleBudget = 6000;
    const SubdivisionResult r = rad::subdivideAdaptively(in, oracle.oracle(), options);
    expectValidRefinement(in, r);
    double nearArea = 0.0, farArea = 0.0;
    std::size_t nearCount = 0, farCount = 0;
    for (std::size_t f = 0; f < r.mesh.faceCount(); ++f) {
        const double x = (corner(r.mesh, f, 0).x() + corner(r.mesh, f, 1).x() + corner(r.mesh, f, 2).x()) / 3.0;
        const double area = areaVector(r.mesh, f).norm();
        if (std::abs(x - 0.3) < 0.1) {
            nearArea += area;
            ++nearCount;
        } else if (std::abs(x - 0.3) > 0.5) {
            farArea += area;
            ++farCount;
        }
    }
    ASSERT_GT(nearCount, 0u);
    ASSERT_GT(farCount, 0u);
    EXPECT_LT(nearArea / nearCount, (farArea / farCount) / 16.0);
    EXPECT_GT(nearCount, farCount);
}

class SeamSplit : public ::testing::TestWithParam<rad::TransferErrorMeasure> {};
INSTANTIATE_TEST_SUITE_P(AdaptiveSubdivision, SeamSplit,
                         ::testing::Values(rad::TransferErrorMeasure::NormalDivergence,
                                           rad::TransferErrorMeasure::ProbedRelative));

TEST_P(SeamSplit, BothSidesWithOneMidpointPerSide) {
    // Transfer depends on the normal, so the two sides of the crease differ; the step crosses the
    // crease (along y) and a second one runs just beside it (along x), so the refinement reaches the
    // crease from one side and must be mirrored on the other.
    const Field field = [](const float* p, const float* n, float* out) {
        out[0] = static_cast<float>(std::tanh((p[1] - 0.2) / 0.03));
        out[1] = static_cast<float>(std::tanh((p[0] + 0.04) / 0.01) + n[0]);
    };
    const PrtMesh in = roofMesh(5, 2, field);
    RecordingOracle oracle{field, 2};
    rad::AdaptiveSubdivisionOptions options;
    options.measure = GetParam();  // probed: each side's probe is cast with that side's normal
    options.triangleBudget = 4000;
    const SubdivisionResult r = rad::subdivideAdaptively(in, oracle.oracle(), options);
    expectValidRefinement(in, r);
    expectTransferIsTheField(r.mesh, field);
    if (!rad::isProbed(GetParam())) EXPECT_EQ(oracle.asked.size(), r.newVertices);

    // Every crease position carries exactly two vertices, one per side with that side's normal;
    // elsewhere one vertex per position.
    std::map<PositionKey, std::vector<std::size_t>> byPosition;
    for (std::size_t v = 0; v < r.mesh.vertexCount(); ++v) byPosition[keyOf(r.mesh, v)].push_back(v);
    std::size_t creasePositions = 0;
    for (const auto& [p, vertices] : byPosition) {
        if (p[0] != 0.0f) {
            ASSERT_EQ(vertices.size(), 1u);
            continue;
        }
        ++creasePositions;
        ASSERT_EQ(vertices.size(), 2u) << "crease point y = " << p[1];
        const float nx0 = r.mesh.normals[3 * vertices[0]], nx1 = r.mesh.normals[3 * vertices[1]];
        EXPECT_NEAR(std::min(nx0, nx1), -0.5 / std::sqrt(1.25), 1e-6);
        EXPECT_NEAR(std::max(nx0, nx1), 0.5 / std::sqrt(1.25), 1e-6);
    }
    EXPECT_GT(creasePositions, 5u + 8u);  // the crease was refined
    // Faces of each side use only that side's crease vertices (the normals tell the sides apart).
    for (std::size_t f = 0; f < r.mesh.faceCount(); ++f) {
        const bool left = r.originFace[f] < in.faceCount() / 2;
        for (int k = 0; k < 3; ++k) {
            const std::size_t v = r.mesh.faces[3 * f + k];
            ASSERT_EQ(r.mesh.normals[3 * v] > 0.0f, left) << "face " << f;
        }
    }
}

// Three triangles: T in the middle, neighbours N1 and N2 across two of its edges. The transfer is
// exp(2 (max(0, x) + max(0, y))), which varies only where N1 (y > 0) and N2 (x > 0) stick out, and
// eq. 2 (contrast) with threshold 1.2: N1 and N2 are above it (2 tanh 1), their children below
// (2 tanh 0.5 at most), T is at 0. So exactly N1 and N2 are split and T keeps two hanging
// midpoints; Fig. 3b cuts the remaining quad along its shorter diagonal.
class TwoHangingMidpoints : public ::testing::TestWithParam<bool> {};

TEST_P(TwoHangingMidpoints, QuadIsCutAlongItsShorterDiagonal) {
    const bool longAlongX = GetParam();
    const float ax = longAlongX ? -2.0f : -1.0f, by = longAlongX ? -1.0f : -2.0f;
    rad::TriangleMesh tm;
    // 0 = origin, 1 = (ax, 0), 2 = (0, by), 3 = N1's apex, 4 = N2's apex.
    tm.positions = {0, 0, 0, ax, 0, 0, 0, by, 0, ax / 2, 1, 0, 1, by / 2, 0};
    tm.normals.assign(15, 0.0f);
    for (int v = 0; v < 5; ++v) tm.normals[3 * v + 2] = 1.0f;
    tm.faces = {0, 1, 2, 1, 0, 3, 0, 2, 4};  // T, N1, N2: counter-clockwise from +z
    const Field field = [](const float* p, const float*, float* out) {
        out[0] = static_cast<float>(std::exp(2.0 * (std::max(0.0f, p[0]) + std::max(0.0f, p[1]))));
    };
    const PrtMesh in = makePrtMesh(tm, 1, field);
    RecordingOracle oracle{field, 1};
    rad::AdaptiveSubdivisionOptions options;
    options.measure = rad::TransferErrorMeasure::Contrast;
    options.threshold = 1.2;
    options.triangleBudget = 100;
    const SubdivisionResult r = rad::subdivideAdaptively(in, oracle.oracle(), options);
    expectValidRefinement(in, r);
    EXPECT_EQ(r.regularSplits, 2u);
    EXPECT_EQ(r.forcedSplits, 0u);
    EXPECT_EQ(r.tVertexFixes, 1u);
    EXPECT_EQ(r.mesh.faceCount(), 4u + 4u + 3u);
    EXPECT_EQ(r.stop, rad::SubdivisionStop::QueueEmpty);

    // The quad (corner 1, midpoint of 0-1, midpoint of 0-2, corner 2) minus the corner at 0.
    const Vector3d c1(ax, 0, 0), c2(0, by, 0), m01(ax / 2, 0, 0), m02(0, by / 2, 0);
    const Vector3d shortA = (c1 - m02).norm() < (c2 - m01).norm() ? c1 : c2;
    const Vector3d shortB = (c1 - m02).norm() < (c2 - m01).norm() ? m02 : m01;
    const Vector3d longA = shortA == c1 ? c2 : c1, longB = shortB == m02 ? m01 : m02;
    const auto hasFaceWith = [&](const Vector3d& p, const Vector3d& q) {
        for (std::size_t f = 0; f < r.mesh.faceCount(); ++f) {
            if (r.originFace[f] != 0) continue;
            bool hasP = false, hasQ = false;
            for (int k = 0; k < 3; ++k) {
                hasP |= corner(r.mesh, f, k) == p;
                hasQ |= corner(r.mesh, f, k) == q;
            }
            if (hasP && hasQ) return true;
        }
        return false;
    };
    EXPECT_TRUE(hasFaceWith(shortA, shortB));
    EXPECT_FALSE(hasFaceWith(longA, longB));
}

INSTANTIATE_TEST_SUITE_P(AdaptiveSubdivision, TwoHangingMidpoints, ::testing::Bool());

TEST(AdaptiveSubdivision, OneHangingMidpointGivesTwoTrianglesAndTheBudgetCountsThem) {
    // Two triangles sharing an edge; only the first varies. Splitting it costs 4 children + 1 for
    // the neighbour's hanging midpoint - 1: budget 6 allows it, budget 5 does not.
    rad::TriangleMesh tm;
    radtest::addQuad(tm, 0, 1, 0, 1, 0);  // faces (0, 1, 2), (0, 2, 3)
    const Field field = [](const float* p, const float*, float* out) { out[0] = p[1] < 0.5f ? p[0] : 0.0f; };
    const PrtMesh in = makePrtMesh(tm, 1, field);
    for (const std::size_t budget : {5u, 6u}) {
        RecordingOracle oracle{field, 1};
        rad::AdaptiveSubdivisionOptions options = differenceOptions(budget, 0.0);
        const SubdivisionResult r = rad::subdivideAdaptively(in, oracle.oracle(), options);
        expectValidRefinement(in, r);
        if (budget == 5) {
            EXPECT_EQ(r.mesh.faceCount(), 2u);
            EXPECT_EQ(oracle.calls, 0u);
            EXPECT_EQ(r.stop, rad::SubdivisionStop::BudgetReached);
        } else {
            EXPECT_EQ(r.mesh.faceCount(), 6u);
            EXPECT_EQ(r.tVertexFixes, 1u);
            EXPECT_EQ(oracle.asked.size(), 3u);  // the three midpoints of the first triangle
            EXPECT_EQ(std::count(r.originFace.begin(), r.originFace.end(), 1u), 2);
        }
    }
}

TEST(AdaptiveSubdivision, EachOutputFaceKeepsItsInputFaceOrientation) {
    // Every other face flipped: the input is inconsistently oriented, the output follows each face.
    const Field field = stepField(0.1, 0.05);
    PrtMesh in = gridMesh(7, 2, field);
    for (std::size_t f = 0; f < in.faceCount(); f += 2) std::swap(in.faces[3 * f + 1], in.faces[3 * f + 2]);
    RecordingOracle oracle{field, 2};
    const SubdivisionResult r = rad::subdivideAdaptively(in, oracle.oracle(), differenceOptions(1500));
    expectValidRefinement(in, r, /*inputConformingAndOriented=*/false);  // orientation checked per face
}

TEST(AdaptiveSubdivision, IsDeterministic) {
    const Field field = stepField(0.3, 0.05);
    const PrtMesh in = gridMesh(9, 2, field);
    RecordingOracle a{field, 2}, b{field, 2};
    const SubdivisionResult ra = rad::subdivideAdaptively(in, a.oracle(), differenceOptions(3000));
    const SubdivisionResult rb = rad::subdivideAdaptively(in, b.oracle(), differenceOptions(3000));
    EXPECT_EQ(ra.mesh.faces, rb.mesh.faces);
    EXPECT_EQ(ra.mesh.positions, rb.mesh.positions);
    EXPECT_EQ(ra.originFace, rb.originFace);
}

TEST(AdaptiveSubdivision, ProgressIsMonotoneAndCancellationThrows) {
    const Field field = stepField(0.3, 0.05);
    const PrtMesh in = gridMesh(9, 2, field);
    std::vector<double> reported;
    rad::AdaptiveSubdivisionOptions options = differenceOptions(3000);
    options.progress = [&](double fraction, const char*) {
        reported.push_back(fraction);
        return true;
    };
    RecordingOracle oracle{field, 2};
    const SubdivisionResult r = rad::subdivideAdaptively(in, oracle.oracle(), options);
    ASSERT_GE(reported.size(), 10u);
    EXPECT_TRUE(std::is_sorted(reported.begin(), reported.end()));
    EXPECT_GE(reported.front(), 0.0);
    EXPECT_LE(reported.back(), 1.0);
    EXPECT_NEAR(reported.back(), double(r.mesh.faceCount()) / 3000.0, 0.011);

    std::size_t calls = 0;
    options.progress = [&](double, const char*) { return ++calls < 5; };
    RecordingOracle cancelled{field, 2};
    EXPECT_THROW(rad::subdivideAdaptively(in, cancelled.oracle(), options), rad::OperationCancelled);
    EXPECT_EQ(calls, 5u);
}

TEST(AdaptiveSubdivision, RejectsInvalidArguments) {
    const Field field = stepField(0.3, 0.05);
    const PrtMesh good = gridMesh(3, 2, field);  // 8 faces
    RecordingOracle oracle{field, 2};
    const auto run = [&](const PrtMesh& m, rad::AdaptiveSubdivisionOptions o) {
        return rad::subdivideAdaptively(m, oracle.oracle(), o);
    };
    EXPECT_NO_THROW(run(good, differenceOptions(8)));
    EXPECT_THROW(run(good, differenceOptions(7)), std::invalid_argument);  // budget below the face count
    EXPECT_THROW(run(good, differenceOptions(100, -1.0)), std::invalid_argument);
    EXPECT_THROW(run(good, differenceOptions(100, std::nan(""))), std::invalid_argument);
    rad::AdaptiveSubdivisionOptions badAlpha;
    badAlpha.measure = rad::TransferErrorMeasure::NormalDivergence;  // the measure alpha belongs to
    badAlpha.triangleBudget = 100;
    badAlpha.alpha = -2.0;
    EXPECT_THROW(run(good, badAlpha), std::invalid_argument);
    badAlpha.alpha = INFINITY;
    EXPECT_THROW(run(good, badAlpha), std::invalid_argument);
    EXPECT_THROW(rad::subdivideAdaptively(good, rad::TransferOracle(), differenceOptions(100)), std::invalid_argument);

    PrtMesh m = good;
    m.faces[4] = 99;
    EXPECT_THROW(run(m, differenceOptions(100)), std::invalid_argument);
    m = good;
    m.width = 0;
    EXPECT_THROW(run(m, differenceOptions(100)), std::invalid_argument);
    m = good;
    m.transfer.pop_back();
    EXPECT_THROW(run(m, differenceOptions(100)), std::invalid_argument);
    m = good;
    m.positions[0] = NAN;
    EXPECT_THROW(run(m, differenceOptions(100)), std::invalid_argument);
    m = good;
    m.normals.clear();
    EXPECT_THROW(run(m, differenceOptions(100)), std::invalid_argument);
    m = good;
    m.faces.clear();
    EXPECT_THROW(run(m, differenceOptions(100)), std::invalid_argument);
    // Structure-breaking topology: a third face on an edge, a face with two corners at one position.
    m = good;
    m.positions.insert(m.positions.end(), {0.0f, 0.0f, 1.0f});
    m.normals.insert(m.normals.end(), {0.0f, 0.0f, 1.0f});
    m.transfer.insert(m.transfer.end(), {0.0f, 0.0f});
    // (faces[0], faces[2]) is the diagonal of the first grid square, shared by its two triangles.
    m.faces.insert(m.faces.end(), {m.faces[0], m.faces[2], std::uint32_t(m.vertexCount() - 1)});
    EXPECT_THROW(run(m, differenceOptions(100)), std::invalid_argument);
    m = good;
    m.positions.insert(m.positions.end(), good.positions.begin(), good.positions.begin() + 3);  // copy of vertex 0
    m.normals.insert(m.normals.end(), {0.0f, 0.0f, 1.0f});
    m.transfer.insert(m.transfer.end(), {0.0f, 0.0f});
    m.faces.insert(m.faces.end(), {0, 1, std::uint32_t(m.vertexCount() - 1)});
    EXPECT_THROW(run(m, differenceOptions(100)), std::invalid_argument);
}

TEST(AdaptiveSubdivision, InputCheckExplainsWhatToDo) {
    const Field field = stepField(0.3, 0.05);
    const PrtMesh good = gridMesh(3, 2, field);
    EXPECT_EQ(rad::checkPrtSubdivisionInput(good), "");
    const auto message = [](const PrtMesh& m) { return rad::checkPrtSubdivisionInput(m); };
    const auto contains = [](const std::string& s, const char* what) { return s.find(what) != std::string::npos; };

    EXPECT_TRUE(contains(message(PrtMesh{}), "no faces"));
    PrtMesh m = good;
    m.normals.clear();
    EXPECT_TRUE(contains(message(m), "Re-Compute Vertex Normals"));
    EXPECT_TRUE(contains(message(m), "Compute normals for point sets"));
    m = good;
    for (int c = 0; c < 3; ++c) m.normals[3 * 4 + c] = 0.0f;
    EXPECT_TRUE(contains(message(m), "1 vertex with a zero"));
    EXPECT_TRUE(contains(message(m), "Re-Compute Vertex Normals"));
    m = good;
    m.transfer.resize(m.transfer.size() - 2);
    EXPECT_TRUE(contains(message(m), "transfer"));
    m = good;
    m.transfer[3] = NAN;
    EXPECT_TRUE(contains(message(m), "not finite"));
    m = good;
    m.positions[4] = INFINITY;
    EXPECT_TRUE(contains(message(m), "non-finite position"));
    m = good;
    m.faces[5] = 99;
    EXPECT_TRUE(contains(message(m), "refers to vertex 99"));

    // Zero area: a collinear face; repeated position: a face using a vertex and its copy.
    m = good;
    m.positions.insert(m.positions.end(), {5.0f, 0.0f, 0.0f, 6.0f, 0.0f, 0.0f, 7.0f, 0.0f, 0.0f});
    m.normals.insert(m.normals.end(), {0, 0, 1, 0, 0, 1, 0, 0, 1});
    m.transfer.insert(m.transfer.end(), 6, 0.0f);
    const auto n = std::uint32_t(good.vertexCount());
    m.faces.insert(m.faces.end(), {n, n + 1, n + 2});
    EXPECT_TRUE(contains(message(m), "1 face of zero area"));
    EXPECT_TRUE(contains(message(m), "Remove Zero Area Faces"));
    m = good;
    m.positions.insert(m.positions.end(), good.positions.begin(), good.positions.begin() + 3);
    m.normals.insert(m.normals.end(), {0, 0, 1});
    m.transfer.insert(m.transfer.end(), 2, 0.0f);
    m.faces.insert(m.faces.end(), {0, 1, n});
    EXPECT_TRUE(contains(message(m), "two corners at the same position"));
    EXPECT_TRUE(contains(message(m), "Remove Zero Area Faces"));

    // Non-manifold by position: a third face on the first square's diagonal (vertices 0 and 4,
    // shared by two triangles) through copies of its ends.
    m = good;
    ASSERT_EQ(good.faces[2], 4u);
    m.positions.insert(m.positions.end(), good.positions.begin(), good.positions.begin() + 3);
    m.positions.insert(m.positions.end(), good.positions.begin() + 12, good.positions.begin() + 15);
    m.positions.insert(m.positions.end(), {0.0f, 0.0f, 1.0f});
    m.normals.insert(m.normals.end(), {0, 0, 1, 0, 0, 1, 0, 0, 1});
    m.transfer.insert(m.transfer.end(), 6, 0.0f);
    m.faces.insert(m.faces.end(), {n, n + 1, n + 2});
    EXPECT_TRUE(contains(message(m), "1 non-manifold edge"));
    EXPECT_TRUE(contains(message(m), "Repair non Manifold Edges"));
    // The seam mesh (duplicated crease vertices) is fine.
    EXPECT_EQ(message(roofMesh(4, 2, [](const float*, const float* nn, float* out) { out[0] = nn[0]; out[1] = 0; })), "");
}

TEST(UniformSubdivision, LevelsFitTheBudgetAndCountsFollow) {
    const Field field = stepField(0.3, 0.05);
    const int n = 4;                            // 16 vertices, 18 faces
    const PrtMesh in = gridMesh(n, 2, field);
    for (const std::size_t budget : {18u, 71u, 72u, 1151u, 1152u, 2000u}) {
        int levels = 0;
        while (18u << (2 * (levels + 1)) <= budget) ++levels;
        RecordingOracle oracle{field, 2};
        const SubdivisionResult r = rad::subdivideUniformly(in, oracle.oracle(), budget,
                                                            rad::TransferErrorMeasure::Difference, 0.0);
        // A grid of (n - 1) 2^L + 1 vertices per side.
        const std::size_t side = std::size_t(n - 1) * (std::size_t(1) << levels) + 1;
        EXPECT_EQ(r.mesh.faceCount(), 18u << (2 * levels)) << "budget " << budget;
        EXPECT_EQ(r.mesh.vertexCount(), side * side);
        EXPECT_EQ(oracle.calls, levels > 0 ? 1u : 0u);
        EXPECT_EQ(oracle.asked.size(), side * side - 16u);
        EXPECT_EQ(r.tVertexFixes, 0u);
        expectValidRefinement(in, r);
        expectTransferIsTheField(r.mesh, field);
        // Every face of level L has 1/4^L of its origin's area.
        for (std::size_t f = 0; f < r.mesh.faceCount(); ++f) ASSERT_NEAR(depthOf(in, r, f), levels, 1e-4);
    }
    RecordingOracle oracle{field, 2};
    EXPECT_THROW(rad::subdivideUniformly(in, oracle.oracle(), 17), std::invalid_argument);
}

TEST(UniformSubdivision, SeamSidesGetTheirOwnMidpoints) {
    const Field field = [](const float* p, const float* nn, float* out) {
        out[0] = p[1];
        out[1] = nn[0];
    };
    const int n = 4;
    const PrtMesh in = roofMesh(n, 2, field);  // 2 x 16 vertices, 36 faces
    RecordingOracle oracle{field, 2};
    const SubdivisionResult r = rad::subdivideUniformly(in, oracle.oracle(), 36 * 16);
    const std::size_t side = std::size_t(n - 1) * 4 + 1;
    EXPECT_EQ(r.mesh.faceCount(), 36u * 16u);
    EXPECT_EQ(r.mesh.vertexCount(), 2 * side * side);  // each side's crease column is its own
    EXPECT_EQ(oracle.asked.size(), r.newVertices);
    expectValidRefinement(in, r);
    expectTransferIsTheField(r.mesh, field);
}

}  // namespace
