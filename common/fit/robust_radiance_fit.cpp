#include "fit/robust_radiance_fit.h"

#include "radiance/radiance_evaluation.h"
#include "radiance/sh_rotation.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
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

// Forward substitution L y = b for the 3 channels (y: 3 columns of `stride`, b on entry), on the
// leading `size` x `size` block of a factor whose rows are `stride` long.
void forward3InPlace(const double* L, const double* invDiag, int stride, int size, double* x) {
    double* x0 = x;
    double* x1 = x + stride;
    double* x2 = x + 2 * stride;
    for (int i = 0; i < size; ++i) {
        const double* ri = L + static_cast<std::size_t>(i) * stride;
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
}

// Back substitution L^T x = y on the leading `size` block (same layout as forward3InPlace). The
// leading block of the factor of A is the factor of A's leading block, and the first `size` entries
// of L^-1 b only depend on the first `size` entries of b: one factorisation solves every lower
// degree too (the bases are ordered by degree).
void backward3InPlace(const double* L, const double* invDiag, int stride, int size, double* x) {
    double* x0 = x;
    double* x1 = x + stride;
    double* x2 = x + 2 * stride;
    for (int i = size - 1; i >= 0; --i) {
        const double* ri = L + static_cast<std::size_t>(i) * stride;
        const double y0 = (x0[i] *= invDiag[i]), y1 = (x1[i] *= invDiag[i]), y2 = (x2[i] *= invDiag[i]);
        for (int k = 0; k < i; ++k) {
            x0[k] -= ri[k] * y0;
            x1[k] -= ri[k] * y1;
            x2[k] -= ri[k] * y2;
        }
    }
}

// Forward substitution of one vector (x on entry = b).
void forward1InPlace(const double* L, const double* invDiag, int K, double* x) {
    for (int i = 0; i < K; ++i) {
        const double* ri = L + static_cast<std::size_t>(i) * K;
        x[i] = (x[i] - dot(ri, x, i)) * invDiag[i];
    }
}

// Leave-one-out residuals are r_j / (1 - h_jj); a self-influence this close to 1 means the sample
// alone determines the candidate there: its validation error is unbounded.
constexpr double kMinLooDenominator = 1e-6;
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
    else if (validationLambdas < 0 || validationLambdas > 8)
        why << "the number of validation lambdas must be in [0, 8] (got " << validationLambdas << ")";
    else if (robustIterations < 0 || robustIterations > 10)
        why << "the number of robust (Huber) iterations must be in [0, 10] (got " << robustIterations << ")";
    else if (!(validationMargin >= 0.0) || !std::isfinite(validationMargin))
        why << "the validation margin must be a finite number of standard errors >= 0 (got " << validationMargin << ")";
    else if (!(huberThreshold > 0.0) || !std::isfinite(huberThreshold))
        why << "the Huber threshold must be a finite number > 0 (got " << huberThreshold << ")";
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
    inverseWeight.resize(newCapacity);
    baseWeight.resize(newCapacity);
    robustWeight.resize(newCapacity);
    values.resize(3 * newCapacity);
    basisValues.resize(static_cast<std::size_t>(k) * newCapacity);
    looNorm.resize(newCapacity);
    looByDegree.resize((std::max(kMaxPolynomialDegree, kMaxHarmonicDegree) + 1) * newCapacity);
    errorScale.resize(3 * newCapacity);
    designT.resize(static_cast<std::size_t>(k) * newCapacity);
    zMatrix.resize(static_cast<std::size_t>(k) * newCapacity);
    hatP.resize(newCapacity);
    hatQ.resize(newCapacity);
    fitted.resize(3 * newCapacity);
    sortBuffer.resize(newCapacity);
    forward.resize(static_cast<std::size_t>(k) * 3);
    virtualLeverage.resize(k);
    virtualSum.resize(k);
    virtualGram.resize(static_cast<std::size_t>(k) * (k + 1) / 2);
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
    for (int i = 0; i < kCoverageDirections; ++i) {
        coverageX_.push_back(coverage_[3 * i]);
        coverageY_.push_back(coverage_[3 * i + 1]);
        coverageZ_.push_back(coverage_[3 * i + 2]);
    }
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
    const std::size_t packedSize = static_cast<std::size_t>(K_) * (K_ + 1) / 2;
    coverageOuter_.assign(packedSize * kCoverageDirections, 0.0);
    coverageGram_.assign(packedSize, 0.0);
    coverageSum_.assign(K_, 0.0);
    for (int i = 0; i < kCoverageDirections; ++i) {
        const double* b = coverageBasis_.data() + static_cast<std::size_t>(i) * K_;
        double* outer = coverageOuter_.data() + packedSize * i;
        for (int r = 0, e = 0; r < K_; ++r)
            for (int k = 0; k <= r; ++k, ++e) outer[e] = b[r] * b[k];
        for (std::size_t e = 0; e < packedSize; ++e) coverageGram_[e] += outer[e];
        for (int k = 0; k < K_; ++k) coverageSum_[k] += b[k];
    }
    const int C = static_cast<int>(check_.size() / 3);
    checkBasis_.assign(static_cast<std::size_t>(K_) * C, 0.0);
    double values[kMaxCoefficientsPerChannel];
    for (int i = 0; i < C; ++i) {
        evaluateBasis(options_.basis, check_[3 * i], check_[3 * i + 1], check_[3 * i + 2], values);
        for (int k = 0; k < K_; ++k) checkBasis_[static_cast<std::size_t>(k) * C + i] = values[k];
    }

    evaluateBasis(options_.basis, 0.0, 0.0, 1.0, values);
    constantValue_ = values[0];

    for (int d = 0; d <= options_.basis.degree; ++d) degreeK_.push_back(BasisSpec{options_.basis.kind, d}.coefficientCount());
    for (int i = 0; i < options_.validationLambdas; ++i)
        lambdaGrid_.push_back(i == 0 ? options_.lambda : std::max(options_.lambda, kEscalationBaseLambda) * std::pow(10.0, i));

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

void RobustRadianceFitter::insideBands(const double* X, int Ka, const bool* test, const double* lo, const double* hi,
                                       bool* inside) const {
    // Values at the points of C, block by block, of the three channels at once (each row of the
    // basis table is read once for the three; k outer, points inner: vectorisable axpys), over the
    // Ka coefficients in use (the others are 0). A channel leaves the test at its first block with
    // a value outside [lo, hi]; the coarse part of C comes first, so most failing fits are rejected
    // after kGuardCoarse* points.
    constexpr int kBlock = 96;
    const int C = kGuardDirections;
    int testing = 0;
    for (int c = 0; c < 3; ++c) {
        inside[c] = test[c];
        testing += test[c];
    }
    double acc[3][kBlock];
    for (int begin = 0; begin < C && testing > 0; begin += kBlock) {
        const int size = std::min(kBlock, C - begin);
        for (int c = 0; c < 3; ++c) {
            const double x0 = X[c * K_];
            for (int i = 0; i < size; ++i) acc[c][i] = x0 * checkBasis_[begin + i];
        }
        for (int k = 1; k < Ka; ++k) {
            const double* row = checkBasis_.data() + static_cast<std::size_t>(k) * C + begin;
            const double x0 = X[k], x1 = X[K_ + k], x2 = X[2 * K_ + k];
            for (int i = 0; i < size; ++i) {
                acc[0][i] += x0 * row[i];
                acc[1][i] += x1 * row[i];
                acc[2][i] += x2 * row[i];
            }
        }
        for (int c = 0; c < 3; ++c) {
            if (!inside[c]) continue;
            for (int i = 0; i < size; ++i)
                if (!(acc[c][i] >= lo[c] && acc[c][i] <= hi[c])) {  // also catches NaN
                    inside[c] = false;
                    --testing;
                    break;
                }
        }
    }
}

// The weighted system of the current effective weights (a_j times the Huber weight).
struct RobustRadianceFitter::Assembly {
    double sumW = 0.0;          // sum of the effective weights
    double mean[3] = {0.0, 0.0, 0.0};
    double virtualWeight = 0.0; // weight of each virtual sample (0: none)
    double trace = 0.0, scale = 0.0;
};

// One candidate of the validation.
struct RobustRadianceFitter::Choice {
    bool constant = false;
    double lambda = 0.0;
    int degree = 0;
    double error = 0.0;          // of the chosen candidate
    double constantError = 0.0;  // of the constant mean colour
};

void RobustRadianceFitter::assemble(FitScratch& scratch, std::size_t n, Assembly& a) const {
    const int K = K_;
    const std::size_t cap = scratch.capacity;
    a = Assembly();
    double sumWY[3] = {0.0, 0.0, 0.0};
    for (std::size_t j = 0; j < n; ++j) {
        const double w = scratch.baseWeight[j] * scratch.robustWeight[j];
        a.sumW += w;
        for (int c = 0; c < 3; ++c) sumWY[c] += w * scratch.values[c * cap + j];
    }
    for (int c = 0; c < 3; ++c) a.mean[c] = sumWY[c] / a.sumW;
    double* design = scratch.design.data();
    double* targets = scratch.targets.data();
    for (std::size_t j = 0; j < n; ++j) {
        const double w = scratch.baseWeight[j] * scratch.robustWeight[j];
        const double sq = std::sqrt(w);
        scratch.sqrtWeight[j] = sq;
        scratch.inverseWeight[j] = w > 0.0 ? 1.0 / w : 0.0;
        const double* b = scratch.basisValues.data() + j * K;
        double* col = design + j * K;
        for (int k = 0; k < K; ++k) {
            col[k] = sq * b[k];
            scratch.designT[static_cast<std::size_t>(k) * cap + j] = col[k];
        }
        for (int c = 0; c < 3; ++c) targets[c * cap + j] = sq * scratch.values[c * cap + j];
    }
    a.virtualWeight = options_.virtualSampleWeight * a.sumW / static_cast<double>(n);
    double* G = scratch.gram.data();  // row-major, lower triangle (what choleskyInPlace reads)
    const double* virtualSum = scratch.virtualSum.data();
    if (a.virtualWeight > 0.0 && scratch.virtualCount > 0) {
        const double* packed = scratch.virtualGram.data();
        for (int r = 0; r < K; ++r, packed += r) {
            double* row = G + static_cast<std::size_t>(r) * K;
            for (int k = 0; k <= r; ++k) row[k] = a.virtualWeight * packed[k];
        }
        for (int c = 0; c < 3; ++c) {
            double* rr = scratch.rhs.data() + c * K;
            const double scaledMean = a.virtualWeight * a.mean[c];
            for (int k = 0; k < K; ++k) rr[k] = scaledMean * virtualSum[k];
        }
    } else {
        std::fill(G, G + static_cast<std::ptrdiff_t>(K) * K, 0.0);
        std::fill(scratch.rhs.begin(), scratch.rhs.begin() + 3 * K, 0.0);
    }
    // The real samples' rows: G += B B^T, r += B Y, by hand (at K <= 121 and a few dozen rows
    // Eigen's blocked products cost more in packing than they save).
    for (std::size_t j = 0; j < n; ++j) {
        const double* col = design + j * K;
        for (int i = 0; i < K; ++i) {
            const double ci = col[i];
            double* row = G + static_cast<std::size_t>(i) * K;
            for (int k = 0; k <= i; ++k) row[k] += ci * col[k];
        }
        for (int c = 0; c < 3; ++c) {
            const double y = targets[c * cap + j];
            double* r = scratch.rhs.data() + c * K;
            for (int k = 0; k < K; ++k) r[k] += y * col[k];
        }
    }
    a.trace = 0.0;
    for (int k = 0; k < K; ++k) a.trace += G[static_cast<std::size_t>(k) * K + k];
    a.scale = a.trace / K;
}

// The virtual samples' unscaled sums, once per vertex (the IRLS only changes their weight): sum b b^T
// (packed lower triangle) and sum b over the uncovered directions of D, or, when fewer are covered,
// D's whole sums minus the covered directions' (the fewer terms either way; the terms are D's
// precomputed packed outer products, so each is one contiguous vectorisable add).
void RobustRadianceFitter::sumVirtualSamples(FitScratch& scratch) const {
    const int K = K_;
    const int D = kCoverageDirections;
    const std::size_t T = static_cast<std::size_t>(K) * (K + 1) / 2;
    int coveredCount = 0;
    for (int i = 0; i < D; ++i) coveredCount += scratch.covered[i];
    scratch.virtualCount = static_cast<std::size_t>(D - coveredCount);
    const bool complement = coveredCount < D - coveredCount;
    const unsigned char wanted = complement ? 1 : 0;
    const double sign = complement ? -1.0 : 1.0;
    double* gram = scratch.virtualGram.data();
    double* sum = scratch.virtualSum.data();
    if (complement) {
        std::copy(coverageGram_.begin(), coverageGram_.end(), gram);
        std::copy(coverageSum_.begin(), coverageSum_.end(), sum);
    } else {
        std::fill(gram, gram + T, 0.0);
        std::fill(sum, sum + K, 0.0);
    }
    for (int i = 0; i < D; ++i) {
        if (scratch.covered[i] != wanted) continue;
        const double* outer = coverageOuter_.data() + static_cast<std::size_t>(i) * T;
        for (std::size_t e = 0; e < T; ++e) gram[e] += sign * outer[e];
        const double* b = coverageBasis_.data() + static_cast<std::size_t>(i) * K;
        for (int k = 0; k < K; ++k) sum[k] += sign * b[k];
    }
}

// Validation errors of the fits at `lambda` of every degree in [degreeLow, degreeHigh] (errors[d]),
// +infinity for a singular system. Leave-one-out through the self-influence h_jj of each real
// sample: the fit is linear in the data, f = S y, and the leave-one-out residual of a linear
// smoother is approximately (f_j - y_j) / (1 - S_jj) (exact for plain ridge regression; here the
// virtual samples' value, the mean colour, also depends on y_j, which the S_jj below includes:
// S_jj = a_j B_j^T A^-1 (B_j + (v / W) sum_virtual B_i)). storeLooNorms: the per-sample
// squared |leave-one-out residual| (mean square over channels) of degree d go to row d of
// scratch.looByDegree, for
// the IRLS.
bool RobustRadianceFitter::scoreModels(FitScratch& scratch, std::size_t n, const Assembly& a, double lambda,
                                       int degreeLow, int degreeHigh, double* errors, double* standardErrors,
                                       bool storeLooNorms) const {
    const int K = K_;
    const std::size_t cap = scratch.capacity;
    for (int d = degreeLow; d <= degreeHigh; ++d) errors[d] = std::numeric_limits<double>::infinity();
    double* A = scratch.system.data();
    std::copy(scratch.gram.begin(), scratch.gram.begin() + static_cast<std::ptrdiff_t>(K) * K, A);
    if (lambda > 0.0)
        for (int k = 1; k < K; ++k) A[k * K + k] += lambda * a.scale;
    const double minPivot = (lambda > 0.0 ? kMinReciprocalCondition : 1e-12) * a.trace;
    if (!choleskyInPlace(A, K, minPivot, scratch.invDiag.data())) return false;
    const double* invDiag = scratch.invDiag.data();
    double* forward = scratch.forward.data();  // L^-1 r: its leading entries serve every lower degree
    std::copy(scratch.rhs.begin(), scratch.rhs.begin() + 3 * K, forward);
    forward3InPlace(A, invDiag, K, K, forward);
    double* u = scratch.virtualLeverage.data();
    std::copy(scratch.virtualSum.begin(), scratch.virtualSum.begin() + K, u);
    forward1InPlace(A, invDiag, K, u);
    const double leak = a.virtualWeight > 0.0 ? a.virtualWeight / a.sumW : 0.0;
    double sums[kMaxPolynomialDegree + kMaxHarmonicDegree + 2] = {};
    double squares[kMaxPolynomialDegree + kMaxHarmonicDegree + 2] = {};
    // Sample-major loops (j contiguous, vectorisable) over the transposed design: Z = L^-1 B of all
    // real samples by a forward substitution of whole rows, each row folded as soon as it is known
    // into the running sums over k that give every degree its self-influences and fitted values.
    const double* designT = scratch.designT.data();  // K rows of cap: sqrt(a_j) B_i(l_j)
    const double* targets = scratch.targets.data();
    double* Z = scratch.zMatrix.data();
    double* P = scratch.hatP.data();
    double* Q = scratch.hatQ.data();
    double* F = scratch.fitted.data();  // 3 x cap
    std::fill(P, P + n, 0.0);
    std::fill(Q, Q + n, 0.0);
    for (int c = 0; c < 3; ++c) std::fill(F + static_cast<std::size_t>(c) * cap, F + static_cast<std::size_t>(c) * cap + n, 0.0);
    int k = 0;
    for (int d = 0; d <= degreeHigh; ++d) {
        // The degree-d fit's (weighted) values at the samples are Z_d^T (L^-1 r)_d, Z_d and (L^-1 r)_d
        // the leading K_d rows: running sums over k, like the self-influences, so no degree needs a
        // back substitution or a pass of its own over the design.
        for (; k < degreeK_[d]; ++k) {
            double* zk = Z + static_cast<std::size_t>(k) * cap;
            const double* Lk = A + static_cast<std::size_t>(k) * K;
            const double inv = invDiag[k];
            const double* bk = designT + static_cast<std::size_t>(k) * cap;
            // Four samples at a time, the sum over the earlier rows kept in registers (rows are
            // padded: cap >= n + kCoverageDirections, and the lanes past n are never read back).
            for (std::size_t jj = 0; jj < n; jj += 4) {
                double a0 = bk[jj], a1 = bk[jj + 1], a2 = bk[jj + 2], a3 = bk[jj + 3];
                for (int i = 0; i < k; ++i) {
                    const double lki = Lk[i];
                    const double* zi = Z + static_cast<std::size_t>(i) * cap + jj;
                    a0 -= lki * zi[0];
                    a1 -= lki * zi[1];
                    a2 -= lki * zi[2];
                    a3 -= lki * zi[3];
                }
                zk[jj] = a0;
                zk[jj + 1] = a1;
                zk[jj + 2] = a2;
                zk[jj + 3] = a3;
            }
            const double uk = u[k];
            const double f0 = forward[k], f1 = forward[K + k], f2 = forward[2 * K + k];
            for (std::size_t jj = 0; jj < n; ++jj) {
                const double z = (zk[jj] *= inv);
                P[jj] += z * z;
                Q[jj] += z * uk;
                F[jj] += z * f0;
                F[cap + jj] += z * f1;
                F[2 * cap + jj] += z * f2;
            }
        }
        if (d < degreeLow) continue;
        for (std::size_t jj = 0; jj < n; ++jj) {
            const double h = P[jj] + leak * scratch.sqrtWeight[jj] * Q[jj];
            const double denominator = 1.0 - h;
            // a_j |f_j - y_j|^2 (the rows are sqrt(a_j)-scaled), in sRGB units and plain.
            double e = 0.0, plain = 0.0;
            for (int c = 0; c < 3; ++c) {
                const double r = F[static_cast<std::size_t>(c) * cap + jj] - targets[static_cast<std::size_t>(c) * cap + jj];
                e += scratch.errorScale[c * cap + jj] * r * r;
                plain += r * r;
            }
            if (denominator < kMinLooDenominator) {
                sums[d] = std::numeric_limits<double>::infinity();
                if (storeLooNorms) scratch.looByDegree[d * cap + jj] = std::numeric_limits<double>::infinity();
                continue;
            }
            const double inverse = 1.0 / denominator;
            const double term = e * inverse * inverse;
            sums[d] += term;
            squares[d] += term * term;
            // Squared, and unweighted by 1 / a_j: the root is only taken for the winner (takeLooNorms).
            if (storeLooNorms)
                scratch.looByDegree[d * cap + jj] = (plain / 3.0) * inverse * inverse * scratch.inverseWeight[jj];
        }
    }
    for (int d = degreeLow; d <= degreeHigh; ++d) {
        errors[d] = sums[d] / a.sumW;
        // Standard error of that mean: the per-sample terms' spread, sqrt(n var) / W.
        if (standardErrors)
            standardErrors[d] = std::sqrt(std::max(0.0, squares[d] - sums[d] * sums[d] / static_cast<double>(n))) / a.sumW;
    }
    return true;
}

// The constant mean colour's validation error: its leave-one-out prediction of sample j is the
// weighted mean of the others, exactly (m - y_j) W / (W - a_j) away from y_j.
double RobustRadianceFitter::scoreConstant(FitScratch& scratch, std::size_t n, const Assembly& a,
                                           bool storeLooNorms) const {
    const std::size_t cap = scratch.capacity;
    double sum = 0.0;
    for (std::size_t j = 0; j < n; ++j) {
        const double w = scratch.baseWeight[j] * scratch.robustWeight[j];
        const double denominator = 1.0 - w / a.sumW;
        double e = 0.0, plain = 0.0;
        for (int c = 0; c < 3; ++c) {
            const double r = a.mean[c] - scratch.values[c * cap + j];
            e += scratch.errorScale[c * cap + j] * r * r;
            plain += r * r;
        }
        if (denominator < kMinLooDenominator) {
            sum = std::numeric_limits<double>::infinity();
            if (storeLooNorms) scratch.looNorm[j] = std::numeric_limits<double>::infinity();
            continue;
        }
        sum += w * e / (denominator * denominator);
        if (storeLooNorms) scratch.looNorm[j] = std::sqrt(plain / 3.0) / denominator;
    }
    return sum / a.sumW;
}

// scratch.looNorm := the leave-one-out residual norms of degree d that scoreModels left squared.
void RobustRadianceFitter::takeLooNorms(FitScratch& scratch, int d, std::size_t n) const {
    const double* squared = scratch.looByDegree.data() + static_cast<std::size_t>(d) * scratch.capacity;
    for (std::size_t j = 0; j < n; ++j) scratch.looNorm[j] = std::sqrt(squared[j]);
}

RobustRadianceFitter::Choice RobustRadianceFitter::choose(FitScratch& scratch, std::size_t n, const Assembly& a) const {
    Choice best;
    best.lambda = options_.lambda;
    best.degree = options_.basis.degree;
    if (lambdaGrid_.empty()) return best;  // validation off
    best.constantError = scoreConstant(scratch, n, a, false);
    best.error = std::numeric_limits<double>::infinity();
    const int high = options_.basis.degree;
    const int low = options_.validateLowerDegrees ? std::min(1, high) : high;
    double errors[kMaxPolynomialDegree + kMaxHarmonicDegree + 2];
    double standardErrors[kMaxPolynomialDegree + kMaxHarmonicDegree + 2];
    double bestStandardError = 0.0;
    // Candidates in order of preference (full degree first, least lambda first): a later one must be
    // strictly better to replace an earlier one.
    // The best candidate's per-sample leave-one-out residuals are kept in scratch.looNorm (the
    // IRLS's first reference, without scoring it again).
    for (const double lambda : lambdaGrid_) {
        if (!scoreModels(scratch, n, a, lambda, low, high, errors, standardErrors, true)) continue;
        for (int d = high; d >= low; --d)
            if (errors[d] < best.error) {
                best.error = errors[d];
                bestStandardError = standardErrors[d];
                best.lambda = lambda;
                best.degree = d;
                takeLooNorms(scratch, d, n);
            }
    }
    // The least validation error among 4 x (degree) candidates is biased low (the best of several
    // noisy estimates), so the constant, the simpler model, is kept unless the best fit beats it by
    // more than one standard error of its validation error (the "one-standard-error rule" of
    // cross-validation, Hastie, Tibshirani and Friedman, The Elements of Statistical Learning, 7.10).
    best.constant = !(best.error + options_.validationMargin * bestStandardError < best.constantError);
    return best;
}

// The observed range of each channel of the vertex's samples (the range guard's band).
struct RobustRadianceFitter::ObservedRange {
    double lo[3] = {0.0, 0.0, 0.0}, hi[3] = {0.0, 0.0, 0.0};
};

// What fit() knows of the vertex at hand, passed to its steps.
struct RobustRadianceFitter::VertexProblem {
    const Frame& frame;
    FitScratch& scratch;
    float* out;
    std::size_t n = 0;    // usable real samples
    double sumA = 0.0;    // sum of their own weights a_j
    ObservedRange range;
};

std::size_t RobustRadianceFitter::loadSamples(const Frame& frame, const DirectionalSample* samples, std::size_t count,
                                              FitScratch& scratch, ObservedRange& range) const {
    const std::size_t cap = scratch.capacity;
    double* lo = range.lo;
    double* hi = range.hi;
    std::size_t n = 0;
    double* local = scratch.local.data();
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
        for (int c = 0; c < 3; ++c) {
            const double v = s.rgb[c];
            scratch.values[c * cap + n] = v;
            if (n == 0 || v < lo[c]) lo[c] = v;
            if (n == 0 || v > hi[c]) hi[c] = v;
        }
        scratch.baseWeight[n] = s.weight;
        scratch.robustWeight[n] = 1.0;
        ++n;
    }
    return n;
}

