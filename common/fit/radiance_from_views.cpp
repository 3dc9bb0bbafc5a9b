#include "fit/radiance_from_views.h"

#include "fit/exposure_compensation.h"
#include "fit/held_out_evaluation.h"

#include "radiance/radiance_evaluation.h"
#include "radiance/radiance_frame.h"
#include "raycast/ray_scene.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <omp.h>
#include <sstream>

namespace rad {

namespace {

const char* const kNormalsHint =
    "compute normals first, e.g. {{Compute normals for point sets}} (point clouds) or {{Re-Compute Vertex Normals}} "
    "(meshes)";

// Every check that needs no heavy work, in the order a user would fix things.
void validateInput(const TriangleMesh& mesh, const std::vector<CalibratedView>& views,
                   const RadianceFromViewsOptions& options) {
    if (mesh.vertexCount() == 0) throw FitError("The mesh has no vertices: open or select a mesh with vertices first.");
    const std::string meshProblem = mesh.validate();
    if (!meshProblem.empty()) {
        std::ostringstream why;
        why << "The mesh cannot be used: " << meshProblem << ".";
        if (meshProblem.find("non-finite coordinate") != std::string::npos)
            why << " Remove or repair such vertices first (e.g. {{Remove Unreferenced Vertices}} after fixing the faces).";
        else if (meshProblem.find("normal") != std::string::npos)
            why << " Radiance functions live on the hemisphere around the vertex normal: " << kNormalsHint << ".";
        else if (meshProblem.find("refers to vertex") != std::string::npos)
            why << " Repair the mesh first (e.g. {{Remove Zero Area Faces}}, {{Remove Unreferenced Vertices}}), or "
                   "reload it.";
        throw FitError(why.str());
    }
    if (!mesh.hasNormals())
        throw FitError(std::string("The mesh has no per-vertex normals; radiance functions live on the hemisphere "
                                   "around the vertex normal: ") + kNormalsHint + ".");
    std::size_t badNormals = 0, firstBad = 0;
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
        const float* n = mesh.normals.data() + 3 * v;
        const double len2 = double(n[0]) * n[0] + double(n[1]) * n[1] + double(n[2]) * n[2];
        if (!std::isfinite(len2) || len2 < 1e-20) {
            if (badNormals == 0) firstBad = v;
            ++badNormals;
        }
    }
    if (badNormals > 0) {
        std::ostringstream why;
        why << badNormals << " vertices (the first is vertex " << firstBad
            << ") have a zero or non-finite normal; radiance functions live on the hemisphere around the vertex "
               "normal: "
            << kNormalsHint << ".";
        throw FitError(why.str());
    }
    if (!options.fit.basis.isValid())
        throw FitError("The basis " + options.fit.basis.name() + " is not supported: choose PB0..PB" +
                       std::to_string(kMaxPolynomialDegree) + " or SH0..SH" + std::to_string(kMaxHarmonicDegree) + ".");
    const std::string fitProblem = options.fit.validate();
    if (!fitProblem.empty()) throw FitError("Invalid fitting parameter: " + fitProblem + ".");
    const std::string samplingProblem = options.sampling.validate();
    if (!samplingProblem.empty()) throw FitError("Invalid sampling parameter: " + samplingProblem + ".");
    const std::string problem = options.validate();
    if (!problem.empty()) throw FitError("Invalid parameter: " + problem + ".");
    if (views.empty())
        throw FitError("There is no raster to fit from: load calibrated photographs first ({{Import Raster}}, or "
                       "open a MeshLab project .mlp / Bundler .out with cameras), aligned with this mesh.");
}

constexpr const char* kStageChecking = "checking the rasters";
constexpr const char* kStageScene = "building the ray-casting scene";
constexpr const char* kStageExposure = "estimating the rasters' exposures";
constexpr const char* kStageFitting = "sampling the rasters and fitting";
constexpr const char* kStageFilling = "filling unseen vertices";
constexpr const char* kStageDone = "done";
// Percent ranges of the stages.
constexpr int kFitStart = 3, kFitEnd = 95;
constexpr const char* kStageSampling = "sampling the rasters";

// The stages are laid out in percent of the whole call.
void reportPercent(const ProgressCallback& progress, int percent, const char* stage) {
    reportProgress(progress, percent / 100.0, stage);
}
ProgressCallback percentRange(const ProgressCallback& progress, int from, int to) {
    return progressRange(progress, from / 100.0, to / 100.0);
}

// ---- Fits from a stored sample set (FitModel Shared and Automatic) ----

struct SampleFitCounters {
    std::vector<std::size_t> perView, histogram;
    std::size_t guardRetried = 0, fallbacks = 0, totalSamples = 0, viewDependent = 0, regularised = 0;
    std::size_t validatedConstant = 0, tooFew = 0, guardConstant = 0, downweighted = 0, saturated = 0;
    std::size_t sharedKept = 0;  // Shared: vertices given d + s * lobe

