#include "fit/robust_radiance_fit.h"

#include "radiance/radiance_evaluation.h"
#include "radiance/sh_rotation.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rad {

namespace {
constexpr double kPi = 3.14159265358979323846;
// Smallest Cholesky pivot, relative to trace(G), of a system that counts as regular when lambda > 0
// (the threshold radiance_projection.cpp applies to its condition estimate); see fit().
constexpr double kMinReciprocalCondition = 1e-14;
// lambda used as the base of the escalation when the user's lambda is 0.
constexpr double kEscalationBaseLambda = 1e-3;

bool finite3(const float* v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

using MatrixMap = Eigen::Map<Eigen::MatrixXd>;
using ConstMatrixMap = Eigen::Map<const Eigen::MatrixXd>;

// Dot product with four partial sums (independent dependency chains; SLP-vectorisable without
// -ffast-math).
inline double dot(const double* a, const double* b, int n) {
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    int k = 0;
    for (; k + 4 <= n; k += 4) {
        s0 += a[k] * b[k];
        s1 += a[k + 1] * b[k + 1];
        s2 += a[k + 2] * b[k + 2];
        s3 += a[k + 3] * b[k + 3];
    }
    for (; k < n; ++k) s0 += a[k] * b[k];
    return (s0 + s1) + (s2 + s3);
}

// In-place Cholesky factorisation a = L L^T of a symmetric K x K matrix stored row-major, reading
// and writing the lower triangle only (a[i * K + j], j <= i); invDiag receives 1 / L_jj. Unblocked,
// row-oriented (every inner product runs over two contiguous rows): at K <= 121 this is faster than
// Eigen's blocked LLT, whose GEMM machinery does not pay off at these sizes (measured: about 2x
// for SH6, K = 49). Returns false when a pivot L_jj^2 is not above minPivot (not positive definite,
// or numerically singular).
bool choleskyInPlace(double* a, int K, double minPivot, double* invDiag) {
    for (int j = 0; j < K; ++j) {
        double* rj = a + static_cast<std::size_t>(j) * K;
        const double d = rj[j] - dot(rj, rj, j);
        if (!(d > minPivot)) return false;
        const double ljj = std::sqrt(d);
        rj[j] = ljj;
        const double inv = 1.0 / ljj;
        invDiag[j] = inv;
        for (int i = j + 1; i < K; ++i) {
            double* ri = a + static_cast<std::size_t>(i) * K;
            ri[j] = (ri[j] - dot(ri, rj, j)) * inv;
        }
    }
    return true;
}

// Solves L L^T x_c = b_c for the 3 channels at once (x: K x 3 column-major, b on entry), with the
// factor of choleskyInPlace. The three substitutions are interleaved: independent dependency chains.
void choleskySolve3InPlace(const double* L, const double* invDiag, int K, double* x) {
    double* x0 = x;
    double* x1 = x + K;
    double* x2 = x + 2 * K;
    for (int i = 0; i < K; ++i) {
        const double* ri = L + static_cast<std::size_t>(i) * K;
        double a0 = 0.0, a1 = 0.0, a2 = 0.0;
        for (int k = 0; k < i; ++k) {
            a0 += ri[k] * x0[k];
            a1 += ri[k] * x1[k];
            a2 += ri[k] * x2[k];
        }
        x0[i] = (x0[i] - a0) * invDiag[i];
        x1[i] = (x1[i] - a1) * invDiag[i];
        x2[i] = (x2[i] - a2) * invDiag[i];
    }
    for (int i = K - 1; i >= 0; --i) {
        const double* ri = L + static_cast<std::size_t>(i) * K;  // row i of L = column i of L^T
        const double y0 = (x0[i] *= invDiag[i]), y1 = (x1[i] *= invDiag[i]), y2 = (x2[i] *= invDiag[i]);
        for (int k = 0; k < i; ++k) {
            x0[k] -= ri[k] * y0;
            x1[k] -= ri[k] * y1;
            x2[k] -= ri[k] * y2;
        }
    }
}
}  // namespace

std::string RobustFitOptions::validate() const {
    std::ostringstream why;
    if (!basis.isValid())
        why << "the basis " << basis.name() << " is not supported (PB0..PB" << kMaxPolynomialDegree << ", SH0..SH"
            << kMaxHarmonicDegree << ")";
    else if (!(lambda >= 0.0) || !std::isfinite(lambda))
        why << "the regularisation lambda must be a finite number >= 0 (got " << lambda << ")";
    else if (!(coverageAngleDegrees > 0.0 && coverageAngleDegrees <= 90.0))
        why << "the coverage angle must be in (0, 90] degrees (got " << coverageAngleDegrees << ")";
    else if (!(virtualSampleWeight >= 0.0) || !std::isfinite(virtualSampleWeight))
        why << "the virtual sample weight must be a finite number >= 0 (got " << virtualSampleWeight << ")";
    else if (!(rangeTolerance >= 0.0) || !std::isfinite(rangeTolerance))
        why << "the range tolerance must be a finite number >= 0 (got " << rangeTolerance << ")";
    else if (minSamples < 1)
        why << "the minimum number of samples must be at least 1 (got " << minSamples << ")";
    else if (maxGuardRetries < 0 || maxGuardRetries > 10)
        why << "the number of range-guard retries must be in [0, 10] (got " << maxGuardRetries << ")";
    else if (!(poorSamplingFactor >= 0.0) || !std::isfinite(poorSamplingFactor))
        why << "the poor-sampling factor must be a finite number >= 0 (got " << poorSamplingFactor << ")";
    else if (rangeGuard != RangeGuardScope::Off && rangeGuard != RangeGuardScope::PoorlySampledOnly &&
             rangeGuard != RangeGuardScope::AllVertices)
        why << "unknown range-guard scope " << int(rangeGuard);
    return why.str();
}

std::vector<double> fibonacciHemisphere(int count, double phase) {
    std::vector<double> out;
    if (count <= 0) return out;
    out.reserve(3 * static_cast<std::size_t>(count));
    const double golden = kPi * (3.0 - std::sqrt(5.0));  // 2 pi / phi^2
    for (int i = 0; i < count; ++i) {
        const double z = 1.0 - (i + 0.5) / count;
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        const double a = i * golden + phase;
        out.push_back(r * std::cos(a));
        out.push_back(r * std::sin(a));
        out.push_back(z);
    }
    return out;
}

void FitScratch::reserveSamples(int k, std::size_t sampleCount) {
    const std::size_t rows = sampleCount + kCoverageDirections;
    if (K == k && rows <= capacity) return;
    // Grow geometrically so that a run of slowly increasing sample counts reallocates rarely.
    const std::size_t newCapacity = std::max<std::size_t>(rows, capacity + capacity / 2);
    K = k;
    capacity = newCapacity;
    local.resize(3 * newCapacity);
    sqrtWeight.resize(newCapacity);
    design.resize(static_cast<std::size_t>(k) * newCapacity);
    targets.resize(3 * newCapacity);
    gram.resize(static_cast<std::size_t>(k) * k);
    system.resize(static_cast<std::size_t>(k) * k);
    solution.resize(static_cast<std::size_t>(k) * 3);
    trial.resize(static_cast<std::size_t>(k) * 3);
    rhs.resize(static_cast<std::size_t>(k) * 3);
    invDiag.resize(k);
    rotateIn.resize(k);
    rotateOut.resize(k);
    covered.resize(kCoverageDirections);
}

RobustRadianceFitter::RobustRadianceFitter(const RobustFitOptions& options) : options_(options) {
    const std::string why = options.validate();
    if (!why.empty()) throw std::invalid_argument("robust radiance fit: " + why);
    K_ = options.basis.coefficientCount();
    cosCoverage_ = std::cos(options.coverageAngleDegrees * kPi / 180.0);

    coverage_ = fibonacciHemisphere(kCoverageDirections);
    // C: spirals turned away from D's (no point of C coincides with one of D), and rings on the border
    // z = 0, where the border extension takes every value of the lower hemisphere.
    const double goldenStep = kPi * (3.0 - std::sqrt(5.0));
    auto appendRing = [&](int count, double phase) {
        for (int i = 0; i < count; ++i) {
            const double a = (i + phase) * 2.0 * kPi / count;
            check_.push_back(std::cos(a));
            check_.push_back(std::sin(a));
            check_.push_back(0.0);
        }
    };
    check_ = fibonacciHemisphere(kGuardCoarseSpiral, 0.5 * goldenStep);
    appendRing(kGuardCoarseEquator, 0.5);
    const std::vector<double> fine = fibonacciHemisphere(kGuardFineSpiral, 0.25 * goldenStep);
    check_.insert(check_.end(), fine.begin(), fine.end());
    appendRing(kGuardFineEquator, 0.25);

    coverageBasis_.assign(static_cast<std::size_t>(K_) * kCoverageDirections, 0.0);
    for (int i = 0; i < kCoverageDirections; ++i)
        evaluateBasis(options_.basis, coverage_[3 * i], coverage_[3 * i + 1], coverage_[3 * i + 2],
                      coverageBasis_.data() + static_cast<std::size_t>(i) * K_);
    const int C = static_cast<int>(check_.size() / 3);
    checkBasis_.assign(static_cast<std::size_t>(K_) * C, 0.0);
    double values[kMaxCoefficientsPerChannel];
    for (int i = 0; i < C; ++i) {
        evaluateBasis(options_.basis, check_[3 * i], check_[3 * i + 1], check_[3 * i + 2], values);
        for (int k = 0; k < K_; ++k) checkBasis_[static_cast<std::size_t>(k) * C + i] = values[k];
    }

    evaluateBasis(options_.basis, 0.0, 0.0, 1.0, values);
    constantValue_ = values[0];

    reflectSign_.assign(K_, 1.0);
    if (options_.basis.usesLocalFrame()) {
        int index = 0;
        for (int total = 0; total <= options_.basis.degree; ++total)
            for (int j = 0; j <= total; ++j, ++index) reflectSign_[index] = (total % 2 == 0) ? 1.0 : -1.0;
    } else {
        for (int l = 0; l <= options_.basis.degree; ++l)
            for (int m = -l; m <= l; ++m) reflectSign_[harmonicIndex(l, m)] = (std::abs(m) % 2 == 0) ? 1.0 : -1.0;
    }
}

FitScratch RobustRadianceFitter::makeScratch() const {
    FitScratch scratch;
    scratch.reserveSamples(K_, 64);
    return scratch;
}

void RobustRadianceFitter::writeConstant(const Frame&, const double mean[3], float* out) const {
    // The constant function is its own reflection and is invariant under SH rotations: only the
    // coefficient of index 0 (PB u^0 v^0, SH Y_0^0) is nonzero, whatever the storage and frame.
    std::fill(out, out + 3 * K_, 0.0f);
    for (int c = 0; c < 3; ++c) out[c * K_] = static_cast<float>(mean[c] / constantValue_);
}

void RobustRadianceFitter::writeSolution(const Frame& frame, const double* solution, FitScratch& scratch,
                                         float* out) const {
    // solution: K x 3 column-major, local frame, plain L.
    const bool reflect = options_.storeReflected;
    if (options_.basis.usesLocalFrame()) {
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < K_; ++k)
                out[c * K_ + k] = static_cast<float>(reflect ? reflectSign_[k] * solution[c * K_ + k] : solution[c * K_ + k]);
        return;
    }
    // SH fitted in the local frame: f_local(l) with l = Rot w (Rot rows t, b, n). The global function
    // is g(w) = f_local(Rot w) = f_local(R^T w) with R = Rot^T, i.e. f_local rotated by R
    // (sh_rotation.h convention).
    const ShRotation rotation(options_.basis.degree, frame.rotation().transpose());
    for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < K_; ++k)
            scratch.rotateIn[k] = reflect ? reflectSign_[k] * solution[c * K_ + k] : solution[c * K_ + k];
        rotation.apply(scratch.rotateIn.data(), scratch.rotateOut.data());
        for (int k = 0; k < K_; ++k) out[c * K_ + k] = static_cast<float>(scratch.rotateOut[k]);
    }
}

