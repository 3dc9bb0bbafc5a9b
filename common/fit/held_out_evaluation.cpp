#include "fit/held_out_evaluation.h"

#include "radiance/radiance_evaluation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <omp.h>
#include <stdexcept>

namespace rad {

double srgbLevel(double linear) {
    const double x = std::min(1.0, std::max(0.0, linear));
    const double s = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
    return 255.0 * s;
}

namespace {
double srgbLevelToLinear(double level) {
    const double c = level / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}
constexpr int kPredictions = 3;  // fitted, constant, projection

// The plain average, in sRGB levels, of a vertex's `count` training samples (MeshLab's projection
// blends the photographs' values so), stored as a linear value; left NaN when there are none.
void averageTrainingColour(const DirectionalSample* samples, std::size_t count, double* linear) {
    if (count == 0) return;
    double sum[3] = {0.0, 0.0, 0.0};
    for (std::size_t j = 0; j < count; ++j)
        for (int c = 0; c < 3; ++c) sum[c] += srgbLevel(samples[j].rgb[c]) / static_cast<double>(count);
    for (int c = 0; c < 3; ++c) linear[c] = srgbLevelToLinear(sum[c]);
}
}  // namespace

HeldOutEvaluation evaluateHeldOutViews(const TriangleMesh& mesh, const RadianceField& field,
                                       const std::vector<float>& meanColor,
                                       const std::vector<CalibratedView>& training,
                                       const std::vector<CalibratedView>& heldOut,
                                       const ViewSamplingOptions& sampling) {
    const std::size_t n = mesh.vertexCount();
    if (field.vertexCount() != n || meanColor.size() != 3 * n)
        throw std::invalid_argument("held-out evaluation: the radiance field or the mean colours do not match the mesh");
    HeldOutEvaluation out;
    out.views.assign(heldOut.size(), HeldOutViewError());
    if (heldOut.empty() || training.empty() || n == 0) return out;
    const ViewSampler trainSampler(mesh, training, sampling);
    const ViewSampler testSampler(mesh, heldOut, sampling);
    const std::size_t H = heldOut.size();
    // Per held-out view, prediction and channel (index (view * 3 + prediction) * 3 + channel):
    // pass 0: sums of p y and p^2 in linear values (the best gain g = sum p y / sum p^2);
    // pass 1: squared sRGB-level errors as is and after the gain.
    const std::size_t slots = H * kPredictions * 3;
    std::vector<double> py(slots, 0.0), pp(slots, 0.0), gain(slots, 1.0), raw(slots, 0.0), matched(slots, 0.0);
    std::vector<std::size_t> counts(H, 0);
    // The training views' plain average at each vertex (MeshLab's projection, linear), found in the
    // first pass and kept for the second; NaN where no training view saw the vertex.
    std::vector<double> projectionColour(3 * n, std::numeric_limits<double>::quiet_NaN());
    // Blocks of neighbouring vertices: their rays toward one camera are cast as one packet.
    constexpr int kBlock = ViewSampler::kBlock;
    const std::ptrdiff_t blocks = static_cast<std::ptrdiff_t>((n + kBlock - 1) / kBlock);
    for (int pass = 0; pass < 2; ++pass) {
#pragma omp parallel
        {
            std::vector<DirectionalSample> train(kBlock * training.size()), test(kBlock * H);
            std::vector<int> testView(kBlock * H);
            std::size_t testCounts[kBlock], trainCounts[kBlock];
            std::vector<double> localA(slots, 0.0), localB(slots, 0.0);
            std::vector<std::size_t> localCounts(H, 0);
#pragma omp for schedule(dynamic, 16) nowait
            for (std::ptrdiff_t block = 0; block < blocks; ++block) {
                const std::size_t first = static_cast<std::size_t>(block) * kBlock;
                const int size = static_cast<int>(std::min<std::size_t>(kBlock, n - first));
                testSampler.sampleVertexBlock(first, size, test.data(), testCounts, nullptr, testView.data());
                if (pass == 0) {
                    trainSampler.sampleVertexBlock(first, size, train.data(), trainCounts);
                    for (int k = 0; k < size; ++k)
                        averageTrainingColour(train.data() + std::size_t(k) * training.size(), trainCounts[k],
                                              projectionColour.data() + 3 * (first + std::size_t(k)));
                }
                for (int k = 0; k < size; ++k) {
                    const std::size_t v = first + static_cast<std::size_t>(k);
                    const double* projection = projectionColour.data() + 3 * v;
                    // No training view saw it: nothing but a guess to compare.
                    if (testCounts[k] == 0 || std::isnan(projection[0])) continue;
                    const DirectionalSample* mine = test.data() + std::size_t(k) * H;
                    const int* views = testView.data() + std::size_t(k) * H;
                    for (std::size_t j = 0; j < testCounts[k]; ++j) {
                        const DirectionalSample& s = mine[j];
                        const Eigen::Vector3d w(s.direction[0], s.direction[1], s.direction[2]);
                        const Eigen::Vector3d fitted = evaluateRadiance(field, v, w);
                        const std::size_t view = static_cast<std::size_t>(views[j]);
                        for (int c = 0; c < 3; ++c) {
                            const double p[kPredictions] = {std::max(0.0, fitted[c]), double(meanColor[3 * v + c]),
                                                            projection[c]};
                            const double y = s.rgb[c], seen = srgbLevel(y);
                            for (int q = 0; q < kPredictions; ++q) {
                                const std::size_t slot = (view * kPredictions + q) * 3 + c;
                                if (pass == 0) {
                                    localA[slot] += p[q] * y;
                                    localB[slot] += p[q] * p[q];
                                } else {
                                    const double e = srgbLevel(p[q]) - seen, f = srgbLevel(gain[slot] * p[q]) - seen;
                                    localA[slot] += e * e;
                                    localB[slot] += f * f;
                                }
                            }
                        }
                        ++localCounts[view];
                    }
                }
            }
#pragma omp critical(held_out_evaluation_merge)
            {
                for (std::size_t i = 0; i < slots; ++i) {
                    (pass == 0 ? py : raw)[i] += localA[i];
                    (pass == 0 ? pp : matched)[i] += localB[i];
                }
                if (pass == 0)
                    for (std::size_t i = 0; i < H; ++i) counts[i] += localCounts[i];
            }
        }
        if (pass == 0)
            for (std::size_t i = 0; i < slots; ++i) gain[i] = pp[i] > 0.0 ? py[i] / pp[i] : 1.0;
    }
    double ratio = 0.0, ratioMatched = 0.0;
    auto rms = [&](const std::vector<double>& sums, std::size_t view, int k) {
        const std::size_t base = (view * kPredictions + k) * 3;
        return std::sqrt((sums[base] + sums[base + 1] + sums[base + 2]) / (3.0 * static_cast<double>(counts[view])));
    };
    for (std::size_t i = 0; i < H; ++i) {
        HeldOutViewError& e = out.views[i];
        e.vertices = counts[i];
        if (counts[i] == 0) continue;
        e.fitted = rms(raw, i, 0);
        e.constant = rms(raw, i, 1);
        e.projection = rms(raw, i, 2);
        e.fittedMatched = rms(matched, i, 0);
        e.constantMatched = rms(matched, i, 1);
        e.projectionMatched = rms(matched, i, 2);
        ++out.viewsCompared;
        out.fittedNotWorseThanConstant += e.fitted <= e.constant;
        out.fittedNotWorseThanConstantMatched += e.fittedMatched <= e.constantMatched;
        out.meanFitted += e.fitted;
        out.meanConstant += e.constant;
        out.meanProjection += e.projection;
        out.meanFittedMatched += e.fittedMatched;
        out.meanConstantMatched += e.constantMatched;
        out.meanProjectionMatched += e.projectionMatched;
        ratio += e.projection > 0.0 ? e.fitted / e.projection : 1.0;
        ratioMatched += e.projectionMatched > 0.0 ? e.fittedMatched / e.projectionMatched : 1.0;
    }
    if (out.viewsCompared > 0) {
        const double k = static_cast<double>(out.viewsCompared);
        out.meanFitted /= k;
        out.meanConstant /= k;
        out.meanProjection /= k;
        out.meanFittedMatched /= k;
        out.meanConstantMatched /= k;
        out.meanProjectionMatched /= k;
        out.meanRatioToProjection = ratio / k;
        out.meanRatioToProjectionMatched = ratioMatched / k;
    }
    return out;
}

}  // namespace rad