    void reset(std::size_t viewCount) {
        perView.assign(viewCount, 0);
        histogram.assign(viewCount + 1, 0);
    }
    // One vertex's fit (its samples were counted per view by the caller).
    void count(const VertexFitResult& r, int minSamples) {
        if (r.sampleCount > 0) {
            ++histogram[static_cast<std::size_t>(r.sampleCount)];
            if (!r.constantFallback) ++viewDependent;
            if (!r.constantFallback && r.regularised) ++regularised;
            if (r.validatedConstant) ++validatedConstant;
            else if (r.constantFallback && r.sampleCount < minSamples) ++tooFew;
            else if (r.constantFallback) ++guardConstant;
            downweighted += static_cast<std::size_t>(r.downweighted);
        }
        guardRetried += r.guardRetries > 0 ? 1 : 0;
        fallbacks += r.constantFallback ? 1 : 0;
        totalSamples += static_cast<std::size_t>(r.sampleCount);
    }
    // Adds a thread's counters (integer sums: the merge order does not matter).
    void merge(const SampleFitCounters& o) {
        for (std::size_t i = 0; i < perView.size(); ++i) perView[i] += o.perView[i];
        for (std::size_t i = 0; i < histogram.size(); ++i) histogram[i] += o.histogram[i];
        guardRetried += o.guardRetried;
        fallbacks += o.fallbacks;
        totalSamples += o.totalSamples;
        viewDependent += o.viewDependent;
        regularised += o.regularised;
        validatedConstant += o.validatedConstant;
        tooFew += o.tooFew;
        guardConstant += o.guardConstant;
        downweighted += o.downweighted;
        saturated += o.saturated;
        sharedKept += o.sharedKept;
    }
};

// The saturation weight applied to one raw sample; returns whether it is saturated.
inline bool weighSaturation(DirectionalSample& s, const RadianceFromViewsOptions& options) {
    const bool saturated = std::max({s.rgb[0], s.rgb[1], s.rgb[2]}) >= options.saturationLevel;
    if (saturated) s.weight *= static_cast<float>(options.saturatedWeight);
    return saturated;
}

// One sample divided by its view's gains (3 values).
inline void divideByGain(DirectionalSample& s, const double* gain) {
    for (int c = 0; c < 3; ++c) s.rgb[c] = static_cast<float>(s.rgb[c] / gain[c]);
}

// One vertex's fit written into the per-vertex outputs.
inline void storeVertexFit(const VertexFitResult& r, std::size_t v, std::vector<float>& meanColor,
                           std::vector<float>& sampleCount, std::vector<float>& residual,
                           std::vector<std::uint8_t>& status) {
    for (int c = 0; c < 3; ++c) meanColor[3 * v + c] = static_cast<float>(r.meanColor[c]);
    sampleCount[v] = static_cast<float>(r.sampleCount);
    residual[v] = static_cast<float>(r.residual);
    status[v] = static_cast<std::uint8_t>(r.status);
}

// Every sample of every vertex, saturation-weighted (raw values: the gains come after), in vertex order
// (each thread gathers a contiguous block of vertices; the blocks are concatenated in order, so the
// set does not depend on the thread count).
SampleSet gatherSamples(std::size_t n, const ViewSampler& sampler,
                        const RadianceFromViewsOptions& options, const ProgressCallback& progress,
                        std::size_t& saturatedOut) {
    SampleSet set;
    set.offsets.assign(n + 1, 0);
    const int threads = std::max(1, omp_get_max_threads());
    std::vector<std::vector<DirectionalSample>> parts(threads);
    std::vector<std::vector<std::uint32_t>> partViews(threads);
    std::size_t saturated = 0;
    const ProgressCallback range = percentRange(progress, kFitStart, kFitStart + 30);
    LoopProgress loop(range, kStageSampling, n);
#pragma omp parallel num_threads(threads) reduction(+ : saturated)
    {
        const int t = omp_get_thread_num(), nt = omp_get_num_threads();
        const std::size_t begin = n * t / nt, end = n * (t + 1) / nt;
        // Blocks of neighbouring vertices: their rays toward one camera are cast as one packet.
        constexpr int kBlock = ViewSampler::kBlock;
        const std::size_t viewCount = sampler.viewCount();
        std::vector<DirectionalSample> buffer(kBlock * viewCount);
        std::vector<int> viewOf(kBlock * viewCount);
        std::size_t counts[kBlock];
        for (std::size_t block = begin; block < end && !loop.stopRequested(); block += kBlock) {
            const int count = static_cast<int>(std::min<std::size_t>(kBlock, end - block));
            loop.runItem(t == 0, [&] {
                sampler.sampleVertexBlock(block, count, buffer.data(), counts, nullptr, viewOf.data());
                for (int k = 0; k < count; ++k) {
                    for (std::size_t j = 0; j < counts[k]; ++j) {
                        DirectionalSample s = buffer[k * viewCount + j];
                        saturated += weighSaturation(s, options) ? 1 : 0;
                        parts[t].push_back(s);
                        partViews[t].push_back(static_cast<std::uint32_t>(viewOf[k * viewCount + j]));
                    }
                    set.offsets[block + k + 1] = counts[k];
                }
            }, static_cast<std::size_t>(count));
        }
    }
    loop.finish();
    for (std::size_t v = 0; v < n; ++v) set.offsets[v + 1] += set.offsets[v];
    set.samples.reserve(set.offsets[n]);
    set.view.reserve(set.offsets[n]);
    for (int t = 0; t < threads; ++t) {
        set.samples.insert(set.samples.end(), parts[t].begin(), parts[t].end());
        set.view.insert(set.view.end(), partViews[t].begin(), partViews[t].end());
        std::vector<DirectionalSample>().swap(parts[t]);
        std::vector<std::uint32_t>().swap(partViews[t]);
    }
    saturatedOut = saturated;
    return set;
}

RadianceField framedField(const TriangleMesh& mesh, const RobustFitOptions& fit) {
    const std::size_t n = mesh.vertexCount();
    RadianceField field(fit.basis, n, fit.storeReflected);
    const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t iv = 0; iv < count; ++iv) {
        const float* nv = mesh.normals.data() + 3 * iv;
        storeFrame(frameFromNormal(Eigen::Vector3d(nv[0], nv[1], nv[2])), field.frame(static_cast<std::size_t>(iv)));
    }
    return field;
}

// The per-vertex robust fit of every vertex from the set (samples with use[i] only, when use is given).
void perVertexFromSet(const RobustRadianceFitter& fitter, const SampleSet& set, const std::uint8_t* use,
                      std::size_t viewCount, RadianceField& field, std::vector<float>& meanColor,
                      std::vector<float>& sampleCount, std::vector<float>& residual, std::vector<std::uint8_t>& status,
                      SampleFitCounters& counters, const ProgressCallback& progress, int percentFrom, int percentTo,
                      const std::uint8_t* skipVertex = nullptr) {
    const std::size_t n = set.vertexCount();
    counters.reset(viewCount);
    const int minSamples = fitter.options().minSamples;
    const ProgressCallback range = percentRange(progress, percentFrom, percentTo);
    LoopProgress loop(range, kStageFitting, n);
    const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel
    {
        std::vector<DirectionalSample> samples(viewCount);
        FitScratch scratch = fitter.makeScratch();
        SampleFitCounters local;
        local.reset(viewCount);
        const bool reporter = omp_get_thread_num() == 0;
#pragma omp for schedule(dynamic, 256) nowait
        for (std::ptrdiff_t iv = 0; iv < count; ++iv)
            loop.runItem(reporter, [&] {
                const std::size_t v = static_cast<std::size_t>(iv);
                if (skipVertex && skipVertex[v]) return;
                std::size_t m = 0;
                for (std::size_t i = set.offsets[v]; i < set.offsets[v + 1]; ++i) {
                    if (use && !use[i]) continue;
                    samples[m++] = set.samples[i];
                    ++local.perView[set.view[i]];
                }
                const Frame frame = frameFromStored(field.frame(v));
                const VertexFitResult r =
                    fitter.fit(frame, samples.data(), m, scratch, field.vertexCoefficients(v));
                local.count(r, minSamples);
                storeVertexFit(r, v, meanColor, sampleCount, residual, status);
            });
#pragma omp critical(radiance_from_views_set_merge)
        counters.merge(local);
    }
    loop.finish();
}

// Optional links of a shared fit to the automatic choice's: the model it starts from (warmStart),
// and where the fitted model and the vertices that kept d + s * lobe go.
struct SharedFitLinks {
    const SharedModel* warmStart = nullptr;
    SharedModel* model = nullptr;
    std::vector<std::uint8_t>* keptShared = nullptr;
    bool choiceCandidate = false;  // the automatic choice's candidate: SharedFitOptions::choiceIterations
    double* lightDistance = nullptr;  // the fitted model's (SharedModel::lightDistance)
};

