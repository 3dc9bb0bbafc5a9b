// Adaptive subdivision of a PRT mesh under a triangle budget, Křivánek et al. 2004
// "Adaptive Mesh Subdivision for Precomputed Radiance Transfer") sec. 3.2, Fig. 2 (the priority-queue
// loop), Fig. 3a (regular 1-to-4 split), Fig. 3b/c (T-vertex removal), with the error estimates of
// sec. 3.3 (eq. 2-4, transfer_error_estimate.h). Design: docs/prt-subdivision.md.
//
// Data layout (flat arrays, no per-triangle allocation):
//   - every vertex carries a position id (pid): input vertices at the same exact position share one,
//     each split edge gets a fresh one for its midpoint; edges are identified by pid pairs, so the two
//     sides of an attribute seam (duplicated vertices) are the same edge;
//   - a refinement tree of triangles (four consecutive children per split triangle) and of edges
//     (two consecutive halves per split edge, three new interior edges per split triangle); an edge
//     knows the (at most two) triangles of ITS level using it, which gives the neighbour across it
//     without any hash table: the neighbour of a level-l triangle across an edge either uses the
//     same edge record (same level), or is the unsplit triangle on the other side of the parent edge
//     (one level coarser; 1-irregularity excludes anything else).
#include "prt/adaptive_subdivision.h"

#include "geometry/coordinate_range.h"
#include "geometry/triangle_mesh.h"

#include <algorithm>
#include <unordered_map>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <queue>
#include <utility>

namespace rad {

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
// Vertex, triangle and edge indices are 32-bit; the tree holds about 4/3 of the leaves and the
// leaves are at most the budget, so this bound keeps every index representable.
constexpr std::size_t kLargestBudget = std::size_t(1) << 30;

struct Edge {
    std::uint32_t side[2] = {kNone, kNone};       // 3 * triangle + local edge, for the triangles of this level
    std::uint32_t midVertex[2] = {kNone, kNone};  // per side: the midpoint vertex that side uses once split
    std::uint32_t firstChild = kNone;             // halves firstChild (at the lowPid end) and firstChild + 1
    std::uint32_t parent = kNone;                 // the edge this one is half of (kNone: input or interior)
    std::uint32_t lowPid = 0;                     // the smaller position id of its ends
    bool boundary = false;                        // on the input boundary: never gets a second side
};

struct Triangle {
    std::uint32_t v[3];     // vertex indices, in the input face's orientation
    std::uint32_t edge[3];  // 2 * edge record + side; edge k joins v[k] and v[(k + 1) % 3]
    std::uint32_t firstChild = kNone;
    std::uint32_t origin = 0;  // the input face containing it
};

std::string validationProblem(const PrtMesh& m) {
    if (m.positions.size() % 3 != 0) return "the positions are not whole (x, y, z) triples";
    if (m.normals.size() != m.positions.size()) return "the mesh needs one normal per vertex";
    if (m.faces.size() % 3 != 0) return "the faces are not whole index triples";
    if (m.faces.empty()) return "the mesh has no faces";
    if (m.width < 1) return "the transfer width must be at least 1";
    if (m.transfer.size() != m.vertexCount() * std::size_t(m.width))
        return "the transfer array does not hold width floats per vertex";
    for (const std::uint32_t i : m.faces)
        if (i >= m.vertexCount()) return "a face refers to a vertex that does not exist";
    const auto finite = [](const std::vector<float>& values) {
        return std::all_of(values.begin(), values.end(), [](float x) { return std::isfinite(x); });
    };
    if (!finite(m.positions) || !finite(m.normals) || !finite(m.transfer))
        return "the mesh has non-finite (NaN or infinite) values";
    return {};
}

// Position ids: vertices at exactly the same position (-0 and +0 equal) share one id, numbered in
// lexicographic position order.
std::vector<std::uint32_t> weldPositions(const std::vector<float>& positions, std::uint32_t& count) {
    const std::size_t V = positions.size() / 3;
    const auto coordinate = [&](std::uint32_t v, int c) { return positions[3 * std::size_t(v) + c] + 0.0f; };
    const auto less = [&](std::uint32_t a, std::uint32_t b) {
        for (int c = 0; c < 3; ++c)
            if (coordinate(a, c) != coordinate(b, c)) return coordinate(a, c) < coordinate(b, c);
        return false;
    };
    std::vector<std::uint32_t> order(V);
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), less);
    std::vector<std::uint32_t> pid(V);
    count = 0;
    for (std::size_t i = 0; i < V; ++i) {
        if (i > 0 && less(order[i - 1], order[i])) ++count;
        pid[order[i]] = count;
    }
    if (V > 0) ++count;
    return pid;
}

