// See irradiance_vector_grid_compute.h. Parallel over grid vertices (dynamic schedule: a vertex in
// an open corner costs a few escaping rays, one facing a lit wall a path per ray); each vertex's
// 6 R rays go to the tracer 16 at a time.
#include "lighting/irradiance_vector_grid_compute.h"

#include "lighting/median_cut_lights.h"
#include "memory/available_memory.h"
#include "sampling/radical_inverse.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rad {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kLanes = RayPacket16::kSize;
constexpr int kMaxResolution = 512;
constexpr int kMaxRays = 1 << 20;

double seconds(std::chrono::steady_clock::time_point since) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

void validateOptions(const IrradianceGridOptions& o) {
    if (o.resolution < 1 || o.resolution > kMaxResolution)
        throw std::invalid_argument("The grid resolution is " + std::to_string(o.resolution) +
                                    " cells: choose 1 to " + std::to_string(kMaxResolution) +
                                    " cells along the longest side (8 to 32 is usual).");
    if (!(o.padding >= 0.0 && o.padding <= 1.0))
        throw std::invalid_argument("The grid padding must be a fraction of the scene's longest side in [0, 1].");
    if (o.raysPerDirection < 1 || o.raysPerDirection > kMaxRays)
        throw std::invalid_argument("The ray count is " + std::to_string(o.raysPerDirection) +
                                    ": choose 1 to 1048576 rays per grid vertex and direction (64 to 1024 is usual).");
    if (!(o.maxBackFaceFraction >= 0.0 && o.maxBackFaceFraction <= 1.0))
        throw std::invalid_argument("The back-face fraction threshold must lie in [0, 1].");
    if (o.threads < 0) throw std::invalid_argument("The thread count must be 0 (every core) or more.");
}

}  // namespace

std::size_t repairInvalidGridVertices(IrradianceVectorGrid& grid, std::vector<std::uint8_t> invalid) {
    const std::array<int, 3> n = grid.vertexCounts();
    const int F = IrradianceVectorGrid::kFloatsPerVertex, D = IrradianceVectorGrid::kFloatsPerDirection;
    std::vector<std::size_t> pending;
    for (std::size_t v = 0; v < invalid.size(); ++v)
        if (invalid[v]) pending.push_back(v);
    while (!pending.empty()) {
        std::vector<std::size_t> filled, still;
        std::vector<float> values;
        for (std::size_t v : pending) {
            const int i = int(v % n[0]), j = int((v / n[0]) % n[1]), k = int(v / (std::size_t(n[0]) * n[1]));
            float all[54] = {}, side[54] = {};
            int allCount = 0, sideCount[6] = {0, 0, 0, 0, 0, 0};
            for (int dk = -1; dk <= 1; ++dk)
                for (int dj = -1; dj <= 1; ++dj)
                    for (int di = -1; di <= 1; ++di) {
                        const int a = i + di, b = j + dj, c = k + dk;
                        if ((di | dj | dk) == 0 || a < 0 || b < 0 || c < 0 || a >= n[0] || b >= n[1] || c >= n[2]) continue;
                        const std::size_t u = grid.vertexIndex(a, b, c);
                        if (invalid[u]) continue;
                        const float* src = grid.vectors.data() + u * F;
                        for (int q = 0; q < F; ++q) all[q] += src[q];
                        ++allCount;
                        const int offset[3] = {di, dj, dk};
                        for (int d = 0; d < 6; ++d) {
                            const int o = offset[d / 2] * (d % 2 == 0 ? 1 : -1);
                            if (o <= 0) continue;
                            for (int q = 0; q < D; ++q) side[d * D + q] += src[d * D + q];
                            ++sideCount[d];
                        }
                    }
            if (allCount == 0) {
                still.push_back(v);
                continue;
            }
            filled.push_back(v);
            for (int d = 0; d < 6; ++d) {
                // Linear extrapolation along delta from the two next vertices when both are valid
                // (the indirect light near a wall varies roughly linearly), per channel kept only
                // when it does not flip the vector's component along delta.
                const int axis = d / 2, step = d % 2 == 0 ? 1 : -1;
                int p1[3] = {i, j, k}, p2[3] = {i, j, k};
                p1[axis] += step;
                p2[axis] += 2 * step;
                const bool inside = p2[axis] >= 0 && p2[axis] < n[axis];
                const std::size_t u1 = inside ? grid.vertexIndex(p1[0], p1[1], p1[2]) : 0;
                const std::size_t u2 = inside ? grid.vertexIndex(p2[0], p2[1], p2[2]) : 0;
                if (inside && !invalid[u1] && !invalid[u2]) {
                    const float* a = grid.vectors.data() + u1 * F + d * D;
                    const float* b = grid.vectors.data() + u2 * F + d * D;
                    const float sign = step > 0 ? 1.0f : -1.0f;
                    for (int c = 0; c < 3; ++c) {
                        float e[3];
                        for (int q = 0; q < 3; ++q) e[q] = 2.0f * a[3 * c + q] - b[3 * c + q];
                        const bool flips = sign * e[axis] < 0.0f;  // a hemisphere's own component is >= 0
                        for (int q = 0; q < 3; ++q) values.push_back(flips ? a[3 * c + q] : e[q]);
                    }
                    continue;
                }
                for (int q = 0; q < D; ++q)
                    values.push_back(sideCount[d] > 0 ? side[d * D + q] / float(sideCount[d]) : all[d * D + q] / float(allCount));
            }
        }
        if (filled.empty()) {
            for (std::size_t v : still) std::fill(grid.vectors.begin() + v * F, grid.vectors.begin() + (v + 1) * F, 0.0f);
            return still.size();
        }
        // Written after the wave: a wave's averages read only vertices valid before it.
        for (std::size_t f = 0; f < filled.size(); ++f) {
            std::copy(values.begin() + f * F, values.begin() + (f + 1) * F, grid.vectors.begin() + filled[f] * F);
            invalid[filled[f]] = 0;
        }
        pending.swap(still);
    }
    return 0;
}

