#include "radiance/radiance_projection.h"

#include "radiance/lebedev_quadrature.h"
#include "radiance/radiance_evaluation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rad {

namespace {
bool isFinite(const Eigen::Vector3d& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

constexpr int kLargestLebedevPrecision = 59;
constexpr double kMinReciprocalCondition = 1e-14;
}  // namespace

// ---------------------------------------------------------------------------------------------
// (a) Weighted least squares.
// ---------------------------------------------------------------------------------------------

bool fitRadiance(const BasisSpec& basis, const Frame& frame, const RadianceSample* samples, std::size_t count,
                 const FitOptions& options, double* out) {
    if (!basis.isValid() || !(options.lambda >= 0.0) || !std::isfinite(options.lambda)) return false;
    const int K = basis.coefficientCount();
    Eigen::MatrixXd G = Eigen::MatrixXd::Zero(K, K);
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(K, kColorChannels);
    Eigen::VectorXd b(K);
    double totalWeight = 0.0;
    for (std::size_t j = 0; j < count; ++j) {
        const RadianceSample& s = samples[j];
        if (!isFinite(s.direction) || !isFinite(s.value) || !std::isfinite(s.weight) || s.weight < 0.0) return false;
        if (s.weight == 0.0) continue;
        const double len = s.direction.norm();
        if (!(len > 0.0)) return false;
        const Eigen::Vector3d d = basisDirection(basis, frame, s.direction / len, options.storeReflected);
        evaluateBasis(basis, d.x(), d.y(), d.z(), b.data());
        G.selfadjointView<Eigen::Lower>().rankUpdate(b, s.weight);
        rhs.noalias() += (s.weight * b) * s.value.transpose();
        totalWeight += s.weight;
    }
    if (!(totalWeight > 0.0)) return false;
    G.triangularView<Eigen::StrictlyUpper>() = G.transpose();
    if (options.lambda > 0.0) {
        const double scale = options.lambda * G.trace() / K;
        for (int k = 1; k < K; ++k) G(k, k) += scale;  // the constant function (k = 0) is not penalised
    }
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(G);
    if (ldlt.info() != Eigen::Success) return false;
    // Numerically singular system (LDLT would silently return a pseudo-solution): a non-positive
    // pivot (exact zeros are skipped by Eigen's solve and rcond), or a reciprocal condition number
    // estimate below 1e-14, about 50 ulps (a rank-deficient G shows ~1e-17).
    const Eigen::VectorXd pivots = ldlt.vectorD();
    if (!(pivots.minCoeff() > 1e-300)) return false;
    if (!(ldlt.rcond() >= kMinReciprocalCondition)) return false;
    const Eigen::MatrixXd solution = ldlt.solve(rhs);
    if (!solution.allFinite()) return false;
    for (int c = 0; c < kColorChannels; ++c)
        for (int k = 0; k < K; ++k) out[c * K + k] = solution(k, c);
    return true;
}

// ---------------------------------------------------------------------------------------------
// (b) L2 projection.
// ---------------------------------------------------------------------------------------------

FunctionProjector::FunctionProjector(const BasisSpec& basis, const ProjectionOptions& options)
    : basis_(basis), options_(options) {
    const int K = basis.coefficientCount();
    int precision = options.quadraturePrecision > 0 ? options.quadraturePrecision : 2 * basis.degree + 10;
    precision = std::max(precision, 2 * basis.degree);
    precision = std::min(precision, kLargestLebedevPrecision);
    const int pointCount = lebedevPointCountForPrecision(precision);
    if (basis.usesLocalFrame()) {
        const HemisphereQuadrature rule = hemisphereRule(pointCount);
        precision_ = rule.precision;
        for (std::size_t i = 0; i < rule.size(); ++i) {
            points_.emplace_back(rule.x[i], rule.y[i], rule.z[i]);
            weights_.push_back(rule.w[i]);
        }
    } else {
        const SphereQuadrature& rule = lebedevRule(pointCount);
        precision_ = rule.precision;
        for (std::size_t i = 0; i < rule.size(); ++i) {
            points_.emplace_back(rule.x[i], rule.y[i], rule.z[i]);
            weights_.push_back(rule.w[i]);
        }
    }
    const int P = static_cast<int>(points_.size());
    basisValues_.resize(K, P);
    for (int i = 0; i < P; ++i)
        evaluateBasis(basis, points_[i].x(), points_[i].y(), points_[i].z(), basisValues_.col(i).data());
    if (basis.usesLocalFrame()) {
        Eigen::MatrixXd G = Eigen::MatrixXd::Zero(K, K);
        for (int i = 0; i < P; ++i) G.noalias() += weights_[i] * basisValues_.col(i) * basisValues_.col(i).transpose();
        gram_.compute(G);
    }
}

void FunctionProjector::projectImpl(const Frame& frame, const RadianceFunction& f, bool reflected, double* out) const {
    const int K = basis_.coefficientCount();
    const int P = static_cast<int>(points_.size());
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(K, kColorChannels);
    for (int i = 0; i < P; ++i) {
        Eigen::Vector3d w;
        if (basis_.usesLocalFrame()) {
            w = frame.toWorld(points_[i]);  // hemisphere of the vertex
        } else {
            w = points_[i];
            if (options_.borderExtension && frame.n.dot(w) < 0.0) w = borderExtendedDirection(frame, w);
        }
        const Eigen::Vector3d value = f(w);
        rhs.noalias() += (weights_[i] * basisValues_.col(i)) * value.transpose();
    }
    const Eigen::MatrixXd solution = basis_.usesLocalFrame() ? Eigen::MatrixXd(gram_.solve(rhs)) : rhs;
    for (int c = 0; c < kColorChannels; ++c)
        for (int k = 0; k < K; ++k) out[c * K + k] = solution(k, c);
    if (reflected) reflectCoefficients(basis_, frame, out, out);
}

void FunctionProjector::project(const Frame& frame, const RadianceFunction& f, double* out) const {
    projectImpl(frame, f, options_.storeReflected, out);
}

void FunctionProjector::projectIntoField(RadianceField& field, std::size_t v, const RadianceFunction& f) const {
    if (field.basis != basis_) throw std::invalid_argument("FunctionProjector: field basis " + field.basis.name() +
                                                           " differs from the projector's " + basis_.name());
    const int count = field.coefficientsPerVertex();
    std::vector<double> buffer(count);
    projectImpl(frameFromStored(field.frame(v)), f, field.reflected, buffer.data());
    float* dst = field.vertexCoefficients(v);
    for (int k = 0; k < count; ++k) dst[k] = static_cast<float>(buffer[k]);
}

void projectFunction(const BasisSpec& basis, const Frame& frame, const RadianceFunction& f,
                     const ProjectionOptions& options, double* out) {
    FunctionProjector(basis, options).project(frame, f, out);
}

}  // namespace rad
