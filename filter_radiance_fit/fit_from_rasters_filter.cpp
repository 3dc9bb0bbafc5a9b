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

#include "fit/held_out_evaluation.h"
#include "fit/radiance_from_views.h"
#include "radiance/view_colors.h"

#include <QElapsedTimer>

#include <algorithm>
#include <cmath>

namespace radml {
namespace {

enum QualityChoice { kQualitySampleCount = 0, kQualityResidual = 1 };

rad::RadianceFromViewsOptions fitOptionsFromParameters(const RichParameterList& par) {
    rad::RadianceFromViewsOptions options;
    options.fit.basis = basisParameters(par);
    options.fit.storeReflected = par.getBool("reflected");
    options.fit.lambda = par.getFloat("regularization");
    options.fit.minSamples = par.getInt("minSamples");
    options.sampling.depthTolerance = absoluteOrPercentParameter(par, "depthTolerance");
    options.sampling.grazingAngleDegrees = par.getFloat("grazingAngle");
    options.sampling.borderMarginPixels = par.getInt("borderMargin");
    if (!par.getBool("validation")) options.fit.validationLambdas = 0;
    if (!par.getBool("robust")) options.fit.robustIterations = 0;
    options.compensateExposure = par.getBool("exposureCompensation");
    const int model = par.getEnum("fitModel");
    options.model = model == 1 ? rad::FitModel::PerVertex
                  : model == 2 ? rad::FitModel::Shared
                               : rad::FitModel::Automatic;
    options.shared.guardStandardErrors = par.getFloat("sharedGuard");
    options.shared.lightDistance = par.getFloat("lightDistance");
    return options;
}

int heldOutEveryFromParameters(const RichParameterList& par) {
    const int heldOutEvery = par.getInt("heldOutEvery");
    if (heldOutEvery < 0 || heldOutEvery == 1)
        throw Refusal(formatLine("Hold out every k-th raster: %d is not usable; use 0 to fit on every raster, or k >= 2 "
                                 "to leave rasters k, 2k, ... out of the fit and test the fit on them.", heldOutEvery));
    return heldOutEvery;
}

void refuseInvalidOptions(const rad::RadianceFromViewsOptions& options) {
    for (const std::string& problem : {options.fit.validate(), options.sampling.validate(), options.validate()}) {
        if (!problem.empty()) throw Refusal(problem);
    }
}

// The document's raster layers (or only the visible ones) that can be used, the others warned about.
RasterViews usableRasters(FilterContext& ctx, bool visibleOnly) {
    RasterViews rasters = collectRasterViews(ctx.document, visibleOnly);
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
    return rasters;
}

// The usable rasters split into those the fit uses and those held out to test it.
struct RasterSplit {
    std::vector<rad::CalibratedView> training, heldOut;
    std::vector<QString> trainingLabels, heldOutLabels;
};

// Held-out rasters: every k-th usable one, in the order of the raster list.
RasterSplit splitHeldOutRasters(const RasterViews& rasters, int heldOutEvery) {
    RasterSplit split;
    for (std::size_t i = 0; i < rasters.views.size(); ++i) {
        const bool out = heldOutEvery >= 2 && (i + 1) % static_cast<std::size_t>(heldOutEvery) == 0;
        (out ? split.heldOut : split.training).push_back(rasters.views[i]);
        (out ? split.heldOutLabels : split.trainingLabels).push_back(rasters.labels[i]);
    }
    if (heldOutEvery >= 2 && split.heldOut.empty())
        throw Refusal(formatLine("Hold out every %d-th raster: only %zu usable rasters, so none would be held out; "
                                 "use a k of at most %zu, or 0.", heldOutEvery, rasters.views.size(),
                                 rasters.views.size()));
    return split;
}

// The layer's positions, faces and (usable) normals for the core.
rad::TriangleMesh meshForFit(FilterContext& ctx, MeshModel& m) {
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
    return mesh;
}

// The radiance attribute (moved out of the result), the vertex quality and, if asked, the colour.
void storeFitInLayer(MeshModel& m, rad::RadianceFromViewsResult& result, bool setColor, bool residualQuality) {
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
}

// The log of a normal acquisition must read as what it is: most vertices of a few dozen photographs
// have fewer samples than a free fit of the basis would need, and the validation, not a
// sample-count threshold, decides whether their view dependence is kept.
void logFitSummary(FilterContext& ctx, const rad::RadianceFromViewsOptions& options,
                   const rad::RadianceFromViewsResult& result, std::size_t n, const RasterSplit& split,
                   std::size_t rasterCount, double seconds) {
    const std::size_t seen = n - result.unseenFilled - result.unseenLeft;
    ctx.log(formatLine("Fitted %s radiance functions%s on %zu vertices from %zu of %zu rasters%s in %.2f s: "
                       "%zu samples, median %.0f per seen vertex.",
                       options.fit.basis.name().c_str(), options.fit.storeReflected ? " (reflected)" : "", n,
                       split.training.size(), rasterCount,
                       split.heldOut.empty() ? "" : formatLine(" (%zu held out)", split.heldOut.size()).c_str(),
                       seconds, result.totalSamples, result.medianSamples));
    ctx.log(formatLine("Of the %zu seen vertices: %zu view-dependent functions (%zu of them with a stronger "
                       "regularisation or a lower degree chosen by validation), %zu constant mean colours because "
                       "validation found them better at predicting the vertex's left-out views, %zu constant because "
                       "of fewer than %d samples, %zu constant after the range guard. %zu unseen vertices filled "
                       "from their neighbours, %zu unseen left black.",
                       seen, result.viewDependent, result.regularised, result.validatedConstant,
                       result.tooFewSamples, options.fit.minSamples, result.guardConstant, result.unseenFilled,
                       result.unseenLeft));
}

// How far the shared lobe takes the lights to be (Vanhoey et al.'s reflected parametrisation assumes
// them distant; the fit chooses a distance unless the user fixed one).
std::string lightDistanceText(double distance, const rad::SharedFitOptions& options) {
    if (!std::isfinite(distance) || distance >= 1e6)
        return options.lightDistance == 0.0 ? "distant lights, chosen" : "distant lights";
    return formatLine("lights at %.2g bounding radii%s", distance, options.lightDistance == 0.0 ? ", chosen" : "");
}

// The automatic choice between the shared and the per-vertex fit, and the robust weights.
void logModelChoice(FilterContext& ctx, const rad::RadianceFromViewsOptions& options,
                    const rad::RadianceFromViewsResult& result) {
    if (result.modelValidated)
        ctx.log(formatLine("Fit model chosen on every %d-th raster left out (%zu rasters, %zu samples at %zu of "
                           "%zu vertices%s): %s; RMS "
                           "error in sRGB levels on them: per-vertex %.2f, shared diffuse + reflected lobe %.2f, "
                           "constant mean colour %.2f; shared better or equal in %zu of %zu left-out rasters, "
                           "worst raster shared / per-vertex %.3f (shared needs: better overall, at least half "
                           "the rasters, none worse than %.3f: the larger of %.3f and its overall gain).",
                           options.validationEvery, result.validationViews, result.validationSamples,
                           result.validationVertices, result.meanColor.size() / 3,
                           result.validationVertices < result.meanColor.size() / 3 ? ", patches of the surface" : "",
                           result.modelUsed == rad::FitModel::Shared ? "shared" : "per vertex",
                           result.validationPerVertex, result.validationShared, result.validationConstant,
                           result.validationViewsSharedWins, result.validationViewsCompared,
                           result.validationWorstViewRatio,
                           rad::sharedWorstViewBound(result.validationPerVertex, result.validationShared,
                                                     options.maxViewLoss),
                           1.0 + options.maxViewLoss));
    if (result.modelUsed == rad::FitModel::Shared)
        ctx.log(formatLine("Shared fit (SH%d lobe of the reflected direction, %s): %zu vertices diffuse + scaled "
                           "lobe; the others (too few photographs, or where the constant predicted their own "
                           "left-out photographs better by more than %g standard errors) %s.",
                           result.lobeDegree, lightDistanceText(result.lightDistance, options.shared).c_str(),
                           result.sharedVertices, options.shared.guardStandardErrors,
                           options.sharedRejectedPerVertex ? "the per-vertex fit" : "their constant mean colour"));
    if (options.fit.robustIterations > 0 || result.saturatedSamples > 0)
        ctx.log(formatLine("Robust weights: %zu samples down-weighted as outliers, %zu samples at saturation "
                           "given 1 %% weight.", result.robustDownweighted, result.saturatedSamples));
}

void logExposureGains(FilterContext& ctx, const rad::RadianceFromViewsResult& result, const RasterSplit& split) {
    std::string gains;
    double lo = 1e300, hi = 0.0;
    for (std::size_t i = 0; i < split.training.size(); ++i) {
        const double* g = result.viewGains.data() + 3 * i;
        gains += formatLine("%s%s %.3f %.3f %.3f", i ? "; " : "", split.trainingLabels[i].toStdString().c_str(), g[0],
                            g[1], g[2]);
        for (int c = 0; c < 3; ++c) {
            lo = std::min(lo, g[c]);
            hi = std::max(hi, g[c]);
        }
    }
    ctx.log(formatLine("Exposure compensation (%zu rasters estimated from %zu samples): gains between %.3f and "
                       "%.3f, per raster (R G B): %s.", result.exposureViews, result.exposureSamples, lo, hi,
                       gains.c_str()));
}

void logHeldOutEvaluation(FilterContext& ctx, const rad::HeldOutEvaluation& evaluation, const RasterSplit& split) {
    for (std::size_t i = 0; i < split.heldOut.size(); ++i) {
        const rad::HeldOutViewError& e = evaluation.views[i];
        if (e.vertices == 0)
            ctx.log(formatLine("Held-out raster %s: no vertex seen by it and by a fitted raster.",
                               split.heldOutLabels[i].toStdString().c_str()));
        else
            ctx.log(formatLine("Held-out raster %s: %zu vertices, RMS error in sRGB levels: fitted %.2f, "
                               "constant mean colour %.2f, colour projection %.2f; exposure-matched: %.2f, "
                               "%.2f, %.2f.",
                               split.heldOutLabels[i].toStdString().c_str(), e.vertices, e.fitted, e.constant,
                               e.projection, e.fittedMatched, e.constantMatched, e.projectionMatched));
    }
    ctx.log(formatLine("Held-out summary: %zu views compared, fitted <= constant in %zu; mean RMS fitted %.2f, "
                       "constant %.2f, colour projection %.2f; mean ratio fitted / projection %.3f.",
                       evaluation.viewsCompared, evaluation.fittedNotWorseThanConstant, evaluation.meanFitted,
                       evaluation.meanConstant, evaluation.meanProjection, evaluation.meanRatioToProjection));
    ctx.log(formatLine("Held-out summary, exposure-matched (each prediction scaled by its best gain per channel "
                       "on the held-out photograph, whose exposure no prediction can know): fitted <= constant "
                       "in %zu; mean RMS fitted %.2f, constant %.2f, colour projection %.2f; mean ratio fitted / "
                       "projection %.3f.",
                       evaluation.fittedNotWorseThanConstantMatched, evaluation.meanFittedMatched,
                       evaluation.meanConstantMatched, evaluation.meanProjectionMatched,
                       evaluation.meanRatioToProjectionMatched));
}

class FitFromRastersFilter : public Filter {
public:
    QString name() const override { return "Radiance: Fit Radiance Functions from Rasters"; }
    QString pythonName() const override { return "radiance_fit_radiance_functions_from_rasters"; }
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
        addBasisParameters(par, "PB(4) (15 coefficients) suits a few dozen photographs. For a glossy object (a sharp "
                                "highlight: glaze, clear coat, polished metal) a higher degree holds more of the "
                                "highlight: on path-traced captures of 40 and 80 photographs, SH(6) predicted held-out "
                                "photographs 1.5-6 % better than PB(4) (PB(6) 1.2-5.5 %), at 49 (28) coefficients per "
                                "channel instead of 15.");
        par.addParam(RichFloat("regularization", float(fitDefaults.lambda), "Regularisation",
                               "Tikhonov weight toward the vertex's mean colour, relative to the data term "
                               "(0 = plain least squares; 1e-3 .. 1e-1 sensible). Larger values give smoother, "
                               "less view-dependent functions."));
        addAbsoluteOrPercentParameter(par, "depthTolerance", diagonal * 1e-3f, 0.0f, diagonal, "Depth tolerance",
                                 "Occluders closer to the vertex than this along the ray toward the camera are "
                                 "ignored (absolute, or a percentage of the bounding-box diagonal). Raise it for "
                                 "noisy scans whose surface self-intersects slightly. A negative value (scripts) "
                                 "means automatic: 1e-4 of the bounding-box diagonal.");
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
        par.addParam(RichBool("validation", true, "Choose the regularisation per vertex",
                              "For every vertex, choose among the regularisation above and 10, 100 and 1000 times it, "
                              "each at the chosen degree and every lower one, and the constant mean colour, the one "
                              "that best predicts each of the vertex's photographs from the others (leave-one-view-out "
                              "validation). A view-dependent function is kept only where it predicts unseen views "
                              "better than the constant. Off: the regularisation above at the chosen degree everywhere."));
        par.addParam(RichBool("robust", true, "Robust to outliers (Huber)",
                              "Down-weight samples that the vertex's other photographs contradict (specular glints, "
                              "misregistered depth edges) by a few iterations of Huber reweighting. Samples with a "
                              "channel at 8-bit saturation (sRGB 250 or more) always get 1 % of their weight: a "
                              "clipped value is a lower bound, not a measurement."));
        par.addParam(RichBool("exposureCompensation", true, "Compensate exposure and white balance",
                              "Estimate one gain per raster and colour channel from the vertices several rasters see "
                              "(normalised to a geometric mean of 1) and divide each raster's colours by its gains "
                              "before the fit: differences of exposure or white balance between the photographs are "
                              "not view dependence. The gains are written to the log."));
        par.addParam(RichEnum("fitModel", 0,
                              QStringList() << "Automatic (chosen on left-out rasters)" << "Per vertex"
                                            << "Shared diffuse + reflected lobe",
                              "Fit model",
                              "Per vertex: each vertex's function from its own photographs only. Shared: a diffuse "
                              "colour per vertex plus one lobe of the reflected view direction shared by the whole "
                              "object, scaled per vertex (a distant light's highlight sits at the same reflected "
                              "direction everywhere; after the reflected parametrisation of Wood et al. 2000 and "
                              "the factorisations of Chen et al. 2002), written into the chosen basis; a vertex keeps "
                              "it unless its own photographs, each left out in turn, are predicted clearly better "
                              "(by more than three standard errors) by its constant mean colour, which it then "
                              "gets. Automatic: both are fitted without every "
                              "5th raster and compared raster by raster on those: the shared fit is used only when it "
                              "is better overall, in at least half of them and in none worse by more than it gains "
                              "overall (or 2 %, the larger); "
                              "otherwise the per-vertex fit (the log says which and why)."));
        par.addParam(RichFloat("sharedGuard", float(rad::SharedFitOptions().guardStandardErrors),
                               "Shared fit: per-vertex guard (standard errors)",
                               "A vertex keeps the shared diffuse + lobe function unless its own photographs, each "
                               "left out in turn, are predicted better by its constant mean colour by more than this "
                               "many standard errors; then it gets the constant. 0: whenever the constant is better "
                               "at all (never worse than the constant on the vertex's own left-out photographs, but "
                               "a vertex whose few photographs missed its highlight then loses the highlight the "
                               "lobe predicts for it in other views)."));
        par.addParam(RichFloat("lightDistance", 0.0f, "Shared fit: distance of the lights (bounding radii)",
                               "How far the lights are from the centre of the mesh's bounding box, in bounding radii "
                               "(the largest distance of a vertex from that centre). The shared lobe is read at the "
                               "reflected direction shifted by the vertex's offset from the centre over that "
                               "distance, so that a near light's highlight is one lobe for the whole object. 0: "
                               "chosen from the photographs (distant, or 10 down to 2 radii; the log says which). "
                               "A value of 1.5 or more fixes it; a very large one (1e9) treats the lights as distant."));
        par.addParam(RichInt("heldOutEvery", 0, "Hold out every k-th raster",
                             "0: fit on every raster. k >= 2: rasters k, 2k, 3k... (in the order of the raster "
                             "list) are left out of the fit, and the log compares, on each of them, the fitted "
                             "functions, the constant mean colour and an average of the other rasters' colours (as "
                             "'Project active rasters color to current mesh' does) with what the photograph shows "
                             "(RMS error in 8-bit sRGB levels over the vertices it sees)."));
        return par;
    }