// The shared fit of fit/shared_radiance_fit.h, written into field / meanColor / ... (samples with use[i]).
void sharedFromSet(const TriangleMesh& mesh, const VertexAdjacency& adj, const SampleSet& set, const std::uint8_t* use,
                   std::size_t viewCount, const RadianceFromViewsOptions& options, RadianceField& field,
                   std::vector<float>& meanColor, std::vector<float>& sampleCount, std::vector<float>& residual,
                   std::vector<std::uint8_t>& status, SampleFitCounters& counters, const ProgressCallback& progress,
                   int percentFrom, int percentTo, const RobustRadianceFitter* rejectedFitter,
                   const SharedFitLinks& links = {}) {
    const std::size_t n = set.vertexCount();
    std::vector<float> normals(3 * n);
    for (std::size_t v = 0; v < n; ++v) {
        const Frame f = frameFromStored(field.frame(v));
        for (int c = 0; c < 3; ++c) normals[3 * v + c] = static_cast<float>(f.n[c]);
    }
    const int mid = (percentFrom + percentTo) / 2;
    SharedFitOptions shared = options.shared;
    if (options.fit.robustIterations == 0) shared.robustIterations = 0;  // "robust" off: no Huber weights anywhere
    if (links.choiceCandidate) {
        shared.iterations = shared.choiceIterations;
        shared.robustIterations = std::min(shared.robustIterations, shared.iterations);
    }
    SharedModel model = fitSharedModel(normals, adj.offsets, adj.neighbours, set, use, shared,
                                       percentRange(progress, percentFrom, mid), links.warmStart, &mesh.positions);
    std::vector<std::uint8_t> kept;
    const int convertTo = rejectedFitter ? (mid + percentTo) / 2 : percentTo;
    const SharedConversionStats stats = writeSharedRadiance(model, set, use, adj.offsets, adj.neighbours, options.fit,
                                                            shared, field, meanColor, residual, status,
                                                            percentRange(progress, mid, convertTo), &kept);
    SampleFitCounters rejected;
    if (rejectedFitter)  // the vertices the shared function did not win: the per-vertex fit
        perVertexFromSet(*rejectedFitter, set, use, viewCount, field, meanColor, sampleCount, residual, status,
                         rejected, progress, convertTo, percentTo, kept.data());
    if (links.keptShared) links.keptShared->swap(kept);
    counters.reset(viewCount);
    for (std::size_t v = 0; v < n; ++v) {
        std::size_t m = 0;
        for (std::size_t i = set.offsets[v]; i < set.offsets[v + 1]; ++i) {
            if (use && !use[i]) continue;
            ++m;
            ++counters.perView[set.view[i]];
        }
        sampleCount[v] = static_cast<float>(m);
        if (m > 0) ++counters.histogram[m];
        counters.totalSamples += m;
    }
    counters.sharedKept = stats.shared;
    if (rejectedFitter) {
        counters.viewDependent = stats.shared + rejected.viewDependent;
        counters.regularised = rejected.regularised;
        counters.validatedConstant = rejected.validatedConstant;
        counters.tooFew = rejected.tooFew;
        counters.guardConstant = rejected.guardConstant;
        counters.guardRetried = rejected.guardRetried;
        counters.fallbacks = rejected.fallbacks;
        counters.downweighted = stats.downweighted + rejected.downweighted;
    } else {
        counters.viewDependent = stats.shared;
        counters.validatedConstant = stats.constant;
        counters.tooFew = stats.tooFew;
        counters.fallbacks = stats.constant + stats.tooFew;
        counters.downweighted = stats.downweighted;
    }
    if (links.lightDistance) *links.lightDistance = model.lightDistance;
    if (links.model) *links.model = std::move(model);
}

// The vertices the shared fit did not keep take the per-vertex fit's coefficients and mean colour:
// what sharedFromSet with a rejectedFitter computes, when that per-vertex fit of the same samples
// already exists.
void takeRejectedFromPerVertex(const RadianceField& perVertexField, const std::vector<float>& perVertexMean,
                               const std::vector<std::uint8_t>& keptShared, RadianceField& field,
                               std::vector<float>& meanColor) {
    const int stride = field.coefficientsPerVertex();
    for (std::size_t v = 0; v < keptShared.size(); ++v) {
        if (keptShared[v]) continue;
        std::copy_n(perVertexField.vertexCoefficients(v), stride, field.vertexCoefficients(v));
        std::copy_n(perVertexMean.data() + 3 * v, 3, meanColor.data() + 3 * v);
    }
}

// Squared errors in 8-bit sRGB levels of the field (and of the mean colours) at the samples with
// heldOut[i], over vertices that have at least one training sample, summed per view (3 per sample).
struct HeldOutSums {
    std::vector<double> fitted, constant;
    std::vector<std::size_t> samples;
    double rms(const std::vector<double>& sums) const {
        double s = 0.0;
        std::size_t m = 0;
        for (std::size_t k = 0; k < sums.size(); ++k) {
            s += sums[k];
            m += samples[k];
        }
        return m ? std::sqrt(s / (3.0 * m)) : 0.0;
    }
    std::size_t total() const {
        std::size_t m = 0;
        for (std::size_t k : samples) m += k;
        return m;
    }
};

HeldOutSums heldOutSampleError(const RadianceField& field, const std::vector<float>& meanColor, const SampleSet& set,
                               const std::vector<std::uint8_t>& heldOut, std::size_t viewCount) {
    const std::size_t n = set.vertexCount();
    HeldOutSums out;
    out.fitted.assign(viewCount, 0.0);
    out.constant.assign(viewCount, 0.0);
    out.samples.assign(viewCount, 0);
    // A fixed number of chunks, each with its own sums, merged in chunk order: the sums (and so the
    // choice made from them) do not depend on the thread count or the schedule.
    constexpr std::ptrdiff_t kChunks = 16;
    std::vector<HeldOutSums> parts(kChunks);
#pragma omp parallel for schedule(dynamic, 1)
    for (std::ptrdiff_t chunk = 0; chunk < kChunks; ++chunk) {
        HeldOutSums& local = parts[chunk];
        local.fitted.assign(viewCount, 0.0);
        local.constant.assign(viewCount, 0.0);
        local.samples.assign(viewCount, 0);
        const std::size_t begin = n * chunk / kChunks, end = n * (chunk + 1) / kChunks;
        for (std::size_t v = begin; v < end; ++v) {
            bool trained = false;
            for (std::size_t i = set.offsets[v]; i < set.offsets[v + 1] && !trained; ++i) trained = !heldOut[i];
            if (!trained) continue;
            for (std::size_t i = set.offsets[v]; i < set.offsets[v + 1]; ++i) {
                if (!heldOut[i]) continue;
                const DirectionalSample& s = set.samples[i];
                const Eigen::Vector3d f =
                    evaluateRadiance(field, v, Eigen::Vector3d(s.direction[0], s.direction[1], s.direction[2]));
                const std::uint32_t view = set.view[i];
                for (int c = 0; c < 3; ++c) {
                    const double y = srgbLevel(s.rgb[c]);
                    const double ef = srgbLevel(f[c]) - y, ec = srgbLevel(meanColor[3 * v + c]) - y;
                    local.fitted[view] += ef * ef;
                    local.constant[view] += ec * ec;
                }
                ++local.samples[view];
            }
        }
    }
    for (const HeldOutSums& local : parts)
        for (std::size_t k = 0; k < viewCount; ++k) {
            out.fitted[k] += local.fitted[k];
            out.constant[k] += local.constant[k];
            out.samples[k] += local.samples[k];
        }
    return out;
}

