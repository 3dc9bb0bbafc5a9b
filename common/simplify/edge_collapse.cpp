#include "simplify/edge_collapse.h"

#include "parallel/parallel_sort.h"
#include "simplify/cost_queue.h"

#include "simplify/quadric_error.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <sstream>
#include <utility>

namespace rad {

std::string EdgeCollapseOptions::validate() const {
    const auto text = [](double x) {
        std::ostringstream out;
        out << x;
        return out.str();
    };
    if (!(geometryWeight >= 0.0 && std::isfinite(geometryWeight)) || !(attributeWeight >= 0.0 && std::isfinite(attributeWeight)))
        return "The geometry and attribute weights must be finite and >= 0 (they are " + text(geometryWeight) + " and " +
               text(attributeWeight) + "): use e.g. 0.01 and 0.99 (Vanhoey et al. 2015, sec. 4.4).";
    if (minValence < 0 || maxValence < 0 || (maxValence > 0 && minValence > maxValence))
        return "The valence bounds must be >= 0 (0 = no bound) with the minimum at most the maximum (they are " +
               std::to_string(minValence) + " and " + std::to_string(maxValence) + "): use e.g. 3 and 12, or 0 and 0.";
    if (!(maxNormalDeviationDegrees >= 0.0 && maxNormalDeviationDegrees <= 180.0))
        return "The largest normal change must be an angle in [0, 180] degrees (it is " +
               text(maxNormalDeviationDegrees) + "): use e.g. 90 to forbid fold-overs, 180 for no bound.";
    if (std::isnan(maxError) || maxError < 0.0)
        return "The largest collapse error must be >= 0 or infinite (it is " + text(maxError) + ").";
    if (threads < 0) return "The thread count must be 0 (all cores) or more.";
    if (!(passFraction >= 0.0 && passFraction <= 1.0))
        return "The fraction of the edges a pass may collapse must be in [0, 1] (it is " + text(passFraction) +
               "): use e.g. 0.15, or 0 for one global queue.";
    return {};
}

std::string describe(StopReason reason) {
    switch (reason) {
        case StopReason::TargetReached: return "target reached";
        case StopReason::MaxErrorReached: return "maximum error reached";
        case StopReason::NoValidCollapse: return "no valid collapse left";
    }
    return "unknown";
}

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

struct QueueEntry {
    double cost;
    std::uint32_t a, b;            // half-edge: a -> b; full: edge (a, b)
    std::uint32_t stampA, stampB;  // versions of a and b when priced; half-edge mode: stampB = 1 marks a
                                   // lazy entry (source not priced since its star changed)
    // Full mode: where the new vertex goes. Placement depends only on state that bumps a's or b's
    // version when it changes, so a non-stale entry's position is the one placing would give now.
    double position[3];
};

// Per-thread buffers of one pricing.
struct Workspace {
    std::vector<StarFace> star0, star1, star0WithoutV1, star1WithoutV0;
    std::vector<std::uint32_t> neighbours0, neighbours1, targets, apexNeighbours;
    std::vector<double> attributeCosts;
    std::vector<std::pair<double, std::uint32_t>> order;
};

Workspace& workspace() {
    thread_local Workspace w;
    return w;
}

bool contains(const std::vector<std::uint32_t>& list, std::uint32_t v) {
    return std::find(list.begin(), list.end(), v) != list.end();
}

// A set of vertices: the list in the order of insertion and a mark per vertex, so that inserting and
// testing cost O(1) and emptying costs the set's size, not the mesh's.
class MarkedVertices {
public:
    void reset(std::size_t vertexCount) {
        mark_.assign(vertexCount, 0);
        list_.clear();
    }
    std::size_t vertexCount() const { return mark_.size(); }
    bool has(std::uint32_t v) const { return mark_[v] != 0; }
    void insert(std::uint32_t v) {
        if (mark_[v]) return;
        mark_[v] = 1;
        list_.push_back(v);
    }
    void clear() {
        for (std::uint32_t v : list_) mark_[v] = 0;
        list_.clear();
    }
    const std::vector<std::uint32_t>& list() const { return list_; }

private:
    std::vector<std::uint8_t> mark_;
    std::vector<std::uint32_t> list_;
};

class Simplifier {
public:
    Simplifier(CollapseMesh& mesh, CollapseMetric* metric, const EdgeCollapseOptions& options)
        : mesh_(mesh), metric_(metric), options_(options), version_(mesh.vertexCount(), 0),
          lastCost_(mesh.vertexCount(), kInfinity) {
        const double degrees = std::clamp(options.maxNormalDeviationDegrees, 0.0, 180.0);
        minNormalCosine_ = std::cos(degrees * 3.14159265358979323846 / 180.0);
        useMetric_ = metric_ != nullptr && options_.attributeWeight > 0.0;
        // An accumulated quadric that measures the geometry itself replaces the memoryless QEM.
        geometryWeight_ = useMetric_ && metric_->ownsGeometry() ? 0.0 : options_.geometryWeight;
        localCosts_ = options_.kind == CollapseKind::Full && useMetric_ && geometryWeight_ == 0.0 &&
                      metric_->costDependsOnEndpointsOnly();
        if (localCosts_) dormant_.assign(mesh.vertexCount(), 0);
        if (options.kind == CollapseKind::Full) listed_.reset(mesh.vertexCount());
        alongBoundary_ = localCosts_ && options_.preserveBoundary && options_.collapseAlongBoundary;
        if (alongBoundary_) classifyBoundaryVertices();
    }