void RobustRadianceFitter::setValidationErrorScales(FitScratch& scratch, std::size_t n) const {
    // Validation errors are measured in sRGB-encoded units, to first order: the squared residual of
    // channel c of sample j is scaled by (d sRGB / d linear)^2 at the sample's value. Photographs
    // are compared (and seen) in those units, where an error of 0.002 in a dark channel weighs as
    // much as one of 0.03 in a bright one; in linear units the model choice of dark vertices would
    // hinge on differences nobody sees while their visible errors went unnoticed.
    const std::size_t cap = scratch.capacity;
    for (std::size_t j = 0; j < n; ++j)
        for (int c = 0; c < 3; ++c) {
            const double y = scratch.values[c * cap + j];
            const double slope = y <= 0.0031308 ? 12.92 : (1.055 / 2.4) * std::pow(std::min(y, 1.0), 1.0 / 2.4 - 1.0);
            scratch.errorScale[c * cap + j] = slope * slope;
        }
}

// Weighted mean of the current effective weights.
void RobustRadianceFitter::weightedMean(const FitScratch& scratch, std::size_t n, double mean[3], double& sumW) const {
    const std::size_t cap = scratch.capacity;
    double sumWY[3] = {0.0, 0.0, 0.0};
    sumW = 0.0;
    for (std::size_t j = 0; j < n; ++j) {
        const double w = scratch.baseWeight[j] * scratch.robustWeight[j];
        sumW += w;
        for (int c = 0; c < 3; ++c) sumWY[c] += w * scratch.values[c * cap + j];
    }
    for (int c = 0; c < 3; ++c) mean[c] = sumWY[c] / sumW;
}