bool irradianceVectorsFinite(const IrradianceVectorGrid& grid) {
    return std::all_of(grid.vectors.begin(), grid.vectors.end(), [](float v) { return std::isfinite(v); });
}

AnalyticLighting environmentLights(const EnvironmentMap& map, int lightCount, double scale) {
    if (lightCount < 1 || lightCount > 4096)
        throw std::invalid_argument("The light count is " + std::to_string(lightCount) +
                                    ": choose 1 to 4096 median-cut lights for the environment map (64 is usual).");
    if (!(scale > 0.0) || !std::isfinite(scale))
        throw std::invalid_argument("The environment map's intensity scale must be a positive number.");
    int levels = 0;
    while ((1 << levels) < lightCount) ++levels;
    AnalyticLighting lights;
    for (DirectionalLight l : medianCutLights(map, levels)) {
        l.irradiance *= scale;
        lights.directional.push_back(l);
    }
    return lights;
}

IrradianceVectorGrid placeIrradianceGrid(const std::array<float, 3>& boxMin, const std::array<float, 3>& boxMax,
                                         int resolution, double padding) {
    if (resolution < 1 || resolution > kMaxResolution)
        throw IrradianceVectorGridError("irradiance vector grid: the resolution is " + std::to_string(resolution) +
                                        " cells; choose 1 to " + std::to_string(kMaxResolution));
    double lo[3], hi[3], longest = 0.0;
    for (int a = 0; a < 3; ++a) {
        if (!std::isfinite(boxMin[a]) || !std::isfinite(boxMax[a]) || boxMax[a] < boxMin[a])
            throw IrradianceVectorGridError("irradiance vector grid: the scene's box is empty or not finite");
        longest = std::max(longest, double(boxMax[a]) - boxMin[a]);
    }
    if (!(longest > 0.0)) throw IrradianceVectorGridError("irradiance vector grid: the scene has no extent");
    for (int a = 0; a < 3; ++a) {
        lo[a] = boxMin[a] - padding * longest;
        hi[a] = boxMax[a] + padding * longest;
    }
    const double side = longest * (1.0 + 2.0 * padding);
    const double cell = side / resolution;
    std::array<int, 3> counts;
    std::array<float, 3> outMin, outMax;
    for (int a = 0; a < 3; ++a) {
        // Cubic cells: as many as cover this axis, the box grown symmetrically to a whole number.
        counts[a] = std::max(1, int(std::ceil((hi[a] - lo[a]) / cell - 1e-9)));
        const double centre = 0.5 * (lo[a] + hi[a]), half = 0.5 * counts[a] * cell;
        outMin[a] = float(centre - half);
        outMax[a] = float(centre + half);
    }
    return IrradianceVectorGrid::covering(outMin, outMax, counts);
}

