// compare_decoration_view: compares a screenshot of MeshLab showing the "Radiance Field" decoration
// with the CPU reference rendering (render/radiance_renderer.h) of the same view, read from the view
// file the decoration writes (docs/decorate-radiance.md, camera/gl_view_camera.h).
//
//   compare_decoration_view --mesh M.rply --view VIEW.txt --screenshot S.png [options]
//
// Steps: the screenshot (a capture of the whole screen, `import -window root`) is cropped to the GL
// viewport (viewportInScreen: widget origin x device pixel ratio, viewport Y counted from the
// widget's bottom); the mesh is rendered with MeshRenderer at cameraFromGlView(view) in the view
// file's mode (or --shading), tone-mapped and sRGB-encoded with the view file's exposure and tone
// curve (render/tone_mapping.h, the decoration's own formulas); the two are compared on the pixels
// fully covered by the mesh in the reference, eroded by --erode pixels (silhouettes: the GL
// rasteriser and the ray caster disagree on edge pixels, and MeshLab's own mesh shows through
// there), minus the excluded rectangles (MeshLab's info panel over the bottom of the view).
//
// Output (stdout), the last line being the figures, in 8-bit sRGB levels over the three channels:
//   pixels N rmse X max Y p99 Z
// rmse = sqrt(mean of squared code differences), max = largest channel difference, p99 = the 99th
// percentile of the per-pixel largest channel difference. Exit status 0 when at least --min-pixels
// pixels were compared, 1 otherwise (or on any error), 2 on a bad command line. The caller judges
// the figures.
//
// Sampling: one ray through each pixel centre by default, which is where GL rasterisation samples
// a fragment (MeshLab's GL surface has no multisampling), so that edges of shading features fall on
// the same pixels; --supersampling N averages N x N rays in linear light before the tone curve.
//
// Mode prt: the transfer vectors (the .rply block "prt") relit by a directional light given with
// --vertex-colors-from-prt X,Y,Z[,INTENSITY] (direction toward the light, object space; windowed
// SH as prt/prt_lighting.h's directionalLightSH), rendered as per-vertex linear colours.
// Environment-map lighting is not reproduced.
#include "camera/gl_view_camera.h"
#include "image/image_io.h"
#include "io/radiance_ply.h"
#include "prt/prt_lighting.h"
#include "render/radiance_renderer.h"
#include "render/tone_mapping.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "command_line.h"