    EdgeCollapseResult run(const std::function<void(const CollapseStep&)>& onStep);

private:
    // --- boundary -----------------------------------------------------------------------------
    // collapseAlongBoundary: each vertex's star as CollapseMesh::StarShape. One open fan may collapse
    // along the boundary; any other open star (a non-manifold edge, several fans) never moves.
    using StarShape = CollapseMesh::StarShape;

    void classifyBoundaryVertices() {
        const long n = static_cast<long>(mesh_.vertexCount());
        starShape_.assign(mesh_.vertexCount(), StarShape::ClosedFan);
        const int threads = options_.threads > 0 ? options_.threads : omp_get_max_threads();
#pragma omp parallel num_threads(threads)
        {
            std::vector<StarFace> star;
#pragma omp for schedule(static)
            for (long v = 0; v < n; ++v) {
                if (!mesh_.vertexAlive(static_cast<std::uint32_t>(v))) continue;
                mesh_.star(static_cast<std::uint32_t>(v), star);
                starShape_[v] = CollapseMesh::starShape(star);
            }
        }
    }

    // collapseAlongBoundary: where edge (v0, v1) may place its survivor. Neither end on the
    // boundary: anywhere; one end: at that end; both ends along a boundary edge: at either end;
    // otherwise nowhere (a fixed end, or a chord between two boundary vertices, which would pinch).
    enum class PlacementRule { Anywhere, AtV0, AtV1, AtEitherEnd, Nowhere };
    PlacementRule placementRule(std::uint32_t v0, std::uint32_t v1) const {
        if (!alongBoundary_) return PlacementRule::Anywhere;
        const StarShape s0 = starShape_[v0], s1 = starShape_[v1];
        if (s0 == StarShape::Other || s1 == StarShape::Other) return PlacementRule::Nowhere;
        if (s0 == StarShape::ClosedFan) return s1 == StarShape::ClosedFan ? PlacementRule::Anywhere : PlacementRule::AtV1;
        if (s1 == StarShape::ClosedFan) return PlacementRule::AtV0;
        return mesh_.edgeFaceCount(v0, v1) == 1 ? PlacementRule::AtEitherEnd : PlacementRule::Nowhere;
    }

    bool placedByRule(PlacementRule rule, std::uint32_t v0, std::uint32_t v1, const Eigen::Vector3d& position) const {
        switch (rule) {
            case PlacementRule::Anywhere: return true;
            case PlacementRule::AtV0: return position == mesh_.position(v0);
            case PlacementRule::AtV1: return position == mesh_.position(v1);
            case PlacementRule::AtEitherEnd: return position == mesh_.position(v0) || position == mesh_.position(v1);
            case PlacementRule::Nowhere: break;
        }
        return false;
    }

    // --- validity -----------------------------------------------------------------------------
    // Faces of `star` on the edge to v (the apexes are the other vertex of those faces).
    static int edgeFaces(const std::vector<StarFace>& star, std::uint32_t v, std::uint32_t apex[2]) {
        int n = 0;
        for (const StarFace& f : star) {
            if (f.a == v || f.b == v) {
                if (n < 2) apex[n] = f.a == v ? f.b : f.a;
                ++n;
            }
        }
        return n;
    }

    bool linkConditionHolds(const std::vector<std::uint32_t>& n0, const std::vector<std::uint32_t>& n1,
                            int edgeFaceCount) const {
        int common = 0;
        for (std::uint32_t u : n0)
            if (contains(n1, u)) ++common;
        return common == edgeFaceCount;
    }

    // Faces (v, a, b) of `star` not touching `other`, with v moved from `from` to `to`: each keeps
    // its orientation within the allowed deviation and a non-degenerate shape.
    bool noFlip(const std::vector<StarFace>& star, std::uint32_t other, const Eigen::Vector3d& from,
                const Eigen::Vector3d& to) const {
        for (const StarFace& f : star) {
            if (f.a == other || f.b == other) continue;
            const Eigen::Vector3d pa = mesh_.position(f.a), pb = mesh_.position(f.b);
            const Eigen::Vector3d before = (pa - from).cross(pb - from);
            const Eigen::Vector3d after = (pa - to).cross(pb - to);
            const double lengthBefore = before.norm(), lengthAfter = after.norm();
            const double scale = (pa - to).squaredNorm() + (pb - to).squaredNorm() + (pa - pb).squaredNorm();
            if (!(lengthAfter > 1e-10 * scale)) return false;  // sliver or zero area after
            if (lengthBefore > 0.0 && before.dot(after) < minNormalCosine_ * lengthBefore * lengthAfter) return false;
        }
        return true;
    }

    bool valenceAllowed(std::size_t newValence, const std::uint32_t* apex, int apexCount, Workspace& w) const {
        if (options_.maxValence > 0 && newValence > static_cast<std::size_t>(options_.maxValence)) return false;
        if (options_.minValence > 0) {
            if (newValence < static_cast<std::size_t>(options_.minValence)) return false;
            for (int i = 0; i < apexCount; ++i) {
                mesh_.neighbours(apex[i], w.apexNeighbours);
                if (w.apexNeighbours.size() - 1 < static_cast<std::size_t>(options_.minValence)) return false;
            }
        }
        return true;
    }

