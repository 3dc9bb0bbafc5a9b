// Robust per-vertex fitting of a radiance function (RF) to the colour samples a vertex receives from
// a few photographs (Vanhoey et al. 2015, sec. 7; the idea of constraining the unobserved directions
// by a low-order estimate follows Vanhoey et al. 2013). Why it is more than least squares: a vertex is
// seen from a handful of directions, often from one side, and a free fit overshoots where nobody
// looked. The remedy: virtual samples of the mean colour where the hemisphere is uncovered, Tikhonov
// regularisation toward the mean, a model (degree, lambda, or the constant) chosen by leave-one-out
// error on the vertex's own samples, Huber reweighting, and a range guard that keeps a poorly
// sampled vertex's function within the range of what was observed. The algorithm step by step, the
// guard's guarantee and its measured cost: docs/fitting.md, "How the per-vertex robust fit works".
#pragma once

#include "radiance/basis.h"
#include "radiance/radiance_frame.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace rad {

// One observation of a vertex: the unit world direction from the vertex toward the camera that
// saw it, the linear RGB colour, and its weight (> 0). Floats: millions of them stream through the
// per-vertex fit (view_sampling.h fills them).
struct DirectionalSample {
    float direction[3];
    float rgb[3];
    float weight;
};

enum class FitStatus : std::uint8_t {
    Fitted = 0,                // enough well spread samples (see PoorlySampled)
    PoorlySampled = 1,         // fitted, but few or clustered samples (or the constant mean colour)
    Unseen = 2,                // no sample: zero radiance
    FilledFromNeighbours = 3,  // set by radiance_from_views.h only: unseen, filled from neighbours
};

enum class RangeGuardScope : std::uint8_t {
    Off = 0,                // never test the range (plain regularised fit with virtual samples)
    PoorlySampledOnly = 1,  // only vertices flagged PoorlySampled (default)
    AllVertices = 2,        // every fitted vertex
};

// Number of directions of the coverage set D and of the guard's check set C. C is evaluated in two
// parts: a coarse part (a Fibonacci spiral of kGuardCoarseSpiral points and kGuardCoarseEquator
// points on the border z = 0) that rejects most failing fits cheaply, then the fine part (a spiral
// of kGuardFineSpiral points and kGuardFineEquator border points); a fit passes when both do.
inline constexpr int kCoverageDirections = 100;
inline constexpr int kGuardCoarseSpiral = 128;
inline constexpr int kGuardCoarseEquator = 16;
inline constexpr int kGuardFineSpiral = 512;
inline constexpr int kGuardFineEquator = 64;
inline constexpr int kGuardDirections = kGuardCoarseSpiral + kGuardCoarseEquator + kGuardFineSpiral + kGuardFineEquator;
// The guard accepts a fit when it stays within this fraction of the tolerance band on C, so that
// the guarantee "within rangeTolerance" holds between the points of C too (step 6 above).
inline constexpr double kGuardMarginFraction = 0.75;

struct RobustFitOptions {
    BasisSpec basis;
    // Store the reflected RF L~(w) = L(R_n w) (Vanhoey et al. 2015 sec. 3.1) instead of L.
    bool storeReflected = false;
    // Tikhonov weight, dimensionless, scaled by trace(G) / K (see the file comment). >= 0.
    double lambda = 1e-3;
    // A direction of D is covered when a sample lies within this angle of it. (0, 90].
    double coverageAngleDegrees = 20.0;
    // Weight of a virtual sample relative to the mean weight of the real samples. >= 0 (0: none).
    double virtualSampleWeight = 0.1;
    // Fraction of the observed range a fitted value may exceed it by. >= 0.
    double rangeTolerance = 0.1;
    // Fewer samples than this: constant RF (the weighted mean colour). >= 1.
    int minSamples = 3;
    // Lambda escalations (x10 each) before the constant fallback. 0..10.
    int maxGuardRetries = 3;
    RangeGuardScope rangeGuard = RangeGuardScope::PoorlySampledOnly;
    // PoorlySampled when the sample count is below poorSamplingFactor * K. >= 0.
    double poorSamplingFactor = 2.0;

    // Per-vertex model choice by leave-one-out validation (step 5 of the file comment): the
    // candidates are validationLambdas values of lambda (lambda, then max(lambda, 1e-3) x 10, x 100,
    // ...), each at the basis degree and, with validateLowerDegrees, at every lower degree >= 1, and
    // the constant mean colour; the candidate with the least validation error is kept.
    // validationLambdas = 0: no validation (the user's lambda at the full degree, as before). 0..8.
    int validationLambdas = 4;
    bool validateLowerDegrees = true;
    // A view-dependent candidate replaces the constant only when its validation error is lower by
    // more than this many standard errors of that error (step 5). >= 0.
    double validationMargin = 2.0;
    // Huber IRLS against outliers (highlights, misregistered depth edges): this many reweighting
    // passes (0: off), threshold huberThreshold x the MAD scale of the leave-one-out residuals. 0..10.
    int robustIterations = 2;
    double huberThreshold = 1.345;  // > 0

