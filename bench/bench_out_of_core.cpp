// bench_out_of_core: the figures of the out-of-core simplification (Granier et al. 2007, Lindstrom
// 2000; common/outofcore). Not a test: it prints numbers (bench/out_of_core.sh drives it).
//
//   bench_out_of_core generate MESH.off N OUT.ply [--ascii]
//       Writes, STREAMING (nothing but the input in memory), MESH with every triangle cut into N x N
//       triangles (N - 1 new points per edge, shared by the two triangles of the edge, so the mesh
//       stays watertight), as a binary little-endian PLY with x y z nx ny nz (normals: the input's
//       area-weighted vertex normals interpolated and renormalised, i.e. smooth) and uchar/int
//       faces. F * N^2 triangles: the 52,000-triangle armadillo with N = 44 gives 100.7 M.
//
//   bench_out_of_core compare SCAN.ply TARGET TEXTURE_SIZE OUT_FOLDER
//       Runs the out-of-core job (streamed map) and, on the SAME simplified mesh and UVs, the in-core
//       bake (bake/normal_map_bake.h, object space, rays from the texel centres) with the scan in
//       memory, then prints the angle between the two maps over the texels whose centre lies inside a
//       triangle (mean, median, p95, max in degrees) and both jobs' times.
#include "bake/bake_description.h"
#include "bake/normal_map_bake.h"
#include "bake/texel_coverage.h"
#include "geometry/mesh_normals.h"
#include "io/off_reader.h"
#include "io/ply_stream_reader.h"
#include "outofcore/out_of_core_simplification.h"
#include "outofcore/streamed_normal_map.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

struct Writer {
    std::FILE* file = nullptr;
    std::vector<char> buffer;
    explicit Writer(const std::string& path) : file(std::fopen(path.c_str(), "wb")) {
        if (!file) throw std::runtime_error("cannot write " + path);
        buffer.reserve(1 << 22);
    }
    template <typename T>
    void put(T v) {
        const char* p = reinterpret_cast<const char*>(&v);
        buffer.insert(buffer.end(), p, p + sizeof(T));
        if (buffer.size() >= (1 << 22)) flush();
    }
    void text(const std::string& s) { buffer.insert(buffer.end(), s.begin(), s.end()); }
    void flush() {
        if (!buffer.empty() && std::fwrite(buffer.data(), 1, buffer.size(), file) != buffer.size())
            throw std::runtime_error("write failed (disk full?)");
        buffer.clear();
    }
    ~Writer() {
        flush();
        std::fclose(file);
    }
};

