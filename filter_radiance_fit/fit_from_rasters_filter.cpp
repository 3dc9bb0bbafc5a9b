// "Radiance: Fit Radiance Functions from Rasters": the adapter between MeshLab's document (mesh +
// raster layers) and the fitting core (common/fit/radiance_from_views.h). Parameters in, views and
// mesh out of MeshLab, one core call, then the layer is changed only after everything succeeded.
#include "radiance_fit_plugin.h"

#include "basis_parameters.h"
#include "citations.h"
#include "mesh_conversion.h"
#include "radiance_attribute.h"
#include "raster_views.h"
#include "usable_normals.h"

#include "fit/radiance_from_views.h"
#include "radiance/view_colors.h"

#include <QElapsedTimer>

#include <cmath>

namespace radml {
namespace {

enum QualityChoice { kQualitySampleCount = 0, kQualityResidual = 1 };

class FitFromRastersFilter : public Filter {
public:
    QString name() const override { return "Radiance: Fit Radiance Functions from Rasters"; }
    QString description() const override;
    int filterClass() const override { return 0x00010 | 0x40000 | 0x00400; /* VertexColoring | Camera | RasterLayer */ }
    int postconditions() const override { return MeshModel::MM_VERTCOLOR | MeshModel::MM_VERTQUALITY; }

    RichParameterList parameters(const MeshDocument&, const MeshModel& m) const override {
        RichParameterList par;
        const rad::RobustFitOptions fitDefaults;
        const rad::ViewSamplingOptions samplingDefaults;
        const float diagonal = m.cm.bbox.IsNull() ? 1.0f : m.cm.bbox.Diag();
        par.addParam(RichBool("visibleOnly", false, "Only visible rasters",
                              "Use only the raster layers that are visible in the raster list (the eye icon); "
                              "otherwise every raster of the document."));
        addBasisParameters(par, "PB(4) (15 coefficients) suits a few dozen photographs.");
        par.addParam(RichFloat("regularization", float(fitDefaults.lambda), "Regularisation",
                               "Tikhonov weight toward the vertex's mean colour, relative to the data term "
                               "(0 = plain least squares; 1e-3 .. 1e-1 sensible). Larger values give smoother, "
                               "less view-dependent functions."));
        addAbsoluteOrPercentParameter(par, "depthTolerance", diagonal * 1e-3f, 0.0f, diagonal, "Depth tolerance",
                                 "Occluders closer to the vertex than this along the ray toward the camera are "
                                 "ignored (absolute, or a percentage of the bounding-box diagonal). Raise it for "
                                 "noisy scans whose surface self-intersects slightly.");
        par.addParam(RichFloat("grazingAngle", float(samplingDefaults.grazingAngleDegrees), "Grazing-angle cut-off",
                               "A photograph is used for a vertex only if the angle between the vertex normal and "
                               "the direction to the camera is below this (degrees, 0..90): grazing views are "
                               "blurred and misregistered."));
        par.addParam(RichInt("borderMargin", int(samplingDefaults.borderMarginPixels), "Image-border margin",
                             "Projections closer than this many pixels to the image border are ignored."));
        par.addParam(RichInt("minSamples", fitDefaults.minSamples, "Minimum sample count",
                             "Vertices with fewer samples get their mean colour as a constant function (counted "
                             "as poorly sampled)."));
        par.addParam(RichBool("reflected", false, "Store reflected functions",
                              "Store the reflected RF L~(w) = L(R_n w) (Vanhoey et al. 2015, sec. 3.1) instead of L; both evaluate to "
                              "the same radiance. Reflected storage suits interpolation and simplification."));
        par.addParam(RichEnum("quality", kQualitySampleCount, QStringList() << "Sample count" << "Fit residual",
                              "Vertex quality", "What the vertex quality holds after the fit: the number of "
                              "photographs used by the vertex, or the RMS residual of its fit (linear units)."));
        par.addParam(RichBool("setColor", true, "Set vertex colour to the mean colour",
                              "Vertex colour := the vertex's mean (diffuse) colour over its samples, "
                              "sRGB-encoded."));
        return par;
    }

