// "Radiance: Fit Radiance Functions from Rasters": the adapter between MeshLab's document (mesh +
// raster layers) and the fitting core (common/fit/radiance_from_views.h). Parameters in, views and
// mesh out of MeshLab, one core call, then the layer is changed only after everything succeeded.
#include "filter_radiance_simplify.h"

#include "mesh_conversion.h"
#include "radiance_attribute.h"
#include "raster_views.h"

#include "fit/radiance_from_views.h"
#include "radiance/view_colors.h"

#include <QElapsedTimer>

#include <cmath>

namespace {

enum QualityChoice { kQualitySampleCount = 0, kQualityResidual = 1 };

}  // namespace

void RadianceFilterPlugin::addFitParameters(MeshModel& m, RichParameterList& par) {
    const rad::RobustFitOptions fitDefaults;
    const rad::ViewSamplingOptions samplingDefaults;
    const float diagonal = m.cm.bbox.IsNull() ? 1.0f : m.cm.bbox.Diag();
    par.addParam(RichBool("visibleOnly", false, "Only visible rasters",
                          "Use only the raster layers that are visible in the raster list (the eye icon); "
                          "otherwise every raster of the document."));
    par.addParam(RichEnum("basis", 0,
                          QStringList() << "Hemispherical polynomials PB(d), local frame"
                                        << "Spherical harmonics SH(d), global frame",
                          "Basis", "Function basis of the radiance functions (paper 000 sec. 6)."));
    par.addParam(RichInt("degree", 4, "Degree",
                         QString("Degree d: PB(d) has (d+1)(d+2)/2 coefficients per channel (0..%1), SH(d) has "
                                 "(d+1)^2 (0..%2). PB(4) (15 coefficients) suits a few dozen photographs.")
                             .arg(rad::kMaxPolynomialDegree)
                             .arg(rad::kMaxHarmonicDegree)));
    par.addParam(RichFloat("regularization", float(fitDefaults.lambda), "Regularisation",
                           "Tikhonov weight toward the vertex's mean colour, relative to the data term "
                           "(0 = plain least squares; 1e-3 .. 1e-1 sensible). Larger values give smoother, "
                           "less view-dependent functions."));
    par.addParam(RichAbsPerc("depthTolerance", diagonal * 1e-3f, 0.0f, diagonal, "Depth tolerance",
                             "Occluders closer to the vertex than this along the ray toward the camera are "
                             "ignored (absolute, or a percentage of the bounding-box diagonal). Raise it for "
                             "noisy scans whose surface self-intersects slightly."));
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
                          "Store the reflected RF L~(w) = L(R_n w) (sec. 3.1) instead of L; both evaluate to "
                          "the same radiance. Reflected storage suits interpolation and simplification."));
    par.addParam(RichEnum("quality", kQualitySampleCount, QStringList() << "Sample count" << "Fit residual",
                          "Vertex quality", "What the vertex quality holds after the fit: the number of "
                          "photographs used by the vertex, or the RMS residual of its fit (linear units)."));
    par.addParam(RichBool("setColor", true, "Set vertex colour to the mean colour",
                          "Vertex colour := the vertex's mean (diffuse) colour over its samples, "
                          "sRGB-encoded."));
}

