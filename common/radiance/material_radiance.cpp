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
                << "(e.g. {{Remove Unreferenced Vertices}} after fixing the faces).";
            return why.str();
        }
        const double len2 = double(n[0]) * n[0] + double(n[1]) * n[1] + double(n[2]) * n[2];
        if (!std::isfinite(len2) || len2 < 1e-20) {
            why << "Vertex " << v << " has no usable normal (zero or not finite): radiance functions live on the "
                << "hemisphere around the normal. Compute vertex normals first ({{Re-Compute Vertex Normals}}, or "
                << "{{Compute normals for point sets}}).";
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

namespace {

// (1/2pi) int over {w.n >= 0} of P_l(w.n) dw = int_0^1 P_l(t) dt = (P_{l-1}(0) - P_{l+1}(0)) / (2l + 1).
double legendreAtZero(int n) {
    if (n % 2 != 0) return 0.0;
    double value = 1.0;  // P_2k(0) = (-1)^k (2k-1)!! / (2k)!!
    for (int k = 1; k <= n / 2; ++k) value *= -(2.0 * k - 1.0) / (2.0 * k);
    return value;
}
double hemisphereMeanOfLegendre(int l) {
    return l == 0 ? 1.0 : (legendreAtZero(l - 1) - legendreAtZero(l + 1)) / (2.0 * l + 1.0);
}

}  // namespace

void meanHemisphereColors(const RadianceField& field, float* rgbOut) {
    // The mean is linear in the coefficients: mean_c = sum_k c_ck mu_k, mu_k the mean of basis function
    // k over the vertex's hemisphere. PB functions live in the vertex's frame, so mu is one vector,
    // integrated once (exactly: the integrand is a polynomial even in z, see lebedev_quadrature.h).
    // An SH function of degree l averages over the hemisphere around n to H_l Y_lm(n) (Funk-Hecke: the
    // hemisphere is zonal about n), H_l = int_0^1 P_l. A reflected function's mean is its own: the
    // reflection about n maps the hemisphere onto itself.
    const int k = field.coefficientsPerChannel();
    std::vector<double> mu(k, 0.0), shMean(k, 0.0);
    if (field.basis.usesLocalFrame()) {
        const int precision = 2 * field.basis.degree + 10;
        const HemisphereQuadrature rule = hemisphereRule(lebedevPointCountForPrecision(std::min(precision, 59)));
        std::vector<double> values(k);
        for (std::size_t i = 0; i < rule.size(); ++i) {
            evaluateBasis(field.basis, rule.x[i], rule.y[i], rule.z[i], values.data());
            for (int j = 0; j < k; ++j) mu[j] += rule.w[i] * values[j] / (2.0 * M_PI);
        }
    } else {
        for (int l = 0; l <= field.basis.degree; ++l)
            for (int j = l * l; j < (l + 1) * (l + 1) && j < k; ++j) shMean[j] = hemisphereMeanOfLegendre(l);
    }
    const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(field.vertexCount());
#pragma omp parallel
    {
        std::vector<double> weights(mu);
#pragma omp for schedule(static)
        for (std::ptrdiff_t v = 0; v < n; ++v) {
            if (!field.basis.usesLocalFrame()) {
                const Eigen::Vector3d normal = frameFromStored(field.frame(static_cast<std::size_t>(v))).n;
                evaluateBasis(field.basis, normal.x(), normal.y(), normal.z(), weights.data());
                for (int j = 0; j < k; ++j) weights[j] *= shMean[j];
            }
            const float* coefficients = field.vertexCoefficients(static_cast<std::size_t>(v));
            for (int c = 0; c < 3; ++c) {
                double sum = 0.0;
                for (int j = 0; j < k; ++j) sum += double(coefficients[c * k + j]) * weights[j];
                rgbOut[3 * v + c] = static_cast<float>(sum);
            }
        }
    }
}

}  // namespace rad