int generate(const std::string& input, int n, const std::string& output) {
    rad::TriangleMesh mesh = rad::readOff(input);
    rad::computeAreaWeightedNormals(mesh);
    const std::size_t V = mesh.vertexCount(), F = mesh.faceCount();
    std::vector<std::uint64_t> edges;
    for (std::size_t f = 0; f < F; ++f)
        for (int k = 0; k < 3; ++k)
            edges.push_back(rad::undirectedEdgeKey(mesh.faces[3 * f + k], mesh.faces[3 * f + (k + 1) % 3]));
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    const std::size_t E = edges.size();
    const std::uint64_t perEdge = std::uint64_t(n - 1), perFace = std::uint64_t(n - 1) * std::uint64_t(n - 2) / 2;
    const std::uint64_t vertices = V + E * perEdge + F * perFace, triangles = std::uint64_t(F) * n * n;
    if (vertices > 0x7fffffffull) throw std::runtime_error("too many vertices for int indices");
    auto edgeId = [&](std::uint32_t a, std::uint32_t b) {
        return std::uint64_t(std::lower_bound(edges.begin(), edges.end(), rad::undirectedEdgeKey(a, b)) - edges.begin());
    };
    auto interiorLocal = [&](int i, int j) {  // rows j = 1..n-2, i = 1..n-1-j
        const std::uint64_t rows = std::uint64_t(j - 1);
        return rows * std::uint64_t(n - 1) - rows * std::uint64_t(j) / 2 + std::uint64_t(i - 1);
    };
    // Index of grid point P(i, j) = c0 + i/n (c1 - c0) + j/n (c2 - c0) of face f.
    std::uint64_t faceEdges[3] = {0, 0, 0};  // edge ids of (c0, c1), (c0, c2), (c1, c2) of the current face
    auto index = [&](std::size_t f, int i, int j) -> std::uint64_t {
        const std::uint32_t c0 = mesh.faces[3 * f], c1 = mesh.faces[3 * f + 1], c2 = mesh.faces[3 * f + 2];
        if (i == 0 && j == 0) return c0;
        if (i == n && j == 0) return c1;
        if (i == 0 && j == n) return c2;
        auto onEdge = [&](std::uint32_t a, std::uint32_t b, std::uint64_t e, int k) {  // k/n from a to b
            const int fromLow = a < b ? k : n - k;
            return V + e * perEdge + std::uint64_t(fromLow - 1);
        };
        if (j == 0) return onEdge(c0, c1, faceEdges[0], i);
        if (i == 0) return onEdge(c0, c2, faceEdges[1], j);
        if (i + j == n) return onEdge(c1, c2, faceEdges[2], j);
        return V + E * perEdge + f * perFace + interiorLocal(i, j);
    };
    Writer out(output);
    out.text("ply\nformat binary_little_endian 1.0\ncomment " + std::filesystem::path(input).filename().string() +
             " with every triangle cut into " + std::to_string(n) + " x " + std::to_string(n) +
             "\nelement vertex " + std::to_string(vertices) +
             "\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\n"
             "property float nz\nelement face " + std::to_string(triangles) +
             "\nproperty list uchar int vertex_indices\nend_header\n");
    auto point = [&](const float* a, const float* b, const float* c, double wa, double wb, double wc, bool normalize) {
        double p[3];
        for (int k = 0; k < 3; ++k) p[k] = wa * a[k] + wb * b[k] + wc * c[k];
        if (normalize) {
            const double l = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
            for (double& x : p) x /= (l > 0 ? l : 1.0);
        }
        for (double x : p) out.put<float>(float(x));
    };
    auto P = [&](std::uint32_t v) { return &mesh.positions[3 * std::size_t(v)]; };
    auto N = [&](std::uint32_t v) { return &mesh.normals[3 * std::size_t(v)]; };
    for (std::size_t v = 0; v < V; ++v) {
        point(P(std::uint32_t(v)), P(std::uint32_t(v)), P(std::uint32_t(v)), 1, 0, 0, false);
        point(N(std::uint32_t(v)), N(std::uint32_t(v)), N(std::uint32_t(v)), 1, 0, 0, true);
    }
    for (std::size_t e = 0; e < E; ++e) {
        const std::uint32_t a = std::uint32_t(edges[e] >> 32), b = std::uint32_t(edges[e] & 0xffffffffu);
        for (int k = 1; k < n; ++k) {
            const double t = double(k) / n;
            point(P(a), P(b), P(a), 1 - t, t, 0, false);
            point(N(a), N(b), N(a), 1 - t, t, 0, true);
        }
    }
    for (std::size_t f = 0; f < F; ++f) {
        const std::uint32_t c0 = mesh.faces[3 * f], c1 = mesh.faces[3 * f + 1], c2 = mesh.faces[3 * f + 2];
        for (int j = 1; j <= n - 2; ++j)
            for (int i = 1; i <= n - 1 - j; ++i) {
                const double wi = double(i) / n, wj = double(j) / n;
                point(P(c0), P(c1), P(c2), 1 - wi - wj, wi, wj, false);
                point(N(c0), N(c1), N(c2), 1 - wi - wj, wi, wj, true);
            }
    }
    for (std::size_t f = 0; f < F; ++f) {
        faceEdges[0] = edgeId(mesh.faces[3 * f], mesh.faces[3 * f + 1]);
        faceEdges[1] = edgeId(mesh.faces[3 * f], mesh.faces[3 * f + 2]);
        faceEdges[2] = edgeId(mesh.faces[3 * f + 1], mesh.faces[3 * f + 2]);
        for (int j = 0; j < n; ++j)
            for (int i = 0; i + j < n; ++i) {
                out.put<std::uint8_t>(3);
                out.put<std::int32_t>(std::int32_t(index(f, i, j)));
                out.put<std::int32_t>(std::int32_t(index(f, i + 1, j)));
                out.put<std::int32_t>(std::int32_t(index(f, i, j + 1)));
                if (i + j < n - 1) {
                    out.put<std::uint8_t>(3);
                    out.put<std::int32_t>(std::int32_t(index(f, i + 1, j)));
                    out.put<std::int32_t>(std::int32_t(index(f, i + 1, j + 1)));
                    out.put<std::int32_t>(std::int32_t(index(f, i, j + 1)));
                }
            }
    }
    std::printf("wrote %s: %llu vertices, %llu triangles\n", output.c_str(), (unsigned long long)vertices,
                (unsigned long long)triangles);
    return 0;
}