    // Topological and geometric validity of v0 -> v1 (half-edge) or (v0, v1) -> position (full).
    // Expects w.star0/w.neighbours0 of v0 filled; fills w.neighbours1 (and w.star1 when the
    // boundary status or the flips of v1's faces matter).
    bool collapseAllowed(std::uint32_t v0, std::uint32_t v1, bool open0, const Eigen::Vector3d& position,
                         bool full, Workspace& w) const {
        std::uint32_t apex[2];
        const int edgeFaceCount = edgeFaces(w.star0, v1, apex);
        if (edgeFaceCount < 1 || edgeFaceCount > 2) return false;
        const bool needStar1 = full || !options_.preserveBoundary;
        if (needStar1) {
            mesh_.star(v1, w.star1);
            const bool open1 = CollapseMesh::isOpenStar(w.star1);
            if (alongBoundary_ && (open0 || open1)) {
                // Only where the placement rule (applied when the edge was priced) puts the survivor:
                // the boundary stays where it was. A rule of Anywhere here would mean a boundary end
                // classified as interior: refused, never moved.
                const PlacementRule rule = placementRule(v0, v1);
                if (rule == PlacementRule::Anywhere || !placedByRule(rule, v0, v1, position)) return false;
            } else if (options_.preserveBoundary ? (open0 || open1) : (open0 && open1 && edgeFaceCount != 1)) {
                return false;  // boundary kept, or an interior edge between two boundary vertices would pinch
            }
        } else if (open0) {
            return false;
        }
        mesh_.neighbours(v1, w.neighbours1);
        if (!linkConditionHolds(w.neighbours0, w.neighbours1, edgeFaceCount)) return false;
        // The edge part of the link condition: the only candidates are edges between the common
        // neighbours, i.e. the two apexes. Joined apexes (a tetrahedron) would leave two faces on
        // one edge pair with opposite orientations.
        if (edgeFaceCount == 2 && mesh_.edgeFaceCount(apex[0], apex[1]) > 0) return false;
        const std::size_t newValence = w.neighbours0.size() + w.neighbours1.size() - 2 - edgeFaceCount;
        if (!valenceAllowed(newValence, apex, std::min(edgeFaceCount, 2), w)) return false;
        const Eigen::Vector3d p0 = mesh_.position(v0), p1 = mesh_.position(v1);
        if (!noFlip(w.star0, v1, p0, position)) return false;
        if (full && !noFlip(w.star1, v0, p1, position)) return false;
        return true;
    }

    // The distinct neighbours of v0 from its star (every 'a', plus the 'b's of an open fan).
    static void neighboursFromStar(const std::vector<StarFace>& star, std::vector<std::uint32_t>& out) {
        out.clear();
        for (const StarFace& f : star) {
            if (!contains(out, f.a)) out.push_back(f.a);
            if (!contains(out, f.b)) out.push_back(f.b);
        }
    }

    // --- pricing ------------------------------------------------------------------------------
    // Half-edge mode: the cheapest valid collapse out of v0, or cost = +inf. Every target is priced
    // (the metric prices them together), then validity is checked in order of increasing cost
    // until one passes: usually the first.
    QueueEntry priceSource(std::uint32_t v0) const {
        QueueEntry best{kInfinity, v0, v0, version_[v0], 0, {0.0, 0.0, 0.0}};
        if (!mesh_.vertexAlive(v0) || mesh_.incidentFaces(v0).empty()) return best;
        Workspace& w = workspace();
        mesh_.star(v0, w.star0);
        const bool open0 = CollapseMesh::isOpenStar(w.star0);
        if (open0 && options_.preserveBoundary) return best;
        neighboursFromStar(w.star0, w.neighbours0);
        w.targets = w.neighbours0;
        const std::size_t n = w.targets.size();
        w.attributeCosts.assign(n, 0.0);
        if (useMetric_) {
            HalfEdgeQuery query;
            query.source = v0;
            query.star = w.star0.data();
            query.starSize = static_cast<int>(w.star0.size());
            query.targets = w.targets.data();
            query.targetCount = static_cast<int>(n);
            metric_->priceHalfEdges(mesh_, query, w.attributeCosts.data());
        }
        const Quadric q = geometryWeight_ > 0.0 ? vertexQuadric(mesh_, v0) : Quadric();
        w.order.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            double cost = geometryWeight_ > 0.0 ? geometryWeight_ * std::max(0.0, q.evaluate(mesh_.position(w.targets[i]))) : 0.0;
            if (useMetric_) cost += options_.attributeWeight * w.attributeCosts[i];
            if (!(cost < kInfinity)) cost = kInfinity;  // NaN and overflow never win
            w.order[i] = {cost, w.targets[i]};
        }
        std::sort(w.order.begin(), w.order.end());
        for (const auto& [cost, v1] : w.order) {
            if (cost == kInfinity) break;
            if (collapseAllowed(v0, v1, open0, mesh_.position(v1), false, w)) {
                best.cost = cost;
                best.b = v1;
                break;
            }
        }
        return best;
    }

    struct Placement {
        Eigen::Vector3d position;
        double s;
        double geometricError;  // the memoryless QEM of both stars at `position`
    };
    Placement placeEdge(std::uint32_t v0, std::uint32_t v1) const {
        const Eigen::Vector3d p0 = mesh_.position(v0), p1 = mesh_.position(v1);
        Eigen::Vector3d p;
        const bool placedByMetric = useMetric_ && metric_->placeEdge(mesh_, v0, v1, p);
        double geometricError = 0.0;
        if (!placedByMetric || geometryWeight_ > 0.0) {
            Quadric q = vertexQuadric(mesh_, v0);
            q += vertexQuadric(mesh_, v1);
            if (!placedByMetric) p = optimalPosition(q, p0, p1);
            geometricError = std::max(0.0, q.evaluate(p));
        }
        return {p, edgeParameter(v0, v1, p), geometricError};
    }

