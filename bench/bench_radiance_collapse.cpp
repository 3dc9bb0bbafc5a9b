// bench_radiance_collapse: figures of the half-edge radiance error of Vanhoey et al. 2015 eq. (7)
// (simplify/radiance_collapse_error.h), printed, never asserted.
//   1. rule table: relative error of every half-edge cost with small Gauss product hemisphere rules
//      against the 12 x 24 = 288-point rule of radiance_distance.h, and time per source vertex, on
//      (a) random smooth RF on bumpy patches, vertex normals tilted up to 15 degrees from the mean
//          (up to 30 between neighbours),
//      (b) the analytic striped glossy material (Vanhoey et al. 2015 Fig. 8) projected on icospheres of level
//          1, 2, 3 (normals 32-36, 16-19, 8-9.5 degrees apart between neighbours);
//   2. speed: every vertex of a >= 100k-vertex icosphere priced (all its half-edges), PB4 and SH6,
//      default rule and 288-point rule, 1 thread and all threads, with the number of heap
//      allocations made while pricing (the metric claims none once its scratch is warm).
// Usage: bench_radiance_collapse [icosphere_level (default 7: 163842 vertices)] [rounds (default 3)] [speed]
// ("speed" skips the rule table).
#include "geometry/primitive_meshes.h"
#include "radiance/material_radiance.h"
#include "radiance/radiance_distance.h"
#include "radiance/radiance_frame.h"
#include "simplify/collapse_mesh.h"
#include "simplify/radiance_collapse_error.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <omp.h>
#include <new>
#include <random>
#include <string>
#include <vector>

