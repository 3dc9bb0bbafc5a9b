// See indirect_light_reference.h. The hemisphere integrals (reference pixels, per-vertex
// irradiance) share one routine: N cosine-distributed rays in 16-ray packets through the tracer.
#include "render/indirect_light_reference.h"

#include "raycast/ray_scene.h"
#include "sampling/radical_inverse.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace rad {

namespace {

constexpr float kPi = 3.14159265358979323846f;
constexpr int kLanes = RayPacket16::kSize;

// Local cosine-distributed Hammersley directions (cell-centred; z up).
struct CosineSet {
    std::vector<float> x, y, z;
    explicit CosineSet(int n) : x(n), y(n), z(n) {
        for (int i = 0; i < n; ++i) {
            const double u1 = (i + 0.5) / n, phi = 2.0 * 3.14159265358979323846 * radicalInverse2(std::uint32_t(i));
            const double r = std::sqrt(u1);
            x[i] = float(r * std::cos(phi));
            y[i] = float(r * std::sin(phi));
            z[i] = float(std::sqrt(std::max(0.0, 1.0 - u1)));
        }
    }
};

// E_ind / pi at point p with unit normal n: mean of L_ind over cosine-distributed directions.
void meanIncidentRadiance(const IndirectLightTracer& tracer, const CosineSet& set, const float p[3], const float n[3],
                          float offset, Pcg32& rng, IndirectTraceCounts& counts, double out[3]) {
    out[0] = out[1] = out[2] = 0.0;
    const float sign = std::copysign(1.0f, n[2]);
    const float a = -1.0f / (sign + n[2]);
    const float b = n[0] * n[1] * a;
    const float t0[3] = {1.0f + sign * n[0] * n[0] * a, sign * b, -sign * n[0]};
    const float b0[3] = {b, sign + n[1] * n[1] * a, -n[1]};
    // A random turn about n per point: the same set, decorrelated between points.
    const float angle = 2.0f * kPi * rng.uniform(), ca = std::cos(angle), sa = std::sin(angle);
    float t[3], bt[3];
    for (int k = 0; k < 3; ++k) {
        t[k] = ca * t0[k] + sa * b0[k];
        bt[k] = -sa * t0[k] + ca * b0[k];
    }
    RayPacket16 packet;
    float radiance[3 * kLanes];
    const int N = int(set.x.size());
    for (int first = 0; first < N; first += kLanes) {
        const int lanes = std::min(kLanes, N - first);
        for (int l = 0; l < lanes; ++l) {
            const float x = set.x[first + l], y = set.y[first + l], z = set.z[first + l];
            packet.originX[l] = p[0] + offset * n[0];
            packet.originY[l] = p[1] + offset * n[1];
            packet.originZ[l] = p[2] + offset * n[2];
            packet.directionX[l] = t[0] * x + bt[0] * y + n[0] * z;
            packet.directionY[l] = t[1] * x + bt[1] * y + n[1] * z;
            packet.directionZ[l] = t[2] * x + bt[2] * y + n[2] * z;
            packet.tNear[l] = 0.0f;
            packet.tFar[l] = std::numeric_limits<float>::infinity();
        }
        std::uint32_t back = 0;
        tracer.trace(packet, lanes == kLanes ? 0xffffu : (1u << lanes) - 1u, rng, radiance, back, counts);
        for (int l = 0; l < lanes; ++l)
            for (int c = 0; c < 3; ++c) out[c] += radiance[3 * l + c];
    }
    for (int c = 0; c < 3; ++c) out[c] /= N;
}

int threadCount(int threads) { return threads > 0 ? threads : omp_get_max_threads(); }

}  // namespace

std::size_t VisibleSurface::visiblePixels() const {
    return std::size_t(std::count(mask.begin(), mask.end(), std::uint8_t(1)));
}

VisibleSurface traceVisibleSurface(const IndirectLightTracer& tracer, const PinholeCamera& camera) {
    const std::string problem = camera.validate();
    if (!problem.empty()) throw std::invalid_argument("The camera is unusable: " + problem);
    VisibleSurface s;
    s.width = camera.width;
    s.height = camera.height;
    const std::size_t n = std::size_t(s.width) * s.height;
    s.points.assign(3 * n, 0.0f);
    s.normals.assign(3 * n, 0.0f);
    s.albedo.assign(3 * n, 0.0f);
    s.mask.assign(n, 0);
    const float origin[3] = {float(camera.center[0]), float(camera.center[1]), float(camera.center[2])};
#pragma omp parallel for schedule(dynamic, 16)
    for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(n); ++i) {
        const int column = int(i % s.width), row = int(i / s.width);
        const Eigen::Vector3d d = camera.rayDirection(column + 0.5, row + 0.5);
        const float direction[3] = {float(d[0]), float(d[1]), float(d[2])};
        bool back = false;
        if (!tracer.firstHit(origin, direction, &s.points[3 * i], &s.normals[3 * i], &s.albedo[3 * i], back)) continue;
        if (back) {
            std::fill(&s.points[3 * i], &s.points[3 * i] + 3, 0.0f);
            continue;
        }
        s.mask[i] = 1;
    }
    return s;
}

