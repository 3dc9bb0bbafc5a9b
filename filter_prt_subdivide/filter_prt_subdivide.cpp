#include "filter_prt_subdivide.h"

#include "mesh_conversion.h"
#include "radiance_attribute.h"
#include "transfer_attribute.h"

#include "lighting/environment_map.h"
#include "prt/adaptive_subdivision.h"
#include "prt/prt_lighting.h"
#include "prt/transfer_vectors.h"
#include "radiance/view_colors.h"
#include "raycast/ray_scene.h"

#include <vcg/complex/algorithms/update/color.h>

#include <QElapsedTimer>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace {

const char* kCitation =
    "<br><br>Transfer vectors: <i>P.-P. Sloan, J. Kautz, J. Snyder</i>, <b>\"Precomputed radiance transfer for "
    "real-time rendering in dynamic, low-frequency lighting environments\"</b>, SIGGRAPH 2002. Adaptive "
    "subdivision: <i>J. Krivanek, S. Pattanaik, J. Zara</i>, <b>\"Adaptive Mesh Subdivision for Precomputed "
    "Radiance Transfer\"</b>, SCCG 2004.";

enum OccluderChoice { kOccludersMesh = 0, kOccludersVisibleLayers = 1 };
enum LightingChoice { kLightEnvironment = 0, kLightDirectional = 1 };

// The faces of the current mesh, or of every visible layer, as one triangle soup for Embree.
struct OccluderScene {
    std::vector<float> positions;
    std::vector<std::uint32_t> faces;
    float diagonal = 0.0f;
};

void appendLayer(CMeshO& mesh, OccluderScene& scene) {
    std::vector<std::uint32_t> index(mesh.vert.size(), 0);
    const std::uint32_t base = static_cast<std::uint32_t>(scene.positions.size() / 3);
    std::uint32_t next = base;
    for (std::size_t i = 0; i < mesh.vert.size(); ++i) {
        if (mesh.vert[i].IsD()) continue;
        index[i] = next++;
        for (int k = 0; k < 3; ++k) scene.positions.push_back(mesh.vert[i].cP()[k]);
    }
    for (const CFaceO& f : mesh.face) {
        if (f.IsD()) continue;
        for (int k = 0; k < 3; ++k) scene.faces.push_back(index[vcg::tri::Index(mesh, f.cV(k))]);
    }
}

OccluderScene collectOccluders(MeshDocument& md, MeshModel& current, bool allVisibleLayers) {
    OccluderScene scene;
    appendLayer(current.cm, scene);
    if (allVisibleLayers)
        for (MeshModel* layer : md.meshList)
            if (layer != &current && layer->isVisible()) appendLayer(layer->cm, scene);
    Eigen::AlignedBox3f box;
    for (std::size_t v = 0; v < scene.positions.size() / 3; ++v)
        box.extend(Eigen::Vector3f(scene.positions[3 * v], scene.positions[3 * v + 1], scene.positions[3 * v + 2]));
    scene.diagonal = box.isEmpty() ? 0.0f : box.diagonal().norm();
    return scene;
}

// Progress in 5 % steps (meshlabserver prints every call) mapped into [from, to].
std::function<bool(double)> progressInRange(vcg::CallBackPos* cb, const char* what, int from, int to) {
    auto last = std::make_shared<int>(-10);
    return [cb, what, from, to, last](double fraction) {
        const int percent = from + static_cast<int>((to - from) * std::clamp(fraction, 0.0, 1.0));
        if (cb && percent / 5 != *last / 5) {
            *last = percent;
            cb(percent, what);
        }
        return true;
    };
}

// Ambient-occlusion-like shading under a constant white sky of unit radiance: L = t_00 sqrt(4 pi).
std::vector<float> whiteSkyShading(const rad::TransferField& field) {
    const std::size_t n = field.vertexCount();
    const int k = field.coefficientCount();
    std::vector<float> rgb(3 * n);
    const float y00Integral = static_cast<float>(std::sqrt(4.0 * M_PI));
    for (std::size_t v = 0; v < n; ++v)
        for (int ch = 0; ch < 3; ++ch) {
            const int c = field.channels == 3 ? ch : 0;
            rgb[3 * v + ch] = field.vertex(v)[c * k] * y00Integral;
        }
    return rgb;
}

