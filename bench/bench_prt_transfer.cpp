// bench_prt_transfer: speed of the shadowed diffuse PRT transfer (Sloan et al. 2002, sec. 5;
// prt/transfer_vectors.h) against the Embree ray loop it is built on. Prints figures, never asserts.
//
// On the same vertices and the SAME rays (the estimator's frames, local direction set and ray
// offset, read back from it) it times
//   (a) a raw Embree loop of rtcOccluded1 single rays,
//   (b) a raw Embree loop of rtcOccluded16 packets (16 directions of one vertex per packet),
// both only counting occluded rays, OpenMP over vertices, on a scene built here straight with
// Embree (same build quality and flags as raycast/ray_scene.cpp), and
//   (c) computeTransferVectors (packets through RayScene, SH row sums, one SH rotation per vertex).
// The figures: Mrays/s of each, (c)/(b) and (c)/(a) (the fraction of the raw ray throughput the
// full computation keeps; the target is >= 0.8), wall and process CPU times (best of the repeats;
// the CPU-time ratio is the steadier one on a shared machine), and the occluded-ray counts of the
// three, which must agree (for (c) recovered from the band-0 coefficient: the rotation leaves band 0
// alone, so t_0 = (visible rays / N) Y_0).
//
// Usage: bench_prt_transfer [mesh.off | mesh.rply] [--subdivide L] [--vertices N] [--rays N]
//                           [--degree D] [--threads T] [--repeat R]
// Defaults: data-cache/meshes/armadillo.off, 256 rays, degree 5, 2 threads, 1 repeat (best of R).
// --subdivide 3 on the armadillo gives the 1.66M-vertex mesh of Vanhoey et al. 2015's scale.
#include "geometry/mesh_normals.h"
#include "geometry/midpoint_subdivision.h"
#include "io/off_reader.h"
#include "io/radiance_ply.h"
#include "prt/transfer_vectors.h"
#include "radiance/spherical_harmonics.h"
#include "raycast/ray_scene.h"

#include <embree3/rtcore.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
// CPU time of the whole process (all threads): on a shared machine the wall time of a phase
// includes waiting for the cores, its CPU time much less so.
double cpuSeconds() {
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

struct Options {
    std::string mesh = std::string(RADIANCE_SOURCE_DIR) + "/data-cache/meshes/armadillo.off";
    int subdivide = 0;
    long long vertices = -1;  // all
    int rays = rad::kDefaultTransferRayCount;
    int degree = rad::kDefaultTransferDegree;
    int threads = 2;
    int repeat = 1;
};

Options parse(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> long long {
            if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
            return std::atoll(argv[++i]);
        };
        if (a == "--subdivide") o.subdivide = int(value());
        else if (a == "--vertices") o.vertices = value();
        else if (a == "--rays") o.rays = int(value());
        else if (a == "--degree") o.degree = int(value());
        else if (a == "--threads") o.threads = int(value());
        else if (a == "--repeat") o.repeat = std::max(1, int(value()));
        else if (!a.empty() && a[0] == '-') throw std::invalid_argument("unknown option " + a);
        else o.mesh = a;
    }
    return o;
}

rad::TriangleMesh load(const std::string& path) {
    const bool ply = path.size() >= 5 && path.compare(path.size() - 5, 5, ".rply") == 0;
    if (!ply) return rad::readOff(path);
    rad::RadianceMesh r = rad::readRadiancePly(path);
    rad::TriangleMesh m;
    m.positions = std::move(r.positions);
    m.normals = std::move(r.normals);
    m.faces = std::move(r.faces);
    return m;
}

// The occluders straight in Embree, as ray_scene.cpp builds them.
struct RawScene {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    explicit RawScene(const rad::TriangleMesh& mesh) {
        device = rtcNewDevice(nullptr);
        scene = rtcNewScene(device);
        rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
        rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
        RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                              3 * sizeof(float), mesh.vertexCount() + 1));
        auto* f = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                      3 * sizeof(std::uint32_t), mesh.faceCount()));
        std::memcpy(v, mesh.positions.data(), mesh.positions.size() * sizeof(float));
        std::memset(v + mesh.positions.size(), 0, 3 * sizeof(float));
        std::memcpy(f, mesh.faces.data(), mesh.faces.size() * sizeof(std::uint32_t));
        rtcCommitGeometry(g);
        rtcAttachGeometry(scene, g);
        rtcReleaseGeometry(g);
        rtcCommitScene(scene);
        if (rtcGetDeviceError(device) != RTC_ERROR_NONE) throw std::runtime_error("Embree scene build failed");
    }
    ~RawScene() {
        rtcReleaseScene(scene);
        rtcReleaseDevice(device);
    }
};