    // The parameter of p's projection on p0 + s (p1 - p0), clamped to [0, 1].
    double edgeParameter(std::uint32_t v0, std::uint32_t v1, const Eigen::Vector3d& p) const {
        const Eigen::Vector3d p0 = mesh_.position(v0), p1 = mesh_.position(v1);
        const double length2 = (p1 - p0).squaredNorm();
        return length2 > 0.0 ? std::clamp((p - p0).dot(p1 - p0) / length2, 0.0, 1.0) : 0.5;
    }

    // The placement a queued, non-stale full-mode entry was priced with.
    Placement storedPlacement(const QueueEntry& e) const {
        const Eigen::Vector3d p(e.position[0], e.position[1], e.position[2]);
        return {p, edgeParameter(e.a, e.b, p), 0.0};
    }

    // Full mode: the cost of collapsing edge (v0, v1) into slot v1, +inf when not allowed. With a
    // cost that depends on the two ends only (localCosts_), the edge is priced without its stars and
    // its validity is checked once, when it is popped (stillAllowed): most priced edges are priced
    // again before they reach the front, so checking them at every pricing (both stars, the link
    // condition, the flips) was most of the work.
    QueueEntry priceEdge(std::uint32_t v0, std::uint32_t v1) const {
        QueueEntry entry{kInfinity, v0, v1, version_[v0], version_[v1], {0.0, 0.0, 0.0}};
        if (!mesh_.vertexAlive(v0) || !mesh_.vertexAlive(v1)) return entry;
        const PlacementRule rule = placementRule(v0, v1);
        if (rule == PlacementRule::Nowhere) return entry;
        if (rule != PlacementRule::Anywhere) return priceAtEnds(v0, v1, rule, entry);
        const Placement place = placeEdge(v0, v1);
        for (int k = 0; k < 3; ++k) entry.position[k] = place.position[k];
        EdgeQuery query;  // no stars: what a metric whose cost depends on the two ends only gets
        query.v0 = v0;
        query.v1 = v1;
        query.position = place.position;
        query.s = place.s;
        if (!localCosts_) {
            Workspace& w = workspace();
            mesh_.star(v0, w.star0);
            neighboursFromStar(w.star0, w.neighbours0);
            if (!collapseAllowed(v0, v1, CollapseMesh::isOpenStar(w.star0), place.position, true, w)) return entry;
            query = edgeQuery(v0, v1, place, w);
        }
        double cost = geometryWeight_ * place.geometricError;
        if (useMetric_) cost += options_.attributeWeight * metric_->priceEdge(mesh_, query);
        entry.cost = std::isfinite(cost) ? cost : kInfinity;
        return entry;
    }

    // collapseAlongBoundary (costs of the two ends only, so no memoryless QEM term): the cheaper of
    // the ends the rule allows.
    QueueEntry priceAtEnds(std::uint32_t v0, std::uint32_t v1, PlacementRule rule, QueueEntry entry) const {
        const auto consider = [&](std::uint32_t end) {
            EdgeQuery query;
            query.v0 = v0;
            query.v1 = v1;
            query.position = mesh_.position(end);
            query.s = end == v1 ? 1.0 : 0.0;
            const double cost = options_.attributeWeight * metric_->priceEdge(mesh_, query);
            if (std::isfinite(cost) && cost < entry.cost) {
                entry.cost = cost;
                for (int k = 0; k < 3; ++k) entry.position[k] = query.position[k];
            }
        };
        if (rule != PlacementRule::AtV0) consider(v1);
        if (rule != PlacementRule::AtV1) consider(v0);
        return entry;
    }

    EdgeQuery edgeQuery(std::uint32_t v0, std::uint32_t v1, const Placement& place, Workspace& w) const {
        w.star0WithoutV1.clear();
        for (const StarFace& f : w.star0)
            if (f.a != v1 && f.b != v1) w.star0WithoutV1.push_back(f);
        w.star1WithoutV0.clear();
        for (const StarFace& f : w.star1)
            if (f.a != v0 && f.b != v0) w.star1WithoutV0.push_back(f);
        EdgeQuery query;
        query.v0 = v0;
        query.v1 = v1;
        query.star0 = w.star0WithoutV1.data();
        query.star0Size = static_cast<int>(w.star0WithoutV1.size());
        query.star1 = w.star1WithoutV0.data();
        query.star1Size = static_cast<int>(w.star1WithoutV0.size());
        query.position = place.position;
        query.s = place.s;
        return query;
    }

    // Whether a popped, non-stale entry is still a valid collapse (validity can change without the
    // source's star changing: the target's link or an apex's valence).
    bool stillAllowed(const QueueEntry& e) const {
        Workspace& w = workspace();
        if (!mesh_.vertexAlive(e.a) || !mesh_.vertexAlive(e.b)) return false;
        mesh_.star(e.a, w.star0);
        neighboursFromStar(w.star0, w.neighbours0);
        if (!contains(w.neighbours0, e.b)) return false;
        const bool open0 = CollapseMesh::isOpenStar(w.star0);
        if (options_.kind == CollapseKind::HalfEdge) return collapseAllowed(e.a, e.b, open0, mesh_.position(e.b), false, w);
        return collapseAllowed(e.a, e.b, open0, storedPlacement(e).position, true, w);
    }

    bool stale(const QueueEntry& e) const {
        if (e.stampA != version_[e.a]) return true;
        return options_.kind == CollapseKind::Full && e.stampB != version_[e.b];
    }