// The per-vertex and the shared fit of the set minus every k-th view, compared view by view on the
// views left out (see FitModel::Automatic); the comparison goes into result. Returns the choice.
FitModel chooseModelOnLeftOutViews(const TriangleMesh& mesh, const VertexAdjacency& adj, const SampleSet& set,
                                   std::size_t viewCount, const RobustRadianceFitter& fitter,
                                   const RadianceFromViewsOptions& options, const ProgressCallback& progress,
                                   RadianceFromViewsResult& result, SharedModel& sharedCandidate) {
    const std::size_t n = mesh.vertexCount();
    const std::size_t k = static_cast<std::size_t>(options.validationEvery);
    // Every k-th view left out; both candidates fitted on the others, compared on it.
    std::vector<std::uint8_t> train(set.samples.size()), heldOut(set.samples.size());
    const std::vector<std::uint8_t> compared = automaticChoiceVertices(mesh);
    result.validationVertices = std::size_t(std::count(compared.begin(), compared.end(), std::uint8_t(1)));
    for (std::size_t v = 0; v < n; ++v)
        for (std::size_t i = set.offsets[v]; i < set.offsets[v + 1]; ++i) {
            heldOut[i] = compared[v] && (set.view[i] + 1) % k == 0;
            train[i] = compared[v] && (set.view[i] + 1) % k != 0;
        }
    result.validationViews = viewCount / k;
    std::vector<float> perVertexMean(3 * n, 0.0f), count(n, 0.0f), residual(n, 0.0f);
    std::vector<std::uint8_t> status(n, static_cast<std::uint8_t>(FitStatus::Unseen));
    SampleFitCounters scratchCounters;
    RadianceField perVertexField = framedField(mesh, options.fit);
    perVertexFromSet(fitter, set, train.data(), viewCount, perVertexField, perVertexMean, count, residual, status,
                     scratchCounters, progress, 33, 50);
    const HeldOutSums perVertex = heldOutSampleError(perVertexField, perVertexMean, set, heldOut, viewCount);
    RadianceField candidate = framedField(mesh, options.fit);
    std::vector<float> mean(3 * n, 0.0f);
    std::vector<std::uint8_t> keptShared;
    sharedFromSet(mesh, adj, set, train.data(), viewCount, options, candidate, mean, count, residual, status,
                  scratchCounters, progress, 50, 65, nullptr, {nullptr, &sharedCandidate, &keptShared, true});
    // The rejected vertices' per-vertex fit of these same training samples is the candidate above.
    if (options.sharedRejectedPerVertex)
        takeRejectedFromPerVertex(perVertexField, perVertexMean, keptShared, candidate, mean);
    const HeldOutSums shared = heldOutSampleError(candidate, mean, set, heldOut, viewCount);
    result.validationPerVertex = perVertex.rms(perVertex.fitted);
    result.validationConstant = perVertex.rms(perVertex.constant);
    result.validationShared = shared.rms(shared.fitted);
    result.validationSamples = perVertex.total();
    // View by view: wins (ties count as wins) and the worst ratio.
    for (std::size_t view = 0; view < viewCount; ++view) {
        if (perVertex.samples[view] == 0) continue;
        const double a = std::sqrt(perVertex.fitted[view] / (3.0 * perVertex.samples[view]));
        const double b = std::sqrt(shared.fitted[view] / (3.0 * shared.samples[view]));
        ++result.validationViewsCompared;
        if (b <= a) ++result.validationViewsSharedWins;
        const double ratio = a > 0.0 ? b / a : (b > 0.0 ? 2.0 : 1.0);
        result.validationWorstViewRatio = std::max(result.validationWorstViewRatio, ratio);
    }
    result.modelValidated = true;
    const bool sharedBetter = sharedWinsOnLeftOutViews(result.validationPerVertex, result.validationShared,
                                                       result.validationViewsSharedWins,
                                                       result.validationViewsCompared,
                                                       result.validationWorstViewRatio, options.maxViewLoss);
    return sharedBetter ? FitModel::Shared : FitModel::PerVertex;
}

// FitModel Shared and Automatic: every sample stored once, then the chosen fit of the whole set.
void fitFromSampleSet(const TriangleMesh& mesh, const SampleSet& set, std::size_t viewCount,
                      const RobustRadianceFitter& fitter, const RadianceFromViewsOptions& options,
                      const ProgressCallback& progress, RadianceFromViewsResult& result, SampleFitCounters& counters) {
    const VertexAdjacency adj = mesh.faceCount() > 0 ? buildVertexAdjacency(mesh) : VertexAdjacency{};
    FitModel model = options.model;
    const std::size_t k = static_cast<std::size_t>(options.validationEvery);
    result.lobeDegree = options.shared.lobeDegree;
    if (model == FitModel::Automatic && viewCount < 2 * k) {
        model = FitModel::PerVertex;
        result.warnings.push_back("Only " + std::to_string(viewCount) + " usable rasters: too few to compare the shared "
                                  "and the per-vertex fit on left-out rasters (" + std::to_string(2 * k) +
                                  " needed); the per-vertex fit was used.");
    }
    SharedModel sharedCandidate;  // the automatic choice's shared fit: the final shared fit starts from it
    if (model == FitModel::Automatic)
        model = chooseModelOnLeftOutViews(mesh, adj, set, viewCount, fitter, options, progress, result,
                                          sharedCandidate);
    result.modelUsed = model;
    result.field = framedField(mesh, options.fit);
    if (model == FitModel::Shared) {
        sharedFromSet(mesh, adj, set, nullptr, viewCount, options, result.field, result.meanColor, result.sampleCount,
                      result.residual, result.status, counters, progress, 65, kFitEnd,
                      options.sharedRejectedPerVertex ? &fitter : nullptr,
                      {result.modelValidated ? &sharedCandidate : nullptr, nullptr, nullptr, false,
                       &result.lightDistance});
        result.sharedVertices = counters.sharedKept;
    } else {
        perVertexFromSet(fitter, set, nullptr, viewCount, result.field, result.meanColor, result.sampleCount,
                         result.residual, result.status, counters, progress, 65, kFitEnd);
    }
}

}  // namespace