    // Empty when usable; otherwise a sentence naming the bad option and its valid range.
    std::string validate() const;
};

// What fit() found for one vertex.
struct VertexFitResult {
    FitStatus status = FitStatus::Unseen;
    int sampleCount = 0;          // valid real samples used
    int coveredDirections = 0;    // of the kCoverageDirections of D
    int guardRetries = 0;         // lambda escalations done (range guard, or singular systems)
    int fallbackChannels = 0;     // channels the guard replaced by their constant mean value
    bool constantFallback = false;  // the whole RF is the constant mean colour (too few samples or guard)
    double meanColor[3] = {0.0, 0.0, 0.0};  // weighted mean of the samples (linear RGB)
    double residual = 0.0;        // sqrt(sum a_j |L(w_j) - y_j|^2 / (3 sum a_j)), real samples only
    // Model choice (step 5): the lambda and degree of the validated fit (before any guard
    // escalation), whether validation preferred the constant mean colour, and the validation errors
    // (weighted mean squared leave-one-out error per sample, summed over channels; 0 when not run).
    double lambda = 0.0;
    int degree = 0;
    bool validatedConstant = false;
    bool regularised = false;     // validation chose a larger lambda or a lower degree than the user's
    double validationError = 0.0;
    double constantValidationError = 0.0;
    int downweighted = 0;         // samples the Huber IRLS gave a weight below 1
};

class RobustRadianceFitter;

// Per-thread buffers of RobustRadianceFitter::fit (make one per thread with makeScratch()).
class FitScratch {
public:
    FitScratch() = default;

private:
    friend class RobustRadianceFitter;
    void reserveSamples(int K, std::size_t sampleCount);

    std::vector<double> local;      // 3 per real sample: local direction
    std::vector<double> sqrtWeight; // per real sample: sqrt of the effective weight
    std::vector<double> inverseWeight;  // per real sample: 1 / the effective weight (0 for weight 0)
    std::vector<double> baseWeight; // per real sample: the sample's weight a_j
    std::vector<double> robustWeight;  // per real sample: the Huber weight (1 without IRLS)
    std::vector<double> values;     // rows x 3, column-major: y (unweighted)
    std::vector<double> basisValues;  // K x real samples, column-major: B(l_j)
    std::vector<double> looNorm;    // per real sample: |leave-one-out residual| (IRLS)
    std::vector<double> looByDegree;  // (max degree + 1) x capacity: the same squared, per degree of one lambda
    std::vector<double> errorScale; // rows x 3, column-major: (d sRGB / d linear)^2 at y (validation)
    std::vector<double> sortBuffer; // per real sample: for the median
    std::vector<double> forward;    // K x 3: L^-1 r
    std::vector<double> designT;    // K x capacity, row-major: sqrt(a_j) B(l_j) of the real samples
                                    // (capacity >= real samples + |D|: rows are read 4 at a time)
    std::vector<double> zMatrix;    // K x capacity, row-major: L^-1 designT
    std::vector<double> hatP, hatQ; // per real sample: the self-influence's two running sums
    std::vector<double> fitted;     // 3 x capacity: weighted fitted values of one candidate
    std::vector<double> virtualLeverage;  // K: L^-1 (sum of B over the virtual samples' directions)
    std::vector<double> virtualSum; // K: sum of the basis over the uncovered directions of D
    std::vector<double> virtualGram;  // K(K+1)/2, packed lower triangle: sum of b b^T over them
    std::size_t virtualCount = 0;     // uncovered directions of D
    std::vector<double> design;     // K x real samples, column-major: sqrt(a) B(l)
    std::vector<double> targets;    // real samples x 3, column-major: sqrt(a) y
    std::vector<double> gram;       // K x K (lower triangle)
    std::vector<double> system;     // K x K, factorised in place
    std::vector<double> invDiag;    // K: 1 / L_kk of the factor
    std::vector<double> rhs;        // K x 3
    std::vector<double> trial;      // K x 3: the solution of one attempt
    std::vector<double> solution;   // K x 3: the accepted coefficients
    std::vector<double> rotateIn, rotateOut;  // K
    std::vector<unsigned char> covered;       // |D|
    std::size_t capacity = 0;       // rows the design matrix can hold
    int K = 0;
};

class RobustRadianceFitter {
public:
    // Throws std::invalid_argument with options.validate()'s sentence when the options are unusable.
    explicit RobustRadianceFitter(const RobustFitOptions& options);

    const RobustFitOptions& options() const { return options_; }
    int coefficientsPerVertex() const { return 3 * K_; }

    // A scratch sized for this fitter's basis (allocates; do it once per thread).
    FitScratch makeScratch() const;