float luminance(const float* rgb) { return 0.2126f * rgb[0] + 0.7152f * rgb[1] + 0.0722f * rgb[2]; }

void setVertexColorsAndQuality(MeshModel& m, const std::vector<float>& linearRgb, float exposure) {
    std::size_t i = 0;
    for (CVertexO& v : m.cm.vert) {
        if (v.IsD()) continue;
        const float* c = &linearRgb[3 * i];
        v.C() = vcg::Color4b(rad::encodeSrgb8(exposure * c[0]), rad::encodeSrgb8(exposure * c[1]),
                             rad::encodeSrgb8(exposure * c[2]), 255);
        v.Q() = luminance(c);
        ++i;
    }
    m.updateDataMask(MeshModel::MM_VERTCOLOR | MeshModel::MM_VERTQUALITY);
}

float decodeSrgb(unsigned char s8) {
    const double s = s8 / 255.0;
    return static_cast<float>(s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4));
}

// Positions and normals of the vertices referenced by faces must be finite with a non-zero normal:
// the transfer integrates over the hemisphere around the normal.
QString checkTransferInput(const rad::RadianceMesh& plain) {
    const std::size_t n = plain.vertexCount();
    if (n == 0) return "The current mesh has no vertices.";
    std::vector<char> used(n, plain.faces.empty() ? 1 : 0);
    for (std::uint32_t v : plain.faces) used[v] = 1;
    std::size_t badPosition = 0, badNormal = 0;
    for (std::size_t v = 0; v < n; ++v) {
        if (!used[v]) continue;
        const float* p = &plain.positions[3 * v];
        const float* q = &plain.normals[3 * v];
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) ++badPosition;
        const float len2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
        if (!std::isfinite(len2) || len2 < 1e-20f) ++badNormal;
    }
    if (badPosition > 0)
        return QString("%1 vertices have NaN or infinite coordinates: remove them first (Cleaning and Repairing > "
                       "Remove Duplicate Vertices / Remove Unreferenced Vertices, or fix the file).")
            .arg(badPosition);
    if (badNormal > 0)
        return QString("%1 vertices have a missing (zero) or invalid normal, and the transfer integrates over the "
                       "hemisphere around the normal. Compute normals first: Normals, Curvatures and Orientation > "
                       "Re-Compute Vertex Normals (meshes) or Compute normals for point sets.")
            .arg(badNormal);
    return {};
}

}  // namespace

PrtFilterPlugin::PrtFilterPlugin() {
    typeList << FP_COMPUTE_TRANSFER << FP_ADAPTIVE_SUBDIVISION << FP_UNIFORM_SUBDIVISION << FP_RELIGHT;
    for (FilterIDType id : types()) actionList << new QAction(filterName(id), this);
}

QString PrtFilterPlugin::filterName(FilterIDType filter) const {
    switch (filter) {
        case FP_COMPUTE_TRANSFER: return "Radiance: Compute PRT Transfer";
        case FP_ADAPTIVE_SUBDIVISION: return "Radiance: Adaptive PRT Subdivision";
        case FP_UNIFORM_SUBDIVISION: return "Radiance: Uniform PRT Subdivision";
        case FP_RELIGHT: return "Radiance: PRT Relighting as Vertex Color";
    }
    return {};
}