// The residual reported for the vertex weighs the samples by their own weights a_j, whatever the
// IRLS did: it says how far the function is from what the photographs show.
double RobustRadianceFitter::constantResidual(const VertexProblem& p, const double mean[3]) const {
    const FitScratch& scratch = p.scratch;
    const std::size_t cap = scratch.capacity;
    double e = 0.0;
    for (std::size_t j = 0; j < p.n; ++j) {
        for (int c = 0; c < 3; ++c) {
            const double d = scratch.values[c * cap + j] - mean[c];
            e += scratch.baseWeight[j] * d * d;
        }
    }
    return std::sqrt(e / (3.0 * p.sumA));
}

// The same for the accepted coefficients (K x 3, column-major) of the real samples.
double RobustRadianceFitter::fittedResidual(const VertexProblem& p, const double* coefficients) const {
    const FitScratch& scratch = p.scratch;
    const std::size_t cap = scratch.capacity;
    const int K = K_;
    double e = 0.0;
    for (std::size_t j = 0; j < p.n; ++j) {
        const double* b = scratch.basisValues.data() + j * K;
        for (int c = 0; c < 3; ++c) {
            const double d = dot(b, coefficients + c * K, K) - scratch.values[c * cap + j];
            e += scratch.baseWeight[j] * d * d;
        }
    }
    return std::sqrt(e / (3.0 * p.sumA));
}

