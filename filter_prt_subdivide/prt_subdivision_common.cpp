#include "prt_subdivision_common.h"

#include "extra_blocks_attribute.h"
#include "mesh_conversion.h"
#include "radiance_attribute.h"
#include "usable_normals.h"
#include "vertex_colors.h"

#include "raycast/ray_scene.h"

#include <vcg/complex/algorithms/update/color.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <new>

namespace radml {
namespace {

void appendLayer(CMeshO& mesh, OccluderScene& scene) {
    std::vector<std::uint32_t> index(mesh.vert.size(), 0);
    std::uint32_t next = static_cast<std::uint32_t>(scene.positions.size() / 3);
    for (std::size_t i = 0; i < mesh.vert.size(); ++i) {
        if (mesh.vert[i].IsD()) continue;
        index[i] = next++;
        for (int k = 0; k < 3; ++k) scene.positions.push_back(float(mesh.vert[i].cP()[k]));
    }
    for (const CFaceO& f : mesh.face) {
        if (f.IsD()) continue;
        for (int k = 0; k < 3; ++k) scene.faces.push_back(index[vcg::tri::Index(mesh, f.cV(k))]);
    }
}

float luminance(const float* rgb) { return 0.2126f * rgb[0] + 0.7152f * rgb[1] + 0.0722f * rgb[2]; }

}  // namespace

OccluderScene collectOccluders(MeshDocument& md, MeshModel& current, bool allVisibleLayers) {
    OccluderScene scene;
    appendLayer(current.cm, scene);
    if (allVisibleLayers)
        for (MeshModel* layer : documentMeshes(md))
            if (layer != &current && layer->isVisible()) appendLayer(layer->cm, scene);
    Eigen::AlignedBox3f box;
    for (std::size_t v = 0; v < scene.positions.size() / 3; ++v)
        box.extend(Eigen::Vector3f(scene.positions[3 * v], scene.positions[3 * v + 1], scene.positions[3 * v + 2]));
    scene.diagonal = box.isEmpty() ? 0.0f : box.diagonal().norm();
    return scene;
}

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

void setShading(MeshModel& m, const std::vector<float>& linearRgb, float exposure) {
    std::vector<float> exposed(linearRgb.size());
    std::vector<float> quality(linearRgb.size() / 3);
    for (std::size_t v = 0; v < quality.size(); ++v) {
        for (int ch = 0; ch < 3; ++ch) exposed[3 * v + ch] = exposure * linearRgb[3 * v + ch];
        quality[v] = luminance(&linearRgb[3 * v]);
    }
    setVertexColorsFromLinear(m, exposed);
    setVertexQuality(m, quality);
}

void addBudgetParameters(RichParameterList& par, const MeshModel& m) {
    par.addParam(RichInt("budget", 4 * m.cm.fn, "Triangle budget",
                         "Maximum number of triangles of the result (used when the factor is 0)."));
    par.addParam(RichFloat("budgetFactor", 0.0f, "Budget factor",
                           "If non-zero, the budget as a multiple of the current face count (e.g. 4)."));
}

QStringList measureChoices() {
    return QStringList() << "Eq. 2: contrast |t1-t2| / |t1+t2|" << "Eq. 3: difference |t1-t2|"
                         << "Eq. 4: difference / (1 + alpha normal divergence)"
                         << "Probed: midpoint interpolation error, relative"
                         << "Probed: midpoint interpolation error, absolute";
}

rad::TransferErrorMeasure measureParameter(const RichParameterList& par) {
    switch (par.getEnum("measure")) {
        case 0: return rad::TransferErrorMeasure::Contrast;
        case 1: return rad::TransferErrorMeasure::Difference;
        case 2: return rad::TransferErrorMeasure::NormalDivergence;
        case 3: return rad::TransferErrorMeasure::ProbedRelative;
        default: return rad::TransferErrorMeasure::ProbedAbsolute;
    }
}

const char* measureCitation(const RichParameterList& par) {
    switch (par.getEnum("measure")) {
        case 0: return "Křivánek et al. 2004, eq. 2";
        case 1: return "Křivánek et al. 2004, eq. 3";
        case 2: return "Křivánek et al. 2004, eq. 4";
        case 3: return "probed midpoint interpolation error, relative";
        default: return "probed midpoint interpolation error, absolute";
    }
}

PrtSubdivisionInput prepareSubdivision(FilterContext& ctx) {
    MeshModel& m = ctx.mesh();
    PrtSubdivisionInput input;
    std::string why;
    if (!gatherTransfer(m.cm, input.stored, why)) throw Refusal(why);
    if (input.stored.field.channels != 1)
        throw Refusal("The transfer vectors of this mesh include the albedo (three channels); the subdivision "
                      "ray-casts the geometric transfer of new vertices and would not know their albedo. Run "
                      "'Radiance: Compute PRT Transfer' with the albedo option off, subdivide, then compute it "
                      "with the albedo on the subdivided mesh.");
    rad::RadianceMesh plain;
    ExportChoice choice;
    choice.colors = choice.quality = choice.radiance = choice.transfer = false;
    if (!exportPlainMesh(m.cm, choice, plain, why)) throw Refusal(why);
    rad::PrtMesh& mesh = input.mesh;
    mesh.positions = std::move(plain.positions);
    mesh.normals = std::move(plain.normals);
    mesh.faces = std::move(plain.faces);
    mesh.width = input.stored.field.width();
    mesh.transfer = input.stored.field.values;
    // MeshLab's normals are area-weighted sums, not always unit, and zero at some vertices of real
    // scans: the estimates need unit normals everywhere.
    makeNormalsUsable(ctx, mesh.positions, mesh.faces, mesh.normals);
    // The cores check only what would break the refinement; this check says which cleaning filter to run.
    const std::string problem = rad::checkPrtSubdivisionInput(mesh);
    if (!problem.empty()) throw Refusal(problem);

    input.faces = mesh.faceCount();
    const double factor = ctx.parameters.getFloat("budgetFactor");
    if (!(factor >= 0.0) || !std::isfinite(factor))
        throw Refusal("The budget factor must be 0 (use the absolute budget) or a positive multiple.");
    // (Clamped far above the cores' largest budget, which they refuse with a message.)
    input.budget = factor > 0.0 ? static_cast<long long>(std::min(std::floor(factor * input.faces), 0x1p62))
                                : ctx.parameters.getInt("budget");
    // (A budget below the face count is refused by the core, with the figures.)
    if (input.budget < 0)
        throw Refusal(formatLine("The triangle budget is negative (%lld): choose at least the layer's %zu faces "
                                 "(e.g. a budget factor of 4).",
                                 input.budget, input.faces));
    return input;
}

rad::SubdivisionResult subdivideWithRayCasting(
    FilterContext& ctx, const PrtSubdivisionInput& input,
    const std::function<rad::SubdivisionResult(const rad::TransferOracle&)>& subdivide) {
    const OccluderScene occluders = collectOccluders(ctx.document, ctx.mesh(), input.stored.allVisibleLayers);
    ctx.progress(1, "Building the ray-tracing scene");
    const rad::RayScene scene(occluders.positions.data(), occluders.positions.size() / 3, occluders.faces.data(),
                              occluders.faces.size() / 3);
    rad::TransferOptions options;
    options.degree = input.stored.field.degree;
    options.rayCount = input.stored.rayCount;
    options.relativeRayOffset = input.stored.relativeRayOffset;
    const rad::TransferEstimator estimator(scene, occluders.diagonal, options);
    std::vector<float> batch;
    const rad::TransferOracle oracle = [&](const float* positions, const float* normals, std::size_t count,
                                           float* out) {
        rad::computeTransferVectors(estimator, positions, normals, count, batch);
        std::copy(batch.begin(), batch.end(), out);
    };
    return subdivide(oracle);
}

void replaceWithSubdivision(FilterContext& ctx, const PrtSubdivisionInput& input,
                            const rad::SubdivisionResult& result) {
    MeshModel& m = ctx.mesh();
    ctx.progress.setPhase(96, 100, "Updating the layer");
    rad::RadianceMesh out;
    out.positions = result.mesh.positions;
    out.normals = result.mesh.normals;
    out.faces = result.mesh.faces;
    const bool hadRadiance = hasRadiance(m.cm);
    StoredTransfer transfer = input.stored;
    transfer.field.values = result.mesh.transfer;
    const std::vector<float> shading = whiteSkyShading(transfer.field);
    // Blocks kept from a .rply have no values for the vertices the subdivision creates: say that they go.
    const std::vector<std::string> dropped = extraBlockPrefixes(m.cm);
    if (!dropped.empty()) {
        std::string names;
        for (const auto& p : dropped) names += (names.empty() ? "'" : ", '") + p + "'";
        ctx.warning("The extra vertex block" + std::string(dropped.size() == 1 ? " " : "s ") + names +
                    " of the opened file " + (dropped.size() == 1 ? "was" : "were") +
                    " removed: the subdivision rebuilds the mesh, and the vertices it creates have no values in " +
                    (dropped.size() == 1 ? "it" : "them") + ". Save the layer before subdividing to keep " +
                    (dropped.size() == 1 ? "it." : "them."));
    }
    enableLoadedData(m, importPlainMesh(out, m.cm));
    attachTransfer(m.cm, std::move(transfer));
    setShading(m, shading, 1.0f);
    m.updateDataMask(MeshModel::MM_FACEQUALITY | MeshModel::MM_FACECOLOR);
    std::size_t f = 0;
    for (CFaceO& face : m.cm.face) face.Q() = result.faceError[f++];
    // Colour ramp up to the 95th percentile, so a few extreme faces do not wash out the picture.
    std::vector<float> sortedErrors = result.faceError;
    float top = 0.0f;
    if (!sortedErrors.empty()) {
        const std::size_t at = std::min(sortedErrors.size() - 1, sortedErrors.size() * 95 / 100);
        std::nth_element(sortedErrors.begin(), sortedErrors.begin() + at, sortedErrors.end());
        top = sortedErrors[at];
    }
    vcg::tri::UpdateColor<CMeshO>::PerFaceQualityRamp(m.cm, 0.0f, top > 0.0f ? top : 1.0f);
    updateBoxAndNormals(m);
    ctx.progress.setPhase(100, 100, "Done");
    if (hadRadiance) ctx.warning("The radiance functions of this layer were dropped: the new vertices have none.");
}

}  // namespace radml