// World direction of local direction d in frame f (the estimator's formula).
inline void toWorld(const rad::TransferFrame& f, const float* d, float& x, float& y, float& z) {
    x = f.tangent[0] * d[0] + f.bitangent[0] * d[1] + f.normal[0] * d[2];
    y = f.tangent[1] * d[0] + f.bitangent[1] * d[1] + f.normal[1] * d[2];
    z = f.tangent[2] * d[0] + f.bitangent[2] * d[1] + f.normal[2] * d[2];
}

// (a): one rtcOccluded1 per ray.
std::uint64_t rawSingle(const RawScene& s, const rad::TriangleMesh& m, std::size_t count, const float* dirs, int rays,
                        float offset, int threads) {
    std::uint64_t occluded = 0;
#pragma omp parallel for num_threads(threads) schedule(dynamic, 32) reduction(+ : occluded)
    for (std::ptrdiff_t v = 0; v < std::ptrdiff_t(count); ++v) {
        rad::TransferFrame f;
        if (!rad::makeTransferFrame(m.normals.data() + 3 * v, f)) continue;
        const float* p = m.positions.data() + 3 * v;
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (int i = 0; i < rays; ++i) {
            RTCRay ray;
            ray.org_x = p[0] + offset * f.normal[0];
            ray.org_y = p[1] + offset * f.normal[1];
            ray.org_z = p[2] + offset * f.normal[2];
            toWorld(f, dirs + 3 * i, ray.dir_x, ray.dir_y, ray.dir_z);
            ray.tnear = offset;
            ray.tfar = std::numeric_limits<float>::infinity();
            ray.time = 0.0f;
            ray.mask = ~0u;
            ray.id = 0;
            ray.flags = 0;
            rtcOccluded1(s.scene, &context, &ray);
            occluded += ray.tfar == -std::numeric_limits<float>::infinity();
        }
    }
    return occluded;
}

// (b): the vertex's rays 16 at a time through rtcOccluded16.
std::uint64_t rawPacket(const RawScene& s, const rad::TriangleMesh& m, std::size_t count, const float* dirs, int rays,
                        float offset, int threads) {
    std::uint64_t occluded = 0;
#pragma omp parallel for num_threads(threads) schedule(dynamic, 32) reduction(+ : occluded)
    for (std::ptrdiff_t v = 0; v < std::ptrdiff_t(count); ++v) {
        rad::TransferFrame f;
        if (!rad::makeTransferFrame(m.normals.data() + 3 * v, f)) continue;
        const float* p = m.positions.data() + 3 * v;
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (int first = 0; first < rays; first += 16) {
            RTCRay16 packet;
            alignas(64) int valid[16];
            for (int i = 0; i < 16; ++i) {
                const bool on = first + i < rays;
                valid[i] = on ? -1 : 0;
                packet.org_x[i] = p[0] + offset * f.normal[0];
                packet.org_y[i] = p[1] + offset * f.normal[1];
                packet.org_z[i] = p[2] + offset * f.normal[2];
                if (on) toWorld(f, dirs + 3 * (first + i), packet.dir_x[i], packet.dir_y[i], packet.dir_z[i]);
                else packet.dir_x[i] = packet.dir_y[i] = packet.dir_z[i] = 0.0f;
                packet.tnear[i] = offset;
                packet.tfar[i] = std::numeric_limits<float>::infinity();
                packet.time[i] = 0.0f;
                packet.mask[i] = ~0u;
                packet.id[i] = i;
                packet.flags[i] = 0;
            }
            rtcOccluded16(valid, s.scene, &context, &packet);
            for (int i = 0; i < 16; ++i)
                occluded += valid[i] && packet.tfar[i] == -std::numeric_limits<float>::infinity();
        }
    }
    return occluded;
}

}  // namespace