QString PrtFilterPlugin::filterInfo(FilterIDType filter) const {
    switch (filter) {
        case FP_COMPUTE_TRANSFER:
            return QString(
                       "Computes the shadowed diffuse transfer vector of precomputed radiance transfer (PRT) at every "
                       "vertex: t_k = 1/pi times the integral over the hemisphere of V(w) cos(n, w) Y_k(w), on real "
                       "spherical harmonics of the chosen order (order 6 = 36 coefficients, as in Krivanek et al.). "
                       "The relit colour under a distant lighting with SH coefficients l is then L = &lt;t, l&gt;. "
                       "Visibility V is ray-cast with Embree against the current mesh or all visible layers, with a "
                       "fixed low-discrepancy set of cosine-weighted directions in each vertex's frame (rays start "
                       "slightly above the surface to avoid self-hits). Rays that leave an open mesh are unoccluded: "
                       "that is what an open mesh means. Optionally multiplied by the vertex colour as albedo "
                       "(three channels). The vertices are coloured by the shading under a uniform white sky "
                       "(ambient occlusion), also stored as vertex quality. The vectors are saved with the mesh in "
                       "the Radiance PLY format (.rply).") +
                   kCitation;
        case FP_ADAPTIVE_SUBDIVISION:
            return QString(
                       "Subdivides the current mesh where its PRT transfer vectors change fast (Krivanek et al., "
                       "Fig. 2): every triangle's error estimate (eq. 2: |t1-t2|/|t1+t2| per edge, eq. 3: |t1-t2| "
                       "per edge, or eq. 4: eq. 3 divided by 1 + alpha times the divergence of the vertex normals, "
                       "the default) enters a priority queue; the worst triangle is split 1-to-4 at its edge "
                       "midpoints (Fig. 3a) until the triangle budget is reached or no triangle is above the "
                       "threshold. The transfer vectors of new vertices are ray-cast with the settings of 'Compute "
                       "PRT Transfer', never interpolated. T-vertices are removed afterwards by splitting the "
                       "neighbouring triangles in 2, 3 or 4 (Fig. 3b, 3c), so the result is conforming; the budget "
                       "counts those triangles too. The error estimate of every face is written as face quality and "
                       "face colour (red = highest), so you see where the mesh is still undersampled. The surface "
                       "does not move (flat splits). Needs a clean manifold mesh with vertex normals and transfer "
                       "vectors of one channel (computed without albedo).") +
                   kCitation;
        case FP_UNIFORM_SUBDIVISION:
            return QString(
                       "The baseline of Krivanek et al. Fig. 1(b): splits every triangle 1-to-4 as many times as the "
                       "triangle budget allows and ray-casts the transfer vectors of the new vertices. Face quality "
                       "and colour show the same error estimate as the adaptive filter.") +
                   kCitation;
        case FP_RELIGHT:
            return QString(
                       "Shades every vertex from its PRT transfer vector, L = &lt;t, l&gt;, under a distant lighting: "
                       "an HDR environment map (equirectangular .exr or .hdr, projected onto spherical harmonics, "
                       "rotatable about the up axis) or a directional light (its SH projection smoothed by a "
                       "Hanning window so that it does not ring). Vertex colour = exposure times L, sRGB-encoded; "
                       "vertex quality = the luminance of L.") +
                   kCitation;
    }
    return {};
}

MeshFilterInterface::FilterClass PrtFilterPlugin::getClass(QAction* action) {
    if (ID(action) == FP_ADAPTIVE_SUBDIVISION || ID(action) == FP_UNIFORM_SUBDIVISION)
        return MeshFilterInterface::Remeshing;
    return MeshFilterInterface::VertexColoring;
}

int PrtFilterPlugin::getPreConditions(QAction*) const { return MeshModel::MM_NONE; }

int PrtFilterPlugin::postCondition(QAction* action) const {
    if (ID(action) == FP_ADAPTIVE_SUBDIVISION || ID(action) == FP_UNIFORM_SUBDIVISION)
        return MeshModel::MM_GEOMETRY_AND_TOPOLOGY_CHANGE | MeshModel::MM_FACEQUALITY | MeshModel::MM_FACECOLOR |
               MeshModel::MM_VERTCOLOR | MeshModel::MM_VERTQUALITY;
    return MeshModel::MM_VERTCOLOR | MeshModel::MM_VERTQUALITY;
}