std::string RadianceFromViewsOptions::validate() const {
    std::ostringstream why;
    if (!(saturationLevel > 0.0) || !std::isfinite(saturationLevel))
        why << "the saturation level must be a finite linear value > 0 (got " << saturationLevel
            << "; 0.955 is sRGB code 250, a value above 1 turns the test off)";
    else if (!(saturatedWeight > 0.0 && saturatedWeight <= 1.0))
        why << "the weight of saturated samples must be in (0, 1] (got " << saturatedWeight << "; 1 keeps them as they are)";
    else if (!(maxViewLoss >= 0.0) || !std::isfinite(maxViewLoss))
        why << "the largest loss of the shared fit in one left-out raster must be finite and >= 0 (got " << maxViewLoss << ")";
    else if (validationEvery < 2)
        why << "the automatic choice of the fit must leave out every k-th raster with k >= 2 (got " << validationEvery << ")";
    else if (model != FitModel::PerVertex && !shared.validate().empty())
        why << shared.validate();
    else if (compensateExposure && exposurePoints < 1)
        why << "the exposure compensation needs at least 1 vertex (got 0; turn the compensation off instead)";
    return why.str();
}

double sharedWorstViewBound(double perVertexRms, double sharedRms, double maxViewLoss) {
    const double pooledGain = sharedRms > 0.0 ? perVertexRms / sharedRms - 1.0 : 0.0;
    return 1.0 + std::max(maxViewLoss, pooledGain);
}

bool sharedWinsOnLeftOutViews(double perVertexRms, double sharedRms, std::size_t sharedWins,
                              std::size_t viewsCompared, double worstViewRatio, double maxViewLoss) {
    if (!(sharedRms < perVertexRms) || 2 * sharedWins < viewsCompared) return false;
    return worstViewRatio <= sharedWorstViewBound(perVertexRms, sharedRms, maxViewLoss);
}

// About an eighth of the mesh, at least kChoiceVertices and at most kMostChoiceVertices vertices:
// measured, the choice was the same on every capture (docs/fitting.md, "Choosing on part of the
// surface"); the cap keeps the choice's share of the fit small on scans of several 100k vertices.
std::vector<std::uint8_t> automaticChoiceVertices(const TriangleMesh& mesh) {
    constexpr std::size_t kChoiceVertices = 8192, kShare = 8, kMostChoiceVertices = 16384;
    const std::size_t n = mesh.vertexCount();
    const std::size_t picked = std::min(kMostChoiceVertices, std::max(kChoiceVertices, n / kShare));
    const std::size_t every = std::max<std::size_t>(1, n / picked);
    std::vector<std::uint8_t> chosen(n, 1);
    if (every == 1) return chosen;
    const auto position = [&](std::size_t v) { return Eigen::Map<const Eigen::Vector3f>(mesh.positions.data() + 3 * v); };
    Eigen::AlignedBox3f box;
    for (std::size_t v = 0; v < n; ++v) box.extend(position(v));
    if (!box.min().allFinite() || !box.max().allFinite()) return chosen;
    // Cells of about 64 vertices or more, so that most of a picked vertex's neighbours are picked too:
    // the finest of 32, 16, 8 and 4 cells across the box that holds that many per occupied cell.
    std::vector<std::uint64_t> cellOf(n, 0);
    for (int across : {32, 16, 8, 4}) {
        const float cell = std::max(box.diagonal().maxCoeff() / float(across), std::numeric_limits<float>::min());
        for (std::size_t v = 0; v < n; ++v) {
            const Eigen::Vector3f p = position(v);
            if (!p.allFinite()) continue;  // left in cell 0; the fit refuses such meshes before choosing
            const Eigen::Vector3f c = ((p - box.min()) / cell).array().floor();
            cellOf[v] = std::uint64_t(c.x()) | std::uint64_t(c.y()) << 21 | std::uint64_t(c.z()) << 42;
        }
        std::vector<std::uint64_t> occupied = cellOf;
        std::sort(occupied.begin(), occupied.end());
        const std::size_t cells = std::size_t(std::unique(occupied.begin(), occupied.end()) - occupied.begin());
        if (n >= 64 * cells) break;
    }
    for (std::size_t v = 0; v < n; ++v) {
        std::uint64_t hash = cellOf[v];  // the cell's packed indices, mixed (splitmix64's finaliser)
        hash = (hash ^ (hash >> 30)) * 0xbf58476d1ce4e5b9ull;
        hash = (hash ^ (hash >> 27)) * 0x94d049bb133111ebull;
        hash ^= hash >> 31;
        chosen[v] = (hash % every) == 0;
    }
    // Too few patches picked (a small or oddly shaped scan): compare on every vertex instead.
    if (std::size_t(std::count(chosen.begin(), chosen.end(), std::uint8_t(1))) * every * 2 < n) chosen.assign(n, 1);
    return chosen;
}

VertexAdjacency buildVertexAdjacency(const TriangleMesh& mesh) {
    const std::size_t n = mesh.vertexCount(), faces = mesh.faceCount();
    VertexAdjacency adj;
    std::vector<std::size_t> start(n + 1, 0);
    for (std::size_t i = 0; i < 3 * faces; ++i) start[mesh.faces[i] + 1] += 2;
    for (std::size_t v = 0; v < n; ++v) start[v + 1] += start[v];
    std::vector<std::uint32_t> all(start[n]);
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (std::size_t f = 0; f < faces; ++f) {
        const std::uint32_t* t = mesh.faces.data() + 3 * f;
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = t[k], b = t[(k + 1) % 3], c = t[(k + 2) % 3];
            all[fill[a]++] = b;
            all[fill[a]++] = c;
        }
    }
    // Sort, drop duplicates (interior edges appear in two faces) and self loops (degenerate faces).
    adj.offsets.assign(n + 1, 0);
    adj.neighbours.reserve(all.size() / 2 + n);
    for (std::size_t v = 0; v < n; ++v) {
        auto first = all.begin() + static_cast<std::ptrdiff_t>(start[v]);
        auto last = all.begin() + static_cast<std::ptrdiff_t>(start[v + 1]);
        std::sort(first, last);
        last = std::unique(first, last);
        for (auto it = first; it != last; ++it)
            if (*it != v) adj.neighbours.push_back(*it);
        adj.offsets[v + 1] = adj.neighbours.size();
    }
    return adj;
}

