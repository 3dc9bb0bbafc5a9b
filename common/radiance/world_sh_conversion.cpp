#include "radiance/world_sh_conversion.h"

#include "radiance/radiance_distance.h"
#include "radiance/radiance_evaluation.h"
#include "radiance/radiance_frame.h"
#include "radiance/sh_rotation.h"

#include <Eigen/Core>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>

namespace rad {

std::vector<double> hemisphereGramMatrix(const BasisSpec& basis) {
    const int k = basis.coefficientCount();
    std::vector<double> gram(static_cast<std::size_t>(k) * k, 0.0);
    // A Gauss product rule exact for the products of two basis functions (degree <= 2 * 10).
    const HemisphereIntegrator rule = HemisphereIntegrator::gaussProduct(12, 24);
    std::vector<double> values(k);
    for (std::size_t i = 0; i < rule.size(); ++i) {
        const Eigen::Vector3d& w = rule.localPoints()[i];
        evaluateBasis(basis, w.x(), w.y(), w.z(), values.data());
        for (int r = 0; r < k; ++r)
            for (int c = 0; c < k; ++c) gram[r * k + c] += rule.weights()[i] * values[r] * values[c];
    }
    return gram;
}

// The two constant matrices of the PB <-> SH conversion, in the local frame of every vertex:
// pbToSh_ (kWorld x K): the SH coefficients of each PB monomial over the whole sphere, by a Gauss
// product rule exact to degree 2d; shToPb_ (K x kWorld): least squares over the hemisphere,
// M^-1 int B Y (M the PB Gram matrix, weights / 2 pi as M's), by a hemisphere rule exact for those
// products.
int worldShCoefficientsPerChannel(const BasisSpec& basis) {
    return basis.usesLocalFrame() ? BasisSpec{BasisKind::SphericalHarmonics, basis.degree}.coefficientCount()
                                  : basis.coefficientCount();
}

WorldShConversion::WorldShConversion(const BasisSpec& basis) : basis_(basis) {
    k_ = basis.coefficientCount();
    kWorld_ = worldShCoefficientsPerChannel(basis);
    convertsFrames_ = basis.usesLocalFrame();
    if (!convertsFrames_) return;
    const int d = basis.degree;
    const BasisSpec sh{BasisKind::SphericalHarmonics, d};
    std::vector<double> b(k_), y(kWorld_);
    pbToSh_.assign(std::size_t(kWorld_) * k_, 0.0);
    std::vector<double> z, wz;
    gaussLegendre(d + 1, -1.0, 1.0, z, wz);
    const double pi = 3.14159265358979323846;
    const int phiNodes = 2 * d + 2;
    for (std::size_t i = 0; i < z.size(); ++i)
        for (int j = 0; j < phiNodes; ++j) {
            const double phi = 2.0 * pi * (j + 0.5) / phiNodes, r = std::sqrt(std::max(0.0, 1.0 - z[i] * z[i]));
            const Eigen::Vector3d w(r * std::cos(phi), r * std::sin(phi), z[i]);
            const double weight = wz[i] * 2.0 * pi / phiNodes;
            evaluateBasis(basis, w.x(), w.y(), w.z(), b.data());
            evaluateBasis(sh, w.x(), w.y(), w.z(), y.data());
            for (int k = 0; k < kWorld_; ++k)
                for (int p = 0; p < k_; ++p) pbToSh_[std::size_t(k) * k_ + p] += weight * y[k] * b[p];
        }
    const HemisphereIntegrator hemisphere = HemisphereIntegrator::gaussProduct(d + 1, 2 * d + 2);
    Eigen::MatrixXd hemisphereProducts = Eigen::MatrixXd::Zero(k_, kWorld_);
    for (std::size_t i = 0; i < hemisphere.size(); ++i) {
        const Eigen::Vector3d& l = hemisphere.localPoints()[i];
        evaluateBasis(basis, l.x(), l.y(), l.z(), b.data());
        evaluateBasis(sh, l.x(), l.y(), l.z(), y.data());
        for (int p = 0; p < k_; ++p)
            for (int k = 0; k < kWorld_; ++k) hemisphereProducts(p, k) += hemisphere.weights()[i] * b[p] * y[k];
    }
    const std::vector<double> g = hemisphereGramMatrix(basis);
    const Eigen::MatrixXd gram =
        Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(g.data(), k_, k_);
    const Eigen::MatrixXd leastSquares = gram.inverse() * hemisphereProducts;
    shToPb_.resize(std::size_t(k_) * kWorld_);
    for (int p = 0; p < k_; ++p)
        for (int k = 0; k < kWorld_; ++k) shToPb_[std::size_t(p) * kWorld_ + k] = leastSquares(p, k);
}

void WorldShConversion::toWorld(const float* coefficients, const float* storedFrame, double* world) const {
    if (!convertsFrames_) {
        std::copy(coefficients, coefficients + worldPerVertex(), world);
        return;
    }
    // f_world(w) = f_local(R w), R = the frame's rotation (local = R world): SH rotated by R^T.
    const ShRotation rotation(basis_.degree, frameFromStored(storedFrame).rotation().transpose());
    double local[kMaxCoefficientsPerChannel];
    for (int c = 0; c < kColorChannels; ++c) {
        const float* coefficient = coefficients + c * k_;
        for (int k = 0; k < kWorld_; ++k) {
            const double* row = pbToSh_.data() + std::size_t(k) * k_;
            double sum = 0.0;
            for (int p = 0; p < k_; ++p) sum += row[p] * coefficient[p];
            local[k] = sum;
        }
        rotation.apply(local, world + c * kWorld_);
    }
}

void WorldShConversion::fromWorld(const double* world, const float* storedFrame, float* coefficients, double divisor) const {
    if (!convertsFrames_) {
        for (int j = 0; j < worldPerVertex(); ++j) coefficients[j] = static_cast<float>(world[j] / divisor);
        return;
    }
    // The world function seen in v's local frame (SH rotated by R), then least squares over its
    // hemisphere.
    const ShRotation rotation(basis_.degree, frameFromStored(storedFrame).rotation());
    double local[kMaxCoefficientsPerChannel];
    for (int c = 0; c < kColorChannels; ++c) {
        rotation.apply(world + c * kWorld_, local);
        for (int p = 0; p < k_; ++p) {
            const double* row = shToPb_.data() + std::size_t(p) * kWorld_;
            double sum = 0.0;
            for (int k = 0; k < kWorld_; ++k) sum += row[k] * local[k];
            coefficients[c * k_ + p] = static_cast<float>(sum / divisor);
        }
    }
}

}  // namespace rad