void PrtFilterPlugin::initParameterSet(QAction* action, MeshModel& m, RichParameterList& par) {
    const int faces = m.cm.fn;
    switch (ID(action)) {
        case FP_COMPUTE_TRANSFER:
            par.addParam(RichInt("order", rad::kDefaultTransferDegree + 1, "SH order",
                                 QString("Order n of the spherical harmonics: n^2 coefficients per vertex (1..%1). "
                                         "Krivanek et al. use order 6 (36 coefficients).")
                                     .arg(rad::kMaxHarmonicDegree + 1)));
            par.addParam(RichInt("rays", rad::kDefaultTransferRayCount, "Rays per vertex",
                                 "Cosine-weighted visibility rays per vertex (low-discrepancy set)."));
            par.addParam(RichEnum("occluders", kOccludersMesh,
                                  QStringList() << "The current mesh" << "All visible layers", "Occluders",
                                  "What casts shadows: the mesh alone, or every visible layer (e.g. a statue and "
                                  "the ground it stands on, loaded as two layers)."));
            par.addParam(RichBool("albedo", false, "Multiply by vertex colour (albedo)",
                                  "Three channels: the transfer times the vertex colour read as sRGB albedo. Leave off "
                                  "to subdivide afterwards (the subdivision needs the geometric transfer)."));
            par.addParam(RichFloat("rayOffset", 1e-4f, "Ray offset",
                                   "Rays start this far above the surface, as a fraction of the scene's bounding-box "
                                   "diagonal (avoids self-intersection)."));
            break;
        case FP_ADAPTIVE_SUBDIVISION:
        case FP_UNIFORM_SUBDIVISION:
            par.addParam(RichInt("budget", 4 * faces, "Triangle budget",
                                 "Maximum number of triangles of the result (used when the factor is 0)."));
            par.addParam(RichFloat("budgetFactor", 0.0f, "Budget factor",
                                   "If non-zero, the budget as a multiple of the current face count (e.g. 4)."));
            if (ID(action) == FP_ADAPTIVE_SUBDIVISION) {
                par.addParam(RichEnum("measure", 2,
                                      QStringList() << "Eq. 2: contrast |t1-t2| / |t1+t2|" << "Eq. 3: difference |t1-t2|"
                                                    << "Eq. 4: difference / (1 + alpha normal divergence)",
                                      "Error estimate",
                                      "Triangle error estimate of Krivanek et al. sec. 3.3 (sum over the edges)."));
                par.addParam(RichFloat("alpha", float(rad::kDefaultNormalDivergenceAlpha), "Alpha (eq. 4)",
                                       "Weight of the normal divergence (radians) in eq. 4: larger values refine "
                                       "curved regions less."));
                par.addParam(RichFloat("threshold", 0.0f, "Error threshold",
                                       "Triangles whose estimate is at or below it are never split."));
            } else {
                par.addParam(RichEnum("measure", 2,
                                      QStringList() << "Eq. 2" << "Eq. 3" << "Eq. 4", "Error estimate shown",
                                      "The estimate written as face quality (for comparison with the adaptive "
                                      "filter)."));
                par.addParam(RichFloat("alpha", float(rad::kDefaultNormalDivergenceAlpha), "Alpha (eq. 4)",
                                       "Weight of the normal divergence in eq. 4."));
            }
            break;
        case FP_RELIGHT:
            par.addParam(RichEnum("lighting", kLightDirectional,
                                  QStringList() << "HDR environment map" << "Directional light", "Lighting",
                                  "An equirectangular HDR map (.exr, .hdr) or a directional light."));
            par.addParam(RichString("environmentMap", "", "Environment map file",
                                    "Path of the equirectangular .exr or .hdr map (for the environment lighting)."));
            par.addParam(RichFloat("rotation", 0.0f, "Rotation (degrees)",
                                   "Turns the environment map about the up axis."));
            par.addParam(RichEnum("upAxis", 0, QStringList() << "+Z" << "+Y" << "+X", "Up axis",
                                  "The mesh's up direction: the map's zenith is put there."));
            par.addParam(RichPoint3f("lightDirection", vcg::Point3f(0.5f, 0.5f, 1.0f), "Direction toward the light",
                                     "For the directional light."));
            par.addParam(RichFloat("lightIntensity", 3.0f, "Light intensity",
                                   "Irradiance of the directional light at normal incidence (linear units)."));
            par.addParam(RichFloat("exposure", 1.0f, "Exposure", "Linear scale applied before sRGB encoding."));
            break;
        default: break;
    }
}