VertexFitResult RobustRadianceFitter::finishConstant(const VertexProblem& p, const double mean[3],
                                                     VertexFitResult result) const {
    for (int c = 0; c < 3; ++c) result.meanColor[c] = mean[c];
    result.constantFallback = true;
    result.residual = constantResidual(p, mean);
    writeConstant(p.frame, mean, p.out);
    return result;
}

// How many directions of D the samples cover; returns whether the vertex is poorly sampled.
bool RobustRadianceFitter::measureCoverage(const VertexProblem& p, VertexFitResult& result) const {
    // Sample by sample, the largest cosine to each direction of D (a vectorisable max over D's
    // coordinate arrays), then the threshold.
    const int D = kCoverageDirections;
    const double* local = p.scratch.local.data();
    double nearest[kCoverageDirections];
    std::fill(nearest, nearest + D, -2.0);
    const double* dx = coverageX_.data();
    const double* dy = coverageY_.data();
    const double* dz = coverageZ_.data();
    for (std::size_t j = 0; j < p.n; ++j) {
        const double lx = local[3 * j], ly = local[3 * j + 1], lz = local[3 * j + 2];
        for (int i = 0; i < D; ++i) nearest[i] = std::max(nearest[i], dx[i] * lx + dy[i] * ly + dz[i] * lz);
    }
    int coveredCount = 0;
    for (int i = 0; i < D; ++i) {
        const unsigned char hit = nearest[i] >= cosCoverage_ ? 1 : 0;
        p.scratch.covered[i] = hit;
        coveredCount += hit;
    }
    result.coveredDirections = coveredCount;
    return static_cast<double>(p.n) < options_.poorSamplingFactor * K_ || 2 * coveredCount < D;
}