class Refiner {
public:
    Refiner(const PrtMesh& input, TransferErrorMeasure measure, double alpha)
        : measure_(measure), alpha_(alpha), width_(input.width), positions_(input.positions),
          normals_(input.normals), transfer_(input.transfer) {
        pid_ = weldPositions(positions_, pidCount_);
        const std::size_t F = input.faceCount();
        triangles_.resize(F);
        std::vector<std::pair<std::uint64_t, std::uint32_t>> halfEdges(3 * F);  // (pid pair, 3 f + k)
        for (std::size_t f = 0; f < F; ++f) {
            Triangle& t = triangles_[f];
            t.origin = static_cast<std::uint32_t>(f);
            for (int k = 0; k < 3; ++k) t.v[k] = input.faces[3 * f + k];
            for (int k = 0; k < 3; ++k) {
                const std::uint64_t a = pid_[t.v[k]], b = pid_[t.v[(k + 1) % 3]];
                if (a == b)
                    throw std::invalid_argument(
                        "Face " + std::to_string(f) + " has two corners at the same position (zero area): remove "
                        "such faces with {{Remove Duplicate Vertices}} and {{Remove Zero Area Faces}}, then compute "
                        "the transfer again.");
                halfEdges[3 * f + k] = {undirectedEdgeKey(a, b), static_cast<std::uint32_t>(3 * f + k)};
            }
        }
        std::sort(halfEdges.begin(), halfEdges.end());
        for (std::size_t i = 0; i < halfEdges.size();) {
            std::size_t j = i;
            while (j < halfEdges.size() && halfEdges[j].first == halfEdges[i].first) ++j;
            if (j - i > 2)
                throw std::invalid_argument(
                    "An edge is shared by more than two faces (non-manifold): repair it with {{Repair non Manifold "
                    "Edges}}, then compute the transfer again.");
            Edge e;
            e.lowPid = static_cast<std::uint32_t>(halfEdges[i].first >> 32);
            e.boundary = j - i == 1;
            const auto index = static_cast<std::uint32_t>(edges_.size());
            for (std::size_t s = 0; s < j - i; ++s) {
                const std::uint32_t h = halfEdges[i + s].second;
                e.side[s] = h;
                triangles_[h / 3].edge[h % 3] = 2 * index + static_cast<std::uint32_t>(s);
            }
            edges_.push_back(e);
            i = j;
        }
        known_.assign(vertexCount(), 1);
        if (isProbed(measure_)) setUpProbes(input);
    }

    std::size_t triangleCount() const { return triangles_.size(); }
    std::size_t vertexCount() const { return positions_.size() / 3; }
    bool isLeaf(std::uint32_t t) const { return triangles_[t].firstChild == kNone; }

    // Splits in dependency order that splitting leaf t needs: first the coarser neighbours it would
    // leave with a quarter-point on their edge (recursively), then t itself. `plan` may already hold
    // splits of the same operation.
    void planSplit(std::uint32_t t, std::vector<std::uint32_t>& plan) const {
        for (int k = 0; k < 3; ++k) {
            const Edge& e = edges_[triangles_[t].edge[k] >> 1];
            if (e.side[1] != kNone || e.boundary) continue;  // neighbour at the same level, or none
            // Only this side at this level: the neighbour is the unsplit triangle across the parent.
            const Edge& parent = edges_[e.parent];
            const std::uint32_t coarser = isLeaf(parent.side[0] / 3) ? parent.side[0] / 3 : parent.side[1] / 3;
            if (std::find(plan.begin(), plan.end(), coarser) == plan.end()) planSplit(coarser, plan);
        }
        plan.push_back(t);
    }