bool RadianceFilterPlugin::fitFromRasters(MeshDocument& md, MeshModel& m, const RichParameterList& par,
                                          vcg::CallBackPos* cb) {
    QElapsedTimer timer;
    timer.start();

    rad::RadianceFromViewsOptions options;
    options.fit.basis.kind = par.getEnum("basis") == 0 ? rad::BasisKind::HemisphericalPolynomial
                                                       : rad::BasisKind::SphericalHarmonics;
    options.fit.basis.degree = par.getInt("degree");
    if (!options.fit.basis.isValid()) {
        errorMessage = QString("Degree %1 is not supported for %2: use PB degrees 0..%3 or SH degrees 0..%4.")
                           .arg(options.fit.basis.degree)
                           .arg(options.fit.basis.kind == rad::BasisKind::SphericalHarmonics ? "SH" : "PB")
                           .arg(rad::kMaxPolynomialDegree)
                           .arg(rad::kMaxHarmonicDegree);
        return false;
    }
    options.fit.storeReflected = par.getBool("reflected");
    options.fit.lambda = par.getFloat("regularization");
    options.fit.minSamples = par.getInt("minSamples");
    options.sampling.depthTolerance = par.getAbsPerc("depthTolerance");
    options.sampling.grazingAngleDegrees = par.getFloat("grazingAngle");
    options.sampling.borderMarginPixels = par.getInt("borderMargin");
    for (const std::string& problem : {options.fit.validate(), options.sampling.validate()}) {
        if (!problem.empty()) {
            errorMessage = QString::fromStdString(problem);
            return false;
        }
    }

    const bool visibleOnly = par.getBool("visibleOnly");
    radml::RasterViews rasters = radml::collectRasterViews(md, visibleOnly);
    if (rasters.rasterCount == 0) {
        errorMessage = visibleOnly ? "No visible raster layer: show some rasters (eye icon) or fit on all rasters."
                                   : "The document has no raster layers: open the photographs with their cameras "
                                     "first (File > Open Project: .mlp, Bundler .out; or File > Import Raster and "
                                     "align them).";
        return false;
    }
    for (const std::string& warning : rasters.warnings) Log(GLLogStream::WARNING, "%s", warning.c_str());
    if (rasters.views.empty()) {
        errorMessage = QString("None of the %1 raster layers is usable (see the warnings above).")
                           .arg(rasters.rasterCount);
        return false;
    }

    rad::RadianceMesh plain;
    std::string why;
    radml::ExportChoice choice;
    choice.transfer = false;  // not used here (and not required to cover every vertex)
    choice.colors = choice.quality = choice.radiance = false;
    if (!radml::exportPlainMesh(m.cm, choice, plain, why)) {
        errorMessage = QString::fromStdString(why);
        return false;
    }
    rad::TriangleMesh mesh;
    mesh.positions = std::move(plain.positions);
    mesh.normals = std::move(plain.normals);
    mesh.faces = std::move(plain.faces);
    if (mesh.faceCount() == 0)
        Log(GLLogStream::WARNING, "The mesh has no faces: occlusion cannot be tested, every facing photograph "
                                  "is used.");

    // Everything is computed aside; the layer changes only once the fit succeeded.
    rad::RadianceFromViewsResult result;
    try {
        // meshlabserver prints every progress call: forward only whole steps of 10 % (and stage changes).
        int lastPercent = -100;
        std::string lastStage;
        result = rad::fitRadianceFromViews(mesh, rasters.views, options,
                                           [cb, &lastPercent, &lastStage](int percent, const char* stage) {
                                               if (!cb) return;
                                               if (percent / 10 == lastPercent / 10 && lastStage == stage) return;
                                               lastPercent = percent;
                                               lastStage = stage;
                                               cb(percent, stage);
                                           });
    } catch (const rad::FitError& e) {
        errorMessage = QString::fromStdString(e.what());
        return false;
    }
    for (const std::string& warning : result.warnings) Log(GLLogStream::WARNING, "%s", warning.c_str());

    const std::size_t n = mesh.vertexCount();
    const bool setColor = par.getBool("setColor");
    const bool residualQuality = par.getEnum("quality") == kQualityResidual;
    radml::attachRadiance(m.cm, std::move(result.field));
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
    if (cb) cb(100, "Done");
    Log("Fitted %s radiance functions%s from %zu of %zu rasters (%zu samples) on %zu vertices in %.2f s: "
        "%zu fitted, %zu poorly sampled (%zu given their mean colour), %zu unseen filled from neighbours, "
        "%zu unseen left black",
        options.fit.basis.name().c_str(), options.fit.storeReflected ? " (reflected)" : "", result.viewsUsed,
        rasters.rasterCount, result.totalSamples, n, timer.elapsed() / 1000.0, result.fitted, result.poorlySampled,
        result.constantFallbacks, result.unseenFilled, result.unseenLeft);
    return true;
}
