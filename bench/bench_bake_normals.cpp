// bench_bake_normals: accuracy and speed of the normal-map baker (bake/normal_baker.h) on the
// per-triangle atlas (bake/texture_atlas.h). Prints figures, never asserts.
//
// (a) Accuracy: a fine icosphere (level 8, 1.31M faces) baked onto a coarse one (level 3), and a
//     fine torus (1024 x 512 segments, 1.05M faces) onto a coarse one (48 x 24). Per valid texel,
//     the baked normal is compared with the ANALYTIC normal of the exact surface where the texel's
//     ray (from the target point along the target normal) meets it: mean / p95 / max angle in
//     degrees, for the float map and for 8- and 16-bit quantised maps (encodeNormal8/16 then
//     decode), in object space and in tangent space (decoded back to object space with the baked
//     tangent T, the target normal N and B = N x T: the atlas is not mirrored).
// (b) Speed: the armadillo subdivided to >= 1M faces (midpoint, 3 levels: 3.33M faces) as the
//     source, the original armadillo (52k faces, area-weighted normals) as the target, at
//     4096 x 4096: seconds for the coverage, the scene (+ automatic ray distance), the rays and in
//     total, texels/s, hits and closest-point fallbacks.
//
// Usage: bench_bake_normals [--size N] [--accuracy-size N] [--mesh armadillo.off] [--subdivide L]
//                           [--threads T] [--skip-accuracy] [--skip-speed]
// Defaults: --size 4096 --accuracy-size 2048 --mesh data-cache/meshes/armadillo.off --subdivide 3
//           --threads 2.
#include "bake/normal_baker.h"
#include "bake/normal_map_bake.h"
#include "bake/texel_coverage.h"
#include "bake/texture_atlas.h"
#include "geometry/mesh_normals.h"
#include "geometry/midpoint_subdivision.h"
#include "geometry/primitive_meshes.h"
#include "io/off_reader.h"

#include <Eigen/Geometry>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct Options {
    int size = 4096;
    int accuracySize = 2048;
    std::string mesh = std::string(RADIANCE_SOURCE_DIR) + "/data-cache/meshes/armadillo.off";
    int subdivide = 3;
    int threads = 2;
    bool accuracy = true, speed = true;
};

Options parse(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
            return argv[++i];
        };
        if (a == "--size") o.size = std::atoi(value().c_str());
        else if (a == "--accuracy-size") o.accuracySize = std::atoi(value().c_str());
        else if (a == "--mesh") o.mesh = value();
        else if (a == "--subdivide") o.subdivide = std::atoi(value().c_str());
        else if (a == "--threads") o.threads = std::atoi(value().c_str());
        else if (a == "--skip-accuracy") o.accuracy = false;
        else if (a == "--skip-speed") o.speed = false;
        else throw std::invalid_argument("unknown argument " + a);
    }
    return o;
}

double angleDegrees(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / 3.14159265358979323846;
}

struct Stats {
    double mean = 0, p95 = 0, max = 0;
};
Stats summarize(std::vector<double> v) {
    Stats s;
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    for (double x : v) s.mean += x;
    s.mean /= double(v.size());
    s.p95 = v[std::min(v.size() - 1, std::size_t(0.95 * double(v.size())))];
    s.max = v.back();
    return s;
}

enum class Quantisation { Float, Bits8, Bits16 };
Eigen::Vector3d quantise(const float* n, Quantisation q) {
    Eigen::Vector3d out;
    for (int k = 0; k < 3; ++k) {
        if (q == Quantisation::Float) out[k] = n[k];
        else if (q == Quantisation::Bits8) out[k] = rad::decodeNormal8(rad::encodeNormal8(n[k]));
        else out[k] = rad::decodeNormal16(rad::encodeNormal16(n[k]));
    }
    return out.normalized();
}

// Point p and unit normal N of the target at each texel (from the same coverage as the bake).
void texelPointAndNormal(const rad::TriangleMesh& m, const rad::TexelCoverage& c, std::size_t t, Eigen::Vector3d& p,
                         Eigen::Vector3d& n) {
    const int f = c.face[t];
    const double b1 = c.barycentric[2 * t], b2 = c.barycentric[2 * t + 1], b0 = 1 - b1 - b2;
    p.setZero();
    n.setZero();
    const double w[3] = {b0, b1, b2};
    for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = m.faces[3 * std::size_t(f) + k];
        p += w[k] * Eigen::Vector3d(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]);
        n += w[k] * Eigen::Vector3d(m.normals[3 * v], m.normals[3 * v + 1], m.normals[3 * v + 2]);
    }
    n.normalize();
}