    void push(const QueueEntry& e) {
        if (e.cost == kInfinity) return;
        queue_.push(e.cost, e.a, e);  // equal costs: by source (half-edge) or first end (full)
    }

    // Geometry-only pricing of a handful of vertices costs less than waking the thread team, and so
    // do the few edges around a collapse under an accumulated quadric (microseconds each: a parallel
    // region per collapse would cost as much on a quiet machine and far more on a busy one); the
    // initial pricing of the whole mesh and the memoryless attribute metrics (eq. 7 integrates over
    // a hemisphere per vertex) are worth it.
    bool parallelWorth(long n) const { return n > 256 || (useMetric_ && !localCosts_ && n > 2); }

    // Prices `vertices` (half-edge) or every edge incident to them (full) in parallel into priced_.
    void price(const std::vector<std::uint32_t>& vertices);
    // price(), then pushes what it priced.
    void reprice(const std::vector<std::uint32_t>& vertices) {
        price(vertices);
        for (const QueueEntry& e : priced_) push(e);
    }
    // Applies a popped, valid collapse: the mesh, the metric, the step callback, the versions.
    // Returns in `affected` the vertices whose edges must be priced again.
    void applyCollapse(const QueueEntry& top, EdgeCollapseResult& result,
                       const std::function<void(const CollapseStep&)>& onStep, std::vector<std::uint32_t>& affected);
    // The collapse loop of one global queue (every mode).
    void runQueue(EdgeCollapseResult& result, const std::function<void(const CollapseStep&)>& onStep);
    // Full collapses under costs that depend on the two ends only (localCosts_), in passes.
    void runInPasses(EdgeCollapseResult& result, const std::function<void(const CollapseStep&)>& onStep);
    // 0, 1, ..., the vertex count - 1: what the first pricing covers.
    std::vector<std::uint32_t> allVertices() const;
    // Reports the faces removed so far, about every 1 % of the work (throws when cancelled).
    void reportCollapseProgress();
    // What one pass hands the next.
    struct PassState {
        std::vector<QueueEntry> entries;  // priced edges; stale ones are dropped when ranking
        std::vector<std::uint32_t> affected;
        MarkedVertices touched;  // whose edges are priced again for the next pass
        // Checks made ahead, in parallel, for a chunk of the ranked entries (checkAhead), and the
        // vertices whose star or version the chunk's collapses have changed since (changed).
        std::vector<std::uint8_t> verdict;
        MarkedVertices changed;
    };
    enum Verdict : std::uint8_t { kStale, kForbidden, kAllowed };
    Verdict verdictOf(const QueueEntry& e) const { return stale(e) ? kStale : stillAllowed(e) ? kAllowed : kForbidden; }
    // stale() and stillAllowed() of entries [begin, end) against the mesh as it is, in parallel.
    void checkAhead(PassState& state, std::size_t begin, std::size_t end) const;
    // Whether a check made ahead still holds: neither end's star nor version changed since. A
    // collapse changes the stars of its two ends and of the survivor's ring only, and validity
    // reads the stars of the two ends, their neighbours' positions (a moved neighbour is the
    // survivor, whose ring holds both ends) and the faces between the apexes (which change only
    // when an apex is an end of the collapse, whose ring again holds both ends). The minimum
    // valence reads the apexes' valences, which change farther away: no checks ahead with it.
    bool checkedAheadStillHolds(const PassState& state, const QueueEntry& e) const {
        return !state.changed.has(e.a) && !state.changed.has(e.b);
    }
    // Appends the finite entries of priced_.
    void keepPriced(std::vector<QueueEntry>& entries) const;
    // Rank: drops stale and dropped entries, sorts the cheapest to the front; returns how many.
    std::size_t rankPass(std::vector<QueueEntry>& entries) const;
    // Perform: the ranked entries in order while current and valid; false when the largest error
    // stops the run.
    bool performPass(PassState& state, std::size_t take, EdgeCollapseResult& result,
                     const std::function<void(const CollapseStep&)>& onStep);
    // Update: prices the touched vertices' edges, in parallel, for the next pass.
    void updatePass(PassState& state);
    // The metric's updates of the deferred collapses, in parallel (their ends are disjoint), then
    // their steps reported in order.
    void flushDeferred(const std::function<void(const CollapseStep&)>& onStep);

    CollapseMesh& mesh_;
    CollapseMetric* metric_;
    EdgeCollapseOptions options_;
    std::vector<std::uint32_t> version_;
    CostQueue<QueueEntry> queue_;  // pushes in an order independent of the thread count: deterministic
    std::vector<QueueEntry> priced_;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges_;
    std::vector<std::uint32_t> around_;
    MarkedVertices listed_;            // price()'s alive vertices, each once, while it runs (full mode)
    std::vector<std::uint32_t> ring_;  // applyCollapse's scratch
    // Progress of one run: faces at its start, faces to remove, the next report's count and step.
    std::size_t startFaces_ = 0, nextReport_ = 0, reportStep_ = 1;
    double work_ = 1.0;
    std::vector<double> lastCost_;  // half-edge: each source's cost when last priced
    double minNormalCosine_ = 0.0;
    double geometryWeight_ = 0.0;
    bool useMetric_ = false;
    bool localCosts_ = false;            // full mode, metric's costs depend on the two ends only
    // EdgeCollapseOptions::collapseAlongBoundary in effect, and each vertex's star.
    bool alongBoundary_ = false;
    std::vector<StarShape> starShape_;
    std::vector<std::uint8_t> dormant_;  // localCosts_: has an edge dropped as invalid since last priced
    // Passes with a metric whose updates can be deferred: the pass's collapses, applied to the mesh,
    // awaiting the metric's update and the step's report (flushDeferred).
    struct DeferredCollapse {
        EdgeQuery query;
        CollapseStep step;
    };
    bool deferUpdates_ = false;
    std::vector<DeferredCollapse> deferred_;
    std::size_t pricings_ = 0;
};