    // Change of the final (post T-vertex removal) face count if `plan` is carried out in order. A leaf
    // contributes 1 + its hanging midpoints; splitting one with h split edges and b boundary edges
    // removes 1 + h, adds 4 children without hanging midpoints (their neighbours across the halves
    // are unsplit: a split there would have needed this leaf split first) and one hanging midpoint
    // to each unsplit neighbour: 6 - 2 h - b.
    std::int64_t planCost(const std::vector<std::uint32_t>& plan) const {
        std::int64_t cost = 0;
        for (std::size_t i = 0; i < plan.size(); ++i) {
            int hanging = 0, boundary = 0;
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t code = triangles_[plan[i]].edge[k];
                const Edge& e = edges_[code >> 1];
                if (e.firstChild != kNone) {
                    ++hanging;
                } else if (e.boundary) {
                    ++boundary;
                } else {
                    const std::uint32_t other = e.side[(code & 1) ^ 1];
                    if (other != kNone && std::find(plan.begin(), plan.begin() + std::ptrdiff_t(i), other / 3) !=
                                              plan.begin() + std::ptrdiff_t(i))
                        ++hanging;  // split earlier in this operation
                }
            }
            cost += 6 - 2 * hanging - boundary;
        }
        return cost;
    }

    // Regular 1-to-4 split of leaf t (Fig. 3a). Its neighbours across all three edges must be at its
    // level (planSplit). New vertices get positions and normals; their transfer is left to the caller.
    void split(std::uint32_t t) {
        const Triangle parent = triangles_[t];  // copy: triangles_ grows below
        std::uint32_t mid[3], halfAtStart[3], halfAtEnd[3];
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t e = parent.edge[k] >> 1, side = parent.edge[k] & 1;
            if (edges_[e].firstChild == kNone) splitEdge(e);
            mid[k] = edges_[e].midVertex[side];
            const bool startIsLow = pid_[parent.v[k]] == edges_[e].lowPid;
            halfAtStart[k] = edges_[e].firstChild + (startIsLow ? 0 : 1);
            halfAtEnd[k] = edges_[e].firstChild + (startIsLow ? 1 : 0);
        }
        const auto first = static_cast<std::uint32_t>(triangles_.size());
        triangles_[t].firstChild = first;
        const std::uint32_t a = parent.v[0], b = parent.v[1], c = parent.v[2];
        // Same layout as geometry/midpoint_subdivision: corners at a, b, c, then the middle one; every
        // child keeps the parent's orientation.
        const std::uint32_t corners[4][3] = {{a, mid[0], mid[2]}, {mid[0], b, mid[1]}, {mid[2], mid[1], c}, {mid[0], mid[1], mid[2]}};
        for (const auto& v : corners) {
            Triangle child;
            std::copy(v, v + 3, child.v);
            child.origin = parent.origin;
            triangles_.push_back(child);
        }
        attach(halfAtStart[0], first + 0, 0);
        attach(halfAtEnd[2], first + 0, 2);
        attach(halfAtEnd[0], first + 1, 0);
        attach(halfAtStart[1], first + 1, 1);
        attach(halfAtEnd[1], first + 2, 1);
        attach(halfAtStart[2], first + 2, 2);
        // Interior edges, each between a corner child and the middle one.
        const std::uint32_t interior[3][4] = {
            {first + 0, 1, first + 3, 2},  // (m_ab, m_ca)
            {first + 1, 2, first + 3, 0},  // (m_bc, m_ab)
            {first + 2, 0, first + 3, 1},  // (m_ca, m_bc)
        };
        for (const auto& in : interior) {
            Edge e;
            const Triangle& corner = triangles_[in[0]];
            e.lowPid = std::min(pid_[corner.v[in[1]]], pid_[corner.v[(in[1] + 1) % 3]]);
            const auto index = static_cast<std::uint32_t>(edges_.size());
            edges_.push_back(e);
            attach(index, in[0], in[1]);
            attach(index, in[2], in[3]);
        }
    }

    // Transfer of the vertices from `firstVertex` on, in one oracle call (none when there are none);
    // vertices whose transfer a probe already gave (probed measures) are not cast again.
    void castTransfer(std::size_t firstVertex, const TransferOracle& oracle) {
        const std::size_t count = vertexCount() - firstVertex;
        const std::size_t w = std::size_t(width_);
        transfer_.resize(vertexCount() * w);
        if (count == 0) return;
        std::vector<std::uint32_t> unknown;
        for (std::size_t v = firstVertex; v < vertexCount(); ++v)
            if (!known_[v]) unknown.push_back(static_cast<std::uint32_t>(v));
        if (unknown.size() == count) {
            oracle(positions_.data() + 3 * firstVertex, normals_.data() + 3 * firstVertex, count,
                   transfer_.data() + w * firstVertex);
        } else if (!unknown.empty()) {
            std::vector<float> p(3 * unknown.size()), n(3 * unknown.size()), t(w * unknown.size());
            for (std::size_t i = 0; i < unknown.size(); ++i)
                for (int c = 0; c < 3; ++c) {
                    p[3 * i + c] = positions_[3 * std::size_t(unknown[i]) + c];
                    n[3 * i + c] = normals_[3 * std::size_t(unknown[i]) + c];
                }
            oracle(p.data(), n.data(), unknown.size(), t.data());
            for (std::size_t i = 0; i < unknown.size(); ++i)
                std::copy(t.begin() + std::ptrdiff_t(w * i), t.begin() + std::ptrdiff_t(w * (i + 1)),
                          transfer_.begin() + std::ptrdiff_t(w * unknown[i]));
        }
        std::fill(known_.begin() + std::ptrdiff_t(firstVertex), known_.end(), 1);
    }

    // Probed measures: ray-casts the transfer at the midpoint of every unsplit edge of the leaves in
    // [first, last) that has no probe yet, in one oracle call (both sides of an edge share a probe
    // when they use the same two vertices; across an attribute seam each side has its own normal).
    void probeEdges(std::size_t first, std::size_t last, const TransferOracle& oracle) {
        if (!probing_) return;
        const std::size_t w = std::size_t(width_);
        probed_.resize(2 * edges_.size(), 0);
        probe_.resize(2 * edges_.size() * w);
        std::vector<float> p, n;
        std::vector<std::pair<std::uint32_t, std::uint32_t>> slots;  // (edge side code, batch slot)
        std::unordered_map<std::uint32_t, std::uint32_t> slotOfCode;
        for (std::size_t t = first; t < last; ++t) {
            if (!isLeaf(std::uint32_t(t))) continue;
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t code = triangles_[t].edge[k];
                const Edge& e = edges_[code >> 1];
                if (e.firstChild != kNone || probed_[code]) continue;
                const std::uint32_t a = triangles_[t].v[k], b = triangles_[t].v[(k + 1) % 3];
                // The other side with the same two vertices: its probe (done, or in this batch).
                const std::uint32_t other = e.side[(code & 1) ^ 1];
                if (other != kNone && sameEnds(other, a, b)) {
                    if (probed_[code ^ 1]) {
                        std::copy_n(&probe_[w * (code ^ 1)], w, &probe_[w * code]);
                        probed_[code] = 1;
                        continue;
                    }
                    if (const auto pending = slotOfCode.find(code ^ 1); pending != slotOfCode.end()) {
                        slots.emplace_back(code, pending->second);
                        slotOfCode.emplace(code, pending->second);
                        continue;
                    }
                }
                float normal[3];
                midpointNormal(a, b, std::uint32_t(t), normal);
                for (int c = 0; c < 3; ++c) {
                    p.push_back(0.5f * (positions_[3 * std::size_t(a) + c] + positions_[3 * std::size_t(b) + c]));
                    n.push_back(normal[c]);
                }
                slots.emplace_back(code, static_cast<std::uint32_t>(p.size() / 3 - 1));
                slotOfCode.emplace(code, static_cast<std::uint32_t>(p.size() / 3 - 1));
            }
        }
        if (p.empty()) return;
        std::vector<float> values(w * (p.size() / 3));
        oracle(p.data(), n.data(), p.size() / 3, values.data());
        probeCount_ += p.size() / 3;
        for (const auto& [code, slot] : slots) {
            std::copy_n(&values[w * slot], w, &probe_[w * code]);
            probed_[code] = 1;
        }
    }

    // The leaf's priority: eq. 2-4 from its corners, or its probed contribution to the mean error.
    double leafError(std::uint32_t t) const {
        if (!probing_) return error(t);
        const std::size_t w = std::size_t(width_);
        const Triangle& tri = triangles_[t];
        double sum = 0.0;
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t code = tri.edge[k];
            const Edge& e = edges_[code >> 1];
            const float* middle = e.firstChild != kNone ? &transfer_[w * e.midVertex[code & 1]] : &probe_[w * code];
            sum += probedEdgeError(measure_, &transfer_[w * tri.v[k]], &transfer_[w * tri.v[(k + 1) % 3]], middle,
                                   width_, probeFloor_);
        }
        return std::sqrt(squaredDoubleArea(tri.v[0], tri.v[1], tri.v[2])) * inverseDoubleArea_ * sum / 3.0;
    }
    std::size_t probeCount() const { return probeCount_; }

    double error(std::uint32_t v0, std::uint32_t v1, std::uint32_t v2) const {
        const std::size_t w = std::size_t(width_);
        return triangleTransferError(measure_, alpha_, &transfer_[w * v0], &transfer_[w * v1], &transfer_[w * v2],
                                     width_, &normals_[3 * std::size_t(v0)], &normals_[3 * std::size_t(v1)],
                                     &normals_[3 * std::size_t(v2)]);
    }
    double error(std::uint32_t t) const { return error(triangles_[t].v[0], triangles_[t].v[1], triangles_[t].v[2]); }

    // Final face count if the refinement stopped now: sum over leaves of 1 + hanging midpoints.
    std::size_t countFinalFaces() const {
        std::size_t faces = 0;
        for (std::size_t t = 0; t < triangles_.size(); ++t)
            if (isLeaf(std::uint32_t(t))) faces += 1 + std::size_t(hangingMidpoints(std::uint32_t(t), nullptr));
        return faces;
    }

    // The conforming output: leaves without hanging midpoints as they are, the others split by the
    // T-vertex removal of Fig. 3b.
    void emit(SubdivisionResult& out) {
        PrtMesh& mesh = out.mesh;
        std::vector<std::uint32_t> leafOfFace;
        for (std::uint32_t t = 0; t < triangles_.size(); ++t) {
            if (!isLeaf(t)) continue;
            const Triangle& tri = triangles_[t];
            std::uint32_t mid[3];
            const int hanging = hangingMidpoints(t, mid);
            const auto face = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
                mesh.faces.insert(mesh.faces.end(), {a, b, c});
                out.originFace.push_back(tri.origin);
                leafOfFace.push_back(t);
            };
            if (hanging > 0) ++out.tVertexFixes;
            if (hanging == 0) {
                face(tri.v[0], tri.v[1], tri.v[2]);
            } else if (hanging == 1) {
                const int k = mid[0] != kNone ? 0 : mid[1] != kNone ? 1 : 2;
                const std::uint32_t a = tri.v[k], b = tri.v[(k + 1) % 3], c = tri.v[(k + 2) % 3];
                face(a, mid[k], c);
                face(mid[k], b, c);
            } else if (hanging == 2) {
                // Rotate so that (c, a) is the unsplit edge: corner triangle at b, then the quad
                // (a, m_ab, m_bc, c) cut along its shorter diagonal.
                const int unsplit = mid[0] == kNone ? 0 : mid[1] == kNone ? 1 : 2;
                const std::uint32_t c = tri.v[unsplit], a = tri.v[(unsplit + 1) % 3], b = tri.v[(unsplit + 2) % 3];
                const std::uint32_t mab = mid[(unsplit + 1) % 3], mbc = mid[(unsplit + 2) % 3];
                face(mab, b, mbc);
                if (squaredDistance(a, mbc) <= squaredDistance(mab, c)) {
                    face(a, mab, mbc);
                    face(a, mbc, c);
                } else {
                    face(a, mab, c);
                    face(mab, mbc, c);
                }
            } else {
                face(tri.v[0], mid[0], mid[2]);
                face(mid[0], tri.v[1], mid[1]);
                face(mid[2], mid[1], tri.v[2]);
                face(mid[0], mid[1], mid[2]);
            }
        }
        const std::size_t F = mesh.faceCount();
        out.faceError.resize(F);
        // Probed measures: every face shows its leaf's probed error (faces of the T-vertex removal have
        // no probes of their own).
        for (std::size_t f = 0; f < F; ++f)
            out.faceError[f] = static_cast<float>(
                probing_ ? leafError(leafOfFace[f]) : error(mesh.faces[3 * f], mesh.faces[3 * f + 1], mesh.faces[3 * f + 2]));
        mesh.width = width_;
        mesh.positions = std::move(positions_);
        mesh.normals = std::move(normals_);
        mesh.transfer = std::move(transfer_);
    }