// Runs both spaces, prints a block of the table. analyticNormal(p, N) gives the exact surface's
// normal where p + t N meets it.
void accuracyCase(const char* name, const rad::TriangleMesh& source, const rad::TriangleMesh& target, int size,
                  const std::function<Eigen::Vector3d(const Eigen::Vector3d&, const Eigen::Vector3d&)>& analyticNormal) {
    const rad::PerTriangleAtlas atlas = rad::makePerTriangleAtlas(target.faceCount(), size);
    const rad::TexelCoverage coverage =
        rad::rasterizeTexelCoverage(atlas.wedgeUv.data(), target.faceCount(), size, size);
    for (const rad::NormalSpace space : {rad::NormalSpace::Object, rad::NormalSpace::Tangent}) {
        rad::NormalBakeOptions options;
        options.width = options.height = size;
        options.space = space;
        const rad::NormalBakeResult r = rad::bakeNormalMap(target, atlas.wedgeUv.data(), source, nullptr, options);
        std::vector<double> errors[3];
        for (std::size_t t = 0; t < r.valid.size(); ++t) {
            if (!r.valid[t]) continue;
            Eigen::Vector3d p, N;
            texelPointAndNormal(target, coverage, t, p, N);
            const Eigen::Vector3d exact = analyticNormal(p, N);
            const Eigen::Vector3d T(r.tangents[3 * t], r.tangents[3 * t + 1], r.tangents[3 * t + 2]);
            const Eigen::Vector3d B = N.cross(T);
            for (int q = 0; q < 3; ++q) {
                Eigen::Vector3d n = quantise(r.normals.data() + 3 * t, Quantisation(q));
                if (space == rad::NormalSpace::Tangent) n = (n.x() * T + n.y() * B + n.z() * N).normalized();
                errors[q].push_back(angleDegrees(n, exact));
            }
        }
        const char* names[3] = {"float", "8-bit", "16-bit"};
        for (int q = 0; q < 3; ++q) {
            const Stats s = summarize(errors[q]);
            std::printf("%-8s %-8s %-7s %5d %10zu %9.4f %9.4f %9.4f %7.2f\n", name,
                        space == rad::NormalSpace::Object ? "object" : "tangent", names[q], size, errors[q].size(),
                        s.mean, s.p95, s.max, r.seconds);
        }
    }
}

void accuracy(const Options& o) {
    std::printf("(a) accuracy: angle (degrees) between the baked and the analytic normal, per valid texel\n");
    std::printf("%-8s %-8s %-7s %5s %10s %9s %9s %9s %7s\n", "surface", "space", "map", "size", "texels", "mean", "p95",
                "max", "bake s");
    {
        const rad::TriangleMesh source = rad::makeIcosphere(8), target = rad::makeIcosphere(3);
        std::printf("# sphere: source icosphere level 8 (%zu faces), target level 3 (%zu faces)\n", source.faceCount(),
                    target.faceCount());
        accuracyCase("sphere", source, target, o.accuracySize, [](const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
            // |p + t n| = 1, the root nearest to t = 0.
            const double b = p.dot(n), c = p.squaredNorm() - 1, disc = std::sqrt(std::max(0.0, b * b - c));
            const double t1 = -b + disc, t2 = -b - disc;
            return (p + (std::fabs(t1) < std::fabs(t2) ? t1 : t2) * n).normalized();
        });
    }
    {
        const double R = 1.0, r = 0.35;
        const rad::TriangleMesh source = rad::makeTorus(float(R), float(r), 1024, 512);
        const rad::TriangleMesh target = rad::makeTorus(float(R), float(r), 48, 24);
        std::printf("# torus: source 1024 x 512 (%zu faces), target 48 x 24 (%zu faces)\n", source.faceCount(),
                    target.faceCount());
        accuracyCase("torus", source, target, o.accuracySize, [R, r](const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
            // Newton on the signed distance to the torus along p + t n (its gradient is the normal).
            const auto normalAt = [R](const Eigen::Vector3d& q) {
                const Eigen::Vector3d axis(q.x(), q.y(), 0.0);
                return (q - R * axis.normalized()).normalized();
            };
            const auto distance = [R, r](const Eigen::Vector3d& q) {
                return std::hypot(std::hypot(q.x(), q.y()) - R, q.z()) - r;
            };
            double t = 0;
            for (int i = 0; i < 20; ++i) {
                const Eigen::Vector3d q = p + t * n;
                t -= distance(q) / normalAt(q).dot(n);
            }
            return normalAt(p + t * n);
        });
    }
}

