// bench_fit: figures of "Fit Radiance Functions from Rasters" (printed, never asserted).
//   1. per-vertex robust fit (fit/robust_radiance_fit.h) throughput, vertices/s, PB4 and SH6, ~25
//      samples per vertex (the views of a 50-camera sphere rig within 80 degrees of the normal),
//      range guard off / poorly sampled only / all vertices, 1 and 2 threads;
//   2. accuracy of the fit against a known glossy radiance (Lambert + Blinn-Phong lobe of
//      radiance/analytic_material.h, one light, 0.01 Gaussian noise on the samples) for the three
//      guard scopes and a few camera rigs: RMS error over the hemisphere and near the samples;
//   3. sample gathering (fit/view_sampling.h) on a synthetic scene: a UV sphere of ~1M vertices,
//      50 cameras around it with synthetic 2 MP images: occlusion rays/s and vertices/s, 1 and 2
//      threads; then the whole driver fitRadianceFromViews (PB4) on the same scene.
// Usage: bench_fit [sphere_vertices (default 1000000)] [views (default 50)] [image_width (default 1632)]
//        (image height = 3/4 of the width; 1632 x 1224 = 2.0 MP)
#include "fit/radiance_from_views.h"
#include "fit/robust_radiance_fit.h"
#include "fit/view_sampling.h"
#include "geometry/primitive_meshes.h"
#include "radiance/analytic_material.h"
#include "radiance/radiance_evaluation.h"
#include "radiance/radiance_field.h"
#include "radiance/radiance_frame.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <omp.h>
#include <random>
#include <string>
#include <vector>

