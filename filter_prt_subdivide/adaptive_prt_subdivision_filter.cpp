// "Radiance: Adaptive PRT Subdivision": Křivánek et al. 2004, Fig. 2-3 and eq. 2-4: the triangles
// whose transfer vectors change fast are split first, under a triangle budget, the transfer of new
// vertices ray-cast (common/prt/adaptive_subdivision.h).
#include "prt_subdivide_plugin.h"

#include "citations.h"
#include "prt_subdivision_common.h"

#include "prt/adaptive_subdivision.h"

#include <QElapsedTimer>

namespace radml {
namespace {

class AdaptivePrtSubdivisionFilter : public Filter {
public:
    QString name() const override { return "Radiance: Adaptive PRT Subdivision"; }
    QString pythonName() const override { return "radiance_adaptive_prt_subdivision"; }
    QString description() const override {
        return QString(
                   "Subdivides the current mesh where its PRT transfer vectors change fast (Křivánek et al. 2004, "
                   "Fig. 2): every triangle's error estimate enters a priority queue; the worst triangle is split "
                   "1-to-4 at its edge midpoints "
                   "(Fig. 3a) until the triangle budget is reached or no triangle is above the threshold. The "
                   "transfer vectors of new vertices are ray-cast with the settings of 'Compute PRT Transfer', "
                   "never interpolated. T-vertices are removed afterwards by splitting the neighbouring triangles "
                   "in 2, 3 or 4 (Fig. 3b, 3c), so the result is conforming; the budget counts those triangles too. "
                   "The error estimate of every face is written as face quality and face colour (red = highest), "
                   "so you see where the mesh is still undersampled. The surface does not move (flat splits). "
                   "Estimates: the paper's eq. 2 (|t1-t2|/|t1+t2| per edge), eq. 3 (|t1-t2| per edge) and eq. 4 "
                   "(eq. 3 divided by 1 + alpha times the divergence of the vertex normals), computed from the "
                   "corners; or, the default, the probed interpolation error: the transfer is ray-cast at each "
                   "edge's midpoint (where a split puts its vertex, so the rays are not wasted) and compared with "
                   "the interpolation of the edge's ends, relative to the transfer's magnitude (or absolute), "
                   "times the triangle's share of the surface. Eq. 2-4 cannot see what the interpolation misses "
                   "on curved, self-shadowing scans (the terminator, shadow edges inside a triangle): there they "
                   "do worse than uniform subdivision, the probed estimate does better (README, PRT figures). It "
                   "costs about three times the rays of eq. 2-4. "
                   "Needs a clean manifold mesh with vertex normals and transfer vectors of one channel (computed "
                   "without albedo).") +
               kCiteSloan2002Krivanek2004;
    }
    int filterClass() const override { return 0x00004; /* Remeshing */ }
    int postconditions() const override {
        return MeshModel::MM_GEOMETRY_AND_TOPOLOGY_CHANGE | MeshModel::MM_FACEQUALITY | MeshModel::MM_FACECOLOR |
               MeshModel::MM_VERTCOLOR | MeshModel::MM_VERTQUALITY;
    }

    RichParameterList parameters(const MeshDocument&, const MeshModel& m) const override {
        RichParameterList par;
        addBudgetParameters(par, m);
        par.addParam(RichEnum("measure", 3, measureChoices(), "Error estimate",
                              "Triangle error estimate: Křivánek et al. 2004, sec. 3.3, eq. 2-4 (sum over the edges, "
                              "from the corners), or the probed midpoint interpolation error (default: it wins on "
                              "curved scans and on the paper's column)."));
        par.addParam(RichFloat("alpha", float(rad::kDefaultNormalDivergenceAlpha), "Alpha (eq. 4)",
                               "Weight of the normal divergence (radians) in eq. 4: larger values refine curved "
                               "regions less."));
        par.addParam(RichFloat("threshold", 0.0f, "Error threshold",
                               "Triangles whose estimate is at or below it are never split (0: spend the whole "
                               "budget). For the probed estimates the value is the triangle's share of the mean "
                               "error over the surface."));
        return par;
    }

    std::string outOfMemoryAdvice() const override { return kPrtOutOfMemoryAdvice; }

    void apply(FilterContext& ctx) const override { subdivide(ctx); }

private:
    void subdivide(FilterContext& ctx) const {
        const RichParameterList& par = ctx.parameters;
        QElapsedTimer timer;
        timer.start();
        const PrtSubdivisionInput input = prepareSubdivision(ctx);
        rad::AdaptiveSubdivisionOptions options;
        options.measure = measureParameter(par);
        options.alpha = par.getFloat("alpha");          // the core refuses a negative or non-finite alpha (eq. 4)
        options.threshold = par.getFloat("threshold");  // and threshold
        options.triangleBudget = static_cast<std::size_t>(input.budget);
        options.progress = ctx.progress.forCore();
        const rad::SubdivisionResult result =
            subdivideWithRayCasting(ctx, input, [&](const rad::TransferOracle& oracle) {
                ctx.progress.setPhase(2, 95, "Adaptive PRT subdivision");
                return rad::subdivideAdaptively(input.mesh, oracle, options);
            });
        replaceWithSubdivision(ctx, input, result);
        ctx.log(formatLine(
            "Adaptive PRT subdivision (%s, alpha %.3g): %zu -> %zu faces, %zu vertices (%zu new, ray-cast; %zu "
            "midpoints probed for the estimate); %zu regular splits (%zu forced for 1-irregularity), %zu T-vertex "
            "fixes; stopped: %s, largest remaining estimate %.4g; %.2f s",
            measureCitation(par), options.alpha, input.faces, result.mesh.faceCount(), result.mesh.vertexCount(),
            result.newVertices, result.probes, result.regularSplits, result.forcedSplits, result.tVertexFixes,
            result.stop == rad::SubdivisionStop::BudgetReached ? "budget reached" : "no triangle above the threshold",
            result.largestRemainingError, timer.elapsed() / 1000.0));
        if (result.mesh.faceCount() == input.faces)
            ctx.warning(formatLine("No triangle was split: the budget (%lld) leaves no room for a split or no "
                                   "estimate exceeds the threshold.",
                                   input.budget));
    }
};

}  // namespace

std::unique_ptr<Filter> makeAdaptivePrtSubdivisionFilter() { return std::make_unique<AdaptivePrtSubdivisionFilter>(); }

}  // namespace radml