int main(int argc, char** argv) try {
    const Options o = parse(argc, argv);
    const auto tLoad = Clock::now();
    rad::TriangleMesh mesh = load(o.mesh);
    if (o.subdivide > 0) mesh = rad::subdivideMidpoint(mesh, o.subdivide);
    if (!mesh.hasNormals()) rad::computeAreaWeightedNormals(mesh);
    std::printf("mesh %s%s: %zu vertices, %zu faces (loaded in %.1f s)\n", o.mesh.c_str(),
                o.subdivide ? (" subdivided " + std::to_string(o.subdivide) + "x").c_str() : "", mesh.vertexCount(),
                mesh.faceCount(), secondsSince(tLoad));

    float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
        for (int c = 0; c < 3; ++c) {
            lo[c] = std::min(lo[c], mesh.positions[3 * v + c]);
            hi[c] = std::max(hi[c], mesh.positions[3 * v + c]);
        }
    const float diagonal = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                     (hi[2] - lo[2]) * (hi[2] - lo[2]));
    const std::size_t count =
        o.vertices >= 0 ? std::min<std::size_t>(std::size_t(o.vertices), mesh.vertexCount()) : mesh.vertexCount();

    auto t0 = Clock::now();
    const rad::RayScene scene(mesh.positions.data(), mesh.vertexCount(), mesh.faces.data(), mesh.faceCount());
    const double buildScene = secondsSince(t0);
    t0 = Clock::now();
    const RawScene raw(mesh);
    const double buildRaw = secondsSince(t0);
    rad::TransferOptions options;
    options.rayCount = o.rays;
    options.degree = o.degree;
    options.threads = o.threads;
    const rad::TransferEstimator estimator(scene, diagonal, options);
    std::size_t valid = 0;
    for (std::size_t v = 0; v < count; ++v) {
        rad::TransferFrame f;
        valid += rad::makeTransferFrame(mesh.normals.data() + 3 * v, f);
    }
    const double raysTotal = double(valid) * o.rays;
    std::printf("BVH build: RayScene %.2f s, raw Embree %.2f s\n", buildScene, buildRaw);
    std::printf("%zu vertices (%zu with a usable normal), %d rays each, degree %d (%d coefficients), %d threads, "
                "best of %d\n",
                count, valid, o.rays, o.degree, estimator.coefficientCount(), o.threads, o.repeat);

    const float* dirs = estimator.localDirections();
    const float offset = estimator.rayOffset();
    double best[3] = {1e300, 1e300, 1e300}, bestCpu[3] = {1e300, 1e300, 1e300};
    std::uint64_t occluded[3] = {0, 0, 0};
    std::vector<float> transfer;
    // Interleaved repeats: machine noise (another build, turbo) hits the three alike.
    for (int r = 0; r < o.repeat; ++r) {
        for (int phase = 0; phase < 3; ++phase) {
            t0 = Clock::now();
            const double c0 = cpuSeconds();
            if (phase == 0) occluded[0] = rawSingle(raw, mesh, count, dirs, o.rays, offset, o.threads);
            if (phase == 1) occluded[1] = rawPacket(raw, mesh, count, dirs, o.rays, offset, o.threads);
            if (phase == 2)
                rad::computeTransferVectors(estimator, mesh.positions.data(), mesh.normals.data(), count, transfer,
                                            {}, o.threads);
            best[phase] = std::min(best[phase], secondsSince(t0));
            bestCpu[phase] = std::min(bestCpu[phase], cpuSeconds() - c0);
        }
    }
    // (c)'s occluded rays from band 0: t_0 = visible * Y_0 / N (the table's float Y_0).
    float y0 = 0.0f;
    rad::evaluateSphericalHarmonics(0, 0.0f, 0.0f, 1.0f, &y0);
    const int K = estimator.coefficientCount();
    for (std::size_t v = 0; v < count; ++v) {
        rad::TransferFrame f;
        if (!rad::makeTransferFrame(mesh.normals.data() + 3 * v, f)) continue;
        const long visible = std::lround(double(transfer[v * K]) * o.rays / double(y0));
        occluded[2] += std::uint64_t(o.rays - visible);
    }

    const char* names[3] = {"(a) raw rtcOccluded1 ", "(b) raw rtcOccluded16", "(c) computeTransfer  "};
    for (int i = 0; i < 3; ++i)
        std::printf("%s  wall %8.3f s  %8.2f Mrays/s   cpu %8.3f s  %6.2f Mrays/cpu-s   occluded %llu (%.2f %%)\n",
                    names[i], best[i], raysTotal / best[i] / 1e6, bestCpu[i], raysTotal / bestCpu[i] / 1e6,
                    static_cast<unsigned long long>(occluded[i]), 100.0 * double(occluded[i]) / raysTotal);
    std::printf("throughput ratio, wall: (c)/(b) = %.3f   (c)/(a) = %.3f   (b)/(a) = %.3f\n", best[1] / best[2],
                best[0] / best[2], best[0] / best[1]);
    std::printf("throughput ratio, cpu:  (c)/(b) = %.3f   (c)/(a) = %.3f   (b)/(a) = %.3f\n", bestCpu[1] / bestCpu[2],
                bestCpu[0] / bestCpu[2], bestCpu[0] / bestCpu[1]);
    std::printf("occluded counts %s\n",
                occluded[0] == occluded[1] && occluded[1] == occluded[2] ? "agree" : "DIFFER");
    std::printf("rays counted by the estimator: %llu (expected %.0f)\n",
                static_cast<unsigned long long>(estimator.raysCast()), raysTotal * o.repeat);
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "bench_prt_transfer: %s\n", e.what());
    return 1;
}
