// "Radiance: Transfer Radiance from Gaussian Splats": a 3D Gaussian Splatting scene (Kerbl et al. 2023)
// read from its .ply (common/splats/gaussian_splat_ply.h) and moved onto the current mesh's vertices as
// SH radiance functions (common/splats/splat_radiance_transfer.h). The layer changes only once the
// file was read whole and the transfer succeeded.
#include "radiance_fit_plugin.h"

#include "citations.h"
#include "radiance_attribute.h"
#include "usable_normals.h"
#include "vertex_colors.h"

#include "splats/gaussian_splat_ply.h"
#include "splats/splat_radiance_transfer.h"

#include <QElapsedTimer>

#include <cmath>
#include <numeric>

namespace radml {
namespace {

class TransferGaussianSplatsFilter : public Filter {
public:
    QString name() const override { return "Radiance: Transfer Radiance from Gaussian Splats"; }
    QString pythonName() const override { return "radiance_transfer_gaussian_splats"; }
    QString description() const override {
        return QString(
                   "Reads a <b>3D Gaussian Splatting</b> scene (the .ply written by the reference implementation "
                   "of Kerbl et al. 2023, \"3D Gaussian Splatting for Real-Time Radiance Field Rendering\", or by "
                   "SuperSplat: f_dc_*, f_rest_*, opacity, scale_*, rot_*; ASCII or binary) and transfers the "
                   "splats' view-dependent colour onto every vertex of the current mesh as a spherical-harmonic "
                   "radiance function of the splats' degree (Vanhoey et al. 2015, sec. 6: SH in the global frame). "
                   "A splat counts for a vertex when it is near (within 3 standard deviations of its Gaussian, "
                   "widened by the vertex's footprint, half its mean edge length) and in front (its centre not "
                   "deeper below the vertex's tangent plane than the front tolerance), weighted by its opacity "
                   "times its Gaussian at the vertex; splats larger than the size limit are ignored (background). "
                   "The splats' display-referred colour (SH + 0.5, SH_C0 = 0.28209479, Condon-Shortley phase, "
                   "camera-to-splat direction) is blended, decoded from sRGB to linear radiance and fitted over "
                   "each vertex's hemisphere. The vertex colour becomes the RF's mean colour. Vertices no splat "
                   "reaches get black and are counted. The mesh and the splats must share one coordinate frame. "
                   "Conventions: docs/gaussian-splats.md.") +
               kCiteVanhoey2015;
    }
    int filterClass() const override { return 0x00010; /* VertexColoring */ }
    int postconditions() const override { return MeshModel::MM_VERTCOLOR; }

    RichParameterList parameters(const MeshDocument&, const MeshModel&) const override {
        const rad::SplatTransferOptions defaults;
        RichParameterList par;
        addOpenFileParameter(par, "splatfile", "", QStringList() << "*.ply", "Splat file",
                             "The 3D Gaussian Splatting .ply (point_cloud/iteration_N/point_cloud.ply of the reference "
                             "trainer, or an uncompressed .ply exported by SuperSplat).");
        par.addParam(RichFloat("maxSplatSize", float(100.0 * defaults.maxSplatSize), "Size limit (%)",
                               "Splats whose largest standard deviation exceeds this percentage of the mesh's "
                               "bounding-box diagonal are ignored: they are background, sky or floaters."));
        par.addParam(RichFloat("frontTolerance", float(defaults.frontTolerance), "Front tolerance (footprints)",
                               "A splat whose centre lies deeper below a vertex's tangent plane than this many vertex "
                               "footprints (half the vertex's mean edge length) is behind the surface and ignored. "
                               "Raise it when the mesh lies outside the splats (a coarse mesh)."));
        par.addParam(RichBool("setColor", true, "Set vertex colour to the mean colour",
                              "Vertex colour := the RF's mean over its hemisphere (sRGB-encoded)."));
        return par;
    }

    void apply(FilterContext& ctx) const override {
        QElapsedTimer timer;
        timer.start();
        const RichParameterList& par = ctx.parameters;
        const QString file = par.getOpenFileName("splatfile").trimmed();
        if (file.isEmpty())
            throw Refusal("Splat file: none given; give the .ply of a 3D Gaussian Splatting scene (splatfile).");
        rad::SplatTransferOptions options;
        options.maxSplatSize = par.getFloat("maxSplatSize") / 100.0;
        options.frontTolerance = par.getFloat("frontTolerance");
        if (!(options.maxSplatSize > 0.0) || !std::isfinite(options.maxSplatSize))
            throw Refusal(formatLine("Size limit: %g %% is not usable; give a positive percentage of the bounding-box "
                                     "diagonal (10 keeps every splat of the object).", 100.0 * options.maxSplatSize));
        if (!(options.frontTolerance >= 0.0) || !std::isfinite(options.frontTolerance))
            throw Refusal(formatLine("Front tolerance: %g is not usable; give 0 or more footprints (1 by default).",
                                     options.frontTolerance));

        // 1. The splats, read and validated whole.
        ctx.progress.setPhase(0, 20, "Reading splats");
        const rad::GaussianSplats splats = rad::readGaussianSplatPly(file.toStdString(), ctx.progress.forCore());
        ctx.log(formatLine("Read %zu splats of SH degree %d from '%s'.", splats.count(), splats.shDegree,
                           file.toStdString().c_str()));

        // 2. The mesh (normals repaired in our copy where unusable).
        MeshModel& m = ctx.mesh();
        VertexArrays vertices = collectVertexArrays(m.cm);
        makeNormalsUsable(ctx, vertices.positions, vertices.faces, vertices.normals);

        // 3. The transfer, computed aside.
        ctx.progress.setPhase(20, 95, "Transferring splat radiance");
        const rad::SplatTransferResult result = rad::transferSplatRadiance(
            vertices.positions, vertices.normals, vertices.faces, splats, options, ctx.progress.forCore());

        // 4. The layer changes only now.
        const std::size_t n = vertices.count();
        const bool setColor = par.getBool("setColor");
        std::vector<float> meanColor = std::move(result.meanColor);
        attachRadiance(m.cm, std::move(result.field));
        if (setColor) setVertexColorsFromLinear(m, meanColor);
        ctx.progress.setPhase(100, 100, "Done");
        const double reached = double(n - result.verticesWithoutSplats);
        const double perVertex =
            reached > 0 ? std::accumulate(result.splatCount.begin(), result.splatCount.end(), 0.0) / reached : 0.0;
        ctx.log(formatLine("Transferred SH%d radiance functions onto %zu vertices in %.2f s: %zu of the %zu splats used "
                           "(%zu larger than the size limit, %zu far from the mesh), %.1f splats per reached vertex, "
                           "mean vertex footprint %g.",
                           splats.shDegree, n, timer.elapsed() / 1000.0, result.splatsUsed, splats.count(),
                           result.splatsTooLarge, result.splatsFar, perVertex, result.meanFootprint));
        if (result.verticesWithoutSplats > 0)
            ctx.warning(formatLine("%zu of the %zu vertices have no splat near them and in front of them: their radiance "
                                   "is black. Check the alignment of mesh and splats, or raise the front tolerance.",
                                   result.verticesWithoutSplats, n));
    }
};

}  // namespace

std::unique_ptr<Filter> makeTransferGaussianSplatsFilter() { return std::make_unique<TransferGaussianSplatsFilter>(); }

}  // namespace radml