namespace {

// The views that pass checkView, with their input indices; the others are warned about.
struct UsableViews {
    std::vector<CalibratedView> views;
    std::vector<std::size_t> index;  // input index of each usable view
};

UsableViews selectUsableViews(const std::vector<CalibratedView>& views, RadianceFromViewsResult& result) {
    UsableViews usable;
    for (std::size_t i = 0; i < views.size(); ++i) {
        const std::string problem = checkView(views[i]);
        if (problem.empty()) {
            usable.views.push_back(views[i]);
            usable.index.push_back(i);
        } else {
            result.warnings.push_back("Raster " + std::to_string(i) + " was skipped: " + problem + ".");
        }
    }
    if (usable.views.empty()) {
        // The warnings are lost with the exception: the message carries the reasons (the first few).
        std::string why = "None of the " + std::to_string(views.size()) + " rasters can be used.";
        for (std::size_t i = 0; i < result.warnings.size() && i < 3; ++i) why += " " + result.warnings[i];
        if (result.warnings.size() > 3) why += " (and " + std::to_string(result.warnings.size() - 3) + " more)";
        throw FitError(why);
    }
    result.viewsUsed = usable.views.size();
    return usable;
}

std::unique_ptr<ViewSampler> buildSampler(const TriangleMesh& mesh, const std::vector<CalibratedView>& usable,
                                          const RadianceFromViewsOptions& options, RadianceFromViewsResult& result) {
    std::unique_ptr<ViewSampler> sampler;
    try {
        sampler = std::make_unique<ViewSampler>(mesh, usable, options.sampling);
    } catch (const std::exception& e) {
        throw FitError(std::string("The ray-casting scene for the visibility test could not be built: ") + e.what() +
                       ". The mesh may be too large for the available memory.");
    }
    if (!sampler->testsOcclusion())
        result.warnings.push_back(
            "The mesh has no faces (a point cloud): occlusion by other parts of the object cannot be tested, so every "
            "point facing a camera counts as seen, and unseen points cannot be filled from neighbours.");
    return sampler;
}

// The samples of every stride-th vertex that at least two views see, sorted by point and view: the
// merge order of the threads depends on the schedule, the solution must not.
std::vector<ExposureSample> gatherExposureSamples(const ViewSampler& sampler, std::size_t n, std::size_t stride) {
    const std::size_t viewCount = sampler.viewCount();
    const std::ptrdiff_t points = static_cast<std::ptrdiff_t>((n + stride - 1) / stride);
    std::vector<ExposureSample> all;
#pragma omp parallel
    {
        std::vector<DirectionalSample> samples(viewCount);
        std::vector<int> viewOf(viewCount);
        std::vector<ExposureSample> mine;
#pragma omp for schedule(dynamic, 256) nowait
        for (std::ptrdiff_t p = 0; p < points; ++p) {
            const std::size_t m =
                sampler.sampleVertex(static_cast<std::size_t>(p) * stride, samples.data(), nullptr, viewOf.data());
            if (m < 2) continue;
            for (std::size_t j = 0; j < m; ++j)
                mine.push_back(ExposureSample{static_cast<std::uint32_t>(p), static_cast<std::uint32_t>(viewOf[j]),
                                              {samples[j].rgb[0], samples[j].rgb[1], samples[j].rgb[2]},
                                              samples[j].weight});
        }
#pragma omp critical(radiance_from_views_exposure)
        all.insert(all.end(), mine.begin(), mine.end());
    }
    std::sort(all.begin(), all.end(), [](const ExposureSample& a, const ExposureSample& b) {
        return a.point != b.point ? a.point < b.point : a.view < b.view;
    });
    return all;
}

// The vertex stride that leaves about options.exposurePoints vertices for the exposure gains.
std::size_t exposureStride(std::size_t n, const RadianceFromViewsOptions& options) {
    return std::max<std::size_t>(1, (n + options.exposurePoints - 1) / options.exposurePoints);
}

// The gains solved from exposure samples, and what the result says about them.
std::vector<double> solveViewGains(const std::vector<ExposureSample>& samples, std::size_t viewCount,
                                   const RadianceFromViewsOptions& options, RadianceFromViewsResult& result) {
    ExposureOptions exposure;
    exposure.saturationLevel = options.saturationLevel;
    const ExposureGains solved = solveExposureGains(samples, viewCount, exposure);
    result.exposureCompensated = true;
    result.exposureSamples = solved.samplesUsed;
    for (std::uint8_t c : solved.constrained) result.exposureViews += c;
    if (result.exposureViews < viewCount)
        result.warnings.push_back(std::to_string(viewCount - result.exposureViews) + " of " +
                                  std::to_string(viewCount) +
                                  " rasters share no vertex with another raster: their exposure was left as it is.");
    return solved.gains;
}

// Exposure / white-balance gains of the usable views (1 when not compensated), from the samples of
// up to options.exposurePoints vertices spread evenly over the vertex order, sampled for the purpose
// (the per-vertex fit streams its samples and keeps none).
std::vector<double> estimateViewGains(const ViewSampler& sampler, std::size_t n, const RadianceFromViewsOptions& options,
                                      const ProgressCallback& progress, RadianceFromViewsResult& result) {
    const std::size_t viewCount = sampler.viewCount();
    if (!options.compensateExposure || viewCount < 2) return std::vector<double>(3 * viewCount, 1.0);
    reportPercent(progress, 2, kStageExposure);
    return solveViewGains(gatherExposureSamples(sampler, n, exposureStride(n, options)), viewCount, options, result);
}

// The same gains from the samples already gathered (raw, before any gain): the same vertices and
// samples as estimateViewGains would sample again, already in (point, view) order (the set is in
// vertex order, each vertex's samples in view order).
std::vector<double> gainsFromSampleSet(const SampleSet& set, std::size_t viewCount, const RadianceFromViewsOptions& options,
                                       const ProgressCallback& progress, RadianceFromViewsResult& result) {
    if (!options.compensateExposure || viewCount < 2) return std::vector<double>(3 * viewCount, 1.0);
    reportPercent(progress, kFitStart + 30, kStageExposure);
    const std::size_t n = set.vertexCount(), stride = exposureStride(n, options);
    std::vector<ExposureSample> samples;
    for (std::size_t v = 0; v < n; v += stride) {
        if (set.offsets[v + 1] - set.offsets[v] < 2) continue;
        for (std::size_t i = set.offsets[v]; i < set.offsets[v + 1]; ++i) {
            const DirectionalSample& x = set.samples[i];
            samples.push_back(ExposureSample{static_cast<std::uint32_t>(v / stride), set.view[i],
                                             {x.rgb[0], x.rgb[1], x.rgb[2]}, x.weight});
        }
    }
    return solveViewGains(samples, viewCount, options, result);
}

// Every sample divided by its view's gains.
void divideByViewGains(SampleSet& set, const std::vector<double>& gains) {
    const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(set.samples.size());
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < count; ++i) divideByGain(set.samples[i], gains.data() + 3 * set.view[i]);
}

void recordViewGains(const std::vector<double>& gains, const UsableViews& usable, std::size_t inputViews,
                     RadianceFromViewsResult& result) {
    result.viewGains.assign(3 * inputViews, 1.0);
    for (std::size_t i = 0; i < usable.index.size(); ++i)
        for (int c = 0; c < 3; ++c) result.viewGains[3 * usable.index[i] + c] = gains[3 * i + c];
}

void allocateOutputs(std::size_t n, const RadianceFromViewsOptions& options, RadianceFromViewsResult& result) {
    result.field = RadianceField(options.fit.basis, n, options.fit.storeReflected);
    result.meanColor.assign(3 * n, 0.0f);
    result.sampleCount.assign(n, 0.0f);
    result.residual.assign(n, 0.0f);
    result.status.assign(n, static_cast<std::uint8_t>(FitStatus::Unseen));
}