private:
    // Hanging midpoints on leaf t's edges (its split edges), their vertices on t's side in mid.
    int hangingMidpoints(std::uint32_t t, std::uint32_t* mid) const {
        int count = 0;
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t code = triangles_[t].edge[k];
            const Edge& e = edges_[code >> 1];
            const bool split = e.firstChild != kNone;
            count += split;
            if (mid) mid[k] = split ? e.midVertex[code & 1] : kNone;
        }
        return count;
    }

    void attach(std::uint32_t edge, std::uint32_t triangle, int k) {
        Edge& e = edges_[edge];
        const std::uint32_t side = e.side[0] == kNone ? 0 : 1;
        e.side[side] = 3 * triangle + std::uint32_t(k);
        triangles_[triangle].edge[k] = 2 * edge + side;
    }

    // Splits edge record e at its midpoint: a fresh position id, one midpoint vertex per side (shared
    // when both sides use the same two vertices, separate across an attribute seam), two halves.
    void splitEdge(std::uint32_t e) {
        const std::uint32_t midPid = pidCount_++;
        std::uint32_t ends[2][2] = {{kNone, kNone}, {kNone, kNone}};
        for (int s = 0; s < 2; ++s) {
            const std::uint32_t h = edges_[e].side[s];
            if (h == kNone) continue;
            const Triangle& t = triangles_[h / 3];
            ends[s][0] = t.v[h % 3];
            ends[s][1] = t.v[(h % 3 + 1) % 3];
            const bool sameVertices = s == 1 && ends[0][0] != kNone &&
                                      ((ends[1][0] == ends[0][0] && ends[1][1] == ends[0][1]) ||
                                       (ends[1][0] == ends[0][1] && ends[1][1] == ends[0][0]));
            edges_[e].midVertex[s] = sameVertices ? edges_[e].midVertex[0] : addMidpoint(ends[s][0], ends[s][1], h / 3, midPid);
            const std::uint32_t code = 2 * e + std::uint32_t(s);
            if (!sameVertices && code < probed_.size() && probed_[code]) {
                // The probe was cast at exactly this point with exactly this normal: it is the transfer.
                const std::size_t w = std::size_t(width_);
                std::copy_n(&probe_[w * code], w, &transfer_[w * edges_[e].midVertex[s]]);
                known_[edges_[e].midVertex[s]] = 1;
            }
        }
        const std::uint32_t anyEnd = ends[0][0] != kNone ? ends[0][0] : ends[1][0];
        const std::uint32_t otherEnd = ends[0][0] != kNone ? ends[0][1] : ends[1][1];
        const std::uint32_t highPid = std::max(pid_[anyEnd], pid_[otherEnd]);
        Edge low, high;
        low.parent = high.parent = e;
        low.boundary = high.boundary = edges_[e].boundary;
        low.lowPid = std::min(edges_[e].lowPid, midPid);
        high.lowPid = std::min(highPid, midPid);
        edges_[e].firstChild = static_cast<std::uint32_t>(edges_.size());
        edges_.push_back(low);
        edges_.push_back(high);
    }

    // A vertex at the exact midpoint of a and b (the same float operations on both sides of a seam,
    // so both sides' midpoints coincide bit for bit) with normal normalize(n_a + n_b).
    std::uint32_t addMidpoint(std::uint32_t a, std::uint32_t b, std::uint32_t triangle, std::uint32_t midPid) {
        const auto index = static_cast<std::uint32_t>(vertexCount());
        float normal[3];
        midpointNormal(a, b, triangle, normal);
        for (int c = 0; c < 3; ++c)
            positions_.push_back(0.5f * (positions_[3 * std::size_t(a) + c] + positions_[3 * std::size_t(b) + c]));
        normals_.insert(normals_.end(), normal, normal + 3);
        pid_.push_back(midPid);
        transfer_.resize(vertexCount() * std::size_t(width_));
        known_.push_back(0);
        return index;
    }

    // normalize(n_a + n_b); for opposite end normals, the geometric normal of `triangle` instead.
    void midpointNormal(std::uint32_t a, std::uint32_t b, std::uint32_t triangle, float out[3]) const {
        double n[3], length2 = 0.0;
        for (int c = 0; c < 3; ++c) {
            n[c] = double(normals_[3 * std::size_t(a) + c]) + double(normals_[3 * std::size_t(b) + c]);
            length2 += n[c] * n[c];
        }
        if (length2 == 0.0) {
            const Triangle& t = triangles_[triangle];
            double p[3][3];
            for (int k = 0; k < 3; ++k)
                for (int c = 0; c < 3; ++c) p[k][c] = positions_[3 * std::size_t(t.v[k]) + c];
            const double u[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
            const double v[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
            n[0] = u[1] * v[2] - u[2] * v[1];
            n[1] = u[2] * v[0] - u[0] * v[2];
            n[2] = u[0] * v[1] - u[1] * v[0];
            length2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
        }
        const double inverse = length2 > 0.0 ? 1.0 / std::sqrt(length2) : 0.0;
        for (int c = 0; c < 3; ++c) out[c] = static_cast<float>(n[c] * inverse);
    }

    // Whether the triangle side `half` (3 * triangle + local edge) joins vertices a and b.
    bool sameEnds(std::uint32_t half, std::uint32_t a, std::uint32_t b) const {
        const Triangle& t = triangles_[half / 3];
        const std::uint32_t x = t.v[half % 3], y = t.v[(half % 3 + 1) % 3];
        return (x == a && y == b) || (x == b && y == a);
    }

    double squaredDoubleArea(std::uint32_t a, std::uint32_t b, std::uint32_t c) const {
        double u[3], v[3];
        for (int k = 0; k < 3; ++k) {
            u[k] = double(positions_[3 * std::size_t(b) + k]) - double(positions_[3 * std::size_t(a) + k]);
            v[k] = double(positions_[3 * std::size_t(c) + k]) - double(positions_[3 * std::size_t(a) + k]);
        }
        const double x = u[1] * v[2] - u[2] * v[1], y = u[2] * v[0] - u[0] * v[2], z = u[0] * v[1] - u[1] * v[0];
        return x * x + y * y + z * z;
    }

    // Probed measures: the floor of the relative form (kProbedRelativeFloor of the mean |t| over the
    // input vertices) or the scale of the absolute one (the mean |t|), and the input's total area, so
    // that a triangle's value is its share of the mean error.
    void setUpProbes(const PrtMesh& input) {
        probing_ = true;
        const std::size_t w = std::size_t(width_);
        double meanNorm = 0.0;
        for (std::size_t v = 0; v < input.vertexCount(); ++v) {
            double t2 = 0.0;
            for (std::size_t i = 0; i < w; ++i) t2 += double(transfer_[w * v + i]) * transfer_[w * v + i];
            meanNorm += std::sqrt(t2);
        }
        meanNorm /= double(std::max<std::size_t>(1, input.vertexCount()));
        probeFloor_ = measure_ == TransferErrorMeasure::ProbedRelative ? kProbedRelativeFloor * meanNorm : meanNorm;
        double total = 0.0;
        for (std::size_t f = 0; f < input.faceCount(); ++f)
            total += std::sqrt(squaredDoubleArea(input.faces[3 * f], input.faces[3 * f + 1], input.faces[3 * f + 2]));
        inverseDoubleArea_ = total > 0.0 ? 1.0 / total : 1.0;
    }

    double squaredDistance(std::uint32_t a, std::uint32_t b) const {
        double d2 = 0.0;
        for (int c = 0; c < 3; ++c) {
            const double d = double(positions_[3 * std::size_t(a) + c]) - double(positions_[3 * std::size_t(b) + c]);
            d2 += d * d;
        }
        return d2;
    }

    TransferErrorMeasure measure_;
    double alpha_;
    int width_;
    std::vector<float> positions_, normals_, transfer_;
    std::vector<std::uint32_t> pid_;
    std::uint32_t pidCount_ = 0;
    std::vector<Triangle> triangles_;
    std::vector<Edge> edges_;
    std::vector<std::uint8_t> known_;   // per vertex: transfer set (input, or from a probe)
    bool probing_ = false;
    double probeFloor_ = 0.0;
    double inverseDoubleArea_ = 1.0;
    std::vector<float> probe_;          // width floats per edge side code (2 * edge + side)
    std::vector<std::uint8_t> probed_;  // per edge side code
    std::size_t probeCount_ = 0;        // oracle points spent on probes
};

void validateArguments(const char* who, const PrtMesh& input, std::size_t budget, TransferErrorMeasure measure,
                       double alpha) {
    if (const std::string problem = validationProblem(input); !problem.empty())
        throw std::invalid_argument(std::string(who) + ": " + problem + ".");
    if (budget < input.faceCount())
        throw std::invalid_argument(std::string(who) + ": the triangle budget (" + std::to_string(budget) +
                                    ") is below the layer's " + std::to_string(input.faceCount()) +
                                    " faces: raise the budget, or set the budget factor (e.g. 4).");
    if (budget > kLargestBudget)
        throw std::invalid_argument(std::string(who) + ": the triangle budget " + std::to_string(budget) +
                                    " is above 2^30 faces: choose a smaller budget.");
    if (measure == TransferErrorMeasure::NormalDivergence && !(std::isfinite(alpha) && alpha >= 0.0))
        throw std::invalid_argument(std::string(who) + ": the normal-divergence weight alpha (Křivánek et al. "
                                    "2004, eq. 4) must be finite and >= 0; it is " + std::to_string(alpha) +
                                    ". Use e.g. 1.");
}

}  // namespace

