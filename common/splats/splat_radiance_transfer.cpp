#include "splats/splat_radiance_transfer.h"

#include "radiance/lebedev_quadrature.h"
#include "radiance/material_radiance.h"
#include "radiance/radiance_frame.h"
#include "radiance/radiance_projection.h"
#include "radiance/spherical_harmonics.h"
#include "splats/splat_radiance_conventions.h"
#include "splats/splat_support_grid.h"

#include <Eigen/Eigenvalues>
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <sstream>

namespace rad {
namespace {

// The hemisphere rule the per-vertex fit samples (precision 17: the upper half of the 110-point
// sphere rule, over three times the 16 coefficients of SH3; precision 23 gave the same errors in
// splat_radiance_transfer_test at twice the cost).
constexpr int kFitPrecision = 17;
// Tikhonov weight of the fit (relative, radiance_projection.h): only a guard on conditioning.
constexpr double kFitLambda = 1e-6;

// An upper bound of |Y_k| over the sphere for our real SH of bands 0..3: sqrt(2) sqrt((2l+1) / (4 pi))
// (the complex Y_l^m are bounded by sqrt((2l+1) / (4 pi)); the real ones are sqrt(2) times a real or
// imaginary part). Only used to prove that a splat's colour never needs the clamp at 0.
const double kShBound[16] = {0.28209479177387814,
                             0.690988298942671, 0.690988298942671, 0.690988298942671,
                             0.892062058076386, 0.892062058076386, 0.892062058076386, 0.892062058076386,
                             0.892062058076386,
                             1.055502061411188, 1.055502061411188, 1.055502061411188, 1.055502061411188,
                             1.055502061411188, 1.055502061411188, 1.055502061411188};

// A splat kept for the transfer, in the form the per-vertex loop needs.
struct KeptSplat {
    std::uint32_t index;        // in GaussianSplats
    Eigen::Vector3d centre;
    Eigen::Matrix3d axes;       // columns: the covariance's eigenvectors
    Eigen::Vector3d variances;  // along them
    double opacity;
};

void checkInput(const std::vector<float>& positions, const std::vector<float>& normals,
                const std::vector<std::uint32_t>& faces, const GaussianSplats& splats) {
    if (positions.empty() || positions.size() % 3 != 0)
        throw std::invalid_argument("the mesh has no vertices (or a broken position array)");
    if (normals.size() != positions.size()) throw std::invalid_argument("the mesh's normals do not match its vertices");
    if (faces.size() % 3 != 0) throw std::invalid_argument("the face array is not whole triangles");
    const std::size_t n = positions.size() / 3;
    for (std::uint32_t f : faces)
        if (f >= n) throw std::invalid_argument("a face refers to a vertex that does not exist");
    for (std::size_t i = 0; i < positions.size(); ++i)
        if (!std::isfinite(positions[i]) || !std::isfinite(normals[i]))
            throw std::invalid_argument("vertex " + std::to_string(i / 3) + " has a position or normal that is not finite");
    const int k = splats.coefficientsPerChannel();
    if (splats.shDegree < 0 || splats.shDegree > kMaxSplatShDegree || splats.count() == 0 ||
        splats.positions.size() != 3 * splats.count() || splats.sh.size() != 3 * std::size_t(k) * splats.count() ||
        splats.logScale.size() != 3 * splats.count() || splats.rotation.size() != 4 * splats.count())
        throw std::invalid_argument("inconsistent splat arrays");
}

// The splats that can matter, with their support boxes for the grid.
std::vector<KeptSplat> keepSplats(const GaussianSplats& splats, const Eigen::AlignedBox3d& meshBox, double diagonal,
                                  double hMax, const SplatTransferOptions& options, std::vector<SupportBox>& boxes,
                                  SplatTransferResult& result) {
    std::vector<KeptSplat> kept;
    const double sizeLimit = options.maxSplatSize * diagonal;
    for (std::size_t i = 0; i < splats.count(); ++i) {
        const float* logScale = splats.logScale.data() + 3 * i;
        const double largest = std::exp(double(*std::max_element(logScale, logScale + 3)));
        if (!(largest <= sizeLimit)) {
            ++result.splatsTooLarge;
            continue;
        }
        KeptSplat s;
        s.index = static_cast<std::uint32_t>(i);
        s.centre = Eigen::Vector3d(splats.positions[3 * i], splats.positions[3 * i + 1], splats.positions[3 * i + 2]);
        const Eigen::Matrix3d covariance = splatCovariance(logScale, splats.rotation.data() + 4 * i);
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
        s.axes = eigen.eigenvectors();
        s.variances = eigen.eigenvalues().cwiseMax(0.0);
        s.opacity = splatOpacity(splats.opacityLogit[i]);
        // The support {m <= k} with the widest footprint of the mesh, as an axis-aligned box.
        const Eigen::Vector3d half =
            options.supportSigmas * (covariance.diagonal().array().max(0.0) + hMax * hMax).sqrt().matrix();
        SupportBox box{s.centre - half, s.centre + half};
        if (!meshBox.intersects(Eigen::AlignedBox3d(box.lo, box.hi))) {
            ++result.splatsFar;
            continue;
        }
        kept.push_back(s);
        boxes.push_back(box);
    }
    return kept;
}

// The mesh's extent and the footprint h of each vertex.
struct MeshScale {
    Eigen::AlignedBox3d box;
    double diagonal = 0.0;
    std::vector<double> footprint;
    double hMax = 0.0;
};

MeshScale measureMesh(const std::vector<float>& positions, const std::vector<std::uint32_t>& faces) {
    MeshScale scale;
    const std::size_t n = positions.size() / 3;
    for (std::size_t v = 0; v < n; ++v)
        scale.box.extend(Eigen::Vector3d(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]));
    scale.diagonal = std::max(scale.box.diagonal().norm(), 1e-12);
    scale.footprint = vertexFootprints(positions, faces);
    scale.hMax = *std::max_element(scale.footprint.begin(), scale.footprint.end());
    return scale;
}

// What every vertex of the transfer reads.
struct VertexTransferInputs {
    const std::vector<float>& positions;
    const std::vector<float>& normals;
    const std::vector<double>& footprint;
    const GaussianSplats& splats;
    const std::vector<KeptSplat>& kept;
    const SplatSupportGrid& grid;
    const SplatTransferOptions& options;
    const HemisphereQuadrature& rule;
    const BasisSpec& basis;
    int degree, k;  // the splats' SH degree and coefficients per channel
};

// One thread's working arrays, reused from vertex to vertex.
struct VertexScratch {
    VertexScratch(int k, std::size_t samplePoints)
        : blended(3 * k), samples(samplePoints), basisValues(k), fitted(3 * k) {}
    std::vector<std::uint32_t> near;
    std::vector<double> weights, clamped, clampedWeights, blended;
    double blendedOffset = 0.0;
    std::vector<RadianceSample> samples;
    std::vector<double> basisValues, fitted;
};

// The kept splats near vertex v (within the support, h-widened) and in front of it, with their
// weights (opacity times the Gaussian), into scratch.near and scratch.weights; returns the sum.
double gatherNearSplats(const VertexTransferInputs& in, std::size_t v, const Eigen::Vector3d& p, const Frame& frame,
                        VertexScratch& scratch) {
    const double h2 = in.footprint[v] * in.footprint[v];
    scratch.near.clear();
    scratch.weights.clear();
    in.grid.forEachContaining(p, [&](std::uint32_t j) {
        const KeptSplat& s = in.kept[j];
        const Eigen::Vector3d d = p - s.centre;
        if ((-d).dot(frame.n) < -in.options.frontTolerance * in.footprint[v]) return;
        const Eigen::Vector3d local = s.axes.transpose() * d;
        const double m2 = (local.array().square() / (s.variances.array() + h2)).sum();
        if (m2 > in.options.supportSigmas * in.options.supportSigmas) return;
        const double w = s.opacity * std::exp(-0.5 * m2);
        if (!(w > 0.0)) return;
        scratch.near.push_back(j);
        scratch.weights.push_back(w);
    });
    double total = 0.0;
    for (double w : scratch.weights) total += w;
    return total;
}

// The near splats' coefficients as functions of our viewer direction. A splat whose colour cannot
// go below 0 in any direction (DC part minus a bound of the other bands) is never clamped, so its
// weighted coefficients are summed once (scratch.blended); only the others are evaluated, and
// clamped, one by one at every direction (scratch.clamped). Both give the same C(w). Marks the
// near splats as used.
void blendNearSplats(const VertexTransferInputs& in, VertexScratch& scratch, std::atomic<unsigned char>* used) {
    const int k = in.k;
    std::fill(scratch.blended.begin(), scratch.blended.end(), 0.0);
    scratch.blendedOffset = 0.0;
    scratch.clamped.clear();
    scratch.clampedWeights.clear();
    for (std::size_t i = 0; i < scratch.near.size(); ++i) {
        used[scratch.near[i]].store(1, std::memory_order_relaxed);
        const float* sh = in.splats.sh.data() + std::size_t(in.kept[scratch.near[i]].index) * 3 * k;
        double converted[3 * 16];
        bool neverNegative = true;
        for (int c = 0; c < 3; ++c) {
            toViewerShCoefficients(in.degree, sh + c * k, converted + c * k);
            double bound = 0.0;
            for (int j = 1; j < k; ++j) bound += std::fabs(converted[c * k + j]) * kShBound[j];
            if (converted[c * k] * kSplatShC0 + kSplatColorOffset - bound < 0.0) neverNegative = false;
        }
        if (neverNegative) {
            for (int j = 0; j < 3 * k; ++j) scratch.blended[j] += scratch.weights[i] * converted[j];
            scratch.blendedOffset += scratch.weights[i] * kSplatColorOffset;
        } else {
            scratch.clamped.insert(scratch.clamped.end(), converted, converted + 3 * k);
            scratch.clampedWeights.push_back(scratch.weights[i]);
        }
    }
}

// The blended, decoded (linear) colour at every hemisphere point of the rule, into scratch.samples.
void sampleBlendedColor(const VertexTransferInputs& in, const Frame& frame, double total, VertexScratch& scratch) {
    const int k = in.k;
    for (std::size_t q = 0; q < in.rule.size(); ++q) {
        const Eigen::Vector3d w = frame.toWorld(Eigen::Vector3d(in.rule.x[q], in.rule.y[q], in.rule.z[q]));
        evaluateSphericalHarmonics(in.degree, w.x(), w.y(), w.z(), scratch.basisValues.data());
        Eigen::Vector3d display = Eigen::Vector3d::Constant(scratch.blendedOffset);
        for (int c = 0; c < 3; ++c)
            for (int j = 0; j < k; ++j) display[c] += scratch.blended[c * k + j] * scratch.basisValues[j];
        for (std::size_t i = 0; i < scratch.clampedWeights.size(); ++i)
            for (int c = 0; c < 3; ++c) {
                const double* a = scratch.clamped.data() + (i * 3 + c) * k;
                double sum = kSplatColorOffset;
                for (int j = 0; j < k; ++j) sum += a[j] * scratch.basisValues[j];
                display[c] += scratch.clampedWeights[i] * std::max(0.0, sum);
            }
        display /= total;
        scratch.samples[q].direction = w;
        scratch.samples[q].value = Eigen::Vector3d(displayToLinear(display[0]), displayToLinear(display[1]),
                                                   displayToLinear(display[2]));
        scratch.samples[q].weight = in.rule.w[q];
    }
}

// Vertex v's frame, and its radiance: the near splats in front, their blended colour over the
// hemisphere, the least-squares SH fit. False when no splat is near (or, with non-finite colours
// only, when the fit fails): the vertex is without splats.
bool transferToVertex(const VertexTransferInputs& in, std::size_t v, VertexScratch& scratch,
                      std::atomic<unsigned char>* used, SplatTransferResult& result) {
    const Eigen::Vector3d p(in.positions[3 * v], in.positions[3 * v + 1], in.positions[3 * v + 2]);
    const Frame frame =
        frameFromNormal(Eigen::Vector3d(in.normals[3 * v], in.normals[3 * v + 1], in.normals[3 * v + 2]));
    storeFrame(frame, result.field.frame(v));
    const double total = gatherNearSplats(in, v, p, frame, scratch);
    if (scratch.near.empty() || !(total > 0.0)) return false;
    blendNearSplats(in, scratch, used);
    sampleBlendedColor(in, frame, total, scratch);
    FitOptions fit;
    fit.lambda = kFitLambda;
    if (!fitRadiance(in.basis, frame, scratch.samples, fit, scratch.fitted.data())) return false;
    float* out = result.field.vertexCoefficients(v);
    for (int j = 0; j < 3 * in.k; ++j) out[j] = static_cast<float>(scratch.fitted[j]);
    result.splatCount[v] = static_cast<std::uint32_t>(scratch.near.size());
    result.weightSum[v] = static_cast<float>(total);
    return true;
}

// Every vertex (OpenMP, dynamic), with progress and stop requests; counts the vertices without
// splats and the splats used into `result`.
void transferToVertices(const VertexTransferInputs& in, const ProgressCallback& progress,
                        SplatTransferResult& result) {
    const std::size_t n = in.positions.size() / 3;
    std::unique_ptr<std::atomic<unsigned char>[]> used(new std::atomic<unsigned char>[in.kept.size() + 1]());
    std::atomic<std::size_t> without{0};
    LoopProgress loop(progress, "Transferring splat radiance", n);
    const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel
    {
        VertexScratch scratch(in.k, in.rule.size());
#pragma omp for schedule(dynamic, 64)
        for (std::ptrdiff_t vi = 0; vi < count; ++vi) {
            if (loop.stopRequested()) continue;
            if (!transferToVertex(in, static_cast<std::size_t>(vi), scratch, used.get(), result)) ++without;
            loop.itemDone(omp_get_thread_num() == 0);
        }
    }
    loop.finish();
    result.verticesWithoutSplats = without.load();
    for (std::size_t j = 0; j < in.kept.size(); ++j) result.splatsUsed += used[j].load();
}

// Nothing near the mesh is a refusal, not a black mesh.
void refuseWhenNoVertexHasSplats(const SplatTransferResult& result, std::size_t n, const GaussianSplats& splats,
                                 const SplatTransferOptions& options) {
    if (result.verticesWithoutSplats != n) return;
    std::ostringstream why;
    why << "no vertex of the mesh has a splat near it and in front of it (" << splats.count() << " splats: "
        << result.splatsTooLarge << " larger than the size limit, " << result.splatsFar
        << " far from the mesh's bounding box, the others not within " << options.supportSigmas
        << " standard deviations of any vertex); check that the mesh and the splats are in the same coordinate "
           "frame and scale (align the mesh to the splat scene first), and that the normals point outward";
    throw SplatTransferError(why.str());
}

}  // namespace