void speed(const Options& o) {
    std::printf("\n(b) speed: %s subdivided %d levels (source) onto itself (target), %d x %d, %d threads\n",
                o.mesh.c_str(), o.subdivide, o.size, o.size, o.threads);
    rad::TriangleMesh target = rad::readOff(o.mesh);
    rad::computeAreaWeightedNormals(target);
    Clock::time_point t0 = Clock::now();
    const rad::TriangleMesh source = rad::subdivideMidpoint(target, o.subdivide);
    std::printf("# source %zu faces, %zu vertices (subdivided in %.2f s, not counted); target %zu faces\n",
                source.faceCount(), source.vertexCount(), secondsSince(t0), target.faceCount());
    t0 = Clock::now();
    const rad::PerTriangleAtlas atlas = rad::makePerTriangleAtlas(target.faceCount(), o.size);
    const double atlasSeconds = secondsSince(t0);
    rad::NormalBakeOptions options;
    options.width = options.height = o.size;
    t0 = Clock::now();
    const rad::NormalBakeResult r = rad::bakeNormalMap(target, atlas.wedgeUv.data(), source, nullptr, options);
    const double total = secondsSince(t0) + atlasSeconds;
    std::printf("%6s %9s %8s %9s %8s %8s %10s %12s %10s %10s %9s %8s\n", "size", "cell", "atlas s", "coverage s",
                "scene s", "rays s", "total s", "chart texels", "texels/s", "hits", "fallbacks", "invalid");
    std::printf("%6d %9d %8.3f %9.3f %8.3f %8.3f %10.3f %12zu %10.3g %10zu %9zu %8zu\n", o.size, atlas.cellSize,
                atlasSeconds, r.coverageSeconds, r.sceneSeconds, r.raySeconds, total, r.chartTexels,
                double(r.chartTexels) / total, r.rayHits, r.closestPointFallbacks, r.invalidTexels);
    std::printf("# ray distance %.4g; all texels (incl. empty) per second: %.3g\n", r.maxRayDistance,
                double(o.size) * o.size / total);

    // (c) The whole job of the filter (bake/normal_map_bake.h): atlas, bake, filling, LEAN, files.
    const std::filesystem::path folder = std::filesystem::temp_directory_path() / "bench_bake_normals";
    std::filesystem::create_directories(folder);
    std::printf("\n(c) whole filter job (atlas, bake, fill, LEAN, 16-bit PNG + EXR + description), %d x %d\n", o.size,
                o.size);
    std::printf("%8s %8s %8s %8s %8s %10s\n", "bake s", "fill s", "LEAN s", "write s", "total s", "MB written");
    rad::NormalMapBakeRequest request;
    request.target = &target;
    request.source = &source;
    request.textureSize = o.size;
    request.outputBase = (folder / "armadillo").string();
    const rad::NormalMapBakeReport job = rad::bakeNormalMapFiles(request);
    double megabytes = 0.0;
    for (const std::string& file : {job.normalMapFile, job.leanFile, job.descriptionFile}) {
        megabytes += std::filesystem::file_size(file) / 1048576.0;
        std::filesystem::remove(file);
    }
    std::printf("%8.3f %8.3f %8.3f %8.3f %8.3f %10.1f\n", job.bakeSeconds, job.fillSeconds, job.leanSeconds,
                job.writeSeconds, job.totalSeconds, megabytes);
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const Options o = parse(argc, argv);
        omp_set_num_threads(o.threads);
        if (o.accuracy) accuracy(o);
        if (o.speed) speed(o);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_bake_normals: %s\n", e.what());
        return 1;
    }
    return 0;
}