// Basis values of the real samples (once for every candidate).
void RobustRadianceFitter::evaluateSampleBasis(FitScratch& scratch, std::size_t n) const {
    const double* local = scratch.local.data();
    for (std::size_t j = 0; j < n; ++j)
        evaluateBasis(options_.basis, local[3 * j], local[3 * j + 1], local[3 * j + 2],
                      scratch.basisValues.data() + j * K_);
}

// The Huber threshold: the median absolute leave-one-out residual / 0.6745 (the MAD of a normal
// distribution), floored so that exact data (residuals at rounding level) keeps weight 1, times the
// option's threshold.
double RobustRadianceFitter::huberThreshold(FitScratch& scratch, std::size_t n, const Assembly& a) const {
    double* sorted = scratch.sortBuffer.data();
    std::copy(scratch.looNorm.begin(), scratch.looNorm.begin() + static_cast<std::ptrdiff_t>(n), sorted);
    std::nth_element(sorted, sorted + n / 2, sorted + n);
    const double floor = 1e-4 + 1e-3 * std::max({std::abs(a.mean[0]), std::abs(a.mean[1]), std::abs(a.mean[2])});
    const double sigma = std::max(sorted[n / 2] / 0.6745, floor);
    return options_.huberThreshold * sigma;
}

// The leave-one-out residuals of the reference model in looNorm: the best view-dependent candidate
// even when the constant won (outliers push the choice toward the constant, whose residuals are
// large everywhere and would inflate the scale; the final choice is made after the reweighting).
// Returns false when the reference cannot be scored.
bool RobustRadianceFitter::referenceResiduals(FitScratch& scratch, std::size_t n, const Assembly& a,
                                              const Choice& choice, int iteration) const {
    if (!std::isfinite(choice.error)) {
        scoreConstant(scratch, n, a, true);
    } else if (iteration > 0 || lambdaGrid_.empty()) {  // at iteration 0, choose() left them in looNorm
        double errors[kMaxPolynomialDegree + kMaxHarmonicDegree + 2];
        if (!scoreModels(scratch, n, a, choice.lambda, choice.degree, choice.degree, errors, nullptr, true))
            return false;
        takeLooNorms(scratch, choice.degree, n);
    }
    return true;
}