bool RobustRadianceFitter::insideBand(const double* x, double lo, double hi) const {
    // Values of one channel (coefficients x[0..K)) at the points of C, block by block (k outer,
    // points inner: the inner loop is a vectorisable axpy), stopping at the first block with a value
    // outside [lo, hi]. The coarse part of C comes first, so most failing fits are rejected after
    // kGuardCoarse* points.
    constexpr int kBlock = 96;
    const int C = kGuardDirections;
    const int K = K_;
    double acc[kBlock];
    for (int begin = 0; begin < C; begin += kBlock) {
        const int size = std::min(kBlock, C - begin);
        for (int i = 0; i < size; ++i) acc[i] = x[0] * checkBasis_[begin + i];
        for (int k = 1; k < K; ++k) {
            const double* row = checkBasis_.data() + static_cast<std::size_t>(k) * C + begin;
            const double xk = x[k];
            for (int i = 0; i < size; ++i) acc[i] += xk * row[i];
        }
        for (int i = 0; i < size; ++i)
            if (!(acc[i] >= lo && acc[i] <= hi)) return false;  // also catches NaN
    }
    return true;
}

VertexFitResult RobustRadianceFitter::fit(const Frame& frame, const DirectionalSample* samples, std::size_t count,
                                          FitScratch& scratch, float* out) const {
    VertexFitResult result;
    const int K = K_;
    scratch.reserveSamples(K, count);

    // 1-2. Local directions (border-extended), weighted mean, observed range.
    double sumW = 0.0, sumWY[3] = {0.0, 0.0, 0.0};
    double lo[3] = {0.0, 0.0, 0.0}, hi[3] = {0.0, 0.0, 0.0};
    std::size_t n = 0;
    double* local = scratch.local.data();
    double* targets = scratch.targets.data();
    const std::size_t rowsCapacity = scratch.capacity;
    for (std::size_t j = 0; j < count; ++j) {
        const DirectionalSample& s = samples[j];
        if (!finite3(s.direction) || !finite3(s.rgb) || !std::isfinite(s.weight) || !(s.weight > 0.0f)) continue;
        const Eigen::Vector3d w(s.direction[0], s.direction[1], s.direction[2]);
        const double len = w.norm();
        if (!(len > 0.0)) continue;
        double x = frame.t.dot(w) / len, y = frame.b.dot(w) / len, z = frame.n.dot(w) / len;
        borderExtendLocal(x, y, z);  // Vanhoey et al. 2015 sec. 7
        local[3 * n] = x;
        local[3 * n + 1] = y;
        local[3 * n + 2] = z;
        const double a = s.weight;
        const double sq = std::sqrt(a);
        for (int c = 0; c < 3; ++c) {
            const double v = s.rgb[c];
            sumWY[c] += a * v;
            targets[c * rowsCapacity + n] = sq * v;
            if (n == 0 || v < lo[c]) lo[c] = v;
            if (n == 0 || v > hi[c]) hi[c] = v;
        }
        scratch.sqrtWeight[n] = sq;
        sumW += a;
        ++n;
    }
    result.sampleCount = static_cast<int>(n);
    if (n == 0) {
        result.status = FitStatus::Unseen;
        std::fill(out, out + 3 * K, 0.0f);
        return result;
    }
    double mean[3];
    for (int c = 0; c < 3; ++c) mean[c] = result.meanColor[c] = sumWY[c] / sumW;

    auto constantResidual = [&]() {
        double e = 0.0;
        for (std::size_t j = 0; j < n; ++j) {
            const double sq = scratch.sqrtWeight[j];
            for (int c = 0; c < 3; ++c) {
                const double d = targets[c * rowsCapacity + j] - sq * mean[c];
                e += d * d;
            }
        }
        return std::sqrt(e / (3.0 * sumW));
    };

    if (static_cast<int>(n) < options_.minSamples) {
        result.status = FitStatus::PoorlySampled;
        result.constantFallback = true;
        result.residual = constantResidual();
        writeConstant(frame, mean, out);
        return result;
    }

    // 3. Coverage of D.
    const int D = kCoverageDirections;
    int coveredCount = 0;
    for (int i = 0; i < D; ++i) {
        const double dx = coverage_[3 * i], dy = coverage_[3 * i + 1], dz = coverage_[3 * i + 2];
        unsigned char hit = 0;
        for (std::size_t j = 0; j < n; ++j)
            if (dx * local[3 * j] + dy * local[3 * j + 1] + dz * local[3 * j + 2] >= cosCoverage_) {
                hit = 1;
                break;
            }
        scratch.covered[i] = hit;
        coveredCount += hit;
    }
    result.coveredDirections = coveredCount;
    const bool poorly = static_cast<double>(n) < options_.poorSamplingFactor * K || 2 * coveredCount < D;
    result.status = poorly ? FitStatus::PoorlySampled : FitStatus::Fitted;

    // 4. Design matrix [sqrt(a_j) B(l_j) | sqrt(v) B(d_i) for uncovered d_i] and targets.
    double* design = scratch.design.data();
    for (std::size_t j = 0; j < n; ++j) {
        const double sq = scratch.sqrtWeight[j];
        double* col = design + j * K;
        evaluateBasis(options_.basis, local[3 * j], local[3 * j + 1], local[3 * j + 2], col);
        for (int k = 0; k < K; ++k) col[k] *= sq;
    }
    std::size_t rows = n;
    const double virtualWeight = options_.virtualSampleWeight * sumW / static_cast<double>(n);
    if (virtualWeight > 0.0) {
        const double sq = std::sqrt(virtualWeight);
        for (int i = 0; i < D; ++i) {
            if (scratch.covered[i]) continue;
            const double* src = coverageBasis_.data() + static_cast<std::size_t>(i) * K;
            double* col = design + rows * K;
            for (int k = 0; k < K; ++k) col[k] = sq * src[k];
            for (int c = 0; c < 3; ++c) targets[c * rowsCapacity + rows] = sq * mean[c];
            ++rows;
        }
    }
    const ConstMatrixMap B(design, K, static_cast<Eigen::Index>(rows));
    // G = B B^T. Eigen fills the upper triangle of the column-major G, which is the lower triangle
    // of the same buffer read row-major, as choleskyInPlace reads it (G is symmetric).
    MatrixMap G(scratch.gram.data(), K, K);
    G.setZero();
    G.selfadjointView<Eigen::Upper>().rankUpdate(B);
    // r = B Y (K x 3), by hand: an Eigen GEMM here would go through its OpenMP-parallel product
    // path, pointless inside our per-vertex parallel loop and costly at these sizes.
    MatrixMap rhs(scratch.rhs.data(), K, 3);
    rhs.setZero();
    for (std::size_t j = 0; j < rows; ++j) {
        const double* col = design + j * K;
        for (int c = 0; c < 3; ++c) {
            const double y = targets[c * rowsCapacity + j];
            double* r = scratch.rhs.data() + c * K;
            for (int k = 0; k < K; ++k) r[k] += y * col[k];
        }
    }
    MatrixMap X(scratch.trial.data(), K, 3);
    const double trace = G.trace();
    const double scale = trace / K;

    const bool guard = options_.rangeGuard == RangeGuardScope::AllVertices ||
                       (options_.rangeGuard == RangeGuardScope::PoorlySampledOnly && poorly);
    // The channels share the matrix but not the right-hand side, so the guard accepts or escalates
    // each channel on its own (our refinement of "retry with 10 lambda": a channel that stays in its
    // range keeps the least regularised fit, whatever the others do). A channel whose observed values
    // are all equal is the constant m_c outright: any fit in its zero-width band would only differ
    // from it by rounding.
    double* final = scratch.solution.data();  // K x 3, column-major: the accepted coefficients
    bool pending[3];
    double bandLo[3], bandHi[3];
    int pendingCount = 0;
    for (int c = 0; c < 3; ++c) {
        const double margin = kGuardMarginFraction * options_.rangeTolerance * (hi[c] - lo[c]);
        bandLo[c] = lo[c] - margin;
        bandHi[c] = hi[c] + margin;
        pending[c] = !(guard && hi[c] == lo[c]);
        if (pending[c]) {
            ++pendingCount;
        } else {
            std::fill(final + c * K, final + (c + 1) * K, 0.0);
            final[c * K] = mean[c] / constantValue_;
        }
    }
    // Without the guard, further attempts only happen when the system is singular.
    const int attempts = options_.maxGuardRetries + 1;
    for (int attempt = 0; attempt < attempts && pendingCount > 0; ++attempt) {
        const double lambda = attempt == 0 ? options_.lambda
                                           : std::max(options_.lambda, kEscalationBaseLambda) * std::pow(10.0, attempt);
        double* A = scratch.system.data();
        std::copy(scratch.gram.begin(), scratch.gram.begin() + static_cast<std::ptrdiff_t>(K) * K, A);
        if (lambda > 0.0)
            for (int k = 1; k < K; ++k) A[k * K + k] += lambda * scale;  // the constant function is not penalised
        X = rhs;
        // Singular systems: with lambda > 0 the matrix is positive definite by construction
        // (G_00 = sum a_j B_0^2 > 0 and lambda s on the other diagonal entries) and its pivots are at
        // least of the order of lambda s; with lambda = 0 a pivot below 1e-12 trace(G) (about
        // 1e-12 of the largest eigenvalue) means degenerate samples.
        const double minPivot = (lambda > 0.0 ? kMinReciprocalCondition : 1e-12) * trace;
        if (!choleskyInPlace(A, K, minPivot, scratch.invDiag.data())) {
            result.guardRetries = attempt + 1;
            continue;  // singular (lambda = 0 with degenerate samples): escalate lambda
        }
        choleskySolve3InPlace(A, scratch.invDiag.data(), K, X.data());
        bool escalate = false;
        for (int c = 0; c < 3; ++c) {
            if (!pending[c]) continue;
            const double* xc = X.data() + c * K;
            bool finite = true;
            for (int k = 0; k < K; ++k) finite = finite && std::isfinite(xc[k]);
            if (finite && (!guard || insideBand(xc, bandLo[c], bandHi[c]))) {
                std::copy(xc, xc + K, final + c * K);
                pending[c] = false;
                --pendingCount;
            } else {
                escalate = true;
            }
        }
        if (escalate) result.guardRetries = attempt + 1;
    }
    // Channels that never passed: the constant m_c (always inside the observed range).
    int constantChannels = 0;
    for (int c = 0; c < 3; ++c) {
        if (!pending[c]) continue;
        std::fill(final + c * K, final + (c + 1) * K, 0.0);
        final[c * K] = mean[c] / constantValue_;
        ++constantChannels;
    }
    result.fallbackChannels = constantChannels;
    if (constantChannels == 3) {
        result.constantFallback = true;
        result.residual = constantResidual();
        writeConstant(frame, mean, out);
        return result;
    }
    // Residual of the real samples: rows 0..n-1 of B^T X - Y are sqrt(a_j) (L(w_j) - y_j).
    double e = 0.0;
    for (std::size_t j = 0; j < n; ++j) {
        const double* col = design + j * K;
        for (int c = 0; c < 3; ++c) {
            double f = 0.0;
            for (int k = 0; k < K; ++k) f += col[k] * final[c * K + k];
            const double d = f - targets[c * rowsCapacity + j];
            e += d * d;
        }
    }
    result.residual = std::sqrt(e / (3.0 * sumW));
    writeSolution(frame, scratch.solution.data(), scratch, out);
    return result;
}

}  // namespace rad