namespace {

using Eigen::Vector3d;
using Clock = std::chrono::steady_clock;
constexpr double kPi = 3.14159265358979323846;
volatile double g_sink = 0.0;

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Directions of a camera rig: count points of a Fibonacci spiral in the elevation band
// [elMin, elMax] degrees (z up), turned by `turn` radians about z.
std::vector<Vector3d> rigDirections(int count, double elMinDeg, double elMaxDeg, double turn) {
    std::vector<Vector3d> out;
    const double golden = kPi * (3.0 - std::sqrt(5.0));
    const double s0 = std::sin(elMinDeg * kPi / 180), s1 = std::sin(elMaxDeg * kPi / 180);
    for (int i = 0; i < count; ++i) {
        const double z = s0 + (s1 - s0) * (i + 0.5) / count, r = std::sqrt(1 - z * z), a = i * golden + turn;
        out.emplace_back(r * std::cos(a), r * std::sin(a), z);
    }
    return out;
}

struct Material {
    rad::AnalyticMaterial material;
    rad::AnalyticLighting lighting;
    Material() {
        material.albedo = rad::Rgb(0.6, 0.4, 0.3);
        material.specular = rad::Rgb(0.3, 0.3, 0.3);
        material.exponent = 20;
        lighting.directional.push_back({Vector3d(0.3, 0.2, 1.0), rad::Rgb::Constant(2.0)});
        lighting.ambient = rad::Rgb::Constant(0.1);
    }
    Vector3d operator()(const Vector3d& n, const Vector3d& w) const {
        return rad::outgoingRadiance(material, lighting, Vector3d::Zero(), n, w);
    }
};

// Samples of a vertex with normal n seen by the rig's cameras within 80 degrees of n.
std::vector<rad::DirectionalSample> rigSamples(const std::vector<Vector3d>& rig, const Vector3d& n, const Material& f,
                                               std::mt19937& rng) {
    std::normal_distribution<double> noise(0.0, 0.01);
    std::vector<rad::DirectionalSample> s;
    for (const Vector3d& d : rig) {
        const double c = d.dot(n);
        if (c < std::cos(80 * kPi / 180)) continue;
        const Vector3d L = f(n, d);
        rad::DirectionalSample x;
        for (int k = 0; k < 3; ++k) {
            x.direction[k] = static_cast<float>(d[k]);
            x.rgb[k] = static_cast<float>(L[k] + noise(rng));
        }
        x.weight = static_cast<float>(c);
        s.push_back(x);
    }
    return s;
}

const char* scopeName(rad::RangeGuardScope s) {
    switch (s) {
        case rad::RangeGuardScope::Off: return "guard off      ";
        case rad::RangeGuardScope::PoorlySampledOnly: return "guard poorly   ";
        default: return "guard all      ";
    }
}

// ---- 1. throughput -------------------------------------------------------------------------------

void benchFitThroughput(const rad::BasisSpec& basis) {
    const int vertices = 20000;
    std::mt19937 rng(1);
    std::normal_distribution<double> g;
    const Material material;
    const std::vector<Vector3d> rig = rigDirections(50, -90, 90, 0.3);
    std::vector<rad::Frame> frames(vertices);
    std::vector<std::vector<rad::DirectionalSample>> samples(vertices);
    double total = 0;
    for (int v = 0; v < vertices; ++v) {
        const Vector3d n = Vector3d(g(rng), g(rng), g(rng)).normalized();
        frames[v] = rad::frameFromNormal(n);
        samples[v] = rigSamples(rig, n, material, rng);
        total += samples[v].size();
    }
    std::vector<float> out(static_cast<std::size_t>(vertices) * 3 * basis.coefficientCount());
    for (rad::RangeGuardScope scope :
         {rad::RangeGuardScope::Off, rad::RangeGuardScope::PoorlySampledOnly, rad::RangeGuardScope::AllVertices}) {
        rad::RobustFitOptions options;
        options.basis = basis;
        options.rangeGuard = scope;
        const rad::RobustRadianceFitter fitter(options);
        for (int threads : {1, 2}) {
            omp_set_num_threads(threads);
            const int rounds = 3;
            long retried = 0;
            const auto t0 = Clock::now();
            for (int r = 0; r < rounds; ++r) {
#pragma omp parallel reduction(+ : retried)
                {
                    rad::FitScratch scratch = fitter.makeScratch();
#pragma omp for schedule(dynamic, 256)
                    for (int v = 0; v < vertices; ++v) {
                        const rad::VertexFitResult res =
                            fitter.fit(frames[v], samples[v].data(), samples[v].size(), scratch,
                                       out.data() + static_cast<std::size_t>(v) * fitter.coefficientsPerVertex());
                        retried += res.guardRetries > 0;
                    }
                }
            }
            const double s = secondsSince(t0);
            std::printf("fit %-4s %s %.1f samples/vertex  %2d thread%s  %9.0f vertices/s  (%4.1f us/vertex/thread, "
                        "%.0f%% guard-retried)\n",
                        basis.name().c_str(), scopeName(scope), total / vertices, threads, threads > 1 ? "s" : " ",
                        rounds * vertices / s, 1e6 * s * threads / (rounds * vertices),
                        100.0 * retried / (rounds * vertices));
            g_sink = g_sink + out[7];
        }
    }
}

// ---- 2. accuracy ---------------------------------------------------------------------------------

void benchAccuracy(const rad::BasisSpec& basis) {
    struct Rig {
        const char* name;
        int count;
        double elMin, elMax;
    };
    const Rig rigs[] = {{"sphere of 300 views", 300, -90, 90},
                        {"sphere of 50 views", 50, -90, 90},
                        {"sphere of 25 views", 25, -90, 90},
                        {"ring of 12 views, elevation 10-40", 12, 10, 40}};
    const Material truth;
    for (const Rig& rig : rigs) {
        for (rad::RangeGuardScope scope :
             {rad::RangeGuardScope::Off, rad::RangeGuardScope::PoorlySampledOnly, rad::RangeGuardScope::AllVertices}) {
            rad::RobustFitOptions options;
            options.basis = basis;
            options.rangeGuard = scope;
            const rad::RobustRadianceFitter fitter(options);
            rad::FitScratch scratch = fitter.makeScratch();
            std::mt19937 rng(42);
            std::normal_distribution<double> g;
            std::uniform_real_distribution<double> u(0, 1);
            double errAll = 0, errNear = 0, worst = 0;
            long nAll = 0, nNear = 0, poorly = 0, retried = 0, samples = 0;
            const int trials = 300;
            for (int t = 0; t < trials; ++t) {
                const Vector3d n = Vector3d(g(rng), g(rng), g(rng)).normalized();
                const std::vector<Vector3d> dirs = rigDirections(rig.count, rig.elMin, rig.elMax, 2 * kPi * u(rng));
                const std::vector<rad::DirectionalSample> s = rigSamples(dirs, n, truth, rng);
                samples += static_cast<long>(s.size());
                rad::RadianceField field(basis, 1, false);
                rad::storeFrame(rad::frameFromNormal(n), field.frame(0));
                const rad::VertexFitResult r =
                    fitter.fit(rad::frameFromStored(field.frame(0)), s.data(), s.size(), scratch, field.coefficients.data());
                poorly += r.status == rad::FitStatus::PoorlySampled;
                retried += r.guardRetries > 0;
                for (int i = 0; i < 400; ++i) {
                    Vector3d w = Vector3d(g(rng), g(rng), g(rng)).normalized();
                    if (w.dot(n) < 0) w = -w;
                    const double e = (rad::evaluateRadiance(field, 0, w) - truth(n, w)).squaredNorm() / 3;
                    errAll += e;
                    ++nAll;
                    worst = std::max(worst, std::sqrt(e));
                    bool near = false;
                    for (const auto& x : s)
                        near = near || Vector3d(x.direction[0], x.direction[1], x.direction[2]).dot(w) > std::cos(15 * kPi / 180);
                    if (near) {
                        errNear += e;
                        ++nNear;
                    }
                }
            }
            std::printf("accuracy %-4s %-34s %s %5.1f samples  poorly %3.0f%%  retried %3.0f%%  RMS hemisphere %.4f  "
                        "RMS within 15 deg of a sample %.4f  worst %.3f\n",
                        basis.name().c_str(), rig.name, scopeName(scope), double(samples) / trials,
                        100.0 * poorly / trials, 100.0 * retried / trials, std::sqrt(errAll / nAll),
                        std::sqrt(errNear / std::max(1L, nNear)), worst);
        }
    }
}

// ---- 3. sampling and the whole driver -------------------------------------------------------------

struct SyntheticViews {
    std::vector<rad::Image8> images;
    std::vector<rad::CalibratedView> views;
};

// `count` cameras on a Fibonacci sphere at distance 3.2 around the unit sphere, 40-degree
// horizontal field of view (the sphere fills most of the frame), images with a smooth synthetic
// pattern that differs per view (so that the fit sees view-dependent colours).
SyntheticViews makeViews(int count, int width, int height) {
    SyntheticViews out;
    out.images.reserve(count);
    const std::vector<Vector3d> dirs = rigDirections(count, -90, 90, 0.1);
    for (int i = 0; i < count; ++i) {
        const rad::PinholeCamera cam =
            rad::PinholeCamera::lookAt(3.2 * dirs[i], Vector3d::Zero(), Vector3d(0.05, 0.1, 1.0), 40.0, width, height);
        out.images.emplace_back(width, height);
        rad::Image8& im = out.images.back();
        for (int r = 0; r < height; ++r)
            for (int c = 0; c < width; ++c) {
                std::uint8_t* p = im.pixel(c, r);
                p[0] = static_cast<std::uint8_t>(96 + 60 * std::sin(0.01 * c + 0.3 * i));
                p[1] = static_cast<std::uint8_t>(96 + 60 * std::sin(0.013 * r + 0.2 * i));
                p[2] = static_cast<std::uint8_t>(128 + ((c + r + 7 * i) & 63));
            }
        out.views.push_back({cam, im.view()});
    }
    return out;
}

void benchSampling(const rad::TriangleMesh& mesh, const SyntheticViews& views) {
    const auto t0 = Clock::now();
    const rad::ViewSampler sampler(mesh, views.views);
    std::printf("Embree scene of %zu faces built in %.2f s\n", mesh.faceCount(), secondsSince(t0));
    const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(mesh.vertexCount());
    for (int threads : {1, 2}) {
        omp_set_num_threads(threads);
        std::size_t rays = 0, samples = 0, facing = 0, occluded = 0;
        const auto t1 = Clock::now();
#pragma omp parallel reduction(+ : rays, samples, facing, occluded)
        {
            std::vector<rad::DirectionalSample> buffer(sampler.viewCount());
            rad::SamplingCounters counters;
#pragma omp for schedule(dynamic, 256)
            for (std::ptrdiff_t v = 0; v < n; ++v) sampler.sampleVertex(static_cast<std::size_t>(v), buffer.data(), &counters);
            rays += counters.raysCast;
            samples += counters.samples;
            facing += counters.facing;
            occluded += counters.occluded;
        }
        const double s = secondsSince(t1);
        std::printf("sampling %zu vertices x %zu views, %d thread%s: %.2f s, %.2f M occlusion rays/s, %.0f vertices/s "
                    "(%.1f samples/vertex, %.1f facing, %zu occluded)\n",
                    mesh.vertexCount(), sampler.viewCount(), threads, threads > 1 ? "s" : " ", s, rays / s / 1e6, n / s,
                    double(samples) / n, double(facing) / n, occluded);
    }
}

void benchDriver(const rad::TriangleMesh& mesh, const SyntheticViews& views, const rad::BasisSpec& basis) {
    omp_set_num_threads(2);
    rad::RadianceFromViewsOptions options;
    options.fit.basis = basis;
    const rad::RadianceFromViewsResult r = rad::fitRadianceFromViews(mesh, views.views, options);
    std::printf("fitRadianceFromViews %s, %zu vertices x %zu views (%d x %d), 2 threads: %.2f s  "
                "(fitted %zu, poorly sampled %zu, filled %zu, left %zu, guard-retried %zu, constant %zu, %.1f samples/vertex)\n",
                basis.name().c_str(), mesh.vertexCount(), views.views.size(), views.views.front().image.width,
                views.views.front().image.height, r.seconds, r.fitted, r.poorlySampled, r.unseenFilled, r.unseenLeft,
                r.guardRetried, r.constantFallbacks, double(r.totalSamples) / mesh.vertexCount());
}

}  // namespace