void computeIrradianceVectors(const IndirectLightTracer& tracer, IrradianceVectorGrid& grid,
                              const IrradianceGridOptions& options, const ProgressCallback& progress,
                              IrradianceGridReport& report, std::vector<std::uint8_t>* invalidOut) {
    validateOptions(options);
    const auto start = std::chrono::steady_clock::now();
    const int R = options.raysPerDirection;
    const int padded = (R + kLanes - 1) / kLanes * kLanes;
    // Hammersley set on the hemisphere around +z, uniform in solid angle: cos theta uniform.
    std::vector<float> cosTheta(padded, 0.0f), phi0(padded, 0.0f);
    for (int i = 0; i < R; ++i) {
        cosTheta[i] = float((i + 0.5) / R);
        phi0[i] = float(2.0 * kPi * radicalInverse2(std::uint32_t(i)));
    }
    const std::size_t vertexCount = grid.vertexCount();
    grid.vectors.assign(vertexCount * IrradianceVectorGrid::kFloatsPerVertex, 0.0f);
    grid.bounces = tracer.setup().bounces;
    grid.raysPerDirection = R;
    std::vector<std::uint8_t> invalid(vertexCount, 0);
    const std::array<int, 3> n = grid.vertexCounts();

    int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
    LoopProgress loop(progress, "casting rays from the grid vertices", vertexCount);
    std::atomic<std::uint64_t> rays{0}, backFaces{0}, escaped{0};
    const double scale = 2.0 * kPi / R;
    const double threshold = options.maxBackFaceFraction * 6.0 * R;
#pragma omp parallel num_threads(threads)
    {
        const bool master = omp_get_thread_num() == 0;
        IndirectTraceCounts counts;
        RayPacket16 packet;
        float radiance[3 * kLanes];
#pragma omp for schedule(dynamic, 4) nowait
        for (std::ptrdiff_t vi = 0; vi < std::ptrdiff_t(vertexCount); ++vi) {
            if (loop.stopRequested()) continue;
            const std::size_t v = std::size_t(vi);
            const int i = int(v % n[0]), j = int((v / n[0]) % n[1]), k = int(v / (std::size_t(n[0]) * n[1]));
            const std::array<float, 3> p = grid.vertexPosition(i, j, k);
            Pcg32 rng(options.seed, v);
            std::uint64_t vertexBackFaces = 0;
            for (int d = 0; d < IrradianceVectorGrid::kDirections; ++d) {
                const int axis = d / 2;
                const float sign = (d % 2 == 0) ? 1.0f : -1.0f;
                const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;  // tangent axes
                const float rotation = float(2.0 * kPi) * rng.uniform();
                double acc[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
                for (int first = 0; first < R; first += kLanes) {
                    const int lanes = std::min(kLanes, R - first);
                    for (int l = 0; l < lanes; ++l) {
                        const float c = cosTheta[first + l], s = std::sqrt(std::max(0.0f, 1.0f - c * c));
                        const float ph = phi0[first + l] + rotation;
                        float w[3];
                        w[axis] = sign * c;
                        w[a1] = s * std::cos(ph);
                        w[a2] = s * std::sin(ph);
                        packet.originX[l] = p[0];
                        packet.originY[l] = p[1];
                        packet.originZ[l] = p[2];
                        packet.directionX[l] = w[0];
                        packet.directionY[l] = w[1];
                        packet.directionZ[l] = w[2];
                        packet.tNear[l] = 0.0f;
                        packet.tFar[l] = std::numeric_limits<float>::infinity();
                    }
                    const std::uint32_t mask = lanes == kLanes ? 0xffffu : (1u << lanes) - 1u;
                    std::uint32_t back = 0;
                    tracer.trace(packet, mask, rng, radiance, back, counts);
                    vertexBackFaces += std::uint64_t(__builtin_popcount(back));
                    for (int l = 0; l < lanes; ++l) {
                        const float* L = radiance + 3 * l;
                        if (L[0] == 0.0f && L[1] == 0.0f && L[2] == 0.0f) continue;
                        const float w[3] = {packet.directionX[l], packet.directionY[l], packet.directionZ[l]};
                        for (int ch = 0; ch < 3; ++ch)
                            for (int q = 0; q < 3; ++q) acc[3 * ch + q] += double(L[ch]) * w[q];
                    }
                }
                float* out = grid.at(v, d);
                for (int q = 0; q < 9; ++q) out[q] = float(acc[q] * scale);
            }
            if (double(vertexBackFaces) > threshold) invalid[v] = 1;
            loop.itemDone(master);
        }
        rays += counts.rays;
        backFaces += counts.backFaces;
        escaped += counts.escaped;
    }
    loop.finish();
    report.traceSeconds = seconds(start);
    report.samples = std::uint64_t(vertexCount) * 6u * std::uint64_t(R);
    report.rays = rays.load();
    report.backFaceSamples = backFaces.load();
    report.escapedSamples = escaped.load();
    report.vertices = vertexCount;
    report.cells = grid.cells;
    report.invalidVertices = std::size_t(std::count(invalid.begin(), invalid.end(), std::uint8_t(1)));
    if (invalidOut) *invalidOut = invalid;
    const auto repairStart = std::chrono::steady_clock::now();
    if (options.repairInvalid && report.invalidVertices > 0) {
        report.unreachableVertices = repairInvalidGridVertices(grid, invalid);
        report.repairedVertices = report.invalidVertices - report.unreachableVertices;
    }
    report.repairSeconds = seconds(repairStart);
    report.memoryBytes = grid.memoryBytes();
}

IrradianceVectorGrid computeIrradianceVectorGrid(const TriangleMesh& mesh, const std::vector<float>& albedo,
                                                 const AnalyticLighting& lights, const IrradianceGridOptions& options,
                                                 const ProgressCallback& progress, IrradianceGridReport* reportOut) {
    const auto start = std::chrono::steady_clock::now();
    validateOptions(options);
    reportProgress(progress, 0.0, "building the ray-casting structure");
    IndirectLightTracer tracer(mesh, albedo, lights, options.light);
    std::array<float, 3> lo{{1e30f, 1e30f, 1e30f}}, hi{{-1e30f, -1e30f, -1e30f}};
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
        for (int c = 0; c < 3; ++c) {
            lo[c] = std::min(lo[c], mesh.positions[3 * v + c]);
            hi[c] = std::max(hi[c], mesh.positions[3 * v + c]);
        }
    // The grid's vectors are allocated at once: refuse up front what the machine cannot hold (with
    // overcommit, a too-large allocation would succeed and the process be killed later).
    {
        double longest = 0.0;
        for (int a = 0; a < 3; ++a) longest = std::max(longest, double(hi[a]) - lo[a]);
        const double cell = longest * (1.0 + 2.0 * options.padding) / options.resolution;
        double vertices = 1.0;
        for (int a = 0; a < 3; ++a)  // as placeIrradianceGrid counts them
            vertices *= std::max(1.0, std::ceil((double(hi[a]) - lo[a] + 2.0 * options.padding * longest) / cell - 1e-9)) + 1.0;
        const double bytes = vertices * IrradianceVectorGrid::kFloatsPerVertex * sizeof(float) * 1.1;
        const std::size_t available = availableMemoryBytes();
        if (available > 0 && bytes > double(available))
            throw std::invalid_argument("A grid of resolution " + std::to_string(options.resolution) + " needs about " +
                                        describeBytes(bytes) + " and " + describeBytes(double(available)) +
                                        " are available: choose a lower resolution.");
    }
    IrradianceVectorGrid grid = placeIrradianceGrid(lo, hi, options.resolution, options.padding);
    IrradianceGridReport report;
    report.setupSeconds = seconds(start);
    computeIrradianceVectors(tracer, grid, options, progressRange(progress, 0.01, 1.0), report);
    report.totalSeconds = seconds(start);
    if (reportOut) *reportOut = report;
    return grid;
}

}  // namespace rad
