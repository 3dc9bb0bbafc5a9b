// compare_radiance_meshes: image-space error of processed radiance meshes (simplified, directionally
// reduced, ...) against their original, with the protocol of render/image_space_error.h: every mesh
// rendered on the CPU from the same ring of cameras around the original's bounding sphere, RMSE and
// PSNR over the pixels covered by either rendering, and the memory each representation needs.
//
//   compare_radiance_meshes ORIGINAL.rply OTHER.rply [more.rply ...]
//                           [--views N] [--size WxH] [--mode per-fragment|per-vertex]
//                           [--supersampling N] [--elevation MIN,MAX] [--up X,Y,Z] [--background R,G,B]
//                           [--heatmaps DIR] [--heatmap-scale S] [--renders] [--per-view]
//
// Prints one table row per mesh (vertices, faces, basis, memory, mean RMSE / PSNR in linear and
// 8-bit sRGB units, worst view) and, with --per-view, one line per view and mesh.
// --heatmaps DIR writes DIR/<stem>_viewNN_heatmap.png (created when missing); --renders also writes
// the renderings (DIR/original_viewNN.png, DIR/<stem>_viewNN.png).
// Exit status: 0 success, 1 file or data error, 2 bad command line.
#include "io/radiance_ply.h"
#include "render/image_space_error.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "command_line.h"