// FitModel PerVertex: each vertex sampled and fitted at once, its samples in a per-thread buffer
// (memory does not grow with the number of samples of the mesh).
void streamPerVertexFit(const TriangleMesh& mesh, const ViewSampler& sampler, const RobustRadianceFitter& fitter,
                        const std::vector<double>& gains, const RadianceFromViewsOptions& options,
                        const ProgressCallback& progress, RadianceFromViewsResult& result,
                        SampleFitCounters& counters) {
    const std::size_t n = mesh.vertexCount(), viewCount = sampler.viewCount();
    counters.reset(viewCount);
    RadianceField& field = result.field;
    const ProgressCallback range = percentRange(progress, kFitStart, kFitEnd);
    LoopProgress loop(range, kStageFitting, n);
    // Blocks of neighbouring vertices: their rays toward one camera are cast as one packet.
    constexpr int kBlock = ViewSampler::kBlock;
    const std::ptrdiff_t blocks = static_cast<std::ptrdiff_t>((n + kBlock - 1) / kBlock);
#pragma omp parallel
    {
        // Per-thread buffers, allocated once: the samples of one block of vertices, and the fit's scratch.
        std::vector<DirectionalSample> samples(kBlock * viewCount);
        std::vector<int> viewOf(kBlock * viewCount);
        std::size_t counts[kBlock];
        FitScratch scratch = fitter.makeScratch();
        SampleFitCounters local;
        local.reset(viewCount);
        const bool reporter = omp_get_thread_num() == 0;
#pragma omp for schedule(dynamic, 16) nowait
        for (std::ptrdiff_t block = 0; block < blocks; ++block) {
            const std::size_t first = static_cast<std::size_t>(block) * kBlock;
            const int size = static_cast<int>(std::min<std::size_t>(kBlock, n - first));
            loop.runItem(reporter, [&] {
                sampler.sampleVertexBlock(first, size, samples.data(), counts, nullptr, viewOf.data());
                for (int k = 0; k < size; ++k) {
                    const std::size_t v = first + static_cast<std::size_t>(k);
                    const float* nv = mesh.normals.data() + 3 * v;
                    storeFrame(frameFromNormal(Eigen::Vector3d(nv[0], nv[1], nv[2])), field.frame(v));
                    // The frame as evaluation will read it back (float storage, re-orthonormalised).
                    const Frame frame = frameFromStored(field.frame(v));
                    DirectionalSample* mine = samples.data() + static_cast<std::size_t>(k) * viewCount;
                    const int* views = viewOf.data() + static_cast<std::size_t>(k) * viewCount;
                    const std::size_t m = counts[k];
                    for (std::size_t j = 0; j < m; ++j) {
                        ++local.perView[views[j]];
                        local.saturated += weighSaturation(mine[j], options) ? 1 : 0;
                        divideByGain(mine[j], gains.data() + 3 * views[j]);
                    }
                    const VertexFitResult r = fitter.fit(frame, mine, m, scratch, field.vertexCoefficients(v));
                    local.count(r, options.fit.minSamples);
                    storeVertexFit(r, v, result.meanColor, result.sampleCount, result.residual, result.status);
                }
            }, static_cast<std::size_t>(size));
        }
#pragma omp critical(radiance_from_views_merge)
        counters.merge(local);
    }
    loop.finish();
}

// Median of the seen vertices' sample counts (the mean of the two middle ones for an even count),
// from the histogram of vertices by sample count.
double medianSampleCount(const std::vector<std::size_t>& histogram) {
    std::size_t seen = 0;
    for (std::size_t i = 1; i < histogram.size(); ++i) seen += histogram[i];
    if (seen == 0) return 0.0;
    auto kth = [&](std::size_t k) {  // 0-based k-th smallest count among the seen vertices
        std::size_t below = 0;
        for (std::size_t i = 1; i < histogram.size(); ++i) {
            below += histogram[i];
            if (below > k) return static_cast<double>(i);
        }
        return static_cast<double>(histogram.size() - 1);
    };
    return 0.5 * (kth((seen - 1) / 2) + kth(seen / 2));
}

void recordCounters(const SampleFitCounters& counters, const UsableViews& usable, std::size_t inputViews,
                    RadianceFromViewsResult& result) {
    result.viewDependent = counters.viewDependent;
    result.regularised = counters.regularised;
    result.validatedConstant = counters.validatedConstant;
    result.tooFewSamples = counters.tooFew;
    result.guardConstant = counters.guardConstant;
    result.robustDownweighted = counters.downweighted;
    result.saturatedSamples = counters.saturated;
    result.medianSamples = medianSampleCount(counters.histogram);
    result.guardRetried = counters.guardRetried;
    result.constantFallbacks = counters.fallbacks;
    result.totalSamples = counters.totalSamples;
    result.samplesPerView.assign(inputViews, 0);
    for (std::size_t i = 0; i < usable.index.size(); ++i) {
        result.samplesPerView[usable.index[i]] = counters.perView[i];
        if (counters.perView[i] == 0)
            result.warnings.push_back("Raster " + std::to_string(usable.index[i]) +
                                      " contributed no sample: no vertex is inside its image, facing its camera and "
                                      "unoccluded (check that its camera is aligned with the mesh).");
    }
}

std::size_t countUnseenOrRefuse(const RadianceFromViewsResult& result) {
    const std::size_t n = result.status.size();
    std::size_t unseen = 0;
    for (std::size_t v = 0; v < n; ++v) unseen += result.status[v] == static_cast<std::uint8_t>(FitStatus::Unseen);
    if (unseen == n)
        throw FitError(
            "No vertex is seen by any raster: check that the cameras look at the mesh (the rasters must be aligned "
            "with this mesh, in the same coordinate frame and scale, e.g. with the Raster Alignment tool or by "
            "importing the project the cameras were computed with), that the vertex normals point outwards toward "
            "the cameras, and that the mesh is not hidden by another surface.");
    return unseen;
}

// Unseen vertex v gets the plain average of its known neighbours' coefficients and mean colours.
// Reads only vertices known before this round and writes only v: no race, and the result is
// independent of the schedule.
void averageKnownNeighbours(std::uint32_t v, const VertexAdjacency& adj, const std::vector<std::uint8_t>& known,
                            RadianceFromViewsResult& result) {
    RadianceField& field = result.field;
    const int per = field.coefficientsPerVertex();
    float* dst = field.vertexCoefficients(v);
    std::fill(dst, dst + per, 0.0f);
    double colour[3] = {0.0, 0.0, 0.0};
    double sum[kColorChannels * kMaxCoefficientsPerChannel];
    std::fill(sum, sum + per, 0.0);
    int k = 0;
    for (std::size_t e = adj.offsets[v]; e < adj.offsets[v + 1]; ++e) {
        const std::uint32_t u = adj.neighbours[e];
        if (!known[u]) continue;
        const float* src = field.vertexCoefficients(u);
        for (int j = 0; j < per; ++j) sum[j] += src[j];
        for (int c = 0; c < 3; ++c) colour[c] += result.meanColor[3 * u + c];
        ++k;
    }
    for (int j = 0; j < per; ++j) dst[j] = static_cast<float>(sum[j] / k);
    for (int c = 0; c < 3; ++c) result.meanColor[3 * v + c] = static_cast<float>(colour[c] / k);
    result.status[v] = static_cast<std::uint8_t>(FitStatus::FilledFromNeighbours);
}