namespace {

using radtools::UsageError;
using radtools::numberList;
using radtools::toInt;

void usage(std::ostream& out) {
    out << "usage: compare_decoration_view --mesh M.rply --view VIEW.txt --screenshot S.png [options]\n"
           "  --shading per-vertex|per-fragment|prt   shading of the reference [the view file's mode]\n"
           "  --vertex-colors-from-prt X,Y,Z[,I]      mode prt: directional light toward (X,Y,Z), intensity I [1]\n"
           "  --supersampling N        N x N rays per pixel, 1..4 [1: the pixel centre, as GL samples]\n"
           "  --erode N                shrink the compared region by N pixels [2]\n"
           "  --exclude X,Y,W,H        ignore this rectangle (viewport pixels, origin top-left); repeatable\n"
           "  --exclude-bottom N       ignore the bottom N rows of the viewport (MeshLab's info panel) [0]\n"
           "  --min-pixels N           fail when fewer pixels are compared [100]\n"
           "  --out-diff D.png         4 x |screenshot - reference| on compared pixels, blue elsewhere\n"
           "  --out-reference R.png    the reference rendering (viewport size)\n"
           "  --out-crop C.png         the screenshot cropped to the viewport\n"
           "prints: pixels N rmse X max Y p99 Z   (8-bit sRGB levels)\n";
}

struct Rect {
    int x, y, w, h;
};

// 0/1 mask eroded by a (2n+1)^2 square: a pixel stays when every pixel within n (Chebyshev) is set;
// pixels closer than n to the border go (what lies outside the image is unknown).
std::vector<std::uint8_t> erode(const std::vector<std::uint8_t>& mask, int W, int H, int n) {
    if (n <= 0) return mask;
    std::vector<std::uint8_t> rows(mask.size(), 0), out(mask.size(), 0);
    for (int y = 0; y < H; ++y)
        for (int x = n; x < W - n; ++x) {
            bool all = true;
            for (int k = -n; k <= n && all; ++k) all = mask[std::size_t(y) * W + x + k] != 0;
            rows[std::size_t(y) * W + x] = all;
        }
    for (int y = n; y < H - n; ++y)
        for (int x = 0; x < W; ++x) {
            bool all = true;
            for (int k = -n; k <= n && all; ++k) all = rows[std::size_t(y + k) * W + x] != 0;
            out[std::size_t(y) * W + x] = all;
        }
    return out;
}

const rad::NamedVertexBlock* findBlock(const rad::RadianceMesh& mesh, const std::string& prefix) {
    for (const auto& b : mesh.extraBlocks)
        if (b.prefix == prefix) return &b;
    return nullptr;
}

int metadataInt(const rad::NamedVertexBlock& block, const std::string& key) {
    const auto it = block.metadata.find(key);
    if (it == block.metadata.end()) throw std::runtime_error("block '" + block.prefix + "' has no '" + key + "' metadata");
    return radtools::toInt(key, it->second);
}

int run(int argc, char** argv) {
    std::string meshPath, viewPath, shotPath, shading, prtLight, diffPath, referencePath, cropPath;
    int supersampling = 1, erosion = 2, excludeBottom = 0, minPixels = 100;
    std::vector<Rect> excluded;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "-h" || a == "--help") {
            usage(std::cout);
            return 0;
        }
        if (i + 1 >= argc) throw UsageError("option " + a + " needs a value");
        const std::string v = argv[++i];
        if (a == "--mesh") meshPath = v;
        else if (a == "--view") viewPath = v;
        else if (a == "--screenshot") shotPath = v;
        else if (a == "--shading") shading = v;
        else if (a == "--vertex-colors-from-prt") prtLight = v;
        else if (a == "--supersampling") supersampling = toInt(a, v);
        else if (a == "--erode") erosion = toInt(a, v);
        else if (a == "--exclude-bottom") excludeBottom = toInt(a, v);
        else if (a == "--min-pixels") minPixels = toInt(a, v);
        else if (a == "--out-diff") diffPath = v;
        else if (a == "--out-reference") referencePath = v;
        else if (a == "--out-crop") cropPath = v;
        else if (a == "--exclude") {
            const std::vector<double> r = numberList(a, v, ',');
            if (r.size() != 4 || r[2] < 0 || r[3] < 0) throw UsageError("--exclude needs X,Y,W,H (W, H >= 0)");
            for (double x : r)
                if (x != std::floor(x)) throw UsageError("--exclude needs whole pixels");
            excluded.push_back({int(r[0]), int(r[1]), int(r[2]), int(r[3])});
        } else throw UsageError("unknown option '" + a + "'");
    }
    if (meshPath.empty() || viewPath.empty() || shotPath.empty())
        throw UsageError("--mesh, --view and --screenshot are required");
    if (supersampling < 1 || supersampling > 4) throw UsageError("--supersampling must lie in 1..4");
    if (erosion < 0 || erosion > 50) throw UsageError("--erode must lie in 0..50");
    if (excludeBottom < 0) throw UsageError("--exclude-bottom must be >= 0");
    if (minPixels < 0) throw UsageError("--min-pixels must be >= 0");

    const auto t0 = std::chrono::steady_clock::now();
    const rad::DecorationViewFile view = rad::readDecorationViewFile(viewPath);
    if (shading.empty()) shading = view.mode == "cpu-per-vertex" ? "per-vertex" : view.mode;
    if (shading != "per-vertex" && shading != "per-fragment" && shading != "prt")
        throw UsageError("--shading must be per-vertex, per-fragment or prt, got '" + shading + "'");
    if (shading == "prt" && prtLight.empty())
        throw UsageError("mode prt needs --vertex-colors-from-prt X,Y,Z[,INTENSITY] (the decoration's light)");

    const rad::PinholeCamera camera = rad::cameraFromGlView(view.view);
    const rad::ScreenRect rect = rad::viewportInScreen(view);
    const int W = rect.width, H = rect.height;

    const rad::Image8 shot = rad::readImage8(shotPath);
    if (rect.x < 0 || rect.y < 0 || rect.x + W > shot.width || rect.y + H > shot.height)
        throw std::runtime_error("the viewport lies at (" + std::to_string(rect.x) + ", " + std::to_string(rect.y) +
                                 ") size " + std::to_string(W) + " x " + std::to_string(H) + " on the screen, outside " +
                                 shotPath + " (" + std::to_string(shot.width) + " x " + std::to_string(shot.height) +
                                 "): was the screenshot taken of the whole screen, and the view file at the same time?");
    rad::Image8 crop(W, H);
    for (int y = 0; y < H; ++y)
        std::copy_n(shot.rgb.data() + (std::size_t(rect.y + y) * shot.width + rect.x) * 3, std::size_t(W) * 3,
                    crop.pixel(0, y));

    const rad::RadianceMesh mesh = rad::readRadiancePly(meshPath);
    const rad::MeshRenderer renderer(mesh.positions.data(), mesh.vertexCount(), mesh.faces.data(), mesh.faceCount());
    rad::RenderOptions options;
    options.supersampling = supersampling;
    rad::Rendering rendering;
    if (shading == "prt") {
        const rad::NamedVertexBlock* block = findBlock(mesh, "prt");
        if (!block) throw std::runtime_error(meshPath + " has no PRT transfer (vertex block 'prt')");
        const int degree = metadataInt(*block, "sh_degree"), channels = metadataInt(*block, "channels");
        if ((channels != 1 && channels != 3) || degree < 0 || block->width != channels * (degree + 1) * (degree + 1))
            throw std::runtime_error(meshPath + ": block 'prt' has width " + std::to_string(block->width) +
                                     ", which does not match sh_degree " + std::to_string(degree) + " and channels " +
                                     std::to_string(channels));
        const std::vector<double> light = numberList("--vertex-colors-from-prt", prtLight, ',');
        if (light.size() != 3 && light.size() != 4) throw UsageError("--vertex-colors-from-prt needs X,Y,Z[,INTENSITY]");
        const double intensity = light.size() == 4 ? light[3] : 1.0;
        const std::vector<double> sh =
            rad::directionalLightSH(degree, Eigen::Vector3d(light[0], light[1], light[2]), Eigen::Vector3d::Constant(intensity));
        const std::vector<float> rgb =
            rad::relightVertices(block->values.data(), mesh.vertexCount(), degree, channels, sh, degree);
        rendering = renderer.renderVertexColors(rgb.data(), camera, options);
    } else {
        if (!mesh.radiance) throw std::runtime_error(meshPath + " has no radiance functions");
        rendering = renderer.renderRadiance(*mesh.radiance, camera,
                                            shading == "per-vertex" ? rad::RadianceShading::PerVertex
                                                                    : rad::RadianceShading::PerFragment,
                                            options);
    }
    rad::ToneMapping tone;
    tone.exposureStops = view.exposureStops;
    tone.curve = view.toneMap == "reinhard" ? rad::ToneCurve::Reinhard : rad::ToneCurve::Clamp;
    const rad::Image8 reference = rad::toneMapToSrgb8(rendering.image, tone);

    std::vector<std::uint8_t> mask = erode(rendering.mask(255), W, H, erosion);
    if (excludeBottom > 0) excluded.push_back({0, H - excludeBottom, W, excludeBottom});
    for (const Rect& r : excluded)
        for (int y = std::max(0, r.y); y < std::min(H, r.y + r.h); ++y)
            for (int x = std::max(0, r.x); x < std::min(W, r.x + r.w); ++x) mask[std::size_t(y) * W + x] = 0;

    std::size_t count = 0;
    double sumSquares = 0.0;
    std::array<double, 3> bias{0, 0, 0};
    int maxDiff = 0;
    std::array<std::size_t, 256> histogram{};  // per-pixel largest channel difference
    rad::Image8 diff(W, H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const std::size_t i = std::size_t(y) * W + x;
            std::uint8_t* d = diff.pixel(x, y);
            if (!mask[i]) {
                d[2] = 96;
                continue;
            }
            int pixelMax = 0;
            for (int c = 0; c < 3; ++c) {
                const int e = int(crop.rgb[3 * i + c]) - int(reference.rgb[3 * i + c]);
                sumSquares += double(e) * e;
                bias[c] += e;
                pixelMax = std::max(pixelMax, std::abs(e));
                d[c] = static_cast<std::uint8_t>(std::min(255, 4 * std::abs(e)));
            }
            maxDiff = std::max(maxDiff, pixelMax);
            ++histogram[pixelMax];
            ++count;
        }
    int p99 = 0;
    if (count > 0) {
        std::size_t cumulative = 0;
        while (p99 < 255 && (cumulative += histogram[p99]) < std::size_t(std::ceil(0.99 * count))) ++p99;
    }
    const double rmse = count > 0 ? std::sqrt(sumSquares / (3.0 * count)) : std::nan("");

    if (!diffPath.empty()) rad::writePng(diffPath, diff);
    if (!referencePath.empty()) rad::writePng(referencePath, reference);
    if (!cropPath.empty()) rad::writePng(cropPath, crop);

    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("view %s: frame %lld, mode %s, viewport %d x %d at (%d, %d) of the %d x %d screenshot\n",
                viewPath.c_str(), view.frame, view.mode.c_str(), W, H, rect.x, rect.y, shot.width, shot.height);
    std::printf("camera: centre (%.6g, %.6g, %.6g), fx %.3f fy %.3f cx %.3f cy %.3f\n", camera.center.x(),
                camera.center.y(), camera.center.z(), camera.fx, camera.fy, camera.cx, camera.cy);
    std::printf("reference: %s shading of %zu vertices, %dx%d rays per pixel, exposure %g stops, %s; erosion %d px; %.2f s\n",
                shading.c_str(), mesh.vertexCount(), supersampling, supersampling, view.exposureStops,
                view.toneMap.c_str(), erosion, seconds);
    if (count > 0)
        std::printf("mean difference screenshot - reference: R %+.2f G %+.2f B %+.2f\n", bias[0] / count,
                    bias[1] / count, bias[2] / count);
    std::printf("pixels %zu rmse %.3f max %d p99 %d\n", count, rmse, maxDiff, p99);
    if (count < static_cast<std::size_t>(minPixels)) {
        std::fprintf(stderr, "compare_decoration_view: only %zu pixels compared (fewer than %d): is the mesh in view?\n",
                     count, minPixels);
        return 1;
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    return radtools::runTool("compare_decoration_view", argc, argv, run, usage);
}