bool PrtFilterPlugin::applyFilter(QAction* action, MeshDocument& md, const RichParameterList& par,
                                  vcg::CallBackPos* cb) {
    MeshModel* m = md.mm();
    if (m == nullptr) {
        errorMessage = "There is no current mesh.";
        return false;
    }
    bool ok = false;
    errorMessage.clear();
    try {
        switch (ID(action)) {
            case FP_COMPUTE_TRANSFER: ok = computeTransfer(md, *m, par, cb); break;
            case FP_ADAPTIVE_SUBDIVISION: ok = subdivide(md, *m, par, cb, true); break;
            case FP_UNIFORM_SUBDIVISION: ok = subdivide(md, *m, par, cb, false); break;
            case FP_RELIGHT: ok = relight(*m, par, cb); break;
            default: errorMessage = "Unknown filter."; break;
        }
    } catch (const rad::TransferCancelled&) {
        errorMessage = "Cancelled; the layer is unchanged.";
    } catch (const rad::SubdivisionCancelled&) {
        errorMessage = "Cancelled; the layer is unchanged.";
    } catch (const std::bad_alloc&) {
        errorMessage = "Out of memory: lower the SH order, the ray count or the triangle budget.";
    } catch (const std::exception& e) {
        errorMessage = QString("Internal error: %1").arg(e.what());
    }
    // The GUI shows errorMessage in a dialog; meshlabserver only prints the log, so log it too.
    if (!ok) Log(GLLogStream::WARNING, qUtf8Printable(filterName(ID(action)) + ": " + errorMessage));
    return ok;
}

bool PrtFilterPlugin::computeTransfer(MeshDocument& md, MeshModel& m, const RichParameterList& par,
                                      vcg::CallBackPos* cb) {
    QElapsedTimer timer;
    timer.start();
    const int order = par.getInt("order");
    const int rays = par.getInt("rays");
    const double offset = par.getFloat("rayOffset");
    if (order < 1 || order > rad::kMaxHarmonicDegree + 1) {
        errorMessage = QString("The SH order must be between 1 and %1.").arg(rad::kMaxHarmonicDegree + 1);
        return false;
    }
    if (rays < 1 || rays > 65536) {
        errorMessage = "The number of rays per vertex must be between 1 and 65536.";
        return false;
    }
    if (!(offset > 0.0 && offset < 0.1)) {
        errorMessage = "The ray offset must be a small positive fraction of the diagonal (e.g. 1e-4).";
        return false;
    }
    rad::RadianceMesh plain;
    std::string why;
    radml::ExportChoice choice;
    choice.quality = choice.radiance = choice.transfer = false;
    if (!radml::exportPlainMesh(m.cm, choice, plain, why)) {
        errorMessage = QString::fromStdString(why);
        return false;
    }
    const QString problem = checkTransferInput(plain);
    if (!problem.isEmpty()) {
        errorMessage = problem;
        return false;
    }
    const bool allVisible = par.getEnum("occluders") == kOccludersVisibleLayers;
    const OccluderScene occluders = collectOccluders(md, m, allVisible);
    if (!(occluders.diagonal > 0.0f)) {
        errorMessage = "The scene has no extent (all vertices coincide); nothing to compute.";
        return false;
    }
    if (cb) cb(1, "Building the ray-tracing scene");
    const rad::RayScene scene(occluders.positions.data(), occluders.positions.size() / 3, occluders.faces.data(),
                              occluders.faces.size() / 3);
    rad::TransferOptions options;
    options.degree = order - 1;
    options.rayCount = rays;
    options.relativeRayOffset = offset;
    const rad::TransferEstimator estimator(scene, occluders.diagonal, options);

    radml::StoredTransfer stored;
    stored.field.degree = options.degree;
    stored.field.channels = 1;
    stored.rayCount = rays;
    stored.relativeRayOffset = offset;
    stored.allVisibleLayers = allVisible;
    const std::size_t n = plain.vertexCount();
    rad::computeTransferVectors(estimator, plain.positions.data(), plain.normals.data(), n, stored.field.values,
                                progressInRange(cb, "Ray-casting PRT transfer", 2, 95));
    const double seconds = timer.elapsed() / 1000.0;
    if (par.getBool("albedo")) {
        std::vector<float> albedo(3 * n);
        for (std::size_t v = 0; v < n; ++v)
            for (int ch = 0; ch < 3; ++ch) albedo[3 * v + ch] = decodeSrgb(plain.colors[4 * v + ch]);
        stored.field = rad::multiplyByAlbedo(stored.field, albedo);
    }
    const std::vector<float> shading = whiteSkyShading(stored.field);
    const int channels = stored.field.channels;
    const int coefficients = stored.field.coefficientCount();
    radml::attachTransfer(m.cm, std::move(stored));
    setVertexColorsAndQuality(m, shading, 1.0f);
    if (cb) cb(100, "Done");
    const double totalRays = double(n) * rays;
    Log("Computed PRT transfer on %zu vertices: SH order %d (%d coefficients x %d channel(s)), %d rays per vertex "
        "against %zu occluding triangles (%s); %.3g M rays in %.2f s = %.2f M rays/s",
        n, order, coefficients, channels, rays, occluders.faces.size() / 3,
        allVisible ? "all visible layers" : "the mesh", totalRays / 1e6, seconds,
        seconds > 0 ? totalRays / seconds / 1e6 : 0.0);
    return true;
}

