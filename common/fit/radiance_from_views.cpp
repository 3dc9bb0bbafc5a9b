#include "fit/radiance_from_views.h"

#include "radiance/radiance_evaluation.h"
#include "radiance/radiance_frame.h"
#include "raycast/ray_scene.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <omp.h>
#include <sstream>

namespace rad {

namespace {

const char* const kNormalsHint =
    "compute normals first, e.g. Filters > Normals, Curvatures and Orientation > Compute normals for point sets "
    "(point clouds) or Re-Compute Vertex Normals (meshes)";

// Every check that needs no heavy work, in the order a user would fix things.
void validateInput(const TriangleMesh& mesh, const std::vector<CalibratedView>& views,
                   const RadianceFromViewsOptions& options) {
    if (mesh.vertexCount() == 0) throw FitError("The mesh has no vertices: open or select a mesh with vertices first.");
    const std::string meshProblem = mesh.validate();
    if (!meshProblem.empty()) {
        std::ostringstream why;
        why << "The mesh cannot be used: " << meshProblem << ".";
        if (meshProblem.find("non-finite coordinate") != std::string::npos)
            why << " Remove or repair such vertices first (e.g. Filters > Cleaning and Repairing).";
        else if (meshProblem.find("normal") != std::string::npos)
            why << " Radiance functions live on the hemisphere around the vertex normal: " << kNormalsHint << ".";
        else if (meshProblem.find("refers to vertex") != std::string::npos)
            why << " Repair the mesh first (e.g. Filters > Cleaning and Repairing > Remove Zero Area Faces / "
                   "Remove Unreferenced Vertices), or reload it.";
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
    if (views.empty())
        throw FitError("There is no raster to fit from: load calibrated photographs first (File > Import Raster, or "
                       "open a MeshLab project .mlp / Bundler .out with cameras), aligned with this mesh.");
}

// Reports percent changes only, from the calling thread (thread 0 of the OpenMP team). A stop
// request is remembered: the parallel loop skips its remaining vertices and the call then throws
// OperationCancelled (an exception cannot leave an OpenMP region).
class Progress {
public:
    explicit Progress(const ProgressCallback& cb) : cb_(cb) {}
    void report(int percent, const char* stage) {
        if (!cb_ || cancelled_.load(std::memory_order_relaxed)) return;
        percent = std::max(0, std::min(100, percent));
        if (percent == last_ && stage == lastStage_) return;
        last_ = percent;
        lastStage_ = stage;
        if (!cb_(percent / 100.0, stage)) cancelled_.store(true, std::memory_order_relaxed);
    }
    bool cancelled() const { return cancelled_.load(std::memory_order_relaxed); }
    void throwIfCancelled() const {
        if (cancelled()) throw OperationCancelled();
    }

private:
    const ProgressCallback& cb_;
    int last_ = -1;
    const char* lastStage_ = nullptr;
    std::atomic<bool> cancelled_{false};
};

constexpr const char* kStageChecking = "checking the rasters";
constexpr const char* kStageScene = "building the ray-casting scene";
constexpr const char* kStageFitting = "sampling the rasters and fitting";
constexpr const char* kStageFilling = "filling unseen vertices";
constexpr const char* kStageDone = "done";
// Percent ranges of the stages.
constexpr int kFitStart = 3, kFitEnd = 95;

}  // namespace

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

RadianceFromViewsResult fitRadianceFromViews(const TriangleMesh& mesh, const std::vector<CalibratedView>& views,
                                             const RadianceFromViewsOptions& options,
                                             const ProgressCallback& progressCallback) {
    const auto t0 = std::chrono::steady_clock::now();
    Progress progress(progressCallback);
    progress.report(0, kStageChecking);
    progress.throwIfCancelled();
    validateInput(mesh, views, options);

    RadianceFromViewsResult result;
    std::vector<CalibratedView> usable;
    std::vector<std::size_t> usableIndex;  // input index of each usable view
    for (std::size_t i = 0; i < views.size(); ++i) {
        const std::string problem = checkView(views[i]);
        if (problem.empty()) {
            usable.push_back(views[i]);
            usableIndex.push_back(i);
        } else {
            result.warnings.push_back("Raster " + std::to_string(i) + " was skipped: " + problem + ".");
        }
    }
    if (usable.empty()) {
        // The warnings are lost with the exception: the message carries the reasons (the first few).
        std::string why = "None of the " + std::to_string(views.size()) + " rasters can be used.";
        for (std::size_t i = 0; i < result.warnings.size() && i < 3; ++i) why += " " + result.warnings[i];
        if (result.warnings.size() > 3) why += " (and " + std::to_string(result.warnings.size() - 3) + " more)";
        throw FitError(why);
    }
    result.viewsUsed = usable.size();

    const std::size_t n = mesh.vertexCount();
    const RobustRadianceFitter fitter(options.fit);  // options validated above: does not throw
    progress.report(1, kStageScene);
    progress.throwIfCancelled();
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

    result.field = RadianceField(options.fit.basis, n, options.fit.storeReflected);
    result.meanColor.assign(3 * n, 0.0f);
    result.sampleCount.assign(n, 0.0f);
    result.residual.assign(n, 0.0f);
    result.status.assign(n, static_cast<std::uint8_t>(FitStatus::Unseen));
    std::vector<std::size_t> perView(usable.size(), 0);
    std::size_t guardRetried = 0, fallbacks = 0, totalSamples = 0;
    progress.report(kFitStart, kStageFitting);

    RadianceField& field = result.field;
    std::atomic<std::size_t> done{0};
    const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel
    {
        // Per-thread buffers, allocated once: the samples of one vertex, and the fit's scratch.
        std::vector<DirectionalSample> samples(usable.size());
        std::vector<int> viewOf(usable.size());
        std::vector<std::size_t> localPerView(usable.size(), 0);
        FitScratch scratch = fitter.makeScratch();
        std::size_t localRetried = 0, localFallbacks = 0, localSamples = 0;
        const bool reporter = omp_get_thread_num() == 0;
#pragma omp for schedule(dynamic, 256) nowait
        for (std::ptrdiff_t iv = 0; iv < count; ++iv) {
            if (progress.cancelled()) continue;
            const std::size_t v = static_cast<std::size_t>(iv);
            const float* nv = mesh.normals.data() + 3 * v;
            storeFrame(frameFromNormal(Eigen::Vector3d(nv[0], nv[1], nv[2])), field.frame(v));
            // The frame as evaluation will read it back (float storage, re-orthonormalised).
            const Frame frame = frameFromStored(field.frame(v));
            const std::size_t m = sampler->sampleVertex(v, samples.data(), nullptr, viewOf.data());
            for (std::size_t j = 0; j < m; ++j) ++localPerView[viewOf[j]];
            const VertexFitResult r = fitter.fit(frame, samples.data(), m, scratch, field.vertexCoefficients(v));
            for (int c = 0; c < 3; ++c) result.meanColor[3 * v + c] = static_cast<float>(r.meanColor[c]);
            result.sampleCount[v] = static_cast<float>(r.sampleCount);
            result.residual[v] = static_cast<float>(r.residual);
            result.status[v] = static_cast<std::uint8_t>(r.status);
            localRetried += r.guardRetries > 0 ? 1 : 0;
            localFallbacks += r.constantFallback ? 1 : 0;
            localSamples += static_cast<std::size_t>(r.sampleCount);
            const std::size_t finished = done.fetch_add(1, std::memory_order_relaxed) + 1;
            if (reporter && (finished & 1023) == 0)
                progress.report(kFitStart + static_cast<int>((kFitEnd - kFitStart) * double(finished) / double(n)),
                                kStageFitting);
        }
#pragma omp critical(radiance_from_views_merge)
        {
            for (std::size_t i = 0; i < usable.size(); ++i) perView[i] += localPerView[i];
            guardRetried += localRetried;
            fallbacks += localFallbacks;
            totalSamples += localSamples;
        }
    }
    progress.throwIfCancelled();
    progress.report(kFitEnd, kStageFitting);
    result.guardRetried = guardRetried;
    result.constantFallbacks = fallbacks;
    result.totalSamples = totalSamples;
    result.samplesPerView.assign(views.size(), 0);
    for (std::size_t i = 0; i < usable.size(); ++i) {
        result.samplesPerView[usableIndex[i]] = perView[i];
        if (perView[i] == 0)
            result.warnings.push_back("Raster " + std::to_string(usableIndex[i]) +
                                      " contributed no sample: no vertex is inside its image, facing its camera and "
                                      "unoccluded (check that its camera is aligned with the mesh).");
    }

    std::size_t unseen = 0;
    for (std::size_t v = 0; v < n; ++v) unseen += result.status[v] == static_cast<std::uint8_t>(FitStatus::Unseen);
    if (unseen == n)
        throw FitError(
            "No vertex is seen by any raster: check that the cameras look at the mesh (the rasters must be aligned "
            "with this mesh, in the same coordinate frame and scale, e.g. with the Raster Alignment tool or by "
            "importing the project the cameras were computed with), that the vertex normals point outwards toward "
            "the cameras, and that the mesh is not hidden by another surface.");

    // Unseen vertices: ring-by-ring averaging of known neighbours (see the header).
    if (unseen > 0 && options.fillUnseen && mesh.faceCount() > 0) {
        progress.report(kFitEnd, kStageFilling);
        const VertexAdjacency adj = buildVertexAdjacency(mesh);
        const int per = field.coefficientsPerVertex();
        std::vector<std::uint8_t> known(n), queued(n, 0);
        for (std::size_t v = 0; v < n; ++v) known[v] = result.status[v] != static_cast<std::uint8_t>(FitStatus::Unseen);
        std::vector<std::uint32_t> frontier, next;
        for (std::size_t v = 0; v < n; ++v) {
            if (known[v]) continue;
            for (std::size_t e = adj.offsets[v]; e < adj.offsets[v + 1]; ++e)
                if (known[adj.neighbours[e]]) {
                    frontier.push_back(static_cast<std::uint32_t>(v));
                    queued[v] = 1;
                    break;
                }
        }
        std::size_t filled = 0;
        while (!frontier.empty()) {
            // Every vertex of the frontier reads only vertices known before this round and writes only
            // itself: no race, and the result is independent of the schedule.
            const std::ptrdiff_t fsize = static_cast<std::ptrdiff_t>(frontier.size());
#pragma omp parallel for schedule(dynamic, 256)
            for (std::ptrdiff_t i = 0; i < fsize; ++i) {
                const std::uint32_t v = frontier[i];
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
            for (std::uint32_t v : frontier) known[v] = 1;
            filled += frontier.size();
            next.clear();
            for (std::uint32_t v : frontier)
                for (std::size_t e = adj.offsets[v]; e < adj.offsets[v + 1]; ++e) {
                    const std::uint32_t u = adj.neighbours[e];
                    if (!known[u] && !queued[u]) {
                        queued[u] = 1;
                        next.push_back(u);
                    }
                }
            frontier.swap(next);
            progress.report(kFitEnd + static_cast<int>((99 - kFitEnd) * double(filled) / double(unseen)), kStageFilling);
            progress.throwIfCancelled();
        }
        result.unseenFilled = filled;
    }
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
    progress.report(100, kStageDone);
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return result;
}

}  // namespace rad
