// Iterative edge-collapse simplification (Hoppe 1996; Garland & Heckbert 1997) with pluggable pricing
// (collapse_metric.h), as Vanhoey et al. 2015 sec. 4 use it: a priority queue of collapsible edges,
// the cheapest collapsed first (or, for an accumulated quadric, passes of sorted edges after
// meshoptimizer's simplifier: passFraction). Cost = geometryWeight * E_G (the memoryless QEM, quadric_error.h)
// + attributeWeight * E_A (the metric), 1 % / 99 % by default (sec. 4.4). Half-edge or full
// collapses; a collapse is done only when it keeps a 2-manifold, the boundary, the faces'
// orientation and the optional valence bounds. Simplifies in place; the metric prices in parallel
// (OpenMP), so its price*() must be safe to call concurrently.
// Details: docs/simplification.md, "`common/simplify/edge_collapse.h`: how it works".
#pragma once

#include "progress/progress_callback.h"
#include "simplify/collapse_mesh.h"
#include "simplify/collapse_metric.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace rad {

enum class CollapseKind {
    HalfEdge,  // v0 -> v1 (sec. 4.1): positions and attributes are never interpolated
    Full,      // (v0, v1) -> QEM-optimal position (sec. 4.3)
};

struct EdgeCollapseOptions {
    CollapseKind kind = CollapseKind::HalfEdge;
    std::size_t targetFaceCount = 0;                              // stop at or below this many faces
    double maxError = std::numeric_limits<double>::infinity();    // stop before a collapse costing more
    double geometryWeight = 0.01;                                 // sec. 4.4
    double attributeWeight = 0.99;
    bool preserveBoundary = true;
    // With preserveBoundary, full collapses under a cost that depends on the two ends only (the
    // accumulated radiance quadric) may still merge a boundary vertex with a neighbour along the
    // boundary, or an interior vertex onto a boundary vertex: the survivor takes the boundary
    // vertex's place, so the boundary's vertices stay a subset of the original ones (meshoptimizer
    // collapses its border vertices the same way). Otherwise, and for other metrics, boundary
    // vertices never move. Vertices on non-manifold edges or with several boundary fans never move.
    bool collapseAlongBoundary = true;
    double maxNormalDeviationDegrees = 90.0;  // a surviving face may turn by at most this much
    int minValence = 0;                       // 0: no bound
    int maxValence = 0;                       // 0: no bound
    // Half-edge mode: after a collapse, re-queue the affected sources at their previous cost and
    // price them only when they reach the front of the queue (instead of at once). Most sources
    // are touched several times before they are collapsed, so this saves most pricings; the
    // order can differ from the eager one where a cost decreased.
    bool lazyRepricing = true;
    // Full mode with a cost that depends on the two ends only (an accumulated quadric): > 0 collapses
    // in passes of at most this fraction of the priced edges, sorted once per pass and re-priced in
    // parallel between passes (after meshoptimizer's simplifier), instead of one global queue; 0: the
    // queue. Other modes always use the queue. Measured: docs/design-notes.md, "Passes".
    double passFraction = 0.3;
    int threads = 0;                          // 0: OpenMP default
    // Called about every 1 % of the work (progress/progress_callback.h); a stop request makes
    // simplify() throw OperationCancelled.
    ProgressCallback progress;

    // Empty when the options are usable; otherwise a sentence for the user naming the option, its
    // value and an acceptable choice (simplifyByEdgeCollapse throws std::invalid_argument with it).
    std::string validate() const;
};

// One applied collapse, in order: what a progressive mesh (progressive_mesh.h) replays.
struct CollapseStep {
    std::uint32_t removed = 0;   // v0
    std::uint32_t survivor = 0;  // v1 (for a full collapse: the slot of the new vertex)
    float position[3] = {0, 0, 0};  // survivor's position after the step
    float cost = 0.0f;              // combined cost when collapsed
    std::uint32_t facesAfter = 0;   // alive faces after the step
};

enum class StopReason { TargetReached, MaxErrorReached, NoValidCollapse };
std::string describe(StopReason reason);

struct EdgeCollapseResult {
    std::size_t collapses = 0;
    std::size_t finalFaceCount = 0, finalVertexCount = 0;
    double lastCost = 0.0;  // combined cost of the last collapse
    double maxCost = 0.0;   // largest combined cost of any collapse
    StopReason stop = StopReason::TargetReached;
    std::size_t repricedVertices = 0;  // half-edge mode: vertex pricings; full mode: edge pricings
    std::size_t staleEntries = 0;      // popped entries found outdated
    bool collapsedAlongBoundary = false;  // collapseAlongBoundary was in effect (its metric and kind)
};

// Simplifies `mesh` in place. `metric` may be null (geometry only). `onStep` (may be empty) is
// called for each collapse, in order, after the metric's onCollapse for it: at once, with the mesh in
// its new state, or, in passes with a metric whose updates can be deferred
// (CollapseMetric::updatesCanBeDeferred), at the end of the step's pass, when the mesh may be in a
// later state (the step's facesAfter tells its face count).
// Throws std::invalid_argument when the options are inconsistent (full collapse with a metric that
// cannot price it: the message carries the metric's reason; negative weights; valence bounds
// inverted).
EdgeCollapseResult simplifyByEdgeCollapse(CollapseMesh& mesh, CollapseMetric* metric, const EdgeCollapseOptions& options,
                                          const std::function<void(const CollapseStep&)>& onStep = {});

}  // namespace rad