    // Fits one vertex. `frame` is the vertex's frame (radiance_frame.h; use frameFromStored of the
    // field's frame so that the coefficients match what evaluation uses). `out` receives
    // 3 * K floats (channel-major, the vertex layout of radiance_field.h): zeros for Unseen.
    // Thread-safe (const) given one scratch per thread; does not throw.
    VertexFitResult fit(const Frame& frame, const DirectionalSample* samples, std::size_t count, FitScratch& scratch,
                        float* out) const;

    // The coverage set D and the guard's check set C, unit directions in the local frame
    // (z = normal), x,y,z interleaved (for tests and documentation).
    const std::vector<double>& coverageDirections() const { return coverage_; }
    const std::vector<double>& guardDirections() const { return check_; }

    // Coefficient of the constant function of the basis giving the value 1 (PB: 1, SH: 1 / Y_0^0).
    double constantCoefficient() const { return 1.0 / constantValue_; }

private:
    void writeConstant(const Frame& frame, const double mean[3], float* out) const;
    void writeSolution(const Frame& frame, const double* solution, FitScratch& scratch, float* out) const;
    void insideBands(const double* X, int Ka, const bool* test, const double* lo, const double* hi, bool* inside) const;
    struct Assembly;
    struct Choice;
    void assemble(FitScratch& scratch, std::size_t n, Assembly& a) const;
    void sumVirtualSamples(FitScratch& scratch) const;
    void takeLooNorms(FitScratch& scratch, int d, std::size_t n) const;
    bool scoreModels(FitScratch& scratch, std::size_t n, const Assembly& a, double lambda, int degreeLow,
                     int degreeHigh, double* errors, double* standardErrors, bool storeLooNorms) const;
    double scoreConstant(FitScratch& scratch, std::size_t n, const Assembly& a, bool storeLooNorms) const;
    Choice choose(FitScratch& scratch, std::size_t n, const Assembly& a) const;
    // The steps of fit().
    struct ObservedRange;
    struct VertexProblem;
    struct GuardState;
    std::size_t loadSamples(const Frame& frame, const DirectionalSample* samples, std::size_t count,
                            FitScratch& scratch, ObservedRange& range) const;
    void setValidationErrorScales(FitScratch& scratch, std::size_t n) const;
    void weightedMean(const FitScratch& scratch, std::size_t n, double mean[3], double& sumW) const;
    double constantResidual(const VertexProblem& p, const double mean[3]) const;
    double fittedResidual(const VertexProblem& p, const double* coefficients) const;
    VertexFitResult finishConstant(const VertexProblem& p, const double mean[3], VertexFitResult result) const;
    bool measureCoverage(const VertexProblem& p, VertexFitResult& result) const;
    void evaluateSampleBasis(FitScratch& scratch, std::size_t n) const;
    double huberThreshold(FitScratch& scratch, std::size_t n, const Assembly& a) const;
    bool referenceResiduals(FitScratch& scratch, std::size_t n, const Assembly& a, const Choice& choice,
                            int iteration) const;
    double reweight(FitScratch& scratch, std::size_t n, double threshold) const;
    Choice chooseRobustly(const VertexProblem& p, Assembly& assembly, VertexFitResult& result) const;
    GuardState startGuard(const VertexProblem& p, bool poorly, const double mean[3]) const;
    bool guardAttempt(FitScratch& scratch, const Assembly& a, double lambda, int Ka, GuardState& g) const;
    VertexFitResult solveUnderGuard(const VertexProblem& p, const Assembly& assembly, const Choice& choice,
                                    bool poorly, const double mean[3], VertexFitResult result) const;

    RobustFitOptions options_;
    int K_ = 0;
    double cosCoverage_ = 0.0;
    double constantValue_ = 1.0;         // B_0, the constant basis function's value
    std::vector<double> coverage_;       // 3 x |D|
    std::vector<double> coverageX_, coverageY_, coverageZ_;  // the same, one array per coordinate
    std::vector<double> check_;          // 3 x |C|
    std::vector<double> coverageBasis_;  // K x |D|, column-major, basis at D (local frame)
    std::vector<double> coverageOuter_;  // |D| x K(K+1)/2: b b^T of each direction of D, packed lower triangle
    std::vector<double> coverageGram_;   // K(K+1)/2, packed lower triangle: sum over D of b b^T
    std::vector<double> coverageSum_;    // K: sum over D of b
    std::vector<double> checkBasis_;     // |C| x K, k-major: checkBasis_[k * |C| + i] (vectorises over i)
    std::vector<double> reflectSign_;    // K: +-1, the local-frame reflection (x, y, z) -> (-x, -y, z)
    std::vector<int> degreeK_;           // coefficients of the basis of degree 0..d (a prefix of the K)
    std::vector<double> lambdaGrid_;     // the validation's lambdas
};

// Unit directions of a Fibonacci spiral on the hemisphere z >= 0: point i has
// z = 1 - (i + 0.5) / count (equal-area bands) and azimuth i * golden angle + phase.
// Returns 3 * count doubles (x, y, z interleaved).
std::vector<double> fibonacciHemisphere(int count, double phase = 0.0);

}  // namespace rad