ImageF renderIndirectReference(const IndirectLightTracer& tracer, const VisibleSurface& surface, int raysPerPixel,
                               std::uint64_t seed, const ProgressCallback& progress, int threads) {
    if (raysPerPixel < 1) throw std::invalid_argument("The reference needs at least one ray per pixel.");
    ImageF image(surface.width, surface.height);
    const CosineSet set(raysPerPixel);
    const std::size_t n = std::size_t(surface.width) * surface.height;
    LoopProgress loop(progress, "integrating the reference hemispheres", n);
#pragma omp parallel num_threads(threadCount(threads))
    {
        const bool master = omp_get_thread_num() == 0;
        IndirectTraceCounts counts;
#pragma omp for schedule(dynamic, 8) nowait
        for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(n); ++i) {
            if (loop.stopRequested()) continue;
            if (surface.mask[i]) {
                Pcg32 rng(seed, std::uint64_t(i));
                double mean[3];
                meanIncidentRadiance(tracer, set, &surface.points[3 * i], &surface.normals[3 * i], tracer.rayOffset(), rng,
                                     counts, mean);
                // rho / pi * E, E = pi * mean.
                for (int c = 0; c < 3; ++c) image.rgb[3 * i + c] = float(surface.albedo[3 * i + c] * mean[c]);
            }
            loop.itemDone(master);
        }
    }
    loop.finish();
    return image;
}

ImageF renderIndirectFromGrid(const IrradianceVectorGrid& grid, const VisibleSurface& surface,
                              DirectionalWeights weights) {
    ImageF image(surface.width, surface.height);
    const std::size_t n = std::size_t(surface.width) * surface.height;
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(n); ++i) {
        if (!surface.mask[i]) continue;
        const float* p = &surface.points[3 * i];
        const float* nn = &surface.normals[3 * i];
        const float* rho = &surface.albedo[3 * i];
        float* out = &image.rgb[3 * i];
        reflectedRadiance(grid, p, nn, rho, out, weights);
    }
    return image;
}

std::vector<float> computeVertexIndirectIrradiance(const IndirectLightTracer& tracer, const TriangleMesh& mesh,
                                                   int raysPerVertex, double relativeOffset, std::uint64_t seed,
                                                   const ProgressCallback& progress, int threads) {
    if (raysPerVertex < 1) throw std::invalid_argument("The per-vertex irradiance needs at least one ray per vertex.");
    if (!mesh.hasNormals()) throw std::invalid_argument("The per-vertex irradiance needs vertex normals.");
    const std::size_t n = mesh.vertexCount();
    std::vector<float> out(3 * n, 0.0f);
    const CosineSet set(raysPerVertex);
    const float offset = float(relativeOffset * tracer.sceneDiagonal());
    LoopProgress loop(progress, "integrating the per-vertex hemispheres", n);
#pragma omp parallel num_threads(threadCount(threads))
    {
        const bool master = omp_get_thread_num() == 0;
        IndirectTraceCounts counts;
#pragma omp for schedule(dynamic, 8) nowait
        for (std::ptrdiff_t v = 0; v < std::ptrdiff_t(n); ++v) {
            if (loop.stopRequested()) continue;
            const float* nn = &mesh.normals[3 * v];
            const float length = std::sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
            if (length > 0.0f) {
                const float unit[3] = {nn[0] / length, nn[1] / length, nn[2] / length};
                Pcg32 rng(seed, std::uint64_t(v));
                double mean[3];
                meanIncidentRadiance(tracer, set, &mesh.positions[3 * v], unit, offset, rng, counts, mean);
                for (int c = 0; c < 3; ++c) out[3 * v + c] = float(kPi * mean[c]);
            }
            loop.itemDone(master);
        }
    }
    loop.finish();
    return out;
}

ImageF renderIndirectFromVertexIrradiance(const TriangleMesh& mesh, const std::vector<float>& vertexIrradiance,
                                          const VisibleSurface& surface) {
    if (vertexIrradiance.size() != 3 * mesh.vertexCount())
        throw std::invalid_argument("The per-vertex irradiance does not match the mesh's vertices.");
    const RayScene scene(mesh.positions.data(), mesh.vertexCount(), mesh.faces.data(), mesh.faceCount());
    ImageF image(surface.width, surface.height);
    const std::size_t n = std::size_t(surface.width) * surface.height;
#pragma omp parallel for schedule(dynamic, 16)
    for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(n); ++i) {
        if (!surface.mask[i]) continue;
        const float* p = &surface.points[3 * i];
        const ClosestPoint c = scene.closestPoint(Eigen::Vector3f(p[0], p[1], p[2]));
        if (!c.found) continue;
        const std::uint32_t* f = &mesh.faces[3 * c.face];
        const float w[3] = {1.0f - c.u - c.v, c.u, c.v};
        for (int ch = 0; ch < 3; ++ch) {
            float e = 0.0f;
            for (int k = 0; k < 3; ++k) e += w[k] * vertexIrradiance[3 * f[k] + ch];
            image.rgb[3 * i + ch] = std::max(0.0f, surface.albedo[3 * i + ch] / kPi * e);
        }
    }
    return image;
}

IndirectImageError indirectImageError(const ImageF& image, const ImageF& reference, const std::vector<std::uint8_t>& mask) {
    if (image.width != reference.width || image.height != reference.height ||
        mask.size() != std::size_t(image.width) * image.height)
        throw std::invalid_argument("The images to compare differ in size.");
    IndirectImageError e;
    double sq = 0.0, sum = 0.0;
    for (std::size_t i = 0; i < mask.size(); ++i) {
        if (!mask[i]) continue;
        ++e.pixels;
        for (int c = 0; c < 3; ++c) {
            const double d = double(image.rgb[3 * i + c]) - reference.rgb[3 * i + c];
            sq += d * d;
            sum += reference.rgb[3 * i + c];
        }
    }
    if (e.pixels) {
        e.rmse = std::sqrt(sq / (3.0 * e.pixels));
        e.meanReference = sum / (3.0 * e.pixels);
    }
    return e;
}

}  // namespace rad