SubdivisionResult subdivideAdaptively(const PrtMesh& input, const TransferOracle& oracle,
                                      const AdaptiveSubdivisionOptions& options) {
    const char* who = "Adaptive PRT subdivision";
    validateArguments(who, input, options.triangleBudget, options.measure, options.alpha);
    if (!(std::isfinite(options.threshold) && options.threshold >= 0.0))
        throw std::invalid_argument(std::string(who) + ": the error threshold must be finite and >= 0; it is " +
                                    std::to_string(options.threshold) + ". Use 0 to spend the whole budget.");
    if (!oracle) throw std::invalid_argument(std::string(who) + ": no transfer oracle");

    Refiner refiner(input, options.measure, options.alpha);
    const std::size_t budget = options.triangleBudget;
    std::size_t faces = input.faceCount();  // after T-vertex removal, maintained per operation
    int reportedPercent = -1;
    const auto report = [&]() {
        if (!options.progress) return;
        const int percent = static_cast<int>(100.0 * double(faces) / double(budget));
        if (percent == reportedPercent) return;
        reportedPercent = percent;
        reportProgress(options.progress, std::min(1.0, double(faces) / double(budget)), "refining triangles");
    };
    report();

    using Entry = std::pair<double, std::uint32_t>;  // (error, triangle): max error first
    std::priority_queue<Entry> queue;
    refiner.probeEdges(0, input.faceCount(), oracle);
    for (std::uint32_t t = 0; t < input.faceCount(); ++t)
        if (const double e = refiner.leafError(t); e > options.threshold) queue.push({e, t});

    SubdivisionResult result;
    std::vector<std::uint32_t> plan;
    while (!queue.empty()) {
        const Entry top = queue.top();
        if (!refiner.isLeaf(top.second)) {  // split meanwhile to keep a finer neighbour 1-irregular
            queue.pop();
            continue;
        }
        plan.clear();
        refiner.planSplit(top.second, plan);
        const std::int64_t cost = refiner.planCost(plan);
        if (faces + std::size_t(cost) > budget) {
            result.stop = SubdivisionStop::BudgetReached;
            result.largestRemainingError = top.first;
            break;
        }
        queue.pop();
        const std::size_t firstVertex = refiner.vertexCount();
        const auto firstChild = static_cast<std::uint32_t>(refiner.triangleCount());
        for (const std::uint32_t t : plan) refiner.split(t);
        refiner.castTransfer(firstVertex, oracle);
        refiner.probeEdges(firstChild, refiner.triangleCount(), oracle);
        for (auto child = firstChild; child < refiner.triangleCount(); ++child)
            if (const double e = refiner.leafError(child); e > options.threshold) queue.push({e, child});
        result.regularSplits += plan.size();
        result.forcedSplits += plan.size() - 1;
        faces += std::size_t(cost);
        report();
    }

    result.newVertices = refiner.vertexCount() - input.vertexCount();
    result.probes = refiner.probeCount();
    refiner.emit(result);
    return result;
}

