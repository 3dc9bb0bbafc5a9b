#include "fit/shared_radiance_fit.h"

#include "geometry/mesh_bounds.h"
#include "radiance/radiance_evaluation.h"
#include "radiance/radiance_frame.h"
#include "radiance/sh_rotation.h"
#include "radiance/spherical_harmonics.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <omp.h>
#include <sstream>
#include <stdexcept>

namespace rad {

namespace {

constexpr double kHuberScale = 1.4826;  // MAD -> standard deviation of a normal distribution

// Octahedral parametrisation of the unit sphere (the square [-1, 1]^2; the lower hemisphere folded
// onto the corners): a table of G with bilinear lookup costs a few multiplications instead of the
// ~(degree+1)^2 of an SH evaluation.
void octEncode(double x, double y, double z, double& u, double& v) {
    const double inverse = 1.0 / (std::abs(x) + std::abs(y) + std::abs(z));
    u = x * inverse;
    v = y * inverse;
    if (z < 0.0) {
        const double pu = u, pv = v;
        u = (1.0 - std::abs(pv)) * (pu >= 0.0 ? 1.0 : -1.0);
        v = (1.0 - std::abs(pu)) * (pv >= 0.0 ? 1.0 : -1.0);
    }
}

void octDecode(double u, double v, double& x, double& y, double& z) {
    z = 1.0 - std::abs(u) - std::abs(v);
    if (z < 0.0) {
        x = (1.0 - std::abs(v)) * (u >= 0.0 ? 1.0 : -1.0);
        y = (1.0 - std::abs(u)) * (v >= 0.0 ? 1.0 : -1.0);
    } else {
        x = u;
        y = v;
    }
    const double len = std::sqrt(x * x + y * y + z * z);
    x /= len;
    y /= len;
    z /= len;
}

class LobeTable {
public:
    LobeTable(const SharedModel& model, int resolution) : n_(resolution), values_(3 * std::size_t(resolution) * resolution) {
        const int degree = model.lobeDegree, M = (degree + 1) * (degree + 1);
#pragma omp parallel
        {
            std::vector<double> Y(M);
#pragma omp for schedule(static)
            for (int i = 0; i < n_; ++i)
                for (int j = 0; j < n_; ++j) {
                    double x, y, z;
                    octDecode(-1.0 + (j + 0.5) * 2.0 / n_, -1.0 + (i + 0.5) * 2.0 / n_, x, y, z);
                    evaluateSphericalHarmonics(degree, x, y, z, Y.data());
                    for (int c = 0; c < 3; ++c) {
                        double acc = 0.0;
                        for (int k = 0; k < M; ++k) acc += model.lobe[c * M + k] * Y[k];
                        values_[3 * (std::size_t(i) * n_ + j) + c] = static_cast<float>(acc);
                    }
                }
        }
    }
    // G at the (not necessarily unit, non-zero) direction (x, y, z).
    void lookup(double x, double y, double z, double* out) const {
        double u, v;
        octEncode(x, y, z, u, v);
        const double fx = std::min(std::max((u + 1.0) * 0.5 * n_ - 0.5, 0.0), n_ - 1.0);
        const double fy = std::min(std::max((v + 1.0) * 0.5 * n_ - 0.5, 0.0), n_ - 1.0);
        const int x0 = std::min(static_cast<int>(fx), n_ - 1), y0 = std::min(static_cast<int>(fy), n_ - 1);
        const int x1 = std::min(x0 + 1, n_ - 1), y1 = std::min(y0 + 1, n_ - 1);
        const double tx = fx - x0, ty = fy - y0;
        const float* a = values_.data() + 3 * (std::size_t(y0) * n_ + x0);
        const float* b = values_.data() + 3 * (std::size_t(y0) * n_ + x1);
        const float* c = values_.data() + 3 * (std::size_t(y1) * n_ + x0);
        const float* d = values_.data() + 3 * (std::size_t(y1) * n_ + x1);
        for (int k = 0; k < 3; ++k)
            out[k] = (1 - ty) * ((1 - tx) * a[k] + tx * b[k]) + ty * ((1 - tx) * c[k] + tx * d[k]);
    }

private:
    int n_;
    std::vector<float> values_;
};

// r = 2 (n.w) n - w; returns the factor the lobe is multiplied by: max(n.w, 0) with the cosine
// factor, 1 without.
// The direction the lobe is read at is r shifted for the lights' distance (SharedModel::lobeShift):
// unit with `unit`, otherwise only its direction is meaningful (enough for the octahedral table).
template <bool unit = true>
inline double reflected(std::size_t v, const float* n, const float* w, double* r, const SharedModel& model) {
    const double nw = double(n[0]) * w[0] + double(n[1]) * w[1] + double(n[2]) * w[2];
    for (int k = 0; k < 3; ++k) r[k] = 2.0 * nw * n[k] - w[k];
    if (unit)
        model.shiftLobeDirection(v, r);
    else
        model.addLobeShift(v, r);
    return model.factor(nw);
}

// Hat function k of the factor curve at x in [0, 1] (knots k / (kCurveKnots - 1)).
inline double hat(int k, double x) {
    const double t = x * (SharedModel::kCurveKnots - 1) - k;
    return std::max(0.0, 1.0 - std::abs(t));
}

// Squared slope of the 8-bit sRGB encoding at a linear value (first-order error in sRGB levels).
inline double srgbSlope2(double y) {
    const double x = std::min(1.0, std::max(y, 0.0031308));
    const double s = 255.0 * (1.055 / 2.4) * std::pow(x, 1.0 / 2.4 - 1.0);
    return s * s;
}

// Mean of the neighbours' s (those with samples); 1 when none.
void neighbourPrior(const std::vector<std::size_t>& off, const std::vector<std::uint32_t>& adj,
                    const std::vector<float>& s, const std::vector<std::uint8_t>& seen, std::size_t v, double* out) {
    out[0] = out[1] = out[2] = 0.0;
    int k = 0;
    if (!off.empty())
        for (std::size_t e = off[v]; e < off[v + 1]; ++e) {
            const std::uint32_t u = adj[e];
            if (!seen[u]) continue;
            for (int c = 0; c < 3; ++c) out[c] += s[3 * u + c];
            ++k;
        }
    if (k == 0) {
        out[0] = out[1] = out[2] = 1.0;
        return;
    }
    for (int c = 0; c < 3; ++c) out[c] /= k;
}

// Ridge regression y ~ d + s g with penalty lambda (s - prior)^2, weights a: returns (d, s).
struct PairSums {
    double W = 0, Sg = 0, Sgg = 0, Sy = 0, Sgy = 0;
};
inline void solvePair(const PairSums& p, double lambda, double prior, double& d, double& s, double inverse[3]) {
    // [W Sg; Sg Sgg+lambda] [d; s] = [Sy; Sgy + lambda prior]
    const double a = p.W, b = p.Sg, c = p.Sgg + lambda;
    const double det = a * c - b * b;
    if (!(det > 1e-12 * a * std::max(c, 1e-300)) || !(a > 0.0)) {
        // g constant over the samples (or no lambda): s undetermined -> the prior.
        s = prior;
        d = a > 0.0 ? (p.Sy - s * p.Sg) / a : 0.0;
        if (inverse) {
            inverse[0] = a > 0.0 ? 1.0 / a : 0.0;
            inverse[1] = inverse[2] = 0.0;
        }
        return;
    }
    const double r0 = p.Sy, r1 = p.Sgy + lambda * prior;
    d = (c * r0 - b * r1) / det;
    s = (a * r1 - b * r0) / det;
    if (inverse) {  // A^-1 = [c -b; -b a] / det, stored as (00, 01, 11)
        inverse[0] = c / det;
        inverse[1] = -b / det;
        inverse[2] = a / det;
    }
}

}  // namespace

std::string SharedFitOptions::validate() const {
    std::ostringstream why;
    if (lobeDegree < 1 || lobeDegree > kMaxHarmonicDegree)
        why << "the degree of the shared reflected lobe must be in 1.." << kMaxHarmonicDegree << " (got " << lobeDegree << ")";
    else if (!(specularPrior >= 0.0) || !std::isfinite(specularPrior))
        why << "the weight of the neighbours' specular scale must be finite and >= 0 (got " << specularPrior << ")";
    else if (iterations < 1 || iterations > 50)
        why << "the shared fit's iterations must be in 1..50 (got " << iterations << ")";
    else if (refitIterations < 1 || refitIterations > 50)
        why << "the shared fit's refit iterations must be in 1..50 (got " << refitIterations << ")";
    else if (choiceIterations < 1 || choiceIterations > 50)
        why << "the automatic choice's shared fit iterations must be in 1..50 (got " << choiceIterations << ")";
    else if (robustIterations < 0 || robustIterations > iterations)
        why << "the shared fit's robust iterations must be in 0..iterations (got " << robustIterations << ")";
    else if (!(huberThreshold > 0.0) || !std::isfinite(huberThreshold))
        why << "the shared fit's Huber threshold must be > 0 (got " << huberThreshold << ")";
    else if (!(lobeRidge >= 0.0) || !std::isfinite(lobeRidge))
        why << "the shared lobe's regularisation must be finite and >= 0 (got " << lobeRidge << ")";
    else if (!(guardStandardErrors >= 0.0) || !std::isfinite(guardStandardErrors))
        why << "the shared fit's guard must be a finite number of standard errors >= 0 (got " << guardStandardErrors << ")";
    else if (lobeSampleBudget < 1000)
        why << "the shared lobe's sample budget must be at least 1000 (got " << lobeSampleBudget << ")";
    else if (octahedralResolution < 16 || octahedralResolution > 1024)
        why << "the shared lobe's table resolution must be in 16..1024 (got " << octahedralResolution << ")";
    else if (!(lightDistance == 0.0 || lightDistance >= kMinLightDistance))
        why << "the distance of the lights must be 0 (chosen by the fit) or at least " << kMinLightDistance
            << " bounding radii, infinity for distant lights (got " << lightDistance << ")";
    return why.str();
}

double SharedModel::factor(double nw) const {
    if (!cosineFactor) return 1.0;
    const double x = std::min(std::max(nw, 0.0), 1.0);
    if (curve.size() != std::size_t(kCurveKnots)) return x;
    const double t = x * (kCurveKnots - 1);
    const int k = std::min(static_cast<int>(t), kCurveKnots - 2);
    return curve[k] + (t - k) * (curve[k + 1] - curve[k]);
}

void SharedModel::evaluate(std::size_t v, const float* n, const double* w, double* rgb) const {
    const int M = (lobeDegree + 1) * (lobeDegree + 1);
    double Y[(kMaxHarmonicDegree + 1) * (kMaxHarmonicDegree + 1)];
    const double nw = n[0] * w[0] + n[1] * w[1] + n[2] * w[2], d = 2.0 * nw;
    double r[3] = {d * n[0] - w[0], d * n[1] - w[1], d * n[2] - w[2]};
    shiftLobeDirection(v, r);
    evaluateSphericalHarmonics(lobeDegree, r[0], r[1], r[2], Y);
    const double f = factor(nw);
    for (int c = 0; c < 3; ++c) {
        double g = 0.0;
        for (int k = 0; k < M; ++k) g += lobe[c * M + k] * Y[k];
        rgb[c] = diffuse[3 * v + c] + specular[3 * v + c] * f * g;
    }
}

namespace {

constexpr const char* kStageLobe = "fitting the shared reflected lobe";
// A fixed number of chunks, each with its own sums, merged in chunk order: the results do not
// depend on the thread count or the schedule.
constexpr std::ptrdiff_t kChunks = 16;

// What every step of the alternation reads: the vertices' normals and adjacency, the samples (those
// with use[i], when use is given) and the options.
struct SharedFitInput {
    const std::vector<float>& normals;
    const std::vector<std::size_t>& off;
    const std::vector<std::uint32_t>& adj;
    const SampleSet& set;
    const std::uint8_t* use;
    const SharedFitOptions& options;
    int degree = 0, M = 0;  // lobe degree, its SH coefficient count
    // (x_v - c) / radius per vertex (c the centre of the bounding box, radius the largest |x_v - c|);
    // empty without positions.
    const std::vector<float>& unitShift;
    bool usable(std::size_t i) const { return !use || use[i]; }
};

// The vertices of the G step and of the factor curve: every stride-th (of all vertices, so the
// subset is spread over the mesh), cut into kChunks chunks.
struct LobeSubset {
    std::size_t stride = 1;
    std::ptrdiff_t count = 0;
    // Every stride-th of n vertices.
    static LobeSubset everyNth(std::size_t n, std::size_t stride) {
        return {stride, static_cast<std::ptrdiff_t>((n + stride - 1) / stride)};
    }
    std::ptrdiff_t begin(std::ptrdiff_t chunk) const { return count * chunk / kChunks; }
    std::ptrdiff_t end(std::ptrdiff_t chunk) const { return count * (chunk + 1) / kChunks; }
};

void validateSharedFitInput(const std::vector<float>& normals, const std::vector<std::size_t>& off,
                            const SampleSet& set, const SharedFitOptions& options) {
    const std::string problem = options.validate();
    if (!problem.empty()) throw std::invalid_argument(problem);
    const std::size_t n = set.vertexCount();
    if (normals.size() != 3 * n || set.samples.size() != set.offsets.back() || set.view.size() != set.samples.size() ||
        (!off.empty() && off.size() != n + 1))
        throw std::invalid_argument("fitSharedModel: inconsistent sizes");
}

// The starting model: lobe 0, specular scales 1, the cosine curve, diffuse = the weighted mean colour
// of each vertex with samples (marked seen). Returns the number of usable samples.
std::size_t initialModel(const SharedFitInput& in, SharedModel& model, std::vector<std::uint8_t>& seen) {
    const SampleSet& set = in.set;
    const std::size_t n = set.vertexCount();
    model.lobeDegree = in.degree;
    model.cosineFactor = in.options.cosineFactor;
    model.curve.resize(SharedModel::kCurveKnots);
    for (int k = 0; k < SharedModel::kCurveKnots; ++k) model.curve[k] = double(k) / (SharedModel::kCurveKnots - 1);
    model.lobe.assign(3 * in.M, 0.0);
    model.diffuse.assign(3 * n, 0.0f);
    model.specular.assign(3 * n, 1.0f);
    model.robustWeight.assign(set.samples.size(), 1.0f);
    seen.assign(n, 0);
    std::size_t usedSamples = 0;
    for (std::size_t v = 0; v < n; ++v) {
        double acc[3] = {0, 0, 0}, W = 0;
        for (std::size_t i = set.offsets[v]; i < set.offsets[v + 1]; ++i) {
            if (!in.usable(i)) continue;
            const DirectionalSample& s = set.samples[i];
            for (int c = 0; c < 3; ++c) acc[c] += s.weight * double(s.rgb[c]);
            W += s.weight;
            ++usedSamples;
        }
        if (W > 0.0) {
            seen[v] = 1;
            for (int c = 0; c < 3; ++c) model.diffuse[3 * v + c] = static_cast<float>(acc[c] / W);
        }
    }
    return usedSamples;
}

// Calls visit(v, nv, s, w) for every usable sample of the chunk's G-step vertices whose effective
// weight w (the sample's own times the robust one) is positive.
template <class Visit>
void forEachWeightedLobeSample(const SharedFitInput& in, const LobeSubset& subset, const SharedModel& model,
                               std::ptrdiff_t chunk, Visit&& visit) {
    for (std::ptrdiff_t p = subset.begin(chunk); p < subset.end(chunk); ++p) {
        const std::size_t v = static_cast<std::size_t>(p) * subset.stride;
        const float* nv = in.normals.data() + 3 * v;
        for (std::size_t i = in.set.offsets[v]; i < in.set.offsets[v + 1]; ++i) {
            if (!in.usable(i)) continue;
            const DirectionalSample& s = in.set.samples[i];
            const double w = double(s.weight) * model.robustWeight[i];
            if (!(w > 0.0)) continue;
            visit(v, nv, s, w);
        }
    }
}

// The normal equations of the G step of one chunk: rows sqrt(w) s_c f(n.w) Y(r) against the
// residual y - d, accumulated by blocks of kBlock rows. Each block's rank update is made in single
// precision (twice the throughput of the dominant product) and added to the double sums, so the
// rounding error stays that of one block of kBlock rows, far below the ridge's weight.
void accumulateLobeChunk(const SharedFitInput& in, const LobeSubset& subset, const SharedModel& model,
                         std::ptrdiff_t chunk, std::array<Eigen::MatrixXd, 3>& A, std::array<Eigen::VectorXd, 3>& b) {
    constexpr int kBlock = 128;
    const int M = in.M;
    Eigen::MatrixXf D[3];
    Eigen::MatrixXf blockProduct(M, M);
    for (int c = 0; c < 3; ++c) {
        A[c] = Eigen::MatrixXd::Zero(M, M);
        b[c] = Eigen::VectorXd::Zero(M);
        D[c].resize(M, kBlock);
    }
    int filled = 0;
    std::vector<double> Y(M);
    auto flush = [&]() {
        if (filled == 0) return;
        for (int c = 0; c < 3; ++c) {
            blockProduct.setZero();
            blockProduct.selfadjointView<Eigen::Lower>().rankUpdate(D[c].leftCols(filled));
            A[c].triangularView<Eigen::Lower>() += blockProduct.cast<double>();
        }
        filled = 0;
    };
    forEachWeightedLobeSample(in, subset, model, chunk,
                              [&](std::size_t v, const float* nv, const DirectionalSample& s, double w) {
        double r[3];
        const double cf = reflected(v, nv, s.direction, r, model);
        evaluateSphericalHarmonics(in.degree, r[0], r[1], r[2], Y.data());
        const double sw = std::sqrt(w);
        for (int c = 0; c < 3; ++c) {
            const double sc = model.specular[3 * v + c] * cf;
            const double t = s.rgb[c] - model.diffuse[3 * v + c];
            float* col = D[c].col(filled).data();
            for (int k = 0; k < M; ++k) col[k] = static_cast<float>(sw * sc * Y[k]);
            const double f = w * sc * t;
            for (int k = 0; k < M; ++k) b[c][k] += f * Y[k];
        }
        if (++filled == kBlock) flush();
    });
    flush();
}

// G step: the lobe's SH coefficients by ridge regression (weight lobeRidge (1 + l(l+1)) of the
// trace / M), with d and s fixed.
void fitLobe(const SharedFitInput& in, const LobeSubset& subset, SharedModel& model) {
    const int M = in.M, degree = in.degree;
    std::vector<std::array<Eigen::MatrixXd, 3>> partA(kChunks);
    std::vector<std::array<Eigen::VectorXd, 3>> partB(kChunks);
#pragma omp parallel for schedule(dynamic, 1)
    for (std::ptrdiff_t chunk = 0; chunk < kChunks; ++chunk)
        accumulateLobeChunk(in, subset, model, chunk, partA[chunk], partB[chunk]);
    Eigen::MatrixXd Atotal[3];
    Eigen::VectorXd btotal[3];
    for (int c = 0; c < 3; ++c) {
        Atotal[c] = Eigen::MatrixXd::Zero(M, M);
        btotal[c] = Eigen::VectorXd::Zero(M);
    }
    for (std::ptrdiff_t chunk = 0; chunk < kChunks; ++chunk)
        for (int c = 0; c < 3; ++c) {
            Atotal[c].triangularView<Eigen::Lower>() += partA[chunk][c];
            btotal[c] += partB[chunk][c];
        }
    for (int c = 0; c < 3; ++c) {
        Eigen::MatrixXd& Ac = Atotal[c];
        const double scale = std::max(Ac.trace() / M, 1e-300);
        for (int l = 0, k = 0; l <= degree; ++l)
            for (int m = -l; m <= l; ++m, ++k) Ac(k, k) += (in.options.lobeRidge * (1.0 + l * (l + 1.0)) + 1e-9) * scale;
        Eigen::LDLT<Eigen::MatrixXd> ldlt(Ac.selfadjointView<Eigen::Lower>());
        Eigen::VectorXd x = ldlt.solve(btotal[c]);
        if (ldlt.info() != Eigen::Success || !x.allFinite()) x.setZero();
        for (int k = 0; k < M; ++k) model.lobe[c * M + k] = x[k];
    }
}

// q_c: the mean of G_c^2 over the G step's samples (sets the strength of the neighbour prior).
void measureLobeEnergy(const SharedFitInput& in, const LobeSubset& subset, SharedModel& model) {
    const int M = in.M;
    double q[3] = {0, 0, 0}, W = 0;
    std::vector<std::array<double, 4>> partQ(kChunks);
#pragma omp parallel for schedule(dynamic, 1)
    for (std::ptrdiff_t chunk = 0; chunk < kChunks; ++chunk) {
        std::vector<double> Y(M);
        double ql[3] = {0, 0, 0}, Wl = 0;
        for (std::ptrdiff_t p = subset.begin(chunk); p < subset.end(chunk); ++p) {
            const std::size_t v = static_cast<std::size_t>(p) * subset.stride;
            const float* nv = in.normals.data() + 3 * v;
            for (std::size_t i = in.set.offsets[v]; i < in.set.offsets[v + 1]; ++i) {
                if (!in.usable(i)) continue;
                const DirectionalSample& s = in.set.samples[i];
                double r[3];
                const double cf = reflected(v, nv, s.direction, r, model);
                evaluateSphericalHarmonics(in.degree, r[0], r[1], r[2], Y.data());
                for (int c = 0; c < 3; ++c) {
                    double g = 0;
                    for (int k = 0; k < M; ++k) g += model.lobe[c * M + k] * Y[k];
                    g *= cf;
                    ql[c] += s.weight * g * g;
                }
                Wl += s.weight;
            }
        }
        partQ[chunk] = {ql[0], ql[1], ql[2], Wl};
    }
    for (const auto& p : partQ) {
        for (int c = 0; c < 3; ++c) q[c] += p[c];
        W += p[3];
    }
    for (int c = 0; c < 3; ++c) model.lobeEnergy[c] = W > 0 ? q[c] / W : 0.0;
}

// The lobe at the reflected direction of sample s, times the factor: g (3 channels).
inline void lobeAtSample(const LobeTable& table, const SharedModel& model, std::size_t v, const float* nv,
                         const DirectionalSample& s, double g[3]) {
    double r[3];
    const double cf = reflected<false>(v, nv, s.direction, r, model);
    table.lookup(r[0], r[1], r[2], g);
    for (int c = 0; c < 3; ++c) g[c] *= cf;
}

// One seen vertex's (d, s) per channel, pulled toward its neighbours' s (prior), and the norms of
// its samples' residuals (for the robust weights).
void fitVertexPair(const SharedFitInput& in, const LobeTable& table, const std::vector<double>& prior, std::size_t v,
                   SharedModel& model, std::vector<float>& residualNorm) {
    const SampleSet& set = in.set;
    const float* nv = in.normals.data() + 3 * v;
    PairSums sums[3];
    for (std::size_t i = set.offsets[v]; i < set.offsets[v + 1]; ++i) {
        if (!in.usable(i)) continue;
        const DirectionalSample& s = set.samples[i];
        const double w = double(s.weight) * model.robustWeight[i];
        double g[3];
        lobeAtSample(table, model, v, nv, s, g);
        for (int c = 0; c < 3; ++c) {
            PairSums& p = sums[c];
            p.W += w;
            p.Sg += w * g[c];
            p.Sgg += w * g[c] * g[c];
            p.Sy += w * s.rgb[c];
            p.Sgy += w * g[c] * s.rgb[c];
        }
    }
    double d[3], sc[3];
    for (int c = 0; c < 3; ++c) {
        const double lambda = in.options.specularPrior * sums[c].W * model.lobeEnergy[c];
        solvePair(sums[c], lambda, prior[3 * v + c], d[c], sc[c], nullptr);
        model.diffuse[3 * v + c] = static_cast<float>(d[c]);
        model.specular[3 * v + c] = static_cast<float>(sc[c]);
    }
    for (std::size_t i = set.offsets[v]; i < set.offsets[v + 1]; ++i) {
        if (!in.usable(i)) continue;
        const DirectionalSample& s = set.samples[i];
        double g[3];
        lobeAtSample(table, model, v, nv, s, g);
        double e2 = 0.0;
        for (int c = 0; c < 3; ++c) {
            const double e = s.rgb[c] - d[c] - sc[c] * g[c];
            e2 += e * e;
        }
        residualNorm[i] = static_cast<float>(std::sqrt(e2));
    }
}

// Per-vertex step, Jacobi in the neighbour prior: every prior is taken from the previous iteration's
// s before any vertex is updated. Every stride-th vertex (1: all).
void fitVertexPairs(const SharedFitInput& in, const LobeTable& table, const std::vector<std::uint8_t>& seen,
                    std::vector<double>& prior, SharedModel& model, std::vector<float>& residualNorm,
                    std::size_t stride = 1) {
    const std::ptrdiff_t count = static_cast<std::ptrdiff_t>((in.set.vertexCount() + stride - 1) / stride);
#pragma omp parallel for schedule(dynamic, 256)
    for (std::ptrdiff_t p = 0; p < count; ++p) {
        const std::size_t v = static_cast<std::size_t>(p) * stride;
        if (seen[v]) neighbourPrior(in.off, in.adj, model.specular, seen, v, prior.data() + 3 * v);
    }
#pragma omp parallel for schedule(dynamic, 256)
    for (std::ptrdiff_t p = 0; p < count; ++p) {
        const std::size_t v = static_cast<std::size_t>(p) * stride;
        if (seen[v]) fitVertexPair(in, table, prior, v, model, residualNorm);
    }
}

constexpr int kKnots = SharedModel::kCurveKnots;
using CurveMatrix = Eigen::Matrix<double, kKnots, kKnots>;
using CurveVector = Eigen::Matrix<double, kKnots, 1>;

// The factor curve's normal equations of one chunk of the G step's vertices.
void accumulateCurveChunk(const SharedFitInput& in, const LobeSubset& subset, const LobeTable& table,
                          const SharedModel& model, std::ptrdiff_t chunk, CurveMatrix& A, CurveVector& b) {
    constexpr int K = kKnots;
    A = CurveMatrix::Zero();
    b = CurveVector::Zero();
    forEachWeightedLobeSample(in, subset, model, chunk,
                              [&](std::size_t v, const float* nv, const DirectionalSample& s, double w) {
        double r[3], g[3];
        reflected<false>(v, nv, s.direction, r, model);
        const double nw = std::min(std::max(double(nv[0]) * s.direction[0] + double(nv[1]) * s.direction[1] +
                                                double(nv[2]) * s.direction[2], 0.0), 1.0);
        table.lookup(r[0], r[1], r[2], g);
        CurveVector phi;
        for (int k = 0; k < K; ++k) phi[k] = hat(k, nw);
        for (int c = 0; c < 3; ++c) {
            const double a = model.specular[3 * v + c] * g[c];
            A.noalias() += (w * a * a) * phi * phi.transpose();
            b.noalias() += (w * a * (s.rgb[c] - model.diffuse[3 * v + c])) * phi;
        }
    });
}

// Factor curve step: h(n.w) = sum_k beta_k hat_k(n.w), shared by every vertex and channel, least
// squares with d, s, G fixed over the G step's vertices, pulled toward the cosine (weight 1e-3 of
// the trace), clamped >= 0, normalised to h(1) = 1 (G takes the scale).
void fitFactorCurve(const SharedFitInput& in, const LobeSubset& subset, const LobeTable& table, SharedModel& model) {
    constexpr int K = kKnots;
    std::vector<CurveMatrix> partA(kChunks);
    std::vector<CurveVector> partB(kChunks);
#pragma omp parallel for schedule(dynamic, 1)
    for (std::ptrdiff_t chunk = 0; chunk < kChunks; ++chunk)
        accumulateCurveChunk(in, subset, table, model, chunk, partA[chunk], partB[chunk]);
    CurveMatrix A = CurveMatrix::Zero();
    CurveVector b = CurveVector::Zero(), prior;
    for (std::ptrdiff_t chunk = 0; chunk < kChunks; ++chunk) {
        A += partA[chunk];
        b += partB[chunk];
    }
    const double mu = 1e-3 * std::max(A.trace() / K, 1e-300);
    for (int k = 0; k < K; ++k) prior[k] = double(k) / (K - 1);
    A.diagonal().array() += mu;
    b += mu * prior;
    CurveVector beta = A.ldlt().solve(b);
    if (!beta.allFinite()) return;
    for (int k = 0; k < K; ++k) beta[k] = std::max(beta[k], 0.0);
    const double top = beta[K - 1];
    if (!(top > 1e-6)) return;
    for (int k = 0; k < K; ++k) model.curve[k] = beta[k] / top;
    for (double& x : model.lobe) x *= top;
    for (double& q : model.lobeEnergy) q *= top * top;
}

// Huber weights for the next iteration, the scale from the median residual norm of at most
// lobeSampleBudget usable samples taken evenly.
void updateRobustWeights(const SharedFitInput& in, std::size_t usedSamples, const std::vector<float>& residualNorm,
                         SharedModel& model) {
    const std::size_t total = in.set.samples.size();
    std::vector<float> pool;
    pool.reserve(std::min<std::size_t>(usedSamples, in.options.lobeSampleBudget) + 16);
    const std::size_t poolStride = std::max<std::size_t>(1, usedSamples / in.options.lobeSampleBudget);
    std::size_t k = 0;
    for (std::size_t i = 0; i < total; ++i)
        if (in.usable(i) && (k++ % poolStride) == 0) pool.push_back(residualNorm[i]);
    if (pool.empty()) return;
    std::nth_element(pool.begin(), pool.begin() + pool.size() / 2, pool.end());
    const double sigma = kHuberScale * pool[pool.size() / 2];
    const double limit = in.options.huberThreshold * sigma;
    for (std::size_t i = 0; i < total; ++i) {
        const double e = residualNorm[i];
        model.robustWeight[i] = (limit > 0.0 && e > limit) ? static_cast<float>(limit / e) : 1.0f;
    }
}

bool warmStartMatches(const SharedModel& warm, const SampleSet& set, const SharedFitOptions& options) {
    const std::size_t M = std::size_t(options.lobeDegree + 1) * (options.lobeDegree + 1);
    return warm.lobeDegree == options.lobeDegree && warm.lobe.size() == 3 * M &&
           warm.specular.size() == 3 * set.vertexCount() && warm.robustWeight.size() == set.samples.size() &&
           warm.curve.size() == std::size_t(SharedModel::kCurveKnots);
}

// What a warm start keeps: the lobe, the factor curve, the scales (vertices the earlier fit did not
// see have 1, the cold start's value) and the robust weights (samples it did not use have 1). The
// diffuse colours stay the initial means: the first per-vertex step refits them.
void takeWarmStart(const SharedModel& warm, SharedModel& model) {
    model.lobe = warm.lobe;
    if (model.cosineFactor && warm.cosineFactor) model.curve = warm.curve;
    model.specular = warm.specular;
    model.robustWeight = warm.robustWeight;
    model.lobeShift = warm.lobeShift;
    model.lightDistance = warm.lightDistance;
}

// (x_v - c) / radius of every vertex: c the centre of the bounding box, radius the largest |x_v - c|.
std::vector<float> unitShifts(const std::vector<float>& positions) {
    const MeshBounds bounds = meshBounds(positions);
    const std::size_t n = positions.size() / 3;
    std::vector<float> unit(3 * n, 0.0f);
    const double radius = bounds.farthestFromCentre;
    if (!(radius > 0.0) || !std::isfinite(radius)) return unit;
    const Eigen::Vector3d centre = bounds.box.center();
    for (std::size_t v = 0; v < n; ++v)
        for (int c = 0; c < 3; ++c) unit[3 * v + c] = static_cast<float>((positions[3 * v + c] - centre[c]) / radius);
    return unit;
}

// The lights at `distance` bounding radii (infinity: distant lights, no shift).
void placeLights(const SharedFitInput& in, double distance, SharedModel& model) {
    model.lightDistance = distance;
    if (!std::isfinite(distance) || in.unitShift.empty()) {
        model.lobeShift.clear();
        model.lightDistance = std::numeric_limits<double>::infinity();
        return;
    }
    model.lobeShift.resize(in.unitShift.size());
    const float scale = static_cast<float>(1.0 / distance);
    for (std::size_t i = 0; i < in.unitShift.size(); ++i) model.lobeShift[i] = scale * in.unitShift[i];
}

// The weighted squared residual of the model over the G step's samples (robust weights included;
// exact SH evaluation of the lobe), summed chunk by chunk in chunk order.
double lobeSubsetResidual(const SharedFitInput& in, const LobeSubset& subset, const SharedModel& model) {
    std::vector<double> part(kChunks, 0.0);
#pragma omp parallel for schedule(dynamic, 1)
    for (std::ptrdiff_t chunk = 0; chunk < kChunks; ++chunk) {
        std::vector<double> Y(in.M);
        double sum = 0.0;
        forEachWeightedLobeSample(in, subset, model, chunk,
                                  [&](std::size_t v, const float* nv, const DirectionalSample& s, double w) {
            double r[3];
            const double cf = reflected(v, nv, s.direction, r, model);
            evaluateSphericalHarmonics(in.degree, r[0], r[1], r[2], Y.data());
            for (int c = 0; c < 3; ++c) {
                double g = 0.0;
                for (int k = 0; k < in.M; ++k) g += model.lobe[c * in.M + k] * Y[k];
                const double e = s.rgb[c] - model.diffuse[3 * v + c] - model.specular[3 * v + c] * cf * g;
                sum += w * e * e;
            }
        });
        part[chunk] = sum;
    }
    double total = 0.0;
    for (const double p : part) total += p;
    return total;
}

constexpr int kSearchDegree = 6;

// The search's own lobe degree and G-step vertices: a lobe of degree at most kSearchDegree on half of
// the G step's samples (each candidate costs two G steps).
struct DistanceSearch {
    SharedFitInput in;
    LobeSubset subset;
    std::vector<double> prior;
    DistanceSearch(const SharedFitInput& full, const LobeSubset& fullSubset)
        : in(full), subset(LobeSubset::everyNth(full.set.vertexCount(), 2 * fullSubset.stride)) {
        in.degree = std::min(full.degree, kSearchDegree);
        in.M = (in.degree + 1) * (in.degree + 1);
        prior.assign(3 * in.set.vertexCount(), 1.0);
    }
};

// The model's residual on the search's samples with the lights at `distance`: the lobe fitted, the
// diffuse colours and scales of the search's vertices refitted against it, the lobe again.
double residualAtDistance(DistanceSearch& search, const std::vector<std::uint8_t>& seen, double distance,
                          SharedModel& model, std::vector<float>& residualScratch) {
    const SharedFitInput& in = search.in;
    placeLights(in, distance, model);
    fitLobe(in, search.subset, model);
    measureLobeEnergy(in, search.subset, model);
    const LobeTable table(model, in.options.octahedralResolution);
    fitVertexPairs(in, table, seen, search.prior, model, residualScratch, search.subset.stride);
    fitLobe(in, search.subset, model);
    return lobeSubsetResidual(in, search.subset, model);
}

// The vertex of the parabola through three (u, residual) points, if it lies strictly between the outer
// two; otherwise u[1].
double parabolaMinimum(const double u[3], const double r[3]) {
    const double num = (u[1] - u[0]) * (u[1] - u[0]) * (r[1] - r[2]) - (u[1] - u[2]) * (u[1] - u[2]) * (r[1] - r[0]);
    const double den = (u[1] - u[0]) * (r[1] - r[2]) - (u[1] - u[2]) * (r[1] - r[0]);
    const double m = den != 0.0 ? u[1] - 0.5 * num / den : u[1];
    return m > u[0] && m < u[2] ? m : u[1];
}

// The lights' distance: each of kLightDistanceCandidates is scored by residualAtDistance, then the
// vertex of the parabola through the best one and its neighbours (in radius / distance, the
// candidates' spacing) when the best is not at an end; the distance with the least residual is kept
// and the lobe of the full degree fitted there. The vertices' colours and scales are restored after
// each candidate (the alternation refits them); refitting them within each candidate matters: with
// those of the distant-light model every near distance starts behind. No robust weights in the
// search: those of a distant-light model mark the samples it could not fit, a near light's
// highlights among them, which are what tells the distances apart. One global parameter chosen on
// tens of thousands of samples: the training residual does not reward it for fitting noise, as it
// would a per-vertex one.
void chooseLightDistance(const SharedFitInput& full, const LobeSubset& fullSubset, const std::vector<std::uint8_t>& seen,
                         SharedModel& model, std::vector<float>& residualScratch) {
    DistanceSearch search(full, fullSubset);
    const std::vector<double> fullLobe = model.lobe;
    const std::vector<float> diffuse = model.diffuse, specular = model.specular;
    const double energy[3] = {model.lobeEnergy[0], model.lobeEnergy[1], model.lobeEnergy[2]};
    std::vector<float> robustWeight(model.robustWeight.size(), 1.0f);
    robustWeight.swap(model.robustWeight);
    model.lobeDegree = search.in.degree;
    model.lobe.assign(3 * search.in.M, 0.0);

    double bestResidual = std::numeric_limits<double>::infinity(), bestDistance = kLightDistanceCandidates[0];
    auto score = [&](double distance) {
        const double residual = residualAtDistance(search, seen, distance, model, residualScratch);
        model.diffuse = diffuse;
        model.specular = specular;
        if (residual < bestResidual) {
            bestResidual = residual;
            bestDistance = distance;
        }
        return residual;
    };
    constexpr int kCandidates = int(std::size(kLightDistanceCandidates));
    double residuals[kCandidates];
    for (int i = 0; i < kCandidates; ++i) residuals[i] = score(kLightDistanceCandidates[i]);
    const int b = int(std::min_element(residuals, residuals + kCandidates) - residuals);
    if (b > 0 && b + 1 < kCandidates) {
        const double u[3] = {1.0 / kLightDistanceCandidates[b - 1], 1.0 / kLightDistanceCandidates[b],
                             1.0 / kLightDistanceCandidates[b + 1]};
        const double between = parabolaMinimum(u, residuals + b - 1);
        if (std::abs(between - u[1]) > 1e-3) score(1.0 / between);
    }

    placeLights(full, bestDistance, model);
    robustWeight.swap(model.robustWeight);
    model.lobeDegree = full.degree;
    model.lobe = fullLobe;
    fitLobe(full, fullSubset, model);
    for (int c = 0; c < 3; ++c) model.lobeEnergy[c] = energy[c];
}

}  // namespace

SharedModel fitSharedModel(const std::vector<float>& normals, const std::vector<std::size_t>& off,
                           const std::vector<std::uint32_t>& adj, const SampleSet& set, const std::uint8_t* use,
                           const SharedFitOptions& options, const ProgressCallback& progress,
                           const SharedModel* warmStart, const std::vector<float>* positions) {
    validateSharedFitInput(normals, off, set, options);
    if (warmStart && !warmStartMatches(*warmStart, set, options))
        throw std::invalid_argument("fitSharedModel: the warm start was fitted with another lobe degree or sample set");
    const int degree = options.lobeDegree;
    if (positions && positions->size() != normals.size())
        throw std::invalid_argument("fitSharedModel: inconsistent sizes");
    const std::vector<float> unitShift = positions ? unitShifts(*positions) : std::vector<float>();
    const SharedFitInput in{normals, off, adj, set, use, options, degree, (degree + 1) * (degree + 1), unitShift};
    const std::size_t n = set.vertexCount();
    SharedModel model;
    std::vector<std::uint8_t> seen;
    const std::size_t usedSamples = initialModel(in, model, seen);
    if (usedSamples == 0) return model;
    const LobeSubset subset = LobeSubset::everyNth(
        n, std::max<std::size_t>(1, (usedSamples + options.lobeSampleBudget - 1) / options.lobeSampleBudget));
    std::vector<float> residualNorm(set.samples.size(), 0.0f);
    if (warmStart) takeWarmStart(*warmStart, model);
    const bool chooseDistance = !warmStart && options.lightDistance == 0.0 && !in.unitShift.empty();
    if (!warmStart && !chooseDistance) placeLights(in, options.lightDistance, model);  // 0 without positions: distant
    const int iterations = warmStart ? options.refitIterations : options.iterations;
    // The distance is chosen at the second G step (the first with fitted diffuse colours and scales).
    const int distanceIteration = std::min(1, iterations - 1);
    const int robustStart = std::max(1, iterations - options.robustIterations);
    std::vector<double> prior(3 * n, 1.0);

    for (int it = 0; it < iterations; ++it) {
        if (progress && !progress(double(it) / iterations, kStageLobe)) throw OperationCancelled();
        if (chooseDistance && it == distanceIteration)
            chooseLightDistance(in, subset, seen, model, residualNorm);
        else if (!(warmStart && it == 0))  // a warm start enters at the vertex step
            fitLobe(in, subset, model);
        measureLobeEnergy(in, subset, model);
        const LobeTable table(model, options.octahedralResolution);
        fitVertexPairs(in, table, seen, prior, model, residualNorm);
        if (options.cosineFactor && options.fitFactorCurve) fitFactorCurve(in, subset, table, model);
        if (it + 1 >= robustStart && it + 1 < iterations)
            updateRobustWeights(in, usedSamples, residualNorm, model);
    }
    if (progress && !progress(1.0, kStageLobe)) throw OperationCancelled();
    return model;
}

namespace {

constexpr const char* kStageConversion = "writing the shared fit into the basis";

// The least-squares projection onto the basis of a function sampled at fixed local directions, and
// what the storage needs of the basis.
struct BasisProjector {
    std::vector<double> dirs;    // 3 x Nd: local frame
    int Nd = 0, K = 0;
    Eigen::MatrixXd P;           // K x Nd: (B^T B + eps I)^-1 B^T, columns times the lobe's factor there
    std::vector<double> sign;    // K: the local reflection (x, y, z) -> (-x, -y, z) of each function
    double constantValue = 1.0;  // value of the constant basis function
};

// factor: the model's factor of n.w (SharedModel::factor); n.w of a local direction is its z, the
// same at every vertex, so the factor is folded into the projection once.
BasisProjector buildBasisProjector(const BasisSpec& basis, const SharedModel& factor) {
    BasisProjector proj;
    const int K = proj.K = basis.coefficientCount();
    // About five directions per coefficient (PB4: 75), at most 136: the per-vertex projection is the
    // conversion's largest cost, and on 416k vertices 136 directions for PB4's 15 coefficients gave
    // the same held-out error as 75 (docs/design-notes.md, "The per-vertex guard of the shared fit").
    const int hemisphere = std::clamp(4 * K, 56, 112), ring = std::clamp(K, 12, 24);
    proj.dirs = fibonacciHemisphere(hemisphere, 0.5);
    for (int i = 0; i < ring; ++i) {
        const double a = 2.0 * M_PI * (i + 0.5) / ring;
        proj.dirs.insert(proj.dirs.end(), {std::cos(a), std::sin(a), 0.0});
    }
    const std::vector<double>& dirs = proj.dirs;
    const int Nd = proj.Nd = static_cast<int>(dirs.size() / 3);
    Eigen::MatrixXd B(Nd, K);
    std::vector<double> tmp(K);
    for (int i = 0; i < Nd; ++i) {
        evaluateBasis(basis, dirs[3 * i], dirs[3 * i + 1], dirs[3 * i + 2], tmp.data());
        for (int k = 0; k < K; ++k) B(i, k) = tmp[k];
    }
    // Least squares weighted by the cosine n.w, as the fit weighs its samples: the basis spends its
    // few coefficients where photographs see the surface, not at the horizon, where they see it edge
    // on or not at all (the floor keeps the horizon tame; measured: docs/design-notes.md, "The
    // per-vertex guard of the shared fit").
    constexpr double kHorizonWeight = 0.05;
    Eigen::VectorXd weight(Nd);
    for (int i = 0; i < Nd; ++i) weight[i] = std::max(dirs[3 * i + 2], kHorizonWeight);
    const Eigen::MatrixXd BtW = B.transpose() * weight.asDiagonal();
    Eigen::MatrixXd BtB = BtW * B;
    BtB.diagonal().array() += 1e-6 * BtB.trace() / K;
    proj.P = BtB.ldlt().solve(BtW);
    for (int i = 0; i < Nd; ++i) proj.P.col(i) *= factor.factor(dirs[3 * i + 2]);
    std::vector<double> at(K), atReflected(K);
    const double x = 0.3141, y = 0.4718, z = std::sqrt(1.0 - x * x - y * y);
    evaluateBasis(basis, x, y, z, at.data());
    evaluateBasis(basis, -x, -y, z, atReflected.data());
    proj.sign.resize(K);
    for (int k = 0; k < K; ++k) proj.sign[k] = atReflected[k] * at[k] >= 0.0 ? 1.0 : -1.0;
    evaluateBasis(basis, 0.0, 0.0, 1.0, tmp.data());
    proj.constantValue = tmp[0];
    return proj;
}

// What the per-vertex conversion reads, and where it writes.
struct ConversionInput {
    const SharedModel& model;
    const SampleSet& set;
    const std::uint8_t* use;
    const std::vector<std::size_t>& off;
    const std::vector<std::uint32_t>& adj;
    const RobustFitOptions& fit;
    const SharedFitOptions& options;
    const BasisProjector& proj;
    const LobeTable& table;
    const std::vector<std::uint8_t>& seen;
    bool usable(std::size_t i) const { return !use || use[i]; }
};
struct ConversionOutputs {
    RadianceField& field;
    std::vector<float>& meanColor;
    std::vector<float>& residual;
    std::vector<std::uint8_t>& status;
    std::vector<std::uint8_t>* keptShared;
};

// Per-thread buffers, allocated once.
struct ConversionScratch {
    Eigen::MatrixXd V, C;  // the lobe at the projection directions; its coefficients (K x 3)
    std::vector<double> basisAt, g, a, raw, y, out, rotOut;
    ConversionScratch(int Nd, int K) : V(Nd, 3), C(K, 3), basisAt(K), out(3 * K), rotOut(K) {}
};

// The vertex's samples against the projected lobe, and their (Huber-weighted) mean colour.
struct VertexSampleSums {
    PairSums sums[3];
    double meanAcc[3] = {0, 0, 0}, W = 0, meanW = 0;
    int m = 0;
    std::size_t downweighted = 0;
};

// C: the lobe times the factor, seen from the vertex, projected onto the basis (local frame).
void projectLobe(const ConversionInput& in, std::size_t v, const Frame& frame, ConversionScratch& scratch) {
    const std::vector<double>& dirs = in.proj.dirs;
    const double nv[3] = {frame.n.x(), frame.n.y(), frame.n.z()};
    for (int i = 0; i < in.proj.Nd; ++i) {
        const Eigen::Vector3d w = frame.toWorld(Eigen::Vector3d(dirs[3 * i], dirs[3 * i + 1], dirs[3 * i + 2]));
        const double d2 = 2.0 * (nv[0] * w.x() + nv[1] * w.y() + nv[2] * w.z());
        double gv[3];
        double r[3] = {d2 * nv[0] - w.x(), d2 * nv[1] - w.y(), d2 * nv[2] - w.z()};
        in.model.addLobeShift(v, r);
        in.table.lookup(r[0], r[1], r[2], gv);
        for (int c = 0; c < 3; ++c) scratch.V(i, c) = gv[c];
    }
    // A coefficient-wise product: at K x 136 x 3 the general product's packing costs more than it saves.
    scratch.C.noalias() = in.proj.P.lazyProduct(scratch.V);
}

// The projected lobe at the vertex's samples (g), their values (y) and weights (a, raw), and the
// sums of the (d, s) regression.
VertexSampleSums sumVertexSamples(const ConversionInput& in, const Frame& frame, std::size_t v,
                                  ConversionScratch& scratch) {
    const int K = in.proj.K;
    const SampleSet& set = in.set;
    VertexSampleSums vs;
    scratch.g.clear();
    scratch.a.clear();
    scratch.raw.clear();
    scratch.y.clear();
    for (std::size_t i = set.offsets[v]; i < set.offsets[v + 1]; ++i) {
        if (!in.usable(i)) continue;
        const DirectionalSample& s = set.samples[i];
        const double w = double(s.weight) * in.model.robustWeight[i];
        if (in.model.robustWeight[i] < 1.0f) ++vs.downweighted;
        const Eigen::Vector3d l = frame.toLocal(Eigen::Vector3d(s.direction[0], s.direction[1], s.direction[2]));
        double lx = l.x(), ly = l.y(), lz = l.z();
        borderExtendLocal(lx, ly, lz);
        evaluateBasis(in.fit.basis, lx, ly, lz, scratch.basisAt.data());
        for (int c = 0; c < 3; ++c) {
            double gc = 0.0;
            for (int k = 0; k < K; ++k) gc += scratch.C(k, c) * scratch.basisAt[k];
            scratch.g.push_back(gc);
            scratch.y.push_back(s.rgb[c]);
            PairSums& p = vs.sums[c];
            p.W += w;
            p.Sg += w * gc;
            p.Sgg += w * gc * gc;
            p.Sy += w * s.rgb[c];
            p.Sgy += w * gc * s.rgb[c];
            vs.meanAcc[c] += w * s.rgb[c];  // the Huber-weighted mean, as robust_radiance_fit.h
        }
        scratch.a.push_back(w);
        scratch.raw.push_back(w);
        vs.W += w;
        vs.meanW += w;
    }
    vs.m = static_cast<int>(scratch.a.size());
    return vs;
}

// Every usable sample has zero weight: the plain mean, and weights 1.
void fallBackToPlainMean(const ConversionInput& in, std::size_t v, VertexSampleSums& vs, ConversionScratch& scratch) {
    vs.W = 0;
    vs.meanW = 0;
    for (int c = 0; c < 3; ++c) vs.meanAcc[c] = 0;
    for (std::size_t i = in.set.offsets[v]; i < in.set.offsets[v + 1]; ++i) {
        if (!in.usable(i)) continue;
        for (int c = 0; c < 3; ++c) vs.meanAcc[c] += in.set.samples[i].rgb[c];
        vs.W += 1.0;
        vs.meanW += 1.0;
    }
    for (int j = 0; j < vs.m; ++j) scratch.a[j] = scratch.raw[j] = 1.0;
}

// The vertex's (d, s) per channel and the inverse of each 2 x 2 system (for the leave-one-out errors).
struct VertexPair {
    double d[3], sc[3], inv[3][3];
};

// The errors of d + s g and of the mean colour at the vertex's own samples, each left out one at a
// time, in first-order sRGB levels (squared, summed over samples and channels).
struct LeaveOneOutErrors {
    double shared = 0.0, constant = 0.0;
    double differenceSquares = 0.0;  // sum over samples of (shared - constant at that sample)^2
    int samples = 0;
};
LeaveOneOutErrors leaveOneOutErrors(const VertexPair& pair, const double mean[3], const VertexSampleSums& vs,
                                    const ConversionScratch& scratch) {
    LeaveOneOutErrors out;
    out.samples = vs.m;
    for (int j = 0; j < vs.m; ++j) {
        double difference = 0.0;
        for (int c = 0; c < 3; ++c) {
            const double gj = scratch.g[3 * j + c], yj = scratch.y[3 * j + c];
            const double scale = scratch.a[j] * srgbSlope2(yj);
            const double hs = scratch.a[j] * (pair.inv[c][0] + 2.0 * gj * pair.inv[c][1] + gj * gj * pair.inv[c][2]);
            const double es = (yj - pair.d[c] - pair.sc[c] * gj) / std::max(1.0 - hs, 1e-3);
            const double hc = scratch.raw[j] / vs.meanW;
            const double ec = (yj - mean[c]) / std::max(1.0 - hc, 1e-3);
            out.shared += scale * es * es;
            out.constant += scale * ec * ec;
            difference += scale * (es * es - ec * ec);
        }
        out.differenceSquares += difference * difference;
    }
    return out;
}

// Whether the constant predicts the left-out samples better than d + s g by more than
// `standardErrors` standard errors of the mean per-sample difference (0: better at all).
bool constantClearlyBetter(const LeaveOneOutErrors& e, double standardErrors) {
    const double m = e.samples;
    if (!(m > 0.0)) return false;
    const double meanDifference = (e.shared - e.constant) / m;
    if (!(meanDifference > 0.0)) return false;
    if (standardErrors <= 0.0 || m < 2.0) return true;
    const double variance = std::max(0.0, e.differenceSquares / m - meanDifference * meanDifference) * m / (m - 1.0);
    return meanDifference > standardErrors * std::sqrt(variance / m);
}

// Weighted RMS residual of the stored function (shared or constant) at the vertex's samples.
double storedResidual(bool keepShared, const VertexPair& pair, const double mean[3], const VertexSampleSums& vs,
                      const ConversionScratch& scratch) {
    double r2 = 0.0;
    for (int j = 0; j < vs.m; ++j)
        for (int c = 0; c < 3; ++c) {
            const double f = keepShared ? pair.d[c] + pair.sc[c] * scratch.g[3 * j + c] : mean[c];
            const double e = f - scratch.y[3 * j + c];
            r2 += scratch.a[j] * e * e;
        }
    return std::sqrt(r2 / (3.0 * vs.W));
}

// Storage: PB local, SH rotated to the global frame; reflected: the local sign flips.
void storeCoefficients(const ConversionInput& in, const Frame& frame, ConversionScratch& scratch, float* dst) {
    const BasisSpec basis = in.fit.basis;
    const int K = in.proj.K;
    std::vector<double>& out = scratch.out;
    if (in.fit.storeReflected)
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < K; ++k) out[c * K + k] *= in.proj.sign[k];
    if (basis.usesLocalFrame()) {
        for (int k = 0; k < 3 * K; ++k) dst[k] = static_cast<float>(out[k]);
    } else {
        const ShRotation rotation(basis.degree, frame.rotation().transpose());
        for (int c = 0; c < 3; ++c) {
            rotation.apply(out.data() + c * K, scratch.rotOut.data());
            for (int k = 0; k < K; ++k) dst[c * K + k] = static_cast<float>(scratch.rotOut[k]);
        }
    }
}

enum class Conversion { Shared, Constant, TooFew };

// One seen vertex: d + s * (projected lobe) when it beats the constant on the vertex's own samples,
// else the constant mean colour.
Conversion convertVertex(const ConversionInput& in, const ConversionOutputs& outputs, std::size_t v,
                         ConversionScratch& scratch, std::size_t& downweighted) {
    const int K = in.proj.K;
    const Frame frame = frameFromStored(outputs.field.frame(v));
    projectLobe(in, v, frame, scratch);
    VertexSampleSums vs = sumVertexSamples(in, frame, v, scratch);
    downweighted += vs.downweighted;
    if (!(vs.W > 0.0) || !(vs.meanW > 0.0)) fallBackToPlainMean(in, v, vs, scratch);
    double mean[3];
    for (int c = 0; c < 3; ++c) mean[c] = vs.meanAcc[c] / vs.meanW;
    double priorS[3];
    neighbourPrior(in.off, in.adj, in.model.specular, in.seen, v, priorS);
    VertexPair pair;
    for (int c = 0; c < 3; ++c) {
        const double lambda = in.options.specularPrior * vs.sums[c].W * in.model.lobeEnergy[c];
        solvePair(vs.sums[c], lambda, priorS[c], pair.d[c], pair.sc[c], pair.inv[c]);
    }
    const bool keepShared = vs.m >= in.fit.minSamples && vs.m >= 2 &&
                            !constantClearlyBetter(leaveOneOutErrors(pair, mean, vs, scratch), in.options.guardStandardErrors);
    std::vector<double>& out = scratch.out;
    std::fill(out.begin(), out.end(), 0.0);
    if (keepShared) {
        for (int c = 0; c < 3; ++c) {
            for (int k = 0; k < K; ++k) out[c * K + k] = pair.sc[c] * scratch.C(k, c);
            out[c * K] += pair.d[c] / in.proj.constantValue;
        }
        if (outputs.keptShared) (*outputs.keptShared)[v] = 1;
    } else {
        for (int c = 0; c < 3; ++c) out[c * K] = mean[c] / in.proj.constantValue;
    }
    outputs.residual[v] = static_cast<float>(storedResidual(keepShared, pair, mean, vs, scratch));
    for (int c = 0; c < 3; ++c) outputs.meanColor[3 * v + c] = static_cast<float>(mean[c]);
    outputs.status[v] = static_cast<std::uint8_t>(vs.m < in.fit.poorSamplingFactor * K || vs.m < in.fit.minSamples
                                                      ? FitStatus::PoorlySampled
                                                      : FitStatus::Fitted);
    storeCoefficients(in, frame, scratch, outputs.field.vertexCoefficients(v));
    if (keepShared) return Conversion::Shared;
    return vs.m < in.fit.minSamples ? Conversion::TooFew : Conversion::Constant;
}

}  // namespace