    void apply(FilterContext& ctx) const override {
        const RichParameterList& par = ctx.parameters;
        MeshDocument& md = ctx.document;
        MeshModel& m = ctx.mesh;
        QElapsedTimer timer;
        timer.start();

        rad::RadianceFromViewsOptions options;
        options.fit.basis = basisParameters(par);
        options.fit.storeReflected = par.getBool("reflected");
        options.fit.lambda = par.getFloat("regularization");
        options.fit.minSamples = par.getInt("minSamples");
        options.sampling.depthTolerance = absoluteOrPercentParameter(par, "depthTolerance");
        options.sampling.grazingAngleDegrees = par.getFloat("grazingAngle");
        options.sampling.borderMarginPixels = par.getInt("borderMargin");
        for (const std::string& problem : {options.fit.validate(), options.sampling.validate()}) {
            if (!problem.empty()) throw Refusal(problem);
        }

        const bool visibleOnly = par.getBool("visibleOnly");
        RasterViews rasters = collectRasterViews(md, visibleOnly);
        if (rasters.rasterCount == 0) {
            throw Refusal(visibleOnly ? "No visible raster layer: show some rasters (eye icon) or fit on all rasters."
                                       : "The document has no raster layers: open the photographs with their cameras "
                                         "first (File > Open Project: .mlp, Bundler .out; or File > Import Raster and "
                                         "align them); from pymeshlab, MeshSet.load_project('photos.mlp') or load_new_raster.");
        }
        for (const std::string& warning : rasters.warnings) ctx.warning(warning);
        if (rasters.views.empty())
            throw Refusal(formatLine("None of the %zu raster layers is usable (see the warnings above).",
                                     rasters.rasterCount));

        rad::RadianceMesh plain;
        std::string why;
        ExportChoice choice;
        choice.transfer = false;  // not used here (and not required to cover every vertex)
        choice.colors = choice.quality = choice.radiance = false;
        if (!exportPlainMesh(m.cm, choice, plain, why)) throw Refusal(why);
        rad::TriangleMesh mesh;
        mesh.positions = std::move(plain.positions);
        mesh.normals = std::move(plain.normals);
        mesh.faces = std::move(plain.faces);
        makeNormalsUsable(ctx, mesh.positions, mesh.faces, mesh.normals);
        if (mesh.faceCount() == 0)
            ctx.warning("The mesh has no faces: occlusion cannot be tested, every facing photograph is used.");

        // Everything is computed aside; the layer changes only once the fit succeeded.
        rad::RadianceFromViewsResult result;
        try {
            result = rad::fitRadianceFromViews(mesh, rasters.views, options, ctx.progress.forCore());
        } catch (const rad::FitError& e) {
            throw Refusal(e.what());
        }
        for (const std::string& warning : result.warnings) ctx.warning(warning);

        const std::size_t n = mesh.vertexCount();
        const bool setColor = par.getBool("setColor");
        const bool residualQuality = par.getEnum("quality") == kQualityResidual;
        attachRadiance(m.cm, std::move(result.field));
        std::size_t i = 0;
        for (CVertexO& v : m.cm.vert) {
            if (v.IsD()) continue;
            v.Q() = residualQuality ? result.residual[i] : result.sampleCount[i];
            if (setColor)
                v.C() = vcg::Color4b(rad::encodeSrgb8(result.meanColor[3 * i]), rad::encodeSrgb8(result.meanColor[3 * i + 1]),
                                     rad::encodeSrgb8(result.meanColor[3 * i + 2]), 255);
            ++i;
        }
        m.updateDataMask(MeshModel::MM_VERTQUALITY);
        if (setColor) m.updateDataMask(MeshModel::MM_VERTCOLOR);
        ctx.progress(100, "Done");
        ctx.log(formatLine("Fitted %s radiance functions%s from %zu of %zu rasters (%zu samples) on %zu vertices in %.2f s: "
            "%zu fitted, %zu poorly sampled (%zu given their mean colour), %zu unseen filled from neighbours, "
            "%zu unseen left black",
            options.fit.basis.name().c_str(), options.fit.storeReflected ? " (reflected)" : "", result.viewsUsed,
            rasters.rasterCount, result.totalSamples, n, timer.elapsed() / 1000.0, result.fitted, result.poorlySampled,
            result.constantFallbacks, result.unseenFilled, result.unseenLeft));
}
};

QString FitFromRastersFilter::description() const {
    return QString(
               "Fits a view-dependent radiance function (RF) to every vertex of the current mesh from the "
               "calibrated photographs of the document's raster layers (open them with File > Import "
               "Raster or a project: .mlp, Bundler .out), keeping the view dependence (highlights, gloss) "
               "that <i>Project active rasters color to current mesh</i> averages away (Vanhoey et al. 2015, sec. 7, "
               "'Data acquisition and reconstruction').<br>"
               "A photograph contributes a sample to a vertex only where the vertex is in front of its "
               "camera, projects inside the image (minus the border margin), faces the camera within the "
               "grazing-angle cut-off, and is not hidden by any part of the mesh (an Embree ray cast from "
               "the vertex toward the camera, ignoring hits closer than the depth tolerance). Pixels are "
               "read with bilinear interpolation and decoded from sRGB to linear radiance.<br>"
               "Each vertex's samples are fitted by weighted least squares (weight = cosine of the viewing "
               "angle) in PB(d) (local frame) or SH(d) (global frame), with a Tikhonov regularisation "
               "toward the vertex's mean colour. Against overshooting on poorly sampled vertices (few or "
               "clustered directions; after Vanhoey et al., 'Robust Fitting on Poorly Sampled Data for "
               "Surface Light Field Rendering and Image Relighting', CGF 2013) the hemisphere directions "
               "no photograph covers receive virtual samples of the mean colour, and a fit that leaves "
               "the range of the vertex's observed colours is regularised further, down to the constant "
               "mean colour. Vertices with fewer samples than the minimum get their mean colour as a "
               "constant RF; vertices no photograph sees are filled from their neighbours.<br>"
               "Output: the radiance data (save as .rply), the vertex colour = the mean (diffuse) colour, "
               "the vertex quality = sample count or fit residual. Cameras with lens distortion are "
               "skipped (undistort the photographs first); the images must have the cameras' size.") +
           kCiteVanhoey2015;
}

}  // namespace

std::unique_ptr<Filter> makeFitFromRastersFilter() { return std::make_unique<FitFromRastersFilter>(); }

}  // namespace radml
