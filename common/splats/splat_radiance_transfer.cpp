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

// Step 3: the splats that can matter, with their support boxes for the grid.
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
    // 1. Input and the mesh's scale.
    checkInput(positions, normals, faces, splats);
    if (!(options.supportSigmas > 0.0) || !(options.frontTolerance >= 0.0) || !(options.maxSplatSize > 0.0))
        throw std::invalid_argument("support, front tolerance and size limit must be positive");
    const std::size_t n = positions.size() / 3;
    Eigen::AlignedBox3d meshBox;
    for (std::size_t v = 0; v < n; ++v)
        meshBox.extend(Eigen::Vector3d(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]));
    const double diagonal = std::max(meshBox.diagonal().norm(), 1e-12);
    const std::vector<double> footprint = vertexFootprints(positions, faces);
    const double hMax = *std::max_element(footprint.begin(), footprint.end());

    SplatTransferResult result;
    for (double h : footprint) result.meanFootprint += h / double(n);

    // 2. The splats that can reach the mesh, indexed by their support.
    reportProgress(progress, 0.0, "Indexing splats");
    std::vector<SupportBox> boxes;
    const std::vector<KeptSplat> kept = keepSplats(splats, meshBox, diagonal, hMax, options, boxes, result);
    const SplatSupportGrid grid(boxes);

    // 3. Per vertex: the near splats in front, their blended colour over the hemisphere, the fit.
    const int degree = splats.shDegree;
    const int k = splats.coefficientsPerChannel();
    const BasisSpec basis{BasisKind::SphericalHarmonics, degree};
    result.field = RadianceField(basis, n, false);
    result.meanColor.assign(3 * n, 0.0f);
    result.splatCount.assign(n, 0);
    result.weightSum.assign(n, 0.0f);
    const HemisphereQuadrature rule = hemisphereRule(lebedevPointCountForPrecision(kFitPrecision));
    std::unique_ptr<std::atomic<unsigned char>[]> used(new std::atomic<unsigned char>[kept.size() + 1]());
    std::atomic<std::size_t> without{0};
    LoopProgress loop(progress, "Transferring splat radiance", n);
    const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel
    {
        std::vector<std::uint32_t> near;
        std::vector<double> weights, clamped, clampedWeights, blended(3 * k);
        std::vector<RadianceSample> samples(rule.size());
        std::vector<double> basisValues(k), fitted(3 * k);
#pragma omp for schedule(dynamic, 64)
        for (std::ptrdiff_t vi = 0; vi < count; ++vi) {
            if (loop.stopRequested()) continue;
            const std::size_t v = static_cast<std::size_t>(vi);
            const Eigen::Vector3d p(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
            const Frame frame = frameFromNormal(Eigen::Vector3d(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]));
            storeFrame(frame, result.field.frame(v));
            const double h2 = footprint[v] * footprint[v];
            // 3a. Near and in front, with their weights.
            near.clear();
            weights.clear();
            grid.forEachContaining(p, [&](std::uint32_t j) {
                const KeptSplat& s = kept[j];
                const Eigen::Vector3d d = p - s.centre;
                if ((-d).dot(frame.n) < -options.frontTolerance * footprint[v]) return;
                const Eigen::Vector3d local = s.axes.transpose() * d;
                const double m2 = (local.array().square() / (s.variances.array() + h2)).sum();
                if (m2 > options.supportSigmas * options.supportSigmas) return;
                const double w = s.opacity * std::exp(-0.5 * m2);
                if (!(w > 0.0)) return;
                near.push_back(j);
                weights.push_back(w);
            });
            double total = 0.0;
            for (double w : weights) total += w;
            if (near.empty() || !(total > 0.0)) {
                ++without;
                loop.itemDone(omp_get_thread_num() == 0);
                continue;
            }
            // 3b. The near splats' coefficients as functions of our viewer direction. A splat whose colour
            // cannot go below 0 in any direction (DC part minus a bound of the other bands) is never
            // clamped, so its weighted coefficients are summed once; only the others are evaluated,
            // and clamped, one by one at every direction. Both give the same C(w).
            std::fill(blended.begin(), blended.end(), 0.0);
            double blendedOffset = 0.0;
            clamped.clear();
            clampedWeights.clear();
            for (std::size_t i = 0; i < near.size(); ++i) {
                used[near[i]].store(1, std::memory_order_relaxed);
                const float* sh = splats.sh.data() + std::size_t(kept[near[i]].index) * 3 * k;
                double converted[3 * 16];
                bool neverNegative = true;
                for (int c = 0; c < 3; ++c) {
                    toViewerShCoefficients(degree, sh + c * k, converted + c * k);
                    double bound = 0.0;
                    for (int j = 1; j < k; ++j) bound += std::fabs(converted[c * k + j]) * kShBound[j];
                    if (converted[c * k] * kSplatShC0 + kSplatColorOffset - bound < 0.0) neverNegative = false;
                }
                if (neverNegative) {
                    for (int j = 0; j < 3 * k; ++j) blended[j] += weights[i] * converted[j];
                    blendedOffset += weights[i] * kSplatColorOffset;
                } else {
                    clamped.insert(clamped.end(), converted, converted + 3 * k);
                    clampedWeights.push_back(weights[i]);
                }
            }
            // 3c. The blended, decoded colour at every hemisphere point.
            for (std::size_t q = 0; q < rule.size(); ++q) {
                const Eigen::Vector3d w = frame.toWorld(Eigen::Vector3d(rule.x[q], rule.y[q], rule.z[q]));
                evaluateSphericalHarmonics(degree, w.x(), w.y(), w.z(), basisValues.data());
                Eigen::Vector3d display = Eigen::Vector3d::Constant(blendedOffset);
                for (int c = 0; c < 3; ++c)
                    for (int j = 0; j < k; ++j) display[c] += blended[c * k + j] * basisValues[j];
                for (std::size_t i = 0; i < clampedWeights.size(); ++i)
                    for (int c = 0; c < 3; ++c) {
                        const double* a = clamped.data() + (i * 3 + c) * k;
                        double sum = kSplatColorOffset;
                        for (int j = 0; j < k; ++j) sum += a[j] * basisValues[j];
                        display[c] += clampedWeights[i] * std::max(0.0, sum);
                    }
                display /= total;
                samples[q].direction = w;
                samples[q].value = Eigen::Vector3d(displayToLinear(display[0]), displayToLinear(display[1]),
                                                   displayToLinear(display[2]));
                samples[q].weight = rule.w[q];
            }
            // 3d. The least-squares SH over the hemisphere.
            FitOptions fit;
            fit.lambda = kFitLambda;
            if (!fitRadiance(basis, frame, samples, fit, fitted.data())) {
                // Only non-finite colours can fail a fit of well-spread samples: counted as without.
                ++without;
                loop.itemDone(omp_get_thread_num() == 0);
                continue;
            }
            float* out = result.field.vertexCoefficients(v);
            for (int j = 0; j < 3 * k; ++j) out[j] = static_cast<float>(fitted[j]);
            result.splatCount[v] = static_cast<std::uint32_t>(near.size());
            result.weightSum[v] = static_cast<float>(total);
            loop.itemDone(omp_get_thread_num() == 0);
        }
    }
    loop.finish();
    result.verticesWithoutSplats = without.load();
    for (std::size_t j = 0; j < kept.size(); ++j) result.splatsUsed += used[j].load();

    // 4. Nothing near the mesh is a refusal, not a black mesh.
    if (result.verticesWithoutSplats == n) {
        std::ostringstream why;
        why << "no vertex of the mesh has a splat near it and in front of it (" << splats.count() << " splats: "
            << result.splatsTooLarge << " larger than the size limit, " << result.splatsFar
            << " far from the mesh's bounding box, the others not within " << options.supportSigmas
            << " standard deviations of any vertex); check that the mesh and the splats are in the same coordinate "
               "frame and scale (align the mesh to the splat scene first), and that the normals point outward";
        throw SplatTransferError(why.str());
    }
    // 5. The vertex colours' source: the RF's exact mean over its hemisphere.
    meanHemisphereColors(result.field, result.meanColor.data());
    return result;
}

}  // namespace rad