// Huber weights of the leave-one-out residuals; returns the largest change of a weight.
double RobustRadianceFitter::reweight(FitScratch& scratch, std::size_t n, double threshold) const {
    double maxChange = 0.0;
    for (std::size_t j = 0; j < n; ++j) {
        const double r = scratch.looNorm[j];
        const double w = r > threshold ? threshold / r : 1.0;  // Huber: 0 for an infinite residual
        maxChange = std::max(maxChange, std::abs(w - scratch.robustWeight[j]));
        scratch.robustWeight[j] = w;
    }
    return maxChange;
}

// Model choice by validation, and Huber IRLS on the chosen model's leave-one-out residuals (plain
// residuals of a sparse fit are near zero even at an outlier, which the fit interpolates; the
// leave-one-out residual is what the other views say about it). The weights are then fixed and the
// model chosen again with them.
RobustRadianceFitter::Choice RobustRadianceFitter::chooseRobustly(const VertexProblem& p, Assembly& assembly,
                                                                  VertexFitResult& result) const {
    FitScratch& scratch = p.scratch;
    const std::size_t n = p.n;
    Choice choice = choose(scratch, n, assembly);
    if (options_.robustIterations <= 0 || n < 3) return choice;
    bool changed = false;
    for (int it = 0; it < options_.robustIterations; ++it) {
        if (!referenceResiduals(scratch, n, assembly, choice, it)) break;
        const double threshold = huberThreshold(scratch, n, assembly);
        // Only vertices with an outlier are reweighted: at least one sample beyond twice the
        // threshold (Huber weight below 1/2). Milder residuals are the noise the validation
        // already weighs, and sparing the others the reweighting and second choice halves the
        // cost of the IRLS on real data.
        if (it == 0) {
            bool outlier = false;
            for (std::size_t j = 0; j < n && !outlier; ++j) outlier = scratch.looNorm[j] > 2.0 * threshold;
            if (!outlier) break;
        }
        if (reweight(scratch, n, threshold) < 0.02) break;  // the weights need not be exact
        changed = true;
        assemble(scratch, n, assembly);
    }
    // The choice is made again with the final weights: the first one was made with the outliers at
    // full weight, which favours strong regularisation.
    if (changed) choice = choose(scratch, n, assembly);
    for (std::size_t j = 0; j < n; ++j) result.downweighted += scratch.robustWeight[j] < 1.0;
    return choice;
}

