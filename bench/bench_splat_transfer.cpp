// Speed of the 3D Gaussian splat transfer (common/splats): a synthetic SH3 splat scene on the unit
// sphere (flat splats of random sizes over a decade, random colours), written as a 3DGS .ply, read
// back and transferred onto an icosphere. Prints the reading and transfer times and the splats per
// vertex. Figures: docs/gaussian-splats.md.
//
//   bench_splat_transfer [--level 5] [--splats 200000] [--threads 0 (all)]
#include "geometry/primitive_meshes.h"
#include "splats/gaussian_splat_ply.h"
#include "splats/splat_radiance_transfer.h"

#include <Eigen/Geometry>

#include <omp.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <random>
#include <string>

namespace {

// The scene as the reference implementation's save_ply lays it out (float32, binary little endian).
void writeScene(const std::string& path, int count, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<float> g;
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::ofstream out(path, std::ios::binary);
    out << "ply\nformat binary_little_endian 1.0\nelement vertex " << count << "\n";
    const char* names[] = {"x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"};
    for (const char* n : names) out << "property float " << n << "\n";
    for (int i = 0; i < 45; ++i) out << "property float f_rest_" << i << "\n";
    out << "property float opacity\n";
    for (int i = 0; i < 3; ++i) out << "property float scale_" << i << "\n";
    for (int i = 0; i < 4; ++i) out << "property float rot_" << i << "\n";
    out << "end_header\n";
    std::vector<float> record(62);
    for (int s = 0; s < count; ++s) {
        Eigen::Vector3f n(g(rng), g(rng), g(rng));
        n.normalize();
        const Eigen::Quaternionf q = Eigen::Quaternionf::FromTwoVectors(Eigen::Vector3f::UnitZ(), n);
        const float sigma = 0.004f * std::pow(10.0f, u(rng));  // 0.004 .. 0.04
        std::fill(record.begin(), record.end(), 0.0f);
        for (int a = 0; a < 3; ++a) record[a] = n[a];
        for (int c = 0; c < 3; ++c) record[6 + c] = 0.5f * g(rng);
        for (int k = 0; k < 45; ++k) record[9 + k] = 0.02f * g(rng);  // trained scenes: mostly small
        record[54] = 2.0f;
        record[55] = record[56] = std::log(sigma);
        record[57] = std::log(0.1f * sigma);
        record[58] = q.w(), record[59] = q.x(), record[60] = q.y(), record[61] = q.z();
        out.write(reinterpret_cast<const char*>(record.data()), record.size() * sizeof(float));
    }
}

double seconds(std::chrono::steady_clock::time_point since) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

}  // namespace

int main(int argc, char** argv) {
    int level = 5, splats = 200000, threads = 0;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--level")) level = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--splats")) splats = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--threads")) threads = std::atoi(argv[i + 1]);
    }
    if (threads > 0) omp_set_num_threads(threads);
    const std::string path = (std::filesystem::temp_directory_path() / "bench_splat_transfer.ply").string();
    writeScene(path, splats, 1);
    const rad::TriangleMesh mesh = rad::makeIcosphere(level);

    auto start = std::chrono::steady_clock::now();
    const rad::GaussianSplats scene = rad::readGaussianSplatPly(path);
    const double read = seconds(start);
    start = std::chrono::steady_clock::now();
    const rad::SplatTransferResult result = rad::transferSplatRadiance(mesh.positions, mesh.normals, mesh.faces, scene);
    const double transfer = seconds(start);
    const double perVertex =
        std::accumulate(result.splatCount.begin(), result.splatCount.end(), 0.0) / double(mesh.vertexCount());
    std::printf("splats %d (SH3, %.1f MB file), icosphere level %d: %zu vertices, %d threads\n", splats,
                std::filesystem::file_size(path) / 1e6, level, mesh.vertexCount(), omp_get_max_threads());
    std::printf("read %.2f s (%.2f M splats/s); transfer %.2f s (%.0f vertices/s), %.1f splats per vertex, "
                "%zu vertices without splats\n",
                read, splats / read / 1e6, transfer, mesh.vertexCount() / transfer, perVertex,
                result.verticesWithoutSplats);
    std::filesystem::remove(path);
    return 0;
}
