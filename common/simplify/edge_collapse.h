// Iterative edge-collapse simplification (Hoppe 1996 "Progressive meshes"; Garland & Heckbert 1997)
// with pluggable pricing (collapse_metric.h), as used by Vanhoey et al. 2015 sec. 4:
// "build a priority queue of all collapsible edges; until the mesh is simplified enough, collapse
// the first edge and update the queue".
//
// Cost of a collapse = geometryWeight * E_G + attributeWeight * E_A, with E_G the memoryless QEM
// (quadric_error.h) and E_A the attribute metric (e.g. the radiance error of eq. 7), defaults
// 1 % / 99 % (sec. 4.4).
//
// Queue with lazy invalidation: every vertex has a version counter, bumped whenever its star
// changes; an entry remembers the versions it was priced with and is dropped when popped stale.
//  - Half-edge mode: one entry per source vertex v0 holding its cheapest valid target (all targets
//    of v0 share the star of v0, which is what eq. 7 and the memoryless QEM depend on, so they are
//    priced together). After v0 -> v1, v1 and its neighbours are re-priced.
//  - Full mode: one entry per edge, holding where the new vertex goes; after (v0, v1) -> v1 every
//    edge incident to v1 or to one of its neighbours is re-priced. When the metric's cost depends on
//    the two ends only (an accumulated quadric, CollapseMetric::costDependsOnEndpointsOnly), only
//    v1's edges are: the ring's other entries stay queued and are re-validated when popped, and an
//    edge dropped as invalid is priced again once a collapse changes the star of one of its ends.
// Re-pricing after a collapse runs in parallel (OpenMP) over the affected vertices/edges (or, with
// lazyRepricing in half-edge mode, when a touched source reaches the front of the queue). Validity
// can also change without the star changing (a neighbour's valence, the link of the target), so an
// entry is re-checked when popped and re-priced if it became invalid.
//
// Validity of a collapse (each check can only forbid):
//  - the edge is manifold (1 or 2 faces) and the link condition holds (Dey et al. 1999: the common
//    neighbours of v0 and v1 are exactly the apexes of the faces on the edge, and those apexes are
//    not joined by an edge), which keeps a
//    2-manifold a 2-manifold and forbids collapsing a tetrahedron;
//  - boundary: with preserveBoundary, a vertex on a boundary never moves or disappears; without it,
//    an edge joining two boundary vertices must itself be a boundary edge (no pinching);
//  - face flip: every face that survives keeps its orientation within maxNormalDeviationDegrees
//    and does not become degenerate;
//  - optional valence bounds [minValence, maxValence] (Vanhoey et al. 2010 uses 4..11) on the vertices
//    whose valence changes.
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
    double maxNormalDeviationDegrees = 90.0;  // a surviving face may turn by at most this much
    int minValence = 0;                       // 0: no bound
    int maxValence = 0;                       // 0: no bound
    // Half-edge mode: after a collapse, re-queue the affected sources at their previous cost and
    // price them only when they reach the front of the queue (instead of at once). Most sources
    // are touched several times before they are collapsed, so this saves most pricings; the
    // order can differ from the eager one where a cost decreased.
    bool lazyRepricing = true;
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
};

// Simplifies `mesh` in place. `metric` may be null (geometry only). `onStep` (may be empty) is
// called after each collapse, after the metric's onCollapse, with the mesh in its new state.
// Throws std::invalid_argument when the options are inconsistent (full collapse with a metric that
// cannot price it: the message carries the metric's reason; negative weights; valence bounds
// inverted).
EdgeCollapseResult simplifyByEdgeCollapse(CollapseMesh& mesh, CollapseMetric* metric, const EdgeCollapseOptions& options,
                                          const std::function<void(const CollapseStep&)>& onStep = {});

}  // namespace rad