// The channels the range guard still has to accept, and their bands.
struct RobustRadianceFitter::GuardState {
    bool guard = false;
    bool pending[3] = {false, false, false};
    double bandLo[3] = {0.0, 0.0, 0.0}, bandHi[3] = {0.0, 0.0, 0.0};
    int pendingCount = 0;
};

// The channels share the matrix but not the right-hand side, so the guard accepts or escalates each
// channel on its own (our refinement of "retry with 10 lambda": a channel that stays in its range
// keeps the least regularised fit, whatever the others do). A channel whose observed values are all
// equal is the constant m_c outright: any fit in its zero-width band would only differ from it by
// rounding. Clears the accepted coefficients (scratch.solution) and writes those constants.
RobustRadianceFitter::GuardState RobustRadianceFitter::startGuard(const VertexProblem& p, bool poorly,
                                                                  const double mean[3]) const {
    GuardState g;
    g.guard = options_.rangeGuard == RangeGuardScope::AllVertices ||
              (options_.rangeGuard == RangeGuardScope::PoorlySampledOnly && poorly);
    double* final = p.scratch.solution.data();  // K x 3, column-major: the accepted coefficients
    std::fill(final, final + 3 * K_, 0.0);
    const double* lo = p.range.lo;
    const double* hi = p.range.hi;
    for (int c = 0; c < 3; ++c) {
        const double margin = kGuardMarginFraction * options_.rangeTolerance * (hi[c] - lo[c]);
        g.bandLo[c] = lo[c] - margin;
        g.bandHi[c] = hi[c] + margin;
        g.pending[c] = !(g.guard && hi[c] == lo[c]);
        if (g.pending[c])
            ++g.pendingCount;
        else
            final[c * K_] = mean[c] / constantValue_;
    }
    return g;
}