SubdivisionResult subdivideUniformly(const PrtMesh& input, const TransferOracle& oracle, std::size_t triangleBudget,
                                     TransferErrorMeasure measure, double alpha) {
    const char* who = "Uniform PRT subdivision";
    validateArguments(who, input, triangleBudget, measure, alpha);
    if (!oracle) throw std::invalid_argument(std::string(who) + ": no transfer oracle");
    int levels = 0;
    for (std::size_t faces = input.faceCount(); faces * 4 <= triangleBudget; faces *= 4) ++levels;

    Refiner refiner(input, measure, alpha);
    SubdivisionResult result;
    // Level by level: all leaves of a level are split before the next, so no split is ever forced
    // and no midpoint hangs.
    std::size_t levelStart = 0;
    for (int level = 0; level < levels; ++level) {
        const std::size_t levelEnd = refiner.triangleCount();
        for (std::size_t t = levelStart; t < levelEnd; ++t) refiner.split(static_cast<std::uint32_t>(t));
        result.regularSplits += levelEnd - levelStart;
        levelStart = levelEnd;
    }
    refiner.castTransfer(input.vertexCount(), oracle);
    // The face error shown for a probed measure needs the leaves' probes (one more oracle call).
    refiner.probeEdges(levelStart, refiner.triangleCount(), oracle);
    result.probes = refiner.probeCount();
    result.newVertices = refiner.vertexCount() - input.vertexCount();
    result.stop = SubdivisionStop::BudgetReached;
    refiner.emit(result);
    return result;
}