SharedConversionStats writeSharedRadiance(const SharedModel& model, const SampleSet& set, const std::uint8_t* use,
                                          const std::vector<std::size_t>& off, const std::vector<std::uint32_t>& adj,
                                          const RobustFitOptions& fit, const SharedFitOptions& options,
                                          RadianceField& field, std::vector<float>& meanColor,
                                          std::vector<float>& residual, std::vector<std::uint8_t>& status,
                                          const ProgressCallback& progress, std::vector<std::uint8_t>* keptShared) {
    const std::size_t n = set.vertexCount();
    if (field.vertexCount() != n || field.basis != fit.basis || meanColor.size() != 3 * n || residual.size() != n ||
        status.size() != n || model.diffuse.size() != 3 * n || model.robustWeight.size() != set.samples.size())
        throw std::invalid_argument("writeSharedRadiance: inconsistent sizes");
    const BasisProjector proj = buildBasisProjector(fit.basis, model);
    const LobeTable table(model, options.octahedralResolution);
    std::vector<std::uint8_t> seen(n, 0);
    for (std::size_t v = 0; v < n; ++v)
        for (std::size_t i = set.offsets[v]; i < set.offsets[v + 1] && !seen[v]; ++i) seen[v] = !use || use[i];
    const ConversionInput in{model, set, use, off, adj, fit, options, proj, table, seen};
    const ConversionOutputs outputs{field, meanColor, residual, status, keptShared};

    if (keptShared) keptShared->assign(n, 0);
    SharedConversionStats stats;
    std::size_t sharedCount = 0, constantCount = 0, tooFew = 0, down = 0;
    LoopProgress loop(progress, kStageConversion, n);
    const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel reduction(+ : sharedCount, constantCount, tooFew, down)
    {
        ConversionScratch scratch(proj.Nd, proj.K);
        const bool reporter = omp_get_thread_num() == 0;
#pragma omp for schedule(dynamic, 256)
        for (std::ptrdiff_t iv = 0; iv < count; ++iv)
            loop.runItem(reporter, [&] {
                const std::size_t v = static_cast<std::size_t>(iv);
                if (!seen[v]) return;
                switch (convertVertex(in, outputs, v, scratch, down)) {
                    case Conversion::Shared: ++sharedCount; break;
                    case Conversion::Constant: ++constantCount; break;
                    case Conversion::TooFew: ++tooFew; break;
                }
            });
    }
    loop.finish();
    stats.shared = sharedCount;
    stats.constant = constantCount;
    stats.tooFew = tooFew;
    stats.downweighted = down;
    return stats;
}

}  // namespace rad