bool PrtFilterPlugin::subdivide(MeshDocument& md, MeshModel& m, const RichParameterList& par, vcg::CallBackPos* cb,
                                bool adaptive) {
    QElapsedTimer timer;
    timer.start();
    radml::StoredTransfer stored;
    std::string why;
    if (!radml::gatherTransfer(m.cm, stored, why)) {
        errorMessage = QString::fromStdString(why);
        return false;
    }
    if (stored.field.channels != 1) {
        errorMessage = "The transfer vectors of this mesh include the albedo (three channels); the subdivision "
                       "ray-casts the geometric transfer of new vertices and would not know their albedo. Run "
                       "'Radiance: Compute PRT Transfer' with the albedo option off, subdivide, then compute it "
                       "with the albedo on the subdivided mesh.";
        return false;
    }
    rad::RadianceMesh plain;
    radml::ExportChoice choice;
    choice.colors = choice.quality = choice.radiance = choice.transfer = false;
    if (!radml::exportPlainMesh(m.cm, choice, plain, why)) {
        errorMessage = QString::fromStdString(why);
        return false;
    }
    rad::PrtMesh input;
    input.positions = std::move(plain.positions);
    input.normals = std::move(plain.normals);
    input.faces = std::move(plain.faces);
    input.width = stored.field.width();
    input.transfer = stored.field.values;
    // MeshLab's normals are area-weighted sums, not always unit: the estimates need unit normals.
    for (std::size_t v = 0; v < input.vertexCount(); ++v) {
        float* q = &input.normals[3 * v];
        const float len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
        if (len > 0.0f && std::isfinite(len))
            for (int k = 0; k < 3; ++k) q[k] /= len;
    }
    const std::string problem = rad::checkPrtSubdivisionInput(input);
    if (!problem.empty()) {
        errorMessage = QString::fromStdString(problem);
        return false;
    }
    const std::size_t faces = input.faceCount();
    const double factor = par.getFloat("budgetFactor");
    if (!(factor >= 0.0) || !std::isfinite(factor)) {
        errorMessage = "The budget factor must be 0 (use the absolute budget) or a positive multiple.";
        return false;
    }
    const long long budget = factor > 0.0 ? static_cast<long long>(std::floor(factor * faces)) : par.getInt("budget");
    if (budget < static_cast<long long>(faces)) {
        errorMessage = QString("The triangle budget of %1 is below the current %2 faces: subdivision only adds "
                               "triangles. Choose a budget of at least %2 (e.g. a factor of 4).")
                           .arg(budget)
                           .arg(faces);
        return false;
    }
    const int measureIndex = par.getEnum("measure");
    const rad::TransferErrorMeasure measure = measureIndex == 0   ? rad::TransferErrorMeasure::Contrast
                                              : measureIndex == 1 ? rad::TransferErrorMeasure::Difference
                                                                  : rad::TransferErrorMeasure::NormalDivergence;
    const double alpha = par.getFloat("alpha");
    if (!(alpha >= 0.0) || !std::isfinite(alpha)) {
        errorMessage = "Alpha must be a finite number >= 0.";
        return false;
    }

    // New vertices are ray-cast against the same occluders with the same settings as the stored vectors.
    const OccluderScene occluders = collectOccluders(md, m, stored.allVisibleLayers);
    if (cb) cb(1, "Building the ray-tracing scene");
    const rad::RayScene scene(occluders.positions.data(), occluders.positions.size() / 3, occluders.faces.data(),
                              occluders.faces.size() / 3);
    rad::TransferOptions transferOptions;
    transferOptions.degree = stored.field.degree;
    transferOptions.rayCount = stored.rayCount;
    transferOptions.relativeRayOffset = stored.relativeRayOffset;
    const rad::TransferEstimator estimator(scene, occluders.diagonal, transferOptions);
    std::vector<float> batch;
    const rad::TransferOracle oracle = [&](const float* positions, const float* normals, std::size_t count,
                                           float* out) {
        rad::computeTransferVectors(estimator, positions, normals, count, batch);
        std::copy(batch.begin(), batch.end(), out);
    };

    rad::SubdivisionResult result;
    if (adaptive) {
        rad::AdaptiveSubdivisionOptions options;
        options.measure = measure;
        options.alpha = alpha;
        options.threshold = par.getFloat("threshold");
        options.triangleBudget = static_cast<std::size_t>(budget);
        options.progress = progressInRange(cb, "Adaptive PRT subdivision", 2, 95);
        if (!(options.threshold >= 0.0) || !std::isfinite(options.threshold)) {
            errorMessage = "The error threshold must be a finite number >= 0.";
            return false;
        }
        result = rad::subdivideAdaptively(input, oracle, options);
    } else {
        if (cb) cb(5, "Uniform subdivision and ray casting");
        result = rad::subdivideUniformly(input, oracle, static_cast<std::size_t>(budget), measure, alpha);
    }

    // Build the new content aside, then replace the layer in one go.
    if (cb) cb(96, "Updating the layer");
    rad::RadianceMesh out;
    out.positions = result.mesh.positions;
    out.normals = result.mesh.normals;
    out.faces = result.mesh.faces;
    const bool hadRadiance = radml::hasRadiance(m.cm);
    radml::StoredTransfer newTransfer = stored;
    newTransfer.field.values = result.mesh.transfer;
    const std::vector<float> shading = whiteSkyShading(newTransfer.field);
    const int mask = radml::importPlainMesh(out, m.cm);
    m.Enable(mask);
    radml::attachTransfer(m.cm, std::move(newTransfer));
    setVertexColorsAndQuality(m, shading, 1.0f);
    m.updateDataMask(MeshModel::MM_FACEQUALITY | MeshModel::MM_FACECOLOR);
    std::vector<float> sortedErrors = result.faceError;
    std::size_t f = 0;
    for (CFaceO& face : m.cm.face) face.Q() = result.faceError[f++];
    // Colour ramp up to the 95th percentile, so a few extreme faces do not wash out the picture.
    float top = 0.0f;
    if (!sortedErrors.empty()) {
        const std::size_t at = std::min(sortedErrors.size() - 1, sortedErrors.size() * 95 / 100);
        std::nth_element(sortedErrors.begin(), sortedErrors.begin() + at, sortedErrors.end());
        top = sortedErrors[at];
    }
    vcg::tri::UpdateColor<CMeshO>::PerFaceQualityRamp(m.cm, 0.0f, top > 0.0f ? top : 1.0f);
    m.UpdateBoxAndNormals();
    if (cb) cb(100, "Done");
    const char* measureName = measureIndex == 0 ? "eq. 2" : measureIndex == 1 ? "eq. 3" : "eq. 4";
    if (adaptive)
        Log("Adaptive PRT subdivision (%s, alpha %.3g): %zu -> %zu faces, %zu vertices (%zu new, ray-cast); %zu "
            "regular splits (%zu forced for 1-irregularity), %zu T-vertex fixes; stopped: %s, largest remaining "
            "estimate %.4g; %.2f s",
            measureName, alpha, faces, result.mesh.faceCount(), result.mesh.vertexCount(), result.newVertices,
            result.regularSplits, result.forcedSplits, result.tVertexFixes,
            result.stop == rad::SubdivisionStop::BudgetReached ? "budget reached" : "no triangle above the threshold",
            result.largestRemainingError, timer.elapsed() / 1000.0);
    else
        Log("Uniform PRT subdivision: %zu -> %zu faces, %zu vertices (%zu new, ray-cast); %.2f s", faces,
            result.mesh.faceCount(), result.mesh.vertexCount(), result.newVertices, timer.elapsed() / 1000.0);
    if (result.mesh.faceCount() == faces)
        Log(GLLogStream::WARNING, "No triangle was split: the budget (%lld) leaves no room for a split%s.", budget,
            adaptive ? " or no estimate exceeds the threshold" : " of every triangle (uniform needs 4x the faces)");
    if (hadRadiance)
        Log(GLLogStream::WARNING, "The radiance functions of this layer were dropped: the new vertices have none.");
    return true;
}