// Every operator new of the program is counted, to check that pricing does not allocate once its
// per-thread scratch has grown (the header's claim).
static std::atomic<long long> g_allocations{0};
void* operator new(std::size_t size) {
    ++g_allocations;
    if (void* p = std::malloc(size ? size : 1)) return p;
    throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace {

volatile double g_sink = 0.0;
using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
// CPU time of the calling thread: single-thread figures that a busy machine does not inflate.
double threadSeconds() {
    timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}
constexpr double kPi = 3.14159265358979323846;

const rad::BasisSpec kPB4{rad::BasisKind::HemisphericalPolynomial, 4};
const rad::BasisSpec kSH6{rad::BasisKind::SphericalHarmonics, 6};

// Stars and neighbour lists of every vertex, flat (built once, outside the timings).
struct Stars {
    std::vector<rad::StarFace> faces;
    std::vector<std::uint32_t> targets;
    std::vector<std::size_t> faceStart, targetStart;  // vertexCount + 1 each
};

Stars allStars(const rad::CollapseMesh& mesh) {
    Stars s;
    std::vector<rad::StarFace> star;
    std::vector<std::uint32_t> ring;
    for (std::uint32_t v = 0; v < mesh.vertexCount(); ++v) {
        s.faceStart.push_back(s.faces.size());
        s.targetStart.push_back(s.targets.size());
        mesh.star(v, star);
        mesh.neighbours(v, ring);
        s.faces.insert(s.faces.end(), star.begin(), star.end());
        s.targets.insert(s.targets.end(), ring.begin(), ring.end());
    }
    s.faceStart.push_back(s.faces.size());
    s.targetStart.push_back(s.targets.size());
    return s;
}

rad::HalfEdgeQuery query(const Stars& s, std::uint32_t v) {
    rad::HalfEdgeQuery q;
    q.source = v;
    q.star = s.faces.data() + s.faceStart[v];
    q.starSize = static_cast<int>(s.faceStart[v + 1] - s.faceStart[v]);
    q.targets = s.targets.data() + s.targetStart[v];
    q.targetCount = static_cast<int>(s.targetStart[v + 1] - s.targetStart[v]);
    return q;
}

// Costs of every half-edge of every vertex (index = position in s.targets), `threads` threads;
// returns the wall-clock seconds spent, and the calling thread's CPU seconds in *cpu (meaningful
// for one thread).
double priceEverything(const rad::RadianceCollapseMetric& metric, const rad::CollapseMesh& mesh, const Stars& s,
                       int threads, std::vector<double>& costs, double* cpu = nullptr) {
    costs.assign(s.targets.size(), 0.0);
    const long long n = static_cast<long long>(mesh.vertexCount());
    const double c0 = threadSeconds();
    const auto t0 = Clock::now();
#pragma omp parallel for num_threads(threads) schedule(dynamic, 512)
    for (long long v = 0; v < n; ++v) {
        const rad::HalfEdgeQuery q = query(s, static_cast<std::uint32_t>(v));
        metric.priceHalfEdges(mesh, q, costs.data() + s.targetStart[v]);
    }
    const double wall = secondsSince(t0);
    if (cpu) *cpu = threadSeconds() - c0;
    return wall;
}

// A jittered bumpy triangular grid n x n (valence 6 inside).
rad::CollapseMesh makePatch(int n, std::mt19937& rng) {
    std::uniform_real_distribution<double> jitter(-0.15, 0.15);
    std::vector<float> p;
    std::vector<std::uint32_t> f;
    const auto at = [n](int i, int j) { return static_cast<std::uint32_t>(j * n + i); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double x = i + 0.5 * j + jitter(rng), y = j * std::sqrt(3.0) / 2 + jitter(rng);
            p.insert(p.end(), {float(x), float(y), float(0.25 * std::sin(1.3 * x) * std::cos(0.9 * y))});
        }
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) f.insert(f.end(), {at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
    return rad::CollapseMesh(p.data(), p.size() / 3, f.data(), f.size() / 3);
}

// Random smooth RF: a random base function (coefficients decaying with the order, like fitted
// data) plus a per-vertex variation of 30 %; normals tilted from +z by up to 15 degrees.
rad::RadianceField randomSmoothField(const rad::BasisSpec& basis, std::size_t count, std::mt19937& rng) {
    rad::RadianceField f(basis, count);
    std::uniform_real_distribution<double> u(-1, 1), angle(0, 15 * kPi / 180);
    std::normal_distribution<double> g;
    const int K = basis.coefficientCount();
    std::vector<double> order(K), base(3 * K);
    if (basis.usesLocalFrame()) {
        int index = 0;
        for (int t = 0; t <= basis.degree; ++t)
            for (int j = 0; j <= t; ++j) order[index++] = t;
    } else {
        for (int l = 0; l <= basis.degree; ++l)
            for (int m = -l; m <= l; ++m) order[l * l + l + m] = l;
    }
    for (int k = 0; k < 3 * K; ++k) base[k] = u(rng) / (1.0 + order[k % K]);
    for (std::size_t v = 0; v < count; ++v) {
        for (int k = 0; k < 3 * K; ++k) f.vertexCoefficients(v)[k] = float(base[k] * (1.0 + 0.3 * u(rng)));
        Eigen::Vector3d axis(g(rng), g(rng), 0.0);
        const Eigen::Vector3d n = Eigen::AngleAxisd(angle(rng), axis.normalized()) * Eigen::Vector3d::UnitZ();
        rad::storeFrame(rad::frameFromNormalAndTangent(n, Eigen::Vector3d(g(rng), g(rng), g(rng))), f.frame(v));
    }
    return f;
}

// Vanhoey et al. 2015 Fig. 8: a sphere alternating diffuse and glossy stripes, lit by a point and a
// directional light, projected on the basis at every vertex with the vertex's own normal.
rad::RadianceField materialField(const rad::BasisSpec& basis, const std::vector<float>& positions,
                                 const std::vector<float>& normals) {
    rad::AnalyticMaterial material;
    material.albedo = rad::Rgb(0.6, 0.35, 0.2);
    material.specular = rad::Rgb(0.35, 0.35, 0.35);
    material.exponent = 30;
    material.stripes = rad::StripePattern::covering(Eigen::Vector3d(0.3, 0.2, 1.0), -1.0, 1.0, 8);
    rad::AnalyticLighting lighting;
    lighting.directional.push_back({Eigen::Vector3d(0.3, 1.0, 0.5), rad::Rgb::Constant(2.0)});
    lighting.points.push_back({Eigen::Vector3d(1.5, -1.0, 2.0), rad::Rgb(8.0, 7.0, 6.0)});
    rad::MaterialRadianceOptions options;
    options.basis = basis;
    return rad::makeMaterialRadiance(positions.data(), normals.data(), positions.size() / 3, material, lighting,
                                     options);
}

rad::CollapseMesh collapseMesh(const rad::TriangleMesh& m) {
    return rad::CollapseMesh(m.positions.data(), m.vertexCount(), m.faces.data(), m.faces.size() / 3);
}

struct RuleSize {
    int z, phi;
};
const std::vector<RuleSize> kRules = {{3, 6}, {4, 8}, {5, 10}, {6, 12}, {7, 14}, {8, 16}, {12, 24}, {24, 48}};

// One line per rule: percentiles of |cost - cost_288| / cost_288 over every half-edge (costs below
// 1e-12 of the largest are left out: their relative error means nothing), and microseconds per
// source vertex (1 thread).
void ruleTable(const char* title, rad::RadianceField field, const rad::CollapseMesh& mesh) {
    const Stars s = allStars(mesh);
    std::vector<double> reference, costs;
    rad::RadianceCollapseOptions options;
    options.rule = rad::HemisphereIntegrator::gaussProduct(12, 24);
    priceEverything(rad::RadianceCollapseMetric(field, options), mesh, s, 1, reference);
    const double largest = *std::max_element(reference.begin(), reference.end());
    std::printf("%s: %s, %zu vertices, %zu half-edges\n", title, field.basis.name().c_str(), mesh.vertexCount(),
                reference.size());
    std::printf("    rule    points   rel. error p50     p90     p99     max    us/vertex (1 thread, CPU time)\n");
    for (const RuleSize& r : kRules) {
        options.rule = rad::HemisphereIntegrator::gaussProduct(r.z, r.phi);
        const rad::RadianceCollapseMetric metric(field, options);
        double seconds = 1e30, cpu = 0;
        for (int round = 0; round < 3; ++round) {
            priceEverything(metric, mesh, s, 1, costs, &cpu);
            seconds = std::min(seconds, cpu);
        }
        std::vector<double> errors;
        for (std::size_t i = 0; i < costs.size(); ++i)
            if (reference[i] > 1e-12 * largest) errors.push_back(std::fabs(costs[i] - reference[i]) / reference[i]);
        std::sort(errors.begin(), errors.end());
        const auto pct = [&](double p) { return errors[std::min(errors.size() - 1, std::size_t(p * errors.size()))]; };
        std::printf("    %2dx%-2d   %4zu      %8.1e  %8.1e %8.1e %8.1e   %8.2f\n", r.z, r.phi, metric.rule().size(),
                    pct(0.5), pct(0.9), pct(0.99), errors.back(), 1e6 * seconds / mesh.vertexCount());
    }
}

void speed(const rad::BasisSpec& basis, int level, int rounds) {
    const rad::TriangleMesh sphere = rad::makeIcosphere(level);
    const rad::CollapseMesh mesh = collapseMesh(sphere);
    const Stars s = allStars(mesh);
    rad::RadianceField field = materialField(basis, sphere.positions, sphere.normals);
    std::vector<double> costs;
    for (bool fine : {false, true}) {
        rad::RadianceCollapseOptions options;  // default rule for the basis, or the 288-point one
        if (fine) options.rule = rad::HemisphereIntegrator::gaussProduct(12, 24);
        const rad::RadianceCollapseMetric metric(field, options);
        const int z = fine ? 12 : rad::defaultCollapseZNodes(basis), phi = fine ? 24 : 2 * z;
        for (int threads : {1, omp_get_max_threads()}) {
            double seconds = 1e30, cpuSeconds = 1e30;
            long long allocations = 0;
            for (int round = 0; round < rounds + 1; ++round) {  // round 0 warms the scratch up
                double cpu = 0;
                const long long before = g_allocations;
                const double wall = priceEverything(metric, mesh, s, threads, costs, &cpu);
                if (round == 0) continue;
                allocations = std::max(allocations, g_allocations - before);
                seconds = std::min(seconds, wall);
                cpuSeconds = std::min(cpuSeconds, cpu);
            }
            double sum = 0;
            for (double c : costs) sum += c;
            g_sink = g_sink + sum;
            std::printf("%-4s rule %2dx%-2d (%3zu points) %d thread%s: %9.0f vertices/s  %6.2f us/vertex wall",
                        basis.name().c_str(), z, phi, metric.rule().size(), threads, threads > 1 ? "s" : " ",
                        mesh.vertexCount() / seconds, 1e6 * seconds / mesh.vertexCount());
            if (threads == 1) std::printf(", %6.2f us/vertex CPU", 1e6 * cpuSeconds / mesh.vertexCount());
            std::printf("  (%zu vertices, %zu half-edges, best of %d; %lld heap allocations while pricing)\n",
                        mesh.vertexCount(), costs.size(), rounds, allocations);
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    const int level = argc > 1 ? std::atoi(argv[1]) : 7;
    const int rounds = argc > 2 ? std::max(1, std::atoi(argv[2])) : 3;
    const bool table = !(argc > 3 && std::string(argv[3]) == "speed");
    std::printf("default collapse rule: Gauss %d x %d for PB4, %d x %d for SH6; %d threads available\n\n",
                rad::defaultCollapseZNodes(kPB4), 2 * rad::defaultCollapseZNodes(kPB4), rad::defaultCollapseZNodes(kSH6),
                2 * rad::defaultCollapseZNodes(kSH6), omp_get_max_threads());

    std::mt19937 rng(1);
    if (table) {
    const rad::CollapseMesh patch = makePatch(40, rng);
    for (const rad::BasisSpec& basis : {kPB4, kSH6})
        ruleTable("random smooth RF, normals up to 30 deg apart", randomSmoothField(basis, patch.vertexCount(), rng),
                  patch);
    for (int sphereLevel : {1, 2, 3}) {
        const rad::TriangleMesh sphere = rad::makeIcosphere(sphereLevel);
        const rad::CollapseMesh mesh = collapseMesh(sphere);
        const std::string title = "striped glossy sphere (Fig. 8), icosphere level " + std::to_string(sphereLevel);
        for (const rad::BasisSpec& basis : {kPB4, kSH6})
            ruleTable(title.c_str(), materialField(basis, sphere.positions, sphere.normals), mesh);
    }
    std::printf("\n");
    }
    for (const rad::BasisSpec& basis : {kPB4, kSH6}) speed(basis, level, rounds);
    std::printf("(%lld heap allocations in the whole run)\n", static_cast<long long>(g_allocations));
    return 0;
}