void Simplifier::price(const std::vector<std::uint32_t>& vertices) {
    const int threads = options_.threads > 0 ? options_.threads : omp_get_max_threads();
    if (options_.kind == CollapseKind::HalfEdge) {
        priced_.resize(vertices.size());
        const long n = static_cast<long>(vertices.size());
#pragma omp parallel for schedule(dynamic, 4) num_threads(threads) if (parallelWorth(n))
        for (long i = 0; i < n; ++i) priced_[i] = priceSource(vertices[i]);
        pricings_ += vertices.size();
        for (const QueueEntry& e : priced_) lastCost_[e.a] = e.cost;
    } else {
        // Every edge once, without sorting them: an edge between two listed vertices is taken from
        // its lower end only.
        edges_.clear();
        for (std::uint32_t v : vertices)
            if (mesh_.vertexAlive(v)) listed_.insert(v);
        const std::vector<std::uint32_t>& listed = listed_.list();
        const auto gather = [&](std::uint32_t v, std::vector<std::uint32_t>& around,
                                std::vector<std::pair<std::uint32_t, std::uint32_t>>& out) {
            mesh_.neighbours(v, around);
            for (std::uint32_t u : around)
                if (!listed_.has(u) || v < u) out.emplace_back(std::min(u, v), std::max(u, v));
        };
        const long listedCount = static_cast<long>(listed.size());
        if (parallelWorth(listedCount)) {
            // Contiguous ranges of the list per thread, joined in thread order: the same edges in
            // the same order as one thread would list them.
            std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> parts(threads);
#pragma omp parallel num_threads(threads)
            {
                std::vector<std::uint32_t> around;
                std::vector<std::pair<std::uint32_t, std::uint32_t>>& mine = parts[omp_get_thread_num()];
#pragma omp for schedule(static)
                for (long i = 0; i < listedCount; ++i) gather(listed[std::size_t(i)], around, mine);
            }
            for (const auto& part : parts) edges_.insert(edges_.end(), part.begin(), part.end());
        } else {
            for (std::uint32_t v : listed) gather(v, around_, edges_);
        }
        listed_.clear();
        priced_.resize(edges_.size());
        const long n = static_cast<long>(edges_.size());
        // Which end survives: the slot with the larger index, so that the choice is stable.
#pragma omp parallel for schedule(dynamic, 4) num_threads(threads) if (parallelWorth(n))
        for (long i = 0; i < n; ++i) priced_[i] = priceEdge(edges_[i].first, edges_[i].second);
        pricings_ += edges_.size();
    }
}

void Simplifier::applyCollapse(const QueueEntry& top, EdgeCollapseResult& result,
                               const std::function<void(const CollapseStep&)>& onStep,
                               std::vector<std::uint32_t>& affected) {
    const std::uint32_t v0 = top.a, v1 = top.b;
    // Half-edge: only v1 and the neighbours of v0 see their star change (v1 does not move, so
    // the faces of v1's other neighbours are untouched). Full: v1 moves, its whole new ring.
    if (options_.kind == CollapseKind::HalfEdge) mesh_.neighbours(v0, ring_);
    EdgeQuery applied;
    applied.v0 = v0;
    applied.v1 = v1;
    if (options_.kind == CollapseKind::HalfEdge) {
        applied.position = mesh_.position(v1);
        applied.s = 1.0;
        applied.halfEdge = true;
        mesh_.collapse(v0, v1);
    } else {
        const Placement place = storedPlacement(top);
        if (localCosts_) {  // the metric reads no stars
            applied.position = place.position;
            applied.s = place.s;
        } else {
            Workspace& w = workspace();
            mesh_.star(v0, w.star0);
            mesh_.star(v1, w.star1);
            applied = edgeQuery(v0, v1, place, w);
        }
        mesh_.setPosition(v1, place.position);
        mesh_.collapse(v0, v1);
        // The survivor sits where a boundary end was (the placement rule): it is on the boundary.
        if (alongBoundary_) starShape_[v1] = std::max(starShape_[v0], starShape_[v1]);
    }
    ++result.collapses;
    result.lastCost = top.cost;
    result.maxCost = std::max(result.maxCost, top.cost);
    CollapseStep step;
    step.removed = v0;
    step.survivor = v1;
    for (int k = 0; k < 3; ++k) step.position[k] = static_cast<float>(applied.position[k]);
    step.cost = static_cast<float>(top.cost);
    step.facesAfter = static_cast<std::uint32_t>(mesh_.aliveFaceCount());
    if (deferUpdates_) {
        deferred_.push_back({applied, step});
    } else {
        if (metric_) metric_->onCollapse(mesh_, applied);
        if (onStep) onStep(step);
    }

    ++version_[v0];
    if (options_.kind == CollapseKind::Full) mesh_.neighbours(v1, ring_);
    affected.assign(1, v1);
    if (localCosts_) {
        // Only the survivor's edges changed cost; the ring's other edges keep their entries and
        // are re-validated when popped. Those found invalid then are priced again once a
        // collapse next to them may have made them valid.
        for (std::uint32_t v : ring_)
            if (v != v1 && dormant_[v]) {
                dormant_[v] = 0;
                affected.push_back(v);
            }
    } else {
        for (std::uint32_t v : ring_)
            if (v != v1) affected.push_back(v);
    }
    for (std::uint32_t v : affected) ++version_[v];
}