int main(int argc, char** argv) {
    const long vertexTarget = argc > 1 ? std::atol(argv[1]) : 1000000;
    const int viewCount = argc > 2 ? std::atoi(argv[2]) : 50;
    const int width = argc > 3 ? std::atoi(argv[3]) : 1632;
    if (vertexTarget < 100 || viewCount < 1 || width < 16) {
        std::fprintf(stderr, "usage: bench_fit [sphere_vertices >= 100] [views >= 1] [image_width >= 16]\n");
        return 2;
    }
    const int height = width * 3 / 4;
    const int maxThreads = omp_get_max_threads();
    std::printf("bench_fit: %d hardware threads available\n", maxThreads);

    benchFitThroughput(rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, 4});
    benchFitThroughput(rad::BasisSpec{rad::BasisKind::SphericalHarmonics, 6});
    omp_set_num_threads(maxThreads);
    benchAccuracy(rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, 4});
    benchAccuracy(rad::BasisSpec{rad::BasisKind::SphericalHarmonics, 6});

    // UV sphere: (stacks - 1) * slices + 2 vertices, slices = 2 stacks.
    const int stacks = std::max(3, static_cast<int>(std::lround(std::sqrt(vertexTarget / 2.0))));
    const rad::TriangleMesh mesh = rad::makeUvSphere(stacks, 2 * stacks);
    const auto t0 = Clock::now();
    const SyntheticViews views = makeViews(viewCount, width, height);
    std::printf("scene: UV sphere of %zu vertices, %d views of %d x %d (%.1f MP), images made in %.1f s\n",
                mesh.vertexCount(), viewCount, width, height, width * double(height) / 1e6, secondsSince(t0));
    benchSampling(mesh, views);
    benchDriver(mesh, views, rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, 4});
    benchDriver(mesh, views, rad::BasisSpec{rad::BasisKind::SphericalHarmonics, 6});
    std::printf("(sink %g)\n", static_cast<double>(g_sink));
    return 0;
}