std::vector<double> vertexFootprints(const std::vector<float>& positions, const std::vector<std::uint32_t>& faces) {
    const std::size_t n = positions.size() / 3;
    std::vector<double> lengthSum(n, 0.0);
    std::vector<std::uint32_t> edgeCount(n, 0);
    auto point = [&](std::uint32_t v) {
        return Eigen::Vector3d(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
    };
    // Each triangle edge counted from both of its ends (an interior edge is seen twice, by its two
    // triangles: the mean is unchanged).
    for (std::size_t f = 0; f + 2 < faces.size(); f += 3)
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t a = faces[f + e], b = faces[f + (e + 1) % 3];
            const double length = (point(a) - point(b)).norm();
            lengthSum[a] += length;
            lengthSum[b] += length;
            ++edgeCount[a];
            ++edgeCount[b];
        }
    std::vector<double> h(n, 0.0);
    double sum = 0.0;
    std::size_t counted = 0;
    for (std::size_t v = 0; v < n; ++v)
        if (edgeCount[v] > 0) {
            h[v] = 0.5 * lengthSum[v] / edgeCount[v];
            sum += h[v];
            ++counted;
        }
    double fallback = counted ? sum / counted : 0.0;
    if (!(fallback > 0.0)) {
        Eigen::AlignedBox3d box;
        for (std::size_t v = 0; v < n; ++v) box.extend(point(static_cast<std::uint32_t>(v)));
        fallback = 1e-3 * std::max(box.diagonal().norm(), 1e-12);
    }
    for (std::size_t v = 0; v < n; ++v)
        if (edgeCount[v] == 0 || !(h[v] > 0.0)) h[v] = fallback;
    return h;
}

