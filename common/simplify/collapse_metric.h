// The pluggable pricing modules of the edge-collapse engine (edge_collapse.h), in the spirit of
// OpenMesh's Decimater modules and CGoGN's Selector/Approximator split: the engine owns the
// connectivity, the queue and the validity checks; a metric prices collapses and keeps its own
// per-vertex attributes up to date after each collapse.
//
// Two kinds of collapse (Vanhoey et al. 2015, sec. 4.1 and 4.3):
//  - half-edge collapse v0 -> v1: v0 disappears, v1 keeps its position and attributes; the faces of
//    v0's star that do not contain v1 become (v1, a, b);
//  - full edge collapse (v0, v1) -> v: the survivor (slot v1) moves to `position` (QEM-optimal,
//    projected on the edge at parameter s for the attributes), attributes are set by the metric.
//
// Threading: price*() is called concurrently from several threads (different sources/edges), never
// concurrently with onCollapse(). Metrics keep their scratch buffers per thread (thread_local).
#pragma once

#include "simplify/collapse_mesh.h"

#include <Eigen/Core>

#include <cstdint>
#include <string>

namespace rad {

struct HalfEdgeQuery {
    std::uint32_t source = 0;         // v0, the vertex that disappears
    const StarFace* star = nullptr;   // every alive face around v0: (v0, a, b) counter-clockwise
    int starSize = 0;
    const std::uint32_t* targets = nullptr;  // candidate v1, each a neighbour of v0
    int targetCount = 0;
};

struct EdgeQuery {
    std::uint32_t v0 = 0, v1 = 0;     // v1 is the slot that survives
    const StarFace* star0 = nullptr;  // faces around v0 that do NOT contain v1, (v0, a, b) CCW
    int star0Size = 0;
    const StarFace* star1 = nullptr;  // faces around v1 that do NOT contain v0, (v1, a, b) CCW
    int star1Size = 0;
    Eigen::Vector3d position;         // where the new vertex goes
    double s = 0.5;                   // parameter of position's projection on p0 + s (p1 - p0), clamped to [0, 1]
    bool halfEdge = false;            // onCollapse of a half-edge collapse (then s == 1, position == p1)
};

class CollapseMetric {
public:
    virtual ~CollapseMetric() = default;
    virtual std::string name() const = 0;

    // costs[i] = error of the half-edge collapse source -> targets[i], >= 0 (or +infinity to
    // forbid). The mesh is in its pre-collapse state.
    virtual void priceHalfEdges(const CollapseMesh& mesh, const HalfEdgeQuery& query, double* costs) const = 0;

    // Full collapse; empty `why` when supported. Default: not supported.
    virtual bool supportsFullCollapse(std::string& why) const {
        why = name() + " prices half-edge collapses only";
        return false;
    }
    virtual double priceEdge(const CollapseMesh& mesh, const EdgeQuery& query) const { return 0.0; }

    // A metric whose cost already measures the geometry (an accumulated quadric) returns true: the
    // engine then adds no memoryless QEM of its own, whatever its geometry weight.
    virtual bool ownsGeometry() const { return false; }
    // True when a full collapse's placement and cost depend only on the metric's state of its two
    // ends and their positions (an accumulated quadric), not on their stars: the engine then
    // re-prices only the survivor's edges after a collapse, instead of its whole ring's, and its
    // priceEdge queries carry no stars (star0Size = star1Size = 0).
    virtual bool costDependsOnEndpointsOnly() const { return false; }
    // True when onCollapse reads only its query and the metric's own state of the two ends (neither
    // the mesh nor the stars), and calls for collapses with disjoint ends may run concurrently: the
    // engine's passes then apply a pass's collapses to the mesh first and update the metric for all
    // of them at the end of the pass, in parallel. (Within a pass no vertex takes part in two
    // collapses, and placements and validity do not read the metric, so the result is the same.)
    virtual bool updatesCanBeDeferred() const { return false; }
    // Full collapse: where the new vertex goes. Return false to let the engine place it (the
    // memoryless QEM's optimum); true with `position` set to choose it.
    virtual bool placeEdge(const CollapseMesh& mesh, std::uint32_t v0, std::uint32_t v1, Eigen::Vector3d& position) const {
        return false;
    }

    // Called after the engine applied a collapse (mesh already in its post-collapse state; for a
    // full collapse the survivor v1 is at query.position). Half-edge: query.halfEdge, s == 1 and
    // position == p1 (a full collapse may also land at s == 1, with halfEdge false). Metrics that own attributes update the survivor's here.
    virtual void onCollapse(const CollapseMesh& mesh, const EdgeQuery& query) {}
};

}  // namespace rad