// One attempt at `lambda` with the chosen degree's Ka coefficients: the channels whose solution is
// finite and (under the guard) inside their band are accepted. Returns false when the attempt
// must be counted as a retry (singular system, or a channel to escalate).
bool RobustRadianceFitter::guardAttempt(FitScratch& scratch, const Assembly& a, double lambda, int Ka,
                                        GuardState& g) const {
    const int K = K_;
    double* X = scratch.trial.data();  // K x 3 column-major; the first Ka rows of each column are used
    double* A = scratch.system.data();
    std::copy(scratch.gram.begin(), scratch.gram.begin() + static_cast<std::ptrdiff_t>(K) * K, A);
    if (lambda > 0.0)
        for (int k = 1; k < K; ++k) A[k * K + k] += lambda * a.scale;  // the constant function is not penalised
    std::copy(scratch.rhs.begin(), scratch.rhs.begin() + 3 * K, X);
    // Singular systems: with lambda > 0 the matrix is positive definite by construction
    // (G_00 = sum a_j B_0^2 > 0 and lambda s on the other diagonal entries) and its pivots are at
    // least of the order of lambda s; with lambda = 0 a pivot below 1e-12 trace(G) (about 1e-12 of
    // the largest eigenvalue) means degenerate samples.
    const double minPivot = (lambda > 0.0 ? kMinReciprocalCondition : 1e-12) * a.trace;
    if (!choleskyInPlace(A, K, minPivot, scratch.invDiag.data())) return false;
    forward3InPlace(A, scratch.invDiag.data(), K, Ka, X);
    backward3InPlace(A, scratch.invDiag.data(), K, Ka, X);
    for (int c = 0; c < 3; ++c) std::fill(X + c * K + Ka, X + (c + 1) * K, 0.0);
    // Accepted: a pending channel whose solution is finite and, under the guard, inside its band.
    bool accept[3], test[3];
    for (int c = 0; c < 3; ++c) {
        const double* xc = X + c * K;
        bool finite = true;
        for (int k = 0; k < K; ++k) finite = finite && std::isfinite(xc[k]);
        accept[c] = g.pending[c] && finite;
        test[c] = accept[c] && g.guard;
    }
    bool inside[3] = {true, true, true};
    if (test[0] || test[1] || test[2]) insideBands(X, Ka, test, g.bandLo, g.bandHi, inside);
    bool escalate = false;
    double* final = scratch.solution.data();
    for (int c = 0; c < 3; ++c) {
        if (!g.pending[c]) continue;
        if (accept[c] && (!test[c] || inside[c])) {
            const double* xc = X + c * K;
            std::copy(xc, xc + K, final + c * K);
            g.pending[c] = false;
            --g.pendingCount;
        } else {
            escalate = true;
        }
    }
    return !escalate;
}

// The chosen model (lambda, degree), under the range guard: lambda is escalated tenfold per attempt
// for the channels still pending (without the guard, further attempts only happen when the system
// is singular); channels that never pass get the constant m_c (always inside the observed range).
VertexFitResult RobustRadianceFitter::solveUnderGuard(const VertexProblem& p, const Assembly& assembly,
                                                      const Choice& choice, bool poorly, const double mean[3],
                                                      VertexFitResult result) const {
    const int K = K_;
    const int Ka = degreeK_[choice.degree];
    GuardState g = startGuard(p, poorly, mean);
    const int attempts = options_.maxGuardRetries + 1;
    for (int attempt = 0; attempt < attempts && g.pendingCount > 0; ++attempt) {
        const double lambda = attempt == 0 ? choice.lambda
                                           : std::max(choice.lambda, kEscalationBaseLambda) * std::pow(10.0, attempt);
        if (!guardAttempt(p.scratch, assembly, lambda, Ka, g)) result.guardRetries = attempt + 1;
    }
    double* final = p.scratch.solution.data();
    int constantChannels = 0;
    for (int c = 0; c < 3; ++c) {
        if (!g.pending[c]) continue;
        std::fill(final + c * K, final + (c + 1) * K, 0.0);
        final[c * K] = mean[c] / constantValue_;
        ++constantChannels;
    }
    result.fallbackChannels = constantChannels;
    if (constantChannels == 3) return finishConstant(p, mean, result);
    result.residual = fittedResidual(p, final);
    writeSolution(p.frame, final, p.scratch, p.out);
    return result;
}

VertexFitResult RobustRadianceFitter::fit(const Frame& frame, const DirectionalSample* samples, std::size_t count,
                                          FitScratch& scratch, float* out) const {
    VertexFitResult result;
    scratch.reserveSamples(K_, count);
    VertexProblem p{frame, scratch, out, 0, 0.0, {}};
    p.n = loadSamples(frame, samples, count, scratch, p.range);  // local directions (border-extended), values
    setValidationErrorScales(scratch, p.n);
    result.sampleCount = static_cast<int>(p.n);
    if (p.n == 0) {
        result.status = FitStatus::Unseen;
        std::fill(out, out + 3 * K_, 0.0f);
        return result;
    }
    for (std::size_t j = 0; j < p.n; ++j) p.sumA += scratch.baseWeight[j];
    if (static_cast<int>(p.n) < options_.minSamples) {
        double mean[3], sumW;
        weightedMean(scratch, p.n, mean, sumW);
        result.status = FitStatus::PoorlySampled;
        return finishConstant(p, mean, result);
    }
    const bool poorly = measureCoverage(p, result);
    result.status = poorly ? FitStatus::PoorlySampled : FitStatus::Fitted;
    sumVirtualSamples(scratch);
    evaluateSampleBasis(scratch, p.n);
    Assembly assembly;
    assemble(scratch, p.n, assembly);
    const Choice choice = chooseRobustly(p, assembly, result);
    double mean[3];
    for (int c = 0; c < 3; ++c) mean[c] = result.meanColor[c] = assembly.mean[c];
    result.lambda = choice.lambda;
    result.degree = choice.degree;
    result.validationError = lambdaGrid_.empty() ? 0.0 : choice.error;
    result.constantValidationError = choice.constantError;
    if (choice.constant) {
        result.validatedConstant = true;
        result.lambda = 0.0;
        result.degree = 0;
        return finishConstant(p, mean, result);
    }
    result.regularised = choice.lambda > options_.lambda || choice.degree < options_.basis.degree;
    return solveUnderGuard(p, assembly, choice, poorly, mean, result);
}

}  // namespace rad