// Full collapses under costs that depend on the two ends only, in passes after meshoptimizer's
// simplifier (rank, sort, perform, update): each pass sorts the cheapest priced edges, collapses them
// in that order while their entries are current (a collapse makes its ends' entries stale) and still
// valid, then prices the touched vertices' edges at once, in parallel, for the next pass. Against
// the global queue, a survivor's new edges wait for the next pass instead of competing at once; a
// pass takes at most passFraction of the priced edges so that it does not run far ahead of the
// greedy order. No stale entry is ever sifted through a heap.
void Simplifier::runInPasses(EdgeCollapseResult& result, const std::function<void(const CollapseStep&)>& onStep) {
    deferUpdates_ = metric_->updatesCanBeDeferred();
    PassState state;
    state.touched.reset(mesh_.vertexCount());
    price(allVertices());
    // The first pricing covers every edge: its array becomes the pass's entries (not a copy of them;
    // the ranking drops the forbidden ones), and the list of edges goes, so that neither holds every
    // edge twice for the rest of the run.
    state.entries.swap(priced_);
    std::vector<QueueEntry>().swap(priced_);
    std::vector<std::pair<std::uint32_t, std::uint32_t>>().swap(edges_);
    while (mesh_.aliveFaceCount() > options_.targetFaceCount) {
        const std::size_t take = rankPass(state.entries);
        if (take == 0) {
            result.stop = StopReason::NoValidCollapse;
            break;
        }
        const bool goOn = performPass(state, take, result, onStep);
        flushDeferred(onStep);
        if (!goOn) break;
        updatePass(state);
    }
}

std::vector<std::uint32_t> Simplifier::allVertices() const {
    std::vector<std::uint32_t> all(mesh_.vertexCount());
    for (std::size_t v = 0; v < all.size(); ++v) all[v] = static_cast<std::uint32_t>(v);
    return all;
}

void Simplifier::reportCollapseProgress() {
    const std::size_t done = startFaces_ - mesh_.aliveFaceCount();
    if (!options_.progress || done < nextReport_) return;
    nextReport_ = done + reportStep_;
    reportProgress(options_.progress, std::min(1.0, static_cast<double>(done) / work_), "collapsing edges");
}

void Simplifier::keepPriced(std::vector<QueueEntry>& entries) const {
    for (const QueueEntry& e : priced_)
        if (e.cost < kInfinity) entries.push_back(e);
}

std::size_t Simplifier::rankPass(std::vector<QueueEntry>& entries) const {
    entries.erase(std::remove_if(entries.begin(), entries.end(),
                                 [&](const QueueEntry& e) { return e.cost == kInfinity || stale(e); }),
                  entries.end());
    if (entries.empty()) return 0;
    const std::size_t needed = (mesh_.aliveFaceCount() - options_.targetFaceCount + 1) / 2;
    const std::size_t share = static_cast<std::size_t>(options_.passFraction * static_cast<double>(entries.size()));
    const std::size_t take = std::min(entries.size(), std::max<std::size_t>(64, std::min(needed, share)));
    // (cost, first end, second end): a total order, the same on any thread count.
    const auto cheaper = [](const QueueEntry& x, const QueueEntry& y) {
        if (x.cost != y.cost) return x.cost < y.cost;
        return x.a != y.a ? x.a < y.a : x.b < y.b;
    };
    std::nth_element(entries.begin(), entries.begin() + (take - 1), entries.end(), cheaper);
    sortInParallel(entries.begin(), entries.begin() + take, cheaper, options_.threads);
    return take;
}

void Simplifier::checkAhead(PassState& state, std::size_t begin, std::size_t end) const {
    const int threads = options_.threads > 0 ? options_.threads : omp_get_max_threads();
    const long n = static_cast<long>(end - begin);
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads)
    for (long k = 0; k < n; ++k) {
        const QueueEntry& e = state.entries[begin + std::size_t(k)];
        state.verdict[std::size_t(k)] = verdictOf(e);
    }
}

// The validity checks, most of a pass's serial time, are made ahead in parallel for chunks of the
// ranked entries; an entry next to a collapse made since its check is checked again in order. The
// collapses are those of the serial loop, whatever the thread count.
bool Simplifier::performPass(PassState& state, std::size_t take, EdgeCollapseResult& result,
                             const std::function<void(const CollapseStep&)>& onStep) {
    constexpr std::size_t kChunk = 2048;
    const int threads = options_.threads > 0 ? options_.threads : omp_get_max_threads();
    const bool ahead = threads > 1 && options_.minValence == 0;
    if (ahead) {
        state.verdict.resize(kChunk);
        if (state.changed.vertexCount() != mesh_.vertexCount()) state.changed.reset(mesh_.vertexCount());
    }
    state.touched.clear();
    std::size_t performed = 0, chunkBegin = 0, chunkEnd = 0;
    for (std::size_t i = 0; i < take && mesh_.aliveFaceCount() > options_.targetFaceCount; ++i) {
        QueueEntry& e = state.entries[i];
        if (ahead && i == chunkEnd) {
            state.changed.clear();
            chunkBegin = i;
            chunkEnd = std::min(take, i + kChunk);
            checkAhead(state, chunkBegin, chunkEnd);
        }
        const Verdict check =
            ahead && checkedAheadStillHolds(state, e) ? static_cast<Verdict>(state.verdict[i - chunkBegin]) : verdictOf(e);
        if (check == kStale) {
            ++result.staleEntries;
            continue;
        }
        if (check == kForbidden) {
            ++result.staleEntries;
            dormant_[e.a] = dormant_[e.b] = 1;
            e.cost = kInfinity;  // dropped; priced again when a collapse touches an end
            continue;
        }
        if (e.cost > options_.maxError) {
            // The rest of this pass costs more, but the edges its collapses made may not: the run
            // stops only when a pass cannot start below the bound.
            if (performed > 0) return true;
            result.stop = StopReason::MaxErrorReached;
            return false;
        }
        applyCollapse(e, result, onStep, state.affected);
        ++performed;
        for (std::uint32_t v : state.affected) state.touched.insert(v);
        if (ahead) {  // the ends and the survivor's ring (ring_, filled by applyCollapse)
            state.changed.insert(e.a);
            state.changed.insert(e.b);
            for (std::uint32_t v : ring_) state.changed.insert(v);
        }
        reportCollapseProgress();
    }
    return true;
}