// The unseen vertices with at least one known neighbour, marked queued.
std::vector<std::uint32_t> firstFillingRing(const VertexAdjacency& adj, const std::vector<std::uint8_t>& known,
                                            std::vector<std::uint8_t>& queued) {
    std::vector<std::uint32_t> frontier;
    for (std::size_t v = 0; v < known.size(); ++v) {
        if (known[v]) continue;
        for (std::size_t e = adj.offsets[v]; e < adj.offsets[v + 1]; ++e)
            if (known[adj.neighbours[e]]) {
                frontier.push_back(static_cast<std::uint32_t>(v));
                queued[v] = 1;
                break;
            }
    }
    return frontier;
}

// The unqueued unknown neighbours of the frontier, marked queued.
void nextFillingRing(const VertexAdjacency& adj, const std::vector<std::uint32_t>& frontier,
                     const std::vector<std::uint8_t>& known, std::vector<std::uint8_t>& queued,
                     std::vector<std::uint32_t>& next) {
    next.clear();
    for (std::uint32_t v : frontier)
        for (std::size_t e = adj.offsets[v]; e < adj.offsets[v + 1]; ++e) {
            const std::uint32_t u = adj.neighbours[e];
            if (!known[u] && !queued[u]) {
                queued[u] = 1;
                next.push_back(u);
            }
        }
}

// Unseen vertices: ring-by-ring averaging of known neighbours (see the header). Returns how many
// were filled.
std::size_t fillUnseenFromNeighbours(const TriangleMesh& mesh, std::size_t unseen, const ProgressCallback& progress,
                                     RadianceFromViewsResult& result) {
    reportPercent(progress, kFitEnd, kStageFilling);
    const std::size_t n = mesh.vertexCount();
    const VertexAdjacency adj = buildVertexAdjacency(mesh);
    std::vector<std::uint8_t> known(n), queued(n, 0);
    for (std::size_t v = 0; v < n; ++v) known[v] = result.status[v] != static_cast<std::uint8_t>(FitStatus::Unseen);
    std::vector<std::uint32_t> frontier = firstFillingRing(adj, known, queued), next;
    std::size_t filled = 0;
    while (!frontier.empty()) {
        const std::ptrdiff_t fsize = static_cast<std::ptrdiff_t>(frontier.size());
#pragma omp parallel for schedule(dynamic, 256)
        for (std::ptrdiff_t i = 0; i < fsize; ++i) averageKnownNeighbours(frontier[i], adj, known, result);
        for (std::uint32_t v : frontier) known[v] = 1;
        filled += frontier.size();
        nextFillingRing(adj, frontier, known, queued, next);
        frontier.swap(next);
        reportPercent(progress, kFitEnd + static_cast<int>((99 - kFitEnd) * double(filled) / double(unseen)),
                      kStageFilling);
    }
    return filled;
}

// The status counts, and the warning about vertices left black.
void summariseStatuses(const TriangleMesh& mesh, const RadianceFromViewsOptions& options, std::size_t unseen,
                       RadianceFromViewsResult& result) {
    const std::size_t n = mesh.vertexCount();
    result.unseenLeft = unseen - result.unseenFilled;
    for (std::size_t v = 0; v < n; ++v) {
        const auto s = static_cast<FitStatus>(result.status[v]);
        if (s == FitStatus::Fitted) ++result.fitted;
        else if (s == FitStatus::PoorlySampled) ++result.poorlySampled;
    }
    if (result.unseenLeft > 0) {
        std::ostringstream why;
        why << result.unseenLeft << " of " << n << " vertices are not seen by any raster";
        if (options.fillUnseen && mesh.faceCount() > 0)
            why << " and belong to parts of the mesh that no raster sees at all";
        why << ": they keep zero radiance (black). Add photographs of those parts, or remove them.";
        result.warnings.push_back(why.str());
    }
}

}  // namespace

RadianceFromViewsResult fitRadianceFromViews(const TriangleMesh& mesh, const std::vector<CalibratedView>& views,
                                             const RadianceFromViewsOptions& options,
                                             const ProgressCallback& progress) {
    const auto t0 = std::chrono::steady_clock::now();
    reportPercent(progress, 0, kStageChecking);
    validateInput(mesh, views, options);
    RadianceFromViewsResult result;
    const UsableViews usable = selectUsableViews(views, result);
    const RobustRadianceFitter fitter(options.fit);  // options validated above: does not throw
    reportPercent(progress, 1, kStageScene);
    const std::unique_ptr<ViewSampler> sampler = buildSampler(mesh, usable.views, options, result);
    const std::size_t n = mesh.vertexCount(), viewCount = sampler->viewCount();
    SampleFitCounters counters;
    if (options.model == FitModel::PerVertex) {
        const std::vector<double> gains = estimateViewGains(*sampler, n, options, progress, result);
        recordViewGains(gains, usable, views.size(), result);
        allocateOutputs(n, options, result);
        reportPercent(progress, kFitStart, kStageFitting);
        streamPerVertexFit(mesh, *sampler, fitter, gains, options, progress, result, counters);
    } else {
        // Shared and Automatic keep every sample: gathered once, raw, the exposure gains solved from
        // them and divided out.
        allocateOutputs(n, options, result);
        reportPercent(progress, kFitStart, kStageSampling);
        std::size_t saturated = 0;
        SampleSet set = gatherSamples(n, *sampler, options, progress, saturated);
        const std::vector<double> gains = gainsFromSampleSet(set, viewCount, options, progress, result);
        recordViewGains(gains, usable, views.size(), result);
        divideByViewGains(set, gains);
        fitFromSampleSet(mesh, set, viewCount, fitter, options, progress, result, counters);
        counters.saturated = saturated;
    }
    reportPercent(progress, kFitEnd, kStageFitting);
    recordCounters(counters, usable, views.size(), result);

    const std::size_t unseen = countUnseenOrRefuse(result);
    if (unseen > 0 && options.fillUnseen && mesh.faceCount() > 0)
        result.unseenFilled = fillUnseenFromNeighbours(mesh, unseen, progress, result);
    summariseStatuses(mesh, options, unseen, result);
    // The last report cannot stop the call any more: the result is complete.
    if (progress) progress(1.0, kStageDone);
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return result;
}

}  // namespace rad
