// bench_core: figures of the radiance core (printed, never asserted).
//   - basis evaluation: all functions of PB(4), SH(6), SH(8) at a direction, per second (1 thread);
//   - RF evaluation at a world direction with border extension (evaluateRadiance), per second;
//   - L2 distance of eq. 5-6 between two vertex RF over a hemisphere, per second (1 thread);
//   - analytic material -> radiance field projection, vertices per second (all threads);
//   - radiance PLY save and load of 1M vertices with PB(4).
// Usage: bench_core [vertex_count_for_io (default 1000000)]
#include "io/radiance_ply.h"
#include "radiance/basis.h"
#include "radiance/material_radiance.h"
#include "radiance/radiance_distance.h"
#include "radiance/radiance_evaluation.h"
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
// Results are folded into this so the compiler cannot drop the measured work.
volatile double g_sink = 0.0;
using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::vector<Eigen::Vector3d> randomDirections(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> g;
    std::vector<Eigen::Vector3d> out(n);
    for (auto& d : out) d = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    return out;
}

void benchBasis(const rad::BasisSpec& basis) {
    const auto dirs = randomDirections(4096, 1);
    std::vector<double> out(basis.coefficientCount());
    double sink = 0.0;
    const int rounds = 400;
    const auto t0 = Clock::now();
    for (int r = 0; r < rounds; ++r)
        for (const auto& d : dirs) {
            rad::evaluateBasis(basis, d.x(), d.y(), d.z(), out.data());
            sink += out.back();
        }
    const double s = secondsSince(t0);
    std::printf("basis %-4s  %3d functions   %8.2f M evaluations/s (1 thread)\n", basis.name().c_str(),
                basis.coefficientCount(), rounds * dirs.size() / s / 1e6);
    g_sink = g_sink + sink;
}

rad::RadianceField makeField(const rad::BasisSpec& basis, std::size_t n) {
    std::vector<float> positions(3 * n), normals(3 * n);
    const auto dirs = randomDirections(n, 7);
    for (std::size_t v = 0; v < n; ++v)
        for (int k = 0; k < 3; ++k) {
            positions[3 * v + k] = static_cast<float>(dirs[v][k]);
            normals[3 * v + k] = static_cast<float>(dirs[v][k]);
        }
    rad::AnalyticMaterial material;
    material.albedo = rad::Rgb(0.7, 0.3, 0.2);
    material.specular = rad::Rgb(0.4, 0.4, 0.4);
    material.exponent = 40;
    rad::AnalyticLighting lighting;
    lighting.directional.push_back({Eigen::Vector3d(0.3, 1.0, 0.5), rad::Rgb::Constant(3.0)});
    rad::MaterialRadianceOptions options;
    options.basis = basis;
    const auto t0 = Clock::now();
    rad::RadianceField field = rad::makeMaterialRadiance(positions.data(), normals.data(), n, material, lighting, options);
    const double s = secondsSince(t0);
    std::printf("material projection %-4s  %8.0f vertices/s (%d threads)\n", basis.name().c_str(), n / s,
                omp_get_max_threads());
    return field;
}

void benchEvaluation(const rad::RadianceField& field) {
    const auto dirs = randomDirections(256, 3);
    double scratch[rad::kMaxCoefficientsPerChannel];
    double sink = 0.0;
    const std::size_t n = std::min<std::size_t>(field.vertexCount(), 2000);
    const auto t0 = Clock::now();
    for (std::size_t v = 0; v < n; ++v) {
        const rad::VertexRadiance rf = rad::vertexRadiance(field, v);
        for (const auto& d : dirs) sink += rad::evaluateRadiance(rf, d, scratch)[0];
    }
    const double s = secondsSince(t0);
    std::printf("RF evaluation %-4s  %8.2f M RGB evaluations/s (1 thread)\n", field.basis.name().c_str(),
                n * dirs.size() / s / 1e6);
    const std::size_t pairs = std::min<std::size_t>(field.vertexCount() - 1, 2000);
    const auto t1 = Clock::now();
    for (std::size_t v = 0; v < pairs; ++v)
        sink += rad::squaredRadianceDistance(field, v, field, v + 1, rad::frameFromStored(field.frame(v)).n);
    const double s1 = secondsSince(t1);
    std::printf("L2 distance eq.5-6 %-4s  %8.0f distances/s (1 thread)\n", field.basis.name().c_str(), pairs / s1);
    g_sink = g_sink + sink;
}

void benchIo(std::size_t n) {
    rad::RadianceMesh mesh;
    rad::BasisSpec basis{rad::BasisKind::HemisphericalPolynomial, 4};
    mesh.radiance = rad::RadianceField(basis, n);
    mesh.positions.resize(3 * n);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (auto& x : mesh.positions) x = u(rng);
    for (auto& c : mesh.radiance->coefficients) c = u(rng);
    for (std::size_t v = 0; v < n; ++v) rad::storeFrame(rad::Frame{}, mesh.radiance->frame(v));
    for (std::size_t i = 0; i + 2 < n; i += 3)
        mesh.faces.insert(mesh.faces.end(), {std::uint32_t(i), std::uint32_t(i + 1), std::uint32_t(i + 2)});
    const std::string path = "bench_core_io.rply";
    auto t0 = Clock::now();
    rad::writeRadiancePly(path, mesh);
    const double save = secondsSince(t0);
    t0 = Clock::now();
    const rad::RadianceMesh back = rad::readRadiancePly(path);
    const double load = secondsSince(t0);
    std::remove(path.c_str());
    std::printf("radiance PLY %zu vertices PB4 (%d floats/vertex): save %.2f s, load %.2f s\n", n,
                3 + 3 + 6 + mesh.radiance->coefficientsPerVertex(), save, load);
}
}  // namespace

int main(int argc, char** argv) {
    const std::size_t ioVertices = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : 1000000;
    for (auto basis : {rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, 4},
                       rad::BasisSpec{rad::BasisKind::SphericalHarmonics, 6},
                       rad::BasisSpec{rad::BasisKind::SphericalHarmonics, 8}})
        benchBasis(basis);
    for (auto basis : {rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, 4},
                       rad::BasisSpec{rad::BasisKind::SphericalHarmonics, 6}}) {
        const rad::RadianceField field = makeField(basis, 20000);
        benchEvaluation(field);
    }
    benchIo(ioVertices);
    return 0;
}