std::string checkPrtSubdivisionInput(const PrtMesh& mesh) {
    const auto plural = [](std::size_t n, const char* what) {
        const std::string word = what;
        return std::to_string(n) + " " + (n == 1 ? word : word == "vertex" ? "vertices" : word + "s");
    };
    if (mesh.positions.empty() || mesh.faces.empty())
        return "the mesh has no faces: PRT subdivision works on triangle meshes, not point clouds; load or "
               "reconstruct a surface first";
    if (mesh.positions.size() % 3 != 0 || mesh.faces.size() % 3 != 0)
        return "the mesh arrays are malformed (positions or faces are not whole triples); reload the mesh";
    if (mesh.normals.size() != mesh.positions.size())
        return "the mesh has no per-vertex normals: compute them first ({{Re-Compute Vertex Normals}}, or "
               "{{Compute normals for point sets}})";
    if (mesh.width < 1 || mesh.transfer.size() != mesh.vertexCount() * std::size_t(std::max(mesh.width, 0)))
        return "the mesh's transfer vectors do not match its vertices (" + std::to_string(mesh.transfer.size()) +
               " floats for " + plural(mesh.vertexCount(), "vertex") + " of width " + std::to_string(mesh.width) +
               "): compute the PRT transfer vectors again on this mesh";
    const std::size_t V = mesh.vertexCount(), F = mesh.faceCount();
    for (const std::uint32_t i : mesh.faces)
        if (i >= V)
            return "a face refers to vertex " + std::to_string(i) + " but the mesh has " + plural(V, "vertex") +
                   "; reload the mesh";

    std::size_t nonFinitePositions = 0, nonFiniteNormals = 0, zeroNormals = 0, nonFiniteTransfer = 0;
    for (std::size_t v = 0; v < V; ++v) {
        const float* p = &mesh.positions[3 * v];
        const float* n = &mesh.normals[3 * v];
        nonFinitePositions += !(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]));
        if (!(std::isfinite(n[0]) && std::isfinite(n[1]) && std::isfinite(n[2])))
            ++nonFiniteNormals;
        else if (n[0] == 0.0f && n[1] == 0.0f && n[2] == 0.0f)
            ++zeroNormals;
        const float* t = &mesh.transfer[v * std::size_t(mesh.width)];
        nonFiniteTransfer += !std::all_of(t, t + mesh.width, [](float x) { return std::isfinite(x); });
    }
    if (nonFinitePositions > 0)
        return "the mesh has " + plural(nonFinitePositions, "vertex") +
               " with a non-finite position (NaN or infinity): fix or delete them (then {{Remove Unreferenced "
               "Vertices}}) and try again";
    if (nonFiniteNormals > 0 || zeroNormals > 0)
        return "the mesh has " + plural(nonFiniteNormals + zeroNormals, "vertex") +
               " with a zero or non-finite normal: recompute the normals ({{Re-Compute Vertex Normals}}) after "
               "removing zero-area faces ({{Remove Zero Area Faces}})";
    if (nonFiniteTransfer > 0)
        return "the transfer vectors of " + plural(nonFiniteTransfer, "vertex") +
               " are not finite (NaN or infinity): compute the PRT transfer vectors again";
    if (std::string range = coordinateRangeProblem(mesh.positions.data(), V); !range.empty()) return range;

    std::uint32_t pidCount = 0;
    const std::vector<std::uint32_t> pid = weldPositions(mesh.positions, pidCount);
    std::size_t repeated = 0, zeroArea = 0;
    std::vector<std::uint64_t> edges;
    edges.reserve(3 * F);
    for (std::size_t f = 0; f < F; ++f) {
        const std::uint32_t* t = &mesh.faces[3 * f];
        const std::uint64_t a = pid[t[0]], b = pid[t[1]], c = pid[t[2]];
        if (a == b || b == c || c == a) {
            ++repeated;
            continue;
        }
        float e1[3], e2[3];
        for (int k = 0; k < 3; ++k) {
            e1[k] = mesh.positions[3 * std::size_t(t[1]) + k] - mesh.positions[3 * std::size_t(t[0]) + k];
            e2[k] = mesh.positions[3 * std::size_t(t[2]) + k] - mesh.positions[3 * std::size_t(t[0]) + k];
        }
        const float cross[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        if (cross[0] == 0.0f && cross[1] == 0.0f && cross[2] == 0.0f) ++zeroArea;
        edges.push_back(undirectedEdgeKey(a, b));
        edges.push_back(undirectedEdgeKey(b, c));
        edges.push_back(undirectedEdgeKey(c, a));
    }
    if (repeated > 0)
        return "the mesh has " + plural(repeated, "face") +
               " with two corners at the same position: run {{Remove Zero Area Faces}} and try again";
    if (zeroArea > 0)
        return "the mesh has " + plural(zeroArea, "face") +
               " of zero area: run {{Remove Zero Area Faces}} and try again";
    const std::size_t nonManifold = countNonManifoldEdges(edges);
    if (nonManifold > 0)
        return "the mesh has " + plural(nonManifold, "non-manifold edge") +
               " (shared by more than two faces, vertices at the same position counted as one): run "
               "{{Repair non Manifold Edges}} and try again";
    return {};
}

}  // namespace rad