namespace {

using radtools::UsageError;
using radtools::numberList;
using radtools::toInt;
using radtools::toNumber;

void usage(std::ostream& out) {
    out << "usage: compare_radiance_meshes ORIGINAL.rply OTHER.rply [more.rply ...] [options]\n"
           "  --views N                 cameras around the original's bounding sphere [16]\n"
           "  --size WxH                image size [512x512]\n"
           "  --mode per-fragment|per-vertex   eq. (8) or per-vertex (Vanhoey et al. 2015 sec. 5) shading [per-fragment]\n"
           "  --supersampling N         N x N rays per pixel, 1..16 [1]\n"
           "  --elevation MIN,MAX       elevation band of the cameras in degrees [-90,90]\n"
           "  --up X,Y,Z                world up axis of the cameras (elevation measured from it) [0,0,1]\n"
           "  --background R,G,B        linear background colour [0,0,0]\n"
           "  --heatmaps DIR            write per-view error heat maps (PNG) into DIR\n"
           "  --heatmap-scale S         linear RMS error drawn white in the heat maps [0.1]\n"
           "  --renders                 also write the renderings into the --heatmaps DIR\n"
           "  --per-view                print one line per view and mesh\n";
}

std::string stemOf(const std::string& path) { return std::filesystem::path(path).stem().string(); }

// "inf" instead of printf's platform-dependent spelling, fixed width.
std::string psnrText(double psnr) {
    char buf[32];
    if (std::isinf(psnr)) return "inf";
    std::snprintf(buf, sizeof buf, "%.2f", psnr);
    return buf;
}

rad::RadianceMesh load(const std::string& path) {
    rad::RadianceMesh mesh = rad::readRadiancePly(path);
    if (!mesh.radiance) throw std::runtime_error(path + " has no radiance data (fit or create it first)");
    return mesh;
}

int run(int argc, char** argv) {
    std::vector<std::string> paths;
    rad::ImageSpaceOptions options;
    rad::ImageSpaceImageOutput output;
    bool renders = false, perView = false;
    std::string heatmapDir;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "-h" || a == "--help") {
            usage(std::cout);
            return 0;
        }
        if (a.rfind("-", 0) != 0) {
            paths.push_back(a);
            continue;
        }
        if (a == "--renders") {
            renders = true;
            continue;
        }
        if (a == "--per-view") {
            perView = true;
            continue;
        }
        if (i + 1 >= argc) throw UsageError("option " + a + " needs a value");
        const std::string v = argv[++i];
        if (a == "--views") options.viewCount = toInt(a, v);
        else if (a == "--supersampling") options.supersampling = toInt(a, v);
        else if (a == "--heatmaps") heatmapDir = v;
        else if (a == "--heatmap-scale") output.heatmapScale = toNumber(a, v);
        else if (a == "--size") {
            const std::size_t x = v.find_first_of("xX");
            if (x == std::string::npos) throw UsageError("--size needs WxH, got '" + v + "'");
            options.width = toInt(a, v.substr(0, x));
            options.height = toInt(a, v.substr(x + 1));
        } else if (a == "--mode") {
            if (v == "per-fragment" || v == "fragment") options.shading = rad::RadianceShading::PerFragment;
            else if (v == "per-vertex" || v == "vertex") options.shading = rad::RadianceShading::PerVertex;
            else throw UsageError("--mode must be per-fragment or per-vertex, got '" + v + "'");
        } else if (a == "--elevation") {
            const std::vector<double> band = numberList(a, v, ',');
            if (band.size() != 2) throw UsageError("--elevation needs MIN,MAX in degrees");
            options.minElevationDegrees = band[0];
            options.maxElevationDegrees = band[1];
        } else if (a == "--up") {
            const std::vector<double> u = numberList(a, v, ',');
            if (u.size() != 3 || (u[0] == 0.0 && u[1] == 0.0 && u[2] == 0.0)) throw UsageError("--up needs a non-zero X,Y,Z");
            options.up = Eigen::Vector3d(u[0], u[1], u[2]);
        } else if (a == "--background") {
            const std::vector<double> c = numberList(a, v, ',');
            if (c.size() != 3) throw UsageError("--background needs R,G,B");
            options.background = Eigen::Vector3d(c[0], c[1], c[2]);
        } else throw UsageError("unknown option '" + a + "'");
    }
    if (paths.size() < 2) throw UsageError("needs an original mesh and at least one mesh to compare with it");
    if (options.viewCount < 1) throw UsageError("--views must be at least 1");
    if (options.width < 1 || options.height < 1 || options.width > 16384 || options.height > 16384)
        throw UsageError("--size must lie in 1x1..16384x16384");
    if (options.supersampling < 1 || options.supersampling > 16) throw UsageError("--supersampling must lie in 1..16");
    if (!(options.minElevationDegrees >= -90.0 && options.maxElevationDegrees <= 90.0 &&
          options.minElevationDegrees < options.maxElevationDegrees))
        throw UsageError("--elevation needs -90 <= MIN < MAX <= 90");
    if (!(output.heatmapScale > 0.0)) throw UsageError("--heatmap-scale must be positive");
    if (renders && heatmapDir.empty()) throw UsageError("--renders needs --heatmaps DIR");

    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    const rad::RadianceMesh original = load(paths[0]);
    std::vector<rad::RadianceMesh> others;
    for (std::size_t i = 1; i < paths.size(); ++i) others.push_back(load(paths[i]));
    std::vector<const rad::RadianceMesh*> pointers;
    for (const rad::RadianceMesh& m : others) pointers.push_back(&m);

    // File labels: the stems, made unique (and never "original", the original's renders).
    std::set<std::string> used{"original"};
    for (std::size_t i = 1; i < paths.size(); ++i) {
        std::string label = stemOf(paths[i]);
        if (label.empty() || used.count(label)) label += "_" + std::to_string(i);
        used.insert(label);
        output.labels.push_back(label);
    }
    if (!heatmapDir.empty()) {
        std::filesystem::create_directories(heatmapDir);
        output.directory = heatmapDir;
        output.heatmaps = true;
        output.renders = renders;
    }

    const std::vector<rad::ImageSpaceError> results = rad::compareRadianceMeshes(original, pointers, options, output);
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();

    std::printf("%d views %dx%d around the bounding sphere of %s, %s shading, supersampling %d, elevation [%g, %g] "
                "from up (%g, %g, %g)\n",
                options.viewCount, options.width, options.height, paths[0].c_str(),
                options.shading == rad::RadianceShading::PerFragment ? "per-fragment (eq. 8)" : "per-vertex",
                options.supersampling, options.minElevationDegrees, options.maxElevationDegrees, options.up.x(),
                options.up.y(), options.up.z());
    std::printf("error over the pixels covered by either mesh; RMSE/PSNR linear (peak 1) and 8-bit sRGB (peak 255),\n"
                "means over views; memory = V (12 + 12 K + frame) + 12 F bytes (render/image_space_error.h), MB = 10^6 B\n\n");
    std::printf("%-28s %9s %9s %5s %10s %7s %10s %9s %9s %9s %12s\n", "mesh", "vertices", "faces", "basis", "memory MB",
                "memory%", "RMSE lin", "PSNR lin", "RMSE 8b", "PSNR 8b", "worst view");
    const double originalBytes = static_cast<double>(rad::radianceMeshMemoryBytes(original));
    std::printf("%-28s %9zu %9zu %5s %10.3f %7.1f %10s %9s %9s %9s %12s\n", stemOf(paths[0]).c_str(),
                original.vertexCount(), original.faceCount(), original.radiance->basis.name().c_str(),
                originalBytes / 1e6, 100.0, "-", "-", "-", "-", "(original)");
    for (std::size_t i = 0; i < results.size(); ++i) {
        const rad::ImageSpaceError& e = results[i];
        const rad::RadianceMesh& m = others[i];
        std::string worst = "-";
        if (e.worstView >= 0)
            worst = std::to_string(e.worstView) + " (" + psnrText(e.views[e.worstView].errors.psnrSrgb8) + ")";
        std::printf("%-28s %9zu %9zu %5s %10.3f %7.1f %10.5f %9s %9.3f %9s %12s\n", stemOf(paths[i + 1]).c_str(),
                    m.vertexCount(), m.faceCount(), m.radiance->basis.name().c_str(), e.otherMemoryBytes / 1e6,
                    100.0 * e.otherMemoryBytes / originalBytes, e.meanRmseLinear, psnrText(e.meanPsnrLinear).c_str(),
                    e.meanRmseSrgb8, psnrText(e.meanPsnrSrgb8).c_str(), worst.c_str());
        if (e.emptyViewCount > 0)
            std::printf("  (%d views where neither mesh covers a pixel were left out of the means)\n", e.emptyViewCount);
    }
    if (perView) {
        std::printf("\n%-28s %5s %9s %9s %9s %10s %9s %9s %9s\n", "mesh", "view", "pixels", "original", "other",
                    "RMSE lin", "PSNR lin", "RMSE 8b", "PSNR 8b");
        for (std::size_t i = 0; i < results.size(); ++i)
            for (std::size_t v = 0; v < results[i].views.size(); ++v) {
                const rad::ViewImageError& ve = results[i].views[v];
                std::printf("%-28s %5zu %9zu %9zu %9zu %10.5f %9s %9.3f %9s\n", stemOf(paths[i + 1]).c_str(), v,
                            ve.errors.pixelCount, ve.originalPixels, ve.otherPixels, ve.errors.rmseLinear,
                            psnrText(ve.errors.psnrLinear).c_str(), ve.errors.rmseSrgb8,
                            psnrText(ve.errors.psnrSrgb8).c_str());
            }
    }
    if (!heatmapDir.empty())
        std::printf("\nheat maps (linear RMS error, black 0 -> red -> yellow -> white >= %g; blue: no mesh) in %s\n",
                    output.heatmapScale, heatmapDir.c_str());
    std::printf("%.2f s\n", seconds);
    return 0;
}

}  // namespace

int main(int argc, char** argv) { return radtools::runTool("compare_radiance_meshes", argc, argv, run, usage); }
