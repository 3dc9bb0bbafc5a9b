#include "simplify/directional_reduction.h"

#include "radiance/radiance_frame.h"
#include "radiance/radiance_projection.h"
#include "render/image_space_error.h"

#include <Eigen/Core>

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace rad {

namespace {

[[noreturn]] void refuse(const std::string& what) { throw std::invalid_argument("directional reduction: " + what); }

// P (K' x K, row-major in a std::vector): column k is the hemisphere L2 projection of the k-th
// function of `high` on `low`, computed with FunctionProjector in the canonical frame (local = world).
std::vector<double> polynomialProjectionMatrix(const BasisSpec& high, const BasisSpec& low) {
    const int K = high.coefficientCount(), Kl = low.coefficientCount();
    ProjectionOptions po;
    // The integrands B'_j B_k have total degree <= deg(low) + deg(high): a rule of that precision
    // integrates them exactly (the hemisphere rule is exact for polynomials in (x, y)).
    po.quadraturePrecision = low.degree + high.degree;
    const FunctionProjector projector(low, po);
    const Frame canonical;
    std::vector<double> P(static_cast<std::size_t>(Kl) * K, 0.0);
    std::vector<double> values(K), out(static_cast<std::size_t>(kColorChannels) * Kl);
    // Three basis functions at a time, one per colour channel.
    for (int k0 = 0; k0 < K; k0 += kColorChannels) {
        const RadianceFunction f = [&](const Eigen::Vector3d& w) {
            std::vector<double> b(K);
            evaluateBasis(high, w.x(), w.y(), w.z(), b.data());
            Eigen::Vector3d r = Eigen::Vector3d::Zero();
            for (int c = 0; c < kColorChannels; ++c)
                if (k0 + c < K) r[c] = b[k0 + c];
            return r;
        };
        projector.project(canonical, f, out.data());
        for (int c = 0; c < kColorChannels && k0 + c < K; ++c)
            for (int j = 0; j < Kl; ++j) P[static_cast<std::size_t>(j) * K + k0 + c] = out[c * Kl + j];
    }
    return P;
}

}  // namespace

RadianceField reduceDirectionalDegree(const RadianceField& field, BasisSpec lowerBasis) {
    const std::string why = field.validate();
    if (!why.empty()) refuse(why);
    if (!lowerBasis.isValid()) refuse("unsupported target basis " + lowerBasis.name());
    if (lowerBasis.kind != field.basis.kind)
        refuse("cannot change the basis kind (" + field.basis.name() + " -> " + lowerBasis.name() +
               "): only the degree is lowered");
    if (lowerBasis.degree > field.basis.degree)
        refuse("target " + lowerBasis.name() + " has a higher degree than the field's " + field.basis.name());
    if (lowerBasis == field.basis) return field;

    const std::size_t n = field.vertexCount();
    RadianceField out(lowerBasis, n, field.reflected);
    out.frames = field.frames;
    const int K = field.coefficientsPerChannel(), Kl = out.coefficientsPerChannel();
    const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(n);

    if (lowerBasis.kind == BasisKind::SphericalHarmonics) {
        // Bands l <= d' are the first (d'+1)^2 coefficients of each channel: exact truncation.
#pragma omp parallel for schedule(static)
        for (std::ptrdiff_t v = 0; v < count; ++v)
            for (int c = 0; c < kColorChannels; ++c) {
                const float* src = field.channelCoefficients(static_cast<std::size_t>(v), c);
                float* dst = out.channelCoefficients(static_cast<std::size_t>(v), c);
                for (int k = 0; k < Kl; ++k) dst[k] = src[k];
            }
        return out;
    }

    const std::vector<double> P = polynomialProjectionMatrix(field.basis, lowerBasis);
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t v = 0; v < count; ++v)
        for (int c = 0; c < kColorChannels; ++c) {
            const float* src = field.channelCoefficients(static_cast<std::size_t>(v), c);
            float* dst = out.channelCoefficients(static_cast<std::size_t>(v), c);
            for (int j = 0; j < Kl; ++j) {
                double s = 0.0;
                const double* row = P.data() + static_cast<std::size_t>(j) * K;
                for (int k = 0; k < K; ++k) s += row[k] * src[k];
                dst[j] = static_cast<float>(s);
            }
        }
    return out;
}

int equalMemoryDegree(const BasisSpec& original, double vertexRatio, double facesPerVertex) {
    if (!original.isValid()) refuse("unsupported basis " + original.name());
    if (!(vertexRatio > 0.0 && vertexRatio <= 1.0))
        refuse("the vertex ratio must lie in (0, 1], got " + std::to_string(vertexRatio));
    if (!(facesPerVertex >= 0.0) || !std::isfinite(facesPerVertex))
        refuse("faces per vertex must be non-negative and finite, got " + std::to_string(facesPerVertex));
    // Memory per original vertex (divide both sides by V).
    const double faceBytes = facesPerVertex * static_cast<double>(kTriangleBytes);
    const double target = vertexRatio * (static_cast<double>(vertexBytes(original)) + faceBytes);
    int best = 0;
    double bestGap = 0.0;
    for (int d = 0; d <= original.degree; ++d) {
        const double mem = static_cast<double>(vertexBytes(BasisSpec{original.kind, d})) + faceBytes;
        const double gap = std::fabs(mem - target);
        if (d == 0 || gap < bestGap) {  // strict: ties keep the lower degree
            best = d;
            bestGap = gap;
        }
    }
    return best;
}

}  // namespace rad
