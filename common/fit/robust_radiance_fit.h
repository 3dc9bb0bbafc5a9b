// Robust per-vertex fitting of a radiance function (RF) to colour samples seen from a few
// directions, as in "Fit Radiance Functions from Rasters" (Vanhoey et al. 2015, Vanhoey et al. 2015, sec. 7
// "Data acquisition and reconstruction": RF "are fitted on photographs ... projected onto the mesh").
//
// The difficulty is the sampling: a vertex of a scan is seen by a handful of photographs, often from
// one side only, so an unconstrained least-squares fit in PB(d) / SH(d) is free to do anything in
// the directions nobody looked from (overshoot, negative radiance, wild highlights when rendered
// from a new viewpoint). The remedy follows the idea of
//   K. Vanhoey, B. Sauvage, O. Genevaux, F. Larue, J.-M. Dischler, "Robust Fitting on Poorly
//   Sampled Data for Surface Light Field Rendering and Image Relighting", CGF 32(6), 2013, 101-112:
// constrain the unobserved part of the hemisphere by a low-order estimate (here the diffuse/mean
// colour) through virtual samples, and keep the fit within the range of what was observed.
// The concrete recipe below (coverage test on a fixed direction set, the weights, the Tikhonov
// term, the range guard with lambda escalation and the constant fallback) is OUR OWN design, not the
// 2013 paper's algorithm (which builds a hierarchy of fits of increasing degree).
//
// Algorithm for one vertex with frame (t, b, n) and samples (w_j unit world direction toward the
// camera, y_j linear RGB, weight a_j > 0):
//  1. Local directions l_j = (t.w_j, b.w_j, n.w_j); a sample below the tangent plane is moved to its
//     border direction (the border extension of Vanhoey et al. 2015 sec. 7, as radiance_projection.h does).
//     Invalid samples (non-finite, zero direction, weight <= 0) are ignored.
//  2. Weighted mean colour m = sum a_j y_j / sum a_j: the diffuse colour, returned, and the prior.
//     Zero samples -> Unseen (zero coefficients). Fewer than minSamples -> the constant RF m
//     (PoorlySampled).
//  3. Coverage: a fixed set D of kCoverageDirections directions on the local hemisphere (a
//     Fibonacci spiral, nearly equal areas, ~14 degrees apart). A direction of D with no sample
//     within coverageAngleDegrees is "uncovered" and receives a virtual sample of value m and
//     weight virtualSampleWeight * (mean real weight).
//  4. Weighted least squares with Tikhonov regularisation, per channel (the 3 channels share the
//     K x K matrix):  (G + lambda s E) c = r,  G = sum_i a_i B(l_i) B(l_i)^T over real + virtual
//     samples, s = trace(G) / K, E = diag(0, 1, ..., 1): the constant function is not penalised, so
//     a large lambda pulls the fit toward the weighted mean colour, not toward black (same scaling
//     as fitRadiance in radiance/radiance_projection.h). Double accumulation, in-place Cholesky.
//     A system whose Cholesky pivot falls below 1e-14 trace(G) (1e-12 when lambda = 0) counts as
//     singular and is treated like a guard failure (lambda escalated).
//  5. Model choice by validation on the vertex's own samples (options validationLambdas,
//     validateLowerDegrees, validationMargin). Candidates: the fits of step 4 at lambda, then
//     max(lambda, 1e-3) x 10, x 100, x 1000, each at the basis degree and every lower degree >= 1
//     (PB and SH are ordered by degree, so the leading block of one Cholesky factor solves every
//     lower degree: all degrees cost one factorisation per lambda), and the constant mean colour.
//     Criterion: leave-one-out error. A vertex gets at most one sample per photograph, so leaving
//     one sample out IS leaving one view out; for a linear smoother the leave-one-out residual is
//     (f_j - y_j) / (1 - S_jj) from the self-influence S_jj, one forward substitution per sample
//     (exact for the constant; for the fits a first-order approximation, since removing a sample
//     also changes the coverage and the virtual samples' value, which S_jj accounts for to first
//     order). Chosen over generalised cross-validation because GCV replaces every S_jj by their
//     mean, and the leverages of a one-sided, clustered vertex are anything but equal: an isolated
//     view alone determines the fit in its direction (S_jj near 1), which GCV would average away
//     and exact leave-one-out exposes. Errors are weighted by a_j and measured in sRGB units to
//     first order (scaled by the sRGB slope at the sample's value), the units photographs are
//     compared in. The constant is kept unless the best fit's error is lower by more than
//     validationMargin standard errors of that error (the least of ~16 noisy estimates is biased
//     low; the one-standard-error rule of cross-validation, here two by default: the constant is
//     what the fit must never be worse than). Huber IRLS (robustIterations, huberThreshold): the
//     samples are reweighted by min(1, k s / |e_j|), e_j the leave-one-out residual of the best
//     view-dependent candidate (plain residuals of a sparse fit are near zero at an outlier, which
//     it interpolates), s = median |e_j| / 0.6745 (MAD), and the choice is made again with the
//     new weights; the mean colour is the weighted mean with them too.
//  6. Range guard: the chosen fit (its lambda and degree) is evaluated on a check set C of kGuardDirections local directions
//     (Fibonacci spirals and rings on the border z = 0, disjoint from D, ~4.5 degrees apart); if
//     channel c leaves [min_c - g R_c, max_c + g R_c] (min/max/range R_c of the vertex's observed
//     values of channel c, g = kGuardMarginFraction * rangeTolerance), lambda is multiplied by 10
//     (from max(lambda, 1e-3)) and the fit redone, at most maxGuardRetries times; then the channel
//     is the constant m_c (always inside the range). Our decisions beyond the recipe: the channels
//     share the matrix but each is accepted or escalated on its own (a channel that stays in range
//     keeps its least regularised fit), and a channel whose observed values are all equal (R_c = 0,
//     e.g. a black or clipped channel) is the constant m_c outright; there is no absolute slack,
//     so the bound holds relative to any range, however small (8-bit data: R_c = 0 or >= 3e-4).
//     Why g < rangeTolerance: C is finite and a polynomial can peak between its points. With
//     g = rangeTolerance, the adversarial fits of the unit test (PB2..PB6, SH4, SH6; 3 samples from
//     one side, 10-degree clusters, great-circle arcs, duplicated directions, K..2K-1 noisy samples)
//     exceeded the bound by up to 3.5 % of the range on a 7201-point (theta, phi) grid; with g = 0.75
//     rangeTolerance and C as above: never, in 10500 such fits (two seeds, 150 trials per case,
//     including 8-bit data with a black channel and a channel of two adjacent codes). The guarantee is therefore: a guarded vertex's RF stays
//     within [min_c - rangeTolerance R_c, max_c + rangeTolerance R_c] (+ float rounding of the
//     stored coefficients, ~1e-7 of the values) on the whole closed hemisphere, hence everywhere
//     (border extension), as far as tested.
//  7. Poorly sampled (status PoorlySampled) := fewer than poorSamplingFactor * K samples (default
//     2K), or fewer than half of D covered, or fewer than minSamples samples.
//     Guard scope (option rangeGuard), measured with bench_fit (glossy analytic radiance, 0.01
//     noise, RMS error over the hemisphere): on WELL-sampled vertices (300 views, ~124 samples)
//     guarding costs PB4 accuracy (RMS 0.019 -> 0.041: 35 % of the vertices escalated, because the
//     samples never contain the exact extremes of a highlight, so a correct fit often leaves their
//     range) and helps SH6 a little (0.012 -> 0.010, damping its ringing near the border). The
//     guarantee is only required where the data cannot constrain the fit, so the default is
//     PoorlySampledOnly; AllVertices is there for SH users who want the bound everywhere. On poorly
//     sampled vertices the guard is the price of the bound: PB4 with 50 views (~21 samples) RMS
//     0.023 -> 0.035, SH6 0.033 -> 0.029 with the worst error 0.59 -> 0.25. With the 2K threshold
//     nearly every vertex of a real acquisition (10-50 photographs) is poorly sampled for PB4 (30
//     samples) and SH6 (98).
//  8. Result: the coefficients (3K floats, PB in the local frame, SH in the global frame; plain L or
//     reflected L~ of Vanhoey et al. 2015 sec. 3.1 per option), mean colour, sample count, weighted RMS
//     residual of the real samples, status, guard retries.
//
// Frames: the whole fit is done in the vertex's local frame, for SH too (SH expressed in the local
// frame), so the basis values at D and C are computed once per basis; for SH the solution is then
// rotated to the global frame (sh_rotation.h, one rotation per vertex). Measured alternative: the
// SH6 rotation costs ~5 us per vertex, evaluating SH6 in the global frame at the ~770 directions of
// C and the uncovered part of D ~13 us (17 ns each), hence the rotation. The Tikhonov term is
// rotation invariant (SH rotations are orthogonal within each band and keep Y_0^0), so this is
// exactly the global-frame fit. The reflection of Vanhoey et al. 2015 sec. 3.1 is, in the local frame,
// (x, y, z) -> (-x, -y, z): the sign (-1)^(i+j) for PB monomials u^i v^j and (-1)^|m| for Y_l^m,
// both keeping E, so the reflected fit is the sign-flipped plain fit.
//
// Memory and threads: RobustRadianceFitter is immutable after construction and shared by all
// threads; every thread owns a FitScratch, sized once for the basis, so fit() does not allocate
// (except when a vertex has more samples than any previous one of that scratch: the buffers grow;
// checked with an interposed malloc: 0 allocations in 1000 fits after the first). Eigen is only used
// for the rank update G = B B^T (its triangular product kernel): Eigen's general products are
// OpenMP-parallel when the library is built with OpenMP, which only costs inside our per-vertex
// parallel loops and at these sizes; the right-hand side, the Cholesky factorisation and the guard's
// evaluation are hand-written loops.
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
    std::vector<double> baseWeight; // per real sample: the sample's weight a_j
    std::vector<double> robustWeight;  // per real sample: the Huber weight (1 without IRLS)
    std::vector<double> values;     // rows x 3, column-major: y (unweighted)
    std::vector<double> basisValues;  // K x real samples, column-major: B(l_j)
    std::vector<double> looNorm;    // per real sample: |leave-one-out residual| (IRLS)
    std::vector<double> looByDegree;  // (max degree + 1) x capacity: the same, per degree of one lambda
    std::vector<double> errorScale; // rows x 3, column-major: (d sRGB / d linear)^2 at y (validation)
    std::vector<double> sortBuffer; // per real sample: for the median
    std::vector<double> forward;    // K x 3: L^-1 r
    std::vector<double> degreeSolutions;  // (degree + 1) x K x 3: the solution at each degree
    std::vector<double> designT;    // K x capacity, row-major: sqrt(a_j) B(l_j) of the real samples
    std::vector<double> zMatrix;    // K x capacity, row-major: L^-1 designT
    std::vector<double> hatP, hatQ; // per real sample: the self-influence's two running sums
    std::vector<double> residuals;  // 3 x capacity: weighted residuals of one candidate
    std::vector<double> virtualLeverage;  // K: L^-1 (sum of B over the virtual samples' directions)
    std::vector<double> virtualSum; // K
    std::vector<double> design;     // K x rows, column-major: sqrt(a) B(l)
    std::vector<double> targets;    // rows x 3, column-major: sqrt(a) y
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
    bool insideBand(const double* channelCoefficients, double lo, double hi) const;
    struct Assembly;
    struct Choice;
    void assemble(FitScratch& scratch, std::size_t n, Assembly& a) const;
    bool scoreModels(FitScratch& scratch, std::size_t n, const Assembly& a, double lambda, int degreeLow,
                     int degreeHigh, double* errors, double* standardErrors, bool storeLooNorms) const;
    double scoreConstant(FitScratch& scratch, std::size_t n, const Assembly& a, bool storeLooNorms) const;
    Choice choose(FitScratch& scratch, std::size_t n, const Assembly& a, const double* onlyLambda = nullptr) const;
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
    std::vector<double> check_;          // 3 x |C|
    std::vector<double> coverageBasis_;  // K x |D|, column-major, basis at D (local frame)
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