void Simplifier::flushDeferred(const std::function<void(const CollapseStep&)>& onStep) {
    if (deferred_.empty()) return;
    const int threads = options_.threads > 0 ? options_.threads : omp_get_max_threads();
    const long n = static_cast<long>(deferred_.size());
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads) if (n > 256)
    for (long i = 0; i < n; ++i) metric_->onCollapse(mesh_, deferred_[std::size_t(i)].query);
    if (onStep)
        for (const DeferredCollapse& d : deferred_) onStep(d.step);
    deferred_.clear();
}

void Simplifier::updatePass(PassState& state) {
    price(state.touched.list());
    state.touched.clear();
    keepPriced(state.entries);
}

EdgeCollapseResult Simplifier::run(const std::function<void(const CollapseStep&)>& onStep) {
    EdgeCollapseResult result;
    result.stop = StopReason::TargetReached;
    result.collapsedAlongBoundary = alongBoundary_;
    startFaces_ = mesh_.aliveFaceCount();
    if (startFaces_ > options_.targetFaceCount) {
        work_ = static_cast<double>(startFaces_ - options_.targetFaceCount);
        nextReport_ = 0;
        reportStep_ = std::max<std::size_t>(1, static_cast<std::size_t>(work_ / 100.0));
        if (localCosts_ && options_.passFraction > 0.0) runInPasses(result, onStep);
        else runQueue(result, onStep);
    }
    result.finalFaceCount = mesh_.aliveFaceCount();
    result.finalVertexCount = mesh_.aliveVertexCount();
    result.repricedVertices = pricings_;
    return result;
}

void Simplifier::runQueue(EdgeCollapseResult& result, const std::function<void(const CollapseStep&)>& onStep) {
    const std::vector<std::uint32_t> all = allVertices();
    queue_.clear();
    queue_.reserve(options_.kind == CollapseKind::HalfEdge ? all.size() : 3 * all.size());
    reprice(all);
    std::vector<std::uint32_t> affected;
    while (mesh_.aliveFaceCount() > options_.targetFaceCount) {
        if (queue_.empty()) {
            result.stop = StopReason::NoValidCollapse;
            break;
        }
        const QueueEntry top = queue_.pop().second;
        if (stale(top)) {
            ++result.staleEntries;
            continue;
        }
        if (options_.kind == CollapseKind::HalfEdge && top.stampB == 1) {
            // A lazy entry reached the front: price its source now.
            const QueueEntry priced = priceSource(top.a);
            ++pricings_;
            lastCost_[top.a] = priced.cost;
            push(priced);
            continue;
        }
        if (!stillAllowed(top)) {
            ++result.staleEntries;
            if (localCosts_) dormant_[top.a] = dormant_[top.b] = 1;
            if (options_.kind == CollapseKind::HalfEdge) {
                ++version_[top.a];  // the old entry is dead; price the source again
                push(priceSource(top.a));
                ++pricings_;
            }
            continue;
        }
        if (top.cost > options_.maxError) {
            result.stop = StopReason::MaxErrorReached;
            break;
        }

        applyCollapse(top, result, onStep, affected);
        if (options_.kind == CollapseKind::HalfEdge && options_.lazyRepricing) {
            // Queue each affected source at its previous cost (a guess: costs mostly grow as the
            // mesh coarsens) and price it only when it reaches the front.
            for (std::uint32_t v : affected) {
                const double guess = lastCost_[v] < kInfinity ? lastCost_[v] : top.cost;
                queue_.push(guess, v, {guess, v, v, version_[v], 1, {0.0, 0.0, 0.0}});
            }
        } else {
            reprice(affected);
        }
        reportCollapseProgress();
    }
}

}  // namespace

EdgeCollapseResult simplifyByEdgeCollapse(CollapseMesh& mesh, CollapseMetric* metric, const EdgeCollapseOptions& options,
                                          const std::function<void(const CollapseStep&)>& onStep) {
    if (const std::string problem = options.validate(); !problem.empty()) throw std::invalid_argument(problem);
    if (options.kind == CollapseKind::Full && metric != nullptr && options.attributeWeight > 0.0) {
        std::string why;
        if (!metric->supportsFullCollapse(why)) throw std::invalid_argument(why);
    }
    Simplifier simplifier(mesh, metric, options);
    return simplifier.run(onStep);
}

}  // namespace rad