bool PrtFilterPlugin::relight(MeshModel& m, const RichParameterList& par, vcg::CallBackPos* cb) {
    radml::StoredTransfer stored;
    std::string why;
    if (!radml::gatherTransfer(m.cm, stored, why)) {
        errorMessage = QString::fromStdString(why);
        return false;
    }
    const int degree = stored.field.degree;
    const float exposure = par.getFloat("exposure");
    if (!(exposure >= 0.0f) || !std::isfinite(exposure)) {
        errorMessage = "The exposure must be a finite number >= 0.";
        return false;
    }
    // World from the map/light frame: the zenith (+Z) goes to the chosen up axis (enum +Z, +Y, +X).
    const Eigen::Matrix3d up = rad::zenithToAxis(2 - par.getEnum("upAxis"));
    std::vector<double> lighting;
    QString description;
    if (par.getEnum("lighting") == kLightEnvironment) {
        const QString path = par.getString("environmentMap").trimmed();
        if (path.isEmpty()) {
            errorMessage = "Choose an environment map file (.exr or .hdr), or the directional light.";
            return false;
        }
        if (cb) cb(10, "Reading the environment map");
        rad::EnvironmentMap map;
        try {
            map = rad::readEnvironmentMap(path.toStdString());
        } catch (const rad::EnvironmentMapError& e) {
            errorMessage = QString::fromStdString(e.what());
            return false;
        }
        const double radians = par.getFloat("rotation") * M_PI / 180.0;
        lighting = rad::environmentLightSH(map, degree, radians);
        rad::rotateLighting(lighting, degree, up);
        description = QString("environment map %1 (%2 x %3), rotated %4 degrees")
                          .arg(path)
                          .arg(map.width())
                          .arg(map.height())
                          .arg(par.getFloat("rotation"));
    } else {
        const vcg::Point3f d = par.getPoint3f("lightDirection");
        const Eigen::Vector3d direction(d[0], d[1], d[2]);
        const double intensity = par.getFloat("lightIntensity");
        if (!direction.allFinite() || direction.norm() < 1e-12 || !(intensity >= 0.0) || !std::isfinite(intensity)) {
            errorMessage = "The light direction must be a finite non-zero vector and the intensity finite and >= 0.";
            return false;
        }
        lighting = rad::directionalLightSH(degree, direction.normalized(), Eigen::Vector3d::Constant(intensity));
        description = QString("directional light toward (%1, %2, %3), intensity %4")
                          .arg(d[0])
                          .arg(d[1])
                          .arg(d[2])
                          .arg(intensity);
    }
    const std::size_t n = stored.field.vertexCount();
    const std::vector<float> rgb = rad::relightVertices(stored.field.values.data(), n, degree, stored.field.channels,
                                                        lighting, degree);
    setVertexColorsAndQuality(m, rgb, exposure);
    if (cb) cb(100, "Done");
    Log("Relit %zu vertices from SH order %d transfer under the %s", n, degree + 1, qUtf8Printable(description));
    return true;
}

MESHLAB_PLUGIN_NAME_EXPORTER(PrtFilterPlugin)