int compare(const std::string& scan, std::size_t target, int size, const std::string& folder) {
    std::filesystem::create_directories(folder);
    rad::OutOfCoreRequest request;
    request.plyPath = scan;
    request.targetTriangles = target;
    request.textureSize = size;
    request.outputBase = folder + "/streamed";
    const rad::OutOfCoreReport streamed = rad::simplifyOutOfCore(request);
    std::printf("streamed: %zu triangles from %llu, %.2f s (clustering %.2f, map %.2f)\n", streamed.mesh.faceCount(),
                (unsigned long long)streamed.read.trianglesEmitted, streamed.totalSeconds, streamed.clusteringSeconds,
                streamed.splatSeconds);

    // The scan in memory for the in-core bake.
    rad::TriangleMesh source;
    rad::PlyStreamReader reader(scan);
    reader.read(
        [&](const rad::PlyVertexChunk& c) {
            source.positions.insert(source.positions.end(), c.positions, c.positions + 3 * c.count);
            if (c.normals) source.normals.insert(source.normals.end(), c.normals, c.normals + 3 * c.count);
        },
        [&](const rad::PlyTriangleChunk& c) { source.faces.insert(source.faces.end(), c.indices, c.indices + 3 * c.count); });
    rad::NormalMapBakeRequest bake;
    bake.target = &streamed.mesh;
    bake.targetWedgeUv = &streamed.wedgeUv;
    bake.source = &source;
    bake.textureSize = size;
    bake.space = rad::NormalSpace::Object;
    bake.writeLean = false;
    bake.bakeDiffuse = false;
    bake.outputBase = folder + "/incore";
    const rad::NormalMapBakeReport incore = rad::bakeNormalMapFiles(bake);
    std::printf("in-core bake: %.2f s (%zu chart texels, %.2f %% ray hits)\n", incore.totalSeconds,
                incore.bake.chartTexels, 100.0 * double(incore.bake.rayHits) / double(std::max<std::size_t>(1, incore.bake.chartTexels)));

    int w1, h1, w2, h2;
    const std::vector<float> a = rad::readNormalMap(streamed.normalMapFile, w1, h1);
    const std::vector<float> b = rad::readNormalMap(incore.normalMapFile, w2, h2);
    const rad::TexelCoverage coverage = rad::rasterizeTexelCoverage(streamed.wedgeUv.data(), streamed.mesh.faceCount(), size, size);
    // The texels points landed in (again, with the scan in memory) to split the error.
    rad::NormalSplatter splatter(streamed.mesh, streamed.wedgeUv, size);
    splatter.splat(source.positions.data(), source.normals.data(), source.vertexCount());
    const rad::StreamedNormalMap again = splatter.finish(request.gutterTexels);
    std::vector<double> angles, reached, filled;
    for (std::size_t t = 0; t < coverage.face.size(); ++t) {
        if (coverage.face[t] < 0 || !coverage.interior[t]) continue;
        double dot = 0;
        for (int k = 0; k < 3; ++k) dot += double(a[3 * t + k]) * b[3 * t + k];
        const double angle = std::acos(std::clamp(dot, -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
        angles.push_back(angle);
        (again.valid[t] ? reached : filled).push_back(angle);
    }
    auto meanOf = [](const std::vector<double>& v) {
        double m = 0;
        for (double x : v) m += x;
        return v.empty() ? 0.0 : m / double(v.size());
    };
    std::printf("texels points landed in: %zu, mean %.3f degrees; texels filled: %zu, mean %.3f degrees\n",
                reached.size(), meanOf(reached), filled.size(), meanOf(filled));
    // How much the in-core map itself changes from one texel to the next (same triangle): the scale
    // of the disagreement between a point sample at the texel centre and an average over the texel.
    double neighbourSum = 0;
    std::size_t neighbourCount = 0;
    for (int row = 0; row < size; ++row)
        for (int column = 0; column + 1 < size; ++column) {
            const std::size_t t = std::size_t(row) * size + column;
            if (coverage.face[t] < 0 || !coverage.interior[t] || !coverage.interior[t + 1] ||
                coverage.face[t + 1] != coverage.face[t])
                continue;
            double dot = 0;
            for (int k = 0; k < 3; ++k) dot += double(b[3 * t + k]) * b[3 * (t + 1) + k];
            neighbourSum += std::acos(std::clamp(dot, -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
            ++neighbourCount;
        }
    std::printf("in-core map: mean angle between horizontally adjacent texels of a triangle %.3f degrees\n",
                neighbourSum / double(std::max<std::size_t>(neighbourCount, 1)));
    std::sort(angles.begin(), angles.end());
    double sum = 0;
    for (double x : angles) sum += x;
    auto q = [&](double f) { return angles[std::min(angles.size() - 1, std::size_t(f * double(angles.size())))]; };
    std::printf("streamed vs in-core, %zu interior texels: mean %.3f, median %.3f, p95 %.3f, max %.2f degrees\n",
                angles.size(), sum / double(angles.size()), q(0.5), q(0.95), angles.back());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const std::string mode = argc > 1 ? argv[1] : "";
        if (mode == "generate" && argc == 5) return generate(argv[2], std::stoi(argv[3]), argv[4]);
        if (mode == "compare" && argc == 6) return compare(argv[2], std::stoul(argv[3]), std::stoi(argv[4]), argv[5]);
        std::fprintf(stderr, "usage: bench_out_of_core generate MESH.off N OUT.ply\n"
                             "       bench_out_of_core compare SCAN.ply TARGET TEXTURE_SIZE OUT_FOLDER\n");
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_out_of_core: %s\n", e.what());
        return 1;
    }
}
