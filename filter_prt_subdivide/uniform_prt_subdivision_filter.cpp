// "Radiance: Uniform PRT Subdivision": the baseline of Křivánek et al. 2004, Fig. 1(b): every
// triangle split 1-to-4 as many times as the budget allows, the transfer of new vertices ray-cast.
#include "prt_subdivide_plugin.h"

#include "citations.h"
#include "prt_subdivision_common.h"

#include "prt/adaptive_subdivision.h"

#include <QElapsedTimer>

namespace radml {
namespace {

class UniformPrtSubdivisionFilter : public Filter {
public:
    QString name() const override { return "Radiance: Uniform PRT Subdivision"; }
    QString pythonName() const override { return "radiance_uniform_prt_subdivision"; }
    QString description() const override {
        return QString(
                   "The baseline of Křivánek et al. 2004, Fig. 1(b): splits every triangle 1-to-4 as many times as "
                   "the triangle budget allows and ray-casts the transfer vectors of the new vertices. Face quality "
                   "and colour show the same error estimate as the adaptive filter.") +
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
        par.addParam(RichEnum("measure", 2, measureChoices(), "Error estimate shown",
                              "The estimate written as face quality, for comparison with the adaptive filter "
                              "(eq. 2-4 of Křivánek et al. 2004 from the corners; the probed ones ray-cast every "
                              "final edge's midpoint, about three times the rays of the subdivision itself, so "
                              "eq. 4 is the default here)."));
        par.addParam(RichFloat("alpha", float(rad::kDefaultNormalDivergenceAlpha), "Alpha (eq. 4)",
                               "Weight of the normal divergence in eq. 4."));
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
        const rad::TransferErrorMeasure measure = measureParameter(par);
        const double alpha = par.getFloat("alpha");  // the core refuses a negative or non-finite alpha (eq. 4)
        const rad::SubdivisionResult result =
            subdivideWithRayCasting(ctx, input, [&](const rad::TransferOracle& oracle) {
                ctx.progress(5, "Uniform subdivision and ray casting");
                return rad::subdivideUniformly(input.mesh, oracle, static_cast<std::size_t>(input.budget), measure,
                                               alpha);
            });
        replaceWithSubdivision(ctx, input, result);
        ctx.log(formatLine("Uniform PRT subdivision (Křivánek et al. 2004, Fig. 1b): %zu -> %zu faces, %zu vertices "
                           "(%zu new, ray-cast); %.2f s",
                           input.faces, result.mesh.faceCount(), result.mesh.vertexCount(), result.newVertices,
                           timer.elapsed() / 1000.0));
        if (result.mesh.faceCount() == input.faces)
            ctx.warning(formatLine("No triangle was split: the budget (%lld) leaves no room for a split of every "
                                   "triangle (uniform needs 4x the faces).",
                                   input.budget));
    }
};

}  // namespace

std::unique_ptr<Filter> makeUniformPrtSubdivisionFilter() { return std::make_unique<UniformPrtSubdivisionFilter>(); }

}  // namespace radml