SplatTransferResult transferSplatRadiance(const std::vector<float>& positions, const std::vector<float>& normals,
                                          const std::vector<std::uint32_t>& faces, const GaussianSplats& splats,
                                          const SplatTransferOptions& options, const ProgressCallback& progress) {
    checkInput(positions, normals, faces, splats);
    if (!(options.supportSigmas > 0.0) || !(options.frontTolerance >= 0.0) || !(options.maxSplatSize > 0.0))
        throw std::invalid_argument("support, front tolerance and size limit must be positive");
    const std::size_t n = positions.size() / 3;
    const MeshScale scale = measureMesh(positions, faces);
    SplatTransferResult result;
    for (double h : scale.footprint) result.meanFootprint += h / double(n);

    reportProgress(progress, 0.0, "Indexing splats");
    std::vector<SupportBox> boxes;
    const std::vector<KeptSplat> kept = keepSplats(splats, scale.box, scale.diagonal, scale.hMax, options, boxes, result);
    const SplatSupportGrid grid(boxes);

    const BasisSpec basis{BasisKind::SphericalHarmonics, splats.shDegree};
    result.field = RadianceField(basis, n, false);
    result.meanColor.assign(3 * n, 0.0f);
    result.splatCount.assign(n, 0);
    result.weightSum.assign(n, 0.0f);
    const HemisphereQuadrature rule = hemisphereRule(lebedevPointCountForPrecision(kFitPrecision));
    const VertexTransferInputs inputs{positions, normals, scale.footprint, splats, kept, grid, options, rule, basis,
                                      splats.shDegree, splats.coefficientsPerChannel()};
    transferToVertices(inputs, progress, result);

    refuseWhenNoVertexHasSplats(result, n, splats, options);
    // The vertex colours' source: the RF's exact mean over its hemisphere.
    meanHemisphereColors(result.field, result.meanColor.data());
    return result;
}

}  // namespace rad
