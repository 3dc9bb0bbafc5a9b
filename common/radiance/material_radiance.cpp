#include "radiance/material_radiance.h"

#include "radiance/lebedev_quadrature.h"
#include "radiance/radiance_evaluation.h"
#include "radiance/radiance_frame.h"
#include "radiance/radiance_projection.h"

#include <atomic>
#include <cmath>
#include <omp.h>
#include <sstream>

namespace rad {

std::string checkMaterialRadianceInput(const float* positions, const float* normals, std::size_t vertexCount,
                                       const MaterialRadianceOptions& options) {
    std::ostringstream why;
    if (!options.basis.isValid()) {
        why << "unsupported basis " << options.basis.name();
        return why.str();
    }
    if (vertexCount == 0) return "The mesh has no vertices.";
    for (std::size_t v = 0; v < vertexCount; ++v) {
        const float* p = positions + 3 * v;
        const float* n = normals + 3 * v;
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
            why << "Vertex " << v << " has a non-finite position (NaN or infinity). Remove such vertices first "
                << "(e.g. Filters > Cleaning and Repairing > Remove Unreferenced Vertices after fixing the faces).";
            return why.str();
        }
        const double len2 = double(n[0]) * n[0] + double(n[1]) * n[1] + double(n[2]) * n[2];
        if (!std::isfinite(len2) || len2 < 1e-20) {
            why << "Vertex " << v << " has no usable normal (zero or not finite): radiance functions live on the "
                << "hemisphere around the normal. Compute vertex normals first (Filters > Normals, Curvatures and "
                << "Orientation > Re-Compute Vertex Normals, or Compute normals for point sets).";
            return why.str();
        }
    }
    return {};
}

RadianceField makeMaterialRadiance(const float* positions, const float* normals, std::size_t vertexCount,
                                   const AnalyticMaterial& material, const AnalyticLighting& lighting,
                                   const MaterialRadianceOptions& options, const ProgressCallback& progress) {
    RadianceField field(options.basis, vertexCount, options.reflected);
    ProjectionOptions projection;
    projection.storeReflected = options.reflected;
    const FunctionProjector projector(options.basis, projection);
    const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(vertexCount);
    LoopProgress loop(progress, "projecting the material's radiance onto the basis", vertexCount);
#pragma omp parallel for schedule(dynamic, 256)
    for (std::ptrdiff_t v = 0; v < n; ++v) {
        if (loop.stopRequested()) continue;
        const Eigen::Vector3d p(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
        const Eigen::Vector3d normal =
            Eigen::Vector3d(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]).normalized();
        storeFrame(frameFromNormal(normal), field.frame(static_cast<std::size_t>(v)));
        projector.projectIntoField(field, static_cast<std::size_t>(v), [&](const Eigen::Vector3d& wo) {
            return outgoingRadiance(material, lighting, p, normal, wo);
        });
        loop.itemDone(omp_get_thread_num() == 0);
    }
    loop.finish();
    return field;
}

void meanHemisphereColors(const RadianceField& field, float* rgbOut) {
    const int precision = 2 * field.basis.degree + 10;
    const HemisphereQuadrature rule = hemisphereRule(lebedevPointCountForPrecision(std::min(precision, 59)));
    const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(field.vertexCount());
#pragma omp parallel
    {
        double scratch[kMaxCoefficientsPerChannel];
#pragma omp for schedule(static)
        for (std::ptrdiff_t v = 0; v < n; ++v) {
            const VertexRadiance rf = vertexRadiance(field, static_cast<std::size_t>(v));
            Eigen::Vector3d sum = Eigen::Vector3d::Zero();
            for (std::size_t i = 0; i < rule.size(); ++i) {
                const Eigen::Vector3d w = rf.frame.toWorld(Eigen::Vector3d(rule.x[i], rule.y[i], rule.z[i]));
                sum += rule.w[i] * evaluateRadiance(rf, w, scratch);
            }
            sum /= 2.0 * M_PI;
            for (int c = 0; c < 3; ++c) rgbOut[3 * v + c] = static_cast<float>(sum[c]);
        }
    }
}

}  // namespace rad