    void apply(FilterContext& ctx) const override {
        const RichParameterList& par = ctx.parameters;
        MeshModel& m = ctx.mesh();
        QElapsedTimer timer;
        timer.start();
        const rad::RadianceFromViewsOptions options = fitOptionsFromParameters(par);
        const int heldOutEvery = heldOutEveryFromParameters(par);
        refuseInvalidOptions(options);
        const RasterViews rasters = usableRasters(ctx, par.getBool("visibleOnly"));
        const RasterSplit split = splitHeldOutRasters(rasters, heldOutEvery);
        const rad::TriangleMesh mesh = meshForFit(ctx, m);

        // Everything is computed aside; the layer changes only once the fit succeeded.
        rad::RadianceFromViewsResult result =
            rad::fitRadianceFromViews(mesh, split.training, options, ctx.progress.forCore());
        for (const std::string& warning : result.warnings) ctx.warning(warning);
        rad::HeldOutEvaluation evaluation;
        if (!split.heldOut.empty())
            evaluation = rad::evaluateHeldOutViews(mesh, result.field, result.meanColor, split.training, split.heldOut,
                                                   options.sampling);

        storeFitInLayer(m, result, par.getBool("setColor"), par.getEnum("quality") == kQualityResidual);
        ctx.progress(100, "Done");
        logFitSummary(ctx, options, result, mesh.vertexCount(), split, rasters.rasterCount, timer.elapsed() / 1000.0);
        logModelChoice(ctx, options, result);
        if (result.exposureCompensated) logExposureGains(ctx, result, split);
        if (!split.heldOut.empty()) logHeldOutEvaluation(ctx, evaluation, split);
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
               "Real photographs: each raster's exposure and white balance are estimated (one gain per "
               "channel) and compensated; each vertex chooses its regularisation, degree, or the constant "
               "mean colour by how well it predicts each of its photographs from the others "
               "(leave-one-view-out validation), so that a view-dependent function is kept only where it "
               "predicts unseen views better than the constant; outliers (glints, misregistered edges, "
               "clipped pixels) are down-weighted. With 'Hold out every k-th raster' the log compares the "
               "fit with the constant and with a colour projection on photographs it never saw.<br>"
               "Output: the radiance data (save as .rply), the vertex colour = the mean (diffuse) colour, "
               "the vertex quality = sample count or fit residual. Cameras with lens distortion are "
               "skipped (undistort the photographs first); the images must have the cameras' size.") +
           kCiteVanhoey2015;
}

}  // namespace

std::unique_ptr<Filter> makeFitFromRastersFilter() { return std::make_unique<FitFromRastersFilter>(); }

}  // namespace radml
