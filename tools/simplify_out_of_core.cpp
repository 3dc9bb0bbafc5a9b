// simplify_out_of_core SCAN.ply OUTPUT_BASE [--target N | --cell-size H] [--texture-size S] [--bits 8|16]
//                      [--gutter G] [--quiet]
//
// The "Out-of-Core Simplification and Normal Map" filter without MeshLab (Granier et al. 2007,
// Lindstrom 2000; common/outofcore/out_of_core_simplification.h): the PLY scan, of any size, is
// streamed from disk, simplified by vertex clustering, and its points streamed again into an
// object-space normal map of the simplified mesh.
//
// Writes OUTPUT_BASE_normal.png and OUTPUT_BASE_bake.txt (as "Bake Normal Map" does), then
// OUTPUT_BASE.obj with its per-wedge texture coordinates and OUTPUT_BASE.mtl naming the map (what
// MeshLab opens with its texture). Prints the counts, the phases' wall times, the throughput in
// millions of input triangles per second and the process's peak resident memory (getrusage).
// Exit status: 0, 1 on an input error (the message names the byte offset of a bad PLY), 2 on a
// usage error.
#include "command_line.h"

#include "io/obj_mesh.h"
#include "outofcore/out_of_core_simplification.h"

#include <sys/resource.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

namespace {

void usage(std::ostream& out) {
    out << "usage: simplify_out_of_core SCAN.ply OUTPUT_BASE [--target N | --cell-size H] [--texture-size S]\n"
           "                            [--bits 8|16] [--gutter G] [--quiet]\n"
           "  --target N        about N triangles in the simplified mesh (default 100000)\n"
           "  --cell-size H     the clustering grid's cell edge instead (model units)\n"
           "  --texture-size S  normal map size, a power of two (default 4096)\n"
           "  --bits B          8 or 16 bits per channel (default 16)\n"
           "  --gutter G        empty texels between the atlas's triangles, 0 to 64 (default 4; 0 packs\n"
           "                    them edge to edge: about 1.34 M triangles in 4096^2)\n"
           "  --quiet           no progress lines\n";
}

double peakResidentMegabytes() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) / 1024.0;  // kilobytes on Linux
}

int run(int argc, char** argv) {
    rad::OutOfCoreRequest request;
    std::vector<std::string> positional;
    bool quiet = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw radtools::UsageError(a + " needs a value");
            return argv[++i];
        };
        if (a == "--target") {
            const int n = radtools::toInt(a, value());
            if (n < 4) throw radtools::UsageError("--target must be at least 4");
            request.targetTriangles = std::size_t(n);
        } else if (a == "--cell-size") {
            request.cellSize = radtools::toNumber(a, value());
            if (!(request.cellSize > 0)) throw radtools::UsageError("--cell-size must be positive");
        } else if (a == "--texture-size") {
            request.textureSize = radtools::toInt(a, value());
        } else if (a == "--bits") {
            request.bits = radtools::toInt(a, value());
        } else if (a == "--gutter") {
            request.gutterTexels = radtools::toInt(a, value());
        } else if (a == "--quiet") {
            quiet = true;
        } else if (a == "-h" || a == "--help") {
            usage(std::cout);
            return 0;
        } else if (!a.empty() && a[0] == '-') {
            throw radtools::UsageError("unknown option " + a);
        } else {
            positional.push_back(a);
        }
    }
    if (positional.size() != 2) throw radtools::UsageError("expected SCAN.ply OUTPUT_BASE");
    request.plyPath = positional[0];
    request.outputBase = positional[1];
    int lastPercent = -10;
    if (!quiet)
        request.progress = [&](double fraction, const char* stage) {
            const int percent = int(fraction * 100.0);
            if (percent >= lastPercent + 10) {
                lastPercent = percent;
                std::fprintf(stderr, "  %3d %% %s\n", percent, stage);
            }
            return true;
        };
    const rad::OutOfCoreReport report = rad::simplifyOutOfCore(request);
    const std::string objPath = request.outputBase + ".obj";
    rad::writeObj(objPath, report.mesh, report.wedgeUv,
                  std::filesystem::path(report.normalMapFile).filename().string());

    const double triangles = double(report.read.trianglesEmitted);
    const rad::ClusteringStats& c = report.clustering;
    std::printf("input %s: %llu vertices, %.0f triangles (%llu polygons fanned), %s, %.2f GB\n",
                request.plyPath.c_str(), (unsigned long long)report.file.vertexCount, triangles,
                (unsigned long long)report.read.polygonsTriangulated,
                report.normalsFromFile ? "normals from the file" : "area-weighted normals from the faces",
                double(report.file.fileBytes) / 1e9);
    std::printf("grid %d x %d x %d, cell %g, %zu occupied cells, %zu duplicate triangles, %zu clamped, %zu mean "
                "fallbacks\n",
                c.gridCells[0], c.gridCells[1], c.gridCells[2], c.cellSize, c.occupiedCells, c.duplicateTriangles,
                c.clampedVertices, c.meanFallbacks);
    std::printf("simplified: %zu vertices, %zu triangles -> %s\n", report.mesh.vertexCount(), report.mesh.faceCount(),
                objPath.c_str());
    std::printf("normal map %dx%d %d bit: %zu points splatted, %zu without normal; %zu chart texels, %zu with "
                "points, %zu filled -> %s\n",
                request.textureSize, request.textureSize, request.bits, report.pointsSplatted,
                report.pointsWithoutNormal, report.chartTexels, report.texelsWithPoints, report.chartTexelsFilled,
                report.normalMapFile.c_str());
    std::printf("time: total %.2f s (clustering pass %.2f, normal-map pass %.2f, fill %.2f, write %.2f); %.2f M "
                "input triangles/s\n",
                report.totalSeconds, report.clusteringSeconds, report.splatSeconds, report.fillSeconds, report.writeSeconds,
                triangles / 1e6 / report.totalSeconds);
    std::printf("peak resident memory: %.0f MB\n", peakResidentMegabytes());
    return 0;
}

}  // namespace

int main(int argc, char** argv) { return radtools::runTool("simplify_out_of_core", argc, argv, run, usage); }
