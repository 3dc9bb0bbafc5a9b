// render_radiance: renders a radiance PLY (.rply) from a camera of a MeshLab project with the CPU
// renderer (render/radiance_renderer.h), optionally against a photograph.
//
//   render_radiance MESH.rply --project project.mlp --view K -o out.png
//   render_radiance MESH.rply --look-at EX,EY,EZ,TX,TY,TZ,UX,UY,UZ --fov HFOV --size WxH -o out.png
//                   [--mode vertex|fragment] [--supersampling N] [--exposure E]
//                   [--background R,G,B] [--compare PHOTO|raster] [--side-by-side FILE.png]
//
// --look-at / --fov / --size: a camera without a project (rad::PinholeCamera::lookAt: horizontal field
//   of view in degrees, principal point at the centre), the camera syntax of the web viewer
//   (python -m pymeshlab_radiance.view --screenshot), so that both render the same view.
// --mode: Vanhoey et al. 2015 sec. 5 per-vertex ("Gouraud-like") or eq. (8) per-fragment shading [fragment].
// --compare: the photograph to compare with; "raster" takes the image of raster K of the project.
//   Prints RMSE and PSNR (render/image_metrics.h) in 8-bit sRGB and linear units over the pixels
//   the mesh covers fully, and over the whole image.
// --side-by-side: writes photograph | rendering | 4 x |difference| (8-bit sRGB) in one PNG
//   (needs --compare).
// The rendering uses the same sub-pixel samples as virtual_acquisition for the same
// --supersampling (default 2 here too), so renderings of the true radiance match its photographs.
#include "image/image_io.h"
#include "io/meshlab_project.h"
#include "io/radiance_ply.h"
#include "render/image_metrics.h"
#include "render/radiance_renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "command_line.h"

namespace {

using radtools::UsageError;
using radtools::toInt;
using radtools::toNumber;

void usage(std::ostream& out) {
    out << "usage: render_radiance MESH.rply --project project.mlp --view K -o out.png [options]\n"
           "       render_radiance MESH.rply --look-at EX,EY,EZ,TX,TY,TZ,UX,UY,UZ [--fov HFOV] --size WxH -o out.png\n"
           "  --look-at, --fov, --size  camera from eye, target, up; horizontal fov in degrees [40]; image size\n"
           "  --mode vertex|fragment   per-vertex (Vanhoey et al. 2015 sec. 5) or per-fragment eq. (8) shading [fragment]\n"
           "  --supersampling N        N x N rays per pixel [2]\n"
           "  --exposure E             linear scale before sRGB encoding [1]\n"
           "  --background R,G,B       linear background colour [0,0,0]\n"
           "  --compare PHOTO|raster   print RMSE / PSNR against a photograph (raster: the view's own image)\n"
           "  --side-by-side FILE.png  write photograph | rendering | 4 x difference (needs --compare)\n";
}


void printErrors(const char* what, const rad::ImageErrors& e) {
    std::printf("%s (%zu pixels): 8-bit sRGB RMSE %.3f, PSNR %.2f dB; linear RMSE %.5f, PSNR %.2f dB\n", what,
                e.pixelCount, e.rmseSrgb8, e.psnrSrgb8, e.rmseLinear, e.psnrLinear);
}

// The camera of --look-at EX,EY,EZ,TX,TY,TZ,UX,UY,UZ --fov HFOV --size WxH.
rad::PinholeCamera lookAtCamera(const std::string& lookAt, double fov, const std::string& size) {
    std::vector<double> v;
    std::stringstream in(lookAt);
    for (std::string item; std::getline(in, item, ',');) v.push_back(toNumber("--look-at", item));
    if (v.size() != 9) throw UsageError("--look-at needs 9 numbers: eye, target, up");
    const std::size_t x = size.find('x');
    if (x == std::string::npos) throw UsageError("--size needs WIDTHxHEIGHT, e.g. 640x480");
    const int width = toInt("--size", size.substr(0, x)), height = toInt("--size", size.substr(x + 1));
    if (width < 1 || height < 1) throw UsageError("--size must be positive");
    if (!(fov > 0.0 && fov < 179.0)) throw UsageError("--fov must lie in (0, 179) degrees");
    return rad::PinholeCamera::lookAt({v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}, fov, width, height);
}

int run(int argc, char** argv) {
    std::string meshPath, projectPath, output, compare, sideBySide, mode = "fragment", lookAt, size;
    double fov = 40.0;
    int view = -1, supersampling = 2;
    double exposure = 1.0;
    Eigen::Vector3d background = Eigen::Vector3d::Zero();
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "-h" || a == "--help") {
            usage(std::cout);
            return 0;
        }
        if (a.rfind("-", 0) != 0) {
            if (!meshPath.empty()) throw UsageError("more than one mesh given: " + meshPath + ", " + a);
            meshPath = a;
            continue;
        }
        if (i + 1 >= argc) throw UsageError("option " + a + " needs a value");
        const std::string v = argv[++i];
        if (a == "-o" || a == "--output") output = v;
        else if (a == "--project") projectPath = v;
        else if (a == "--look-at") lookAt = v;
        else if (a == "--fov") fov = toNumber(a, v);
        else if (a == "--size") size = v;
        else if (a == "--view") view = toInt(a, v);
        else if (a == "--mode") mode = v;
        else if (a == "--supersampling") supersampling = toInt(a, v);
        else if (a == "--exposure") exposure = toNumber(a, v);
        else if (a == "--compare") compare = v;
        else if (a == "--side-by-side") sideBySide = v;
        else if (a == "--background") {
            std::stringstream in(v);
            std::string item;
            int k = 0;
            while (std::getline(in, item, ',')) {
                if (k > 2) throw UsageError("--background needs R,G,B");
                background[k++] = toNumber(a, item);
            }
            if (k != 3) throw UsageError("--background needs R,G,B");
        } else throw UsageError("unknown option '" + a + "'");
    }
    if (meshPath.empty()) throw UsageError("no mesh given");
    if (projectPath.empty() == lookAt.empty())
        throw UsageError("give one camera: --project project.mlp --view K, or --look-at ... --size WxH");
    if (output.empty()) throw UsageError("no output image (-o out.png)");
    if (mode != "vertex" && mode != "fragment") throw UsageError("--mode must be vertex or fragment, got '" + mode + "'");
    if (!sideBySide.empty() && compare.empty()) throw UsageError("--side-by-side needs --compare");
    if (!(exposure > 0.0)) throw UsageError("--exposure must be positive");

    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    rad::ProjectRaster raster;
    if (!projectPath.empty()) {
        const rad::MeshLabProject project = rad::readMeshLabProject(projectPath);
        if (view < 0 || view >= static_cast<int>(project.rasters.size()))
            throw UsageError("--view must lie in 0.." + std::to_string(static_cast<int>(project.rasters.size()) - 1) +
                             " (the project has " + std::to_string(project.rasters.size()) + " rasters)");
        raster = project.rasters[view];
    } else {
        raster.label = "look-at";
    }
    const rad::PinholeCamera camera =
        projectPath.empty() ? lookAtCamera(lookAt, fov, size) : rad::fromVcgCamera(raster.camera);

    const rad::RadianceMesh mesh = rad::readRadiancePly(meshPath);
    if (!mesh.radiance) throw std::runtime_error(meshPath + " has no radiance data (fit or create it first)");
    const auto t1 = Clock::now();
    const rad::MeshRenderer renderer(mesh.positions.data(), mesh.vertexCount(), mesh.faces.data(), mesh.faceCount());
    const auto t2 = Clock::now();
    rad::RenderOptions options;
    options.supersampling = supersampling;
    options.background = background;
    const rad::Rendering r = renderer.renderRadiance(
        *mesh.radiance, camera, mode == "vertex" ? rad::RadianceShading::PerVertex : rad::RadianceShading::PerFragment,
        options);
    const auto t3 = Clock::now();
    const rad::Image8 encoded = rad::encodeToSrgb8(r.image, static_cast<float>(exposure));
    rad::writePng(output, encoded);
    auto sec = [](Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); };
    const double rays = double(camera.width) * camera.height * supersampling * supersampling;
    std::printf("rendered %s (%zu vertices, %s) from raster %d '%s' (%dx%d), %s mode: %s\n", meshPath.c_str(),
                mesh.vertexCount(), mesh.radiance->basis.name().c_str(), view, raster.label.c_str(), camera.width,
                camera.height, mode.c_str(), output.c_str());
    std::printf("load %.2f s, Embree scene %.2f s, render %.3f s (%.2f M rays/s)\n", sec(t0, t1), sec(t1, t2),
                sec(t2, t3), rays / sec(t2, t3) / 1e6);

    if (!compare.empty()) {
        const std::string photoPath = compare == "raster" ? raster.imagePath : compare;
        const rad::Image8 photo = rad::readImage8(photoPath);
        if (photo.width != camera.width || photo.height != camera.height)
            throw std::runtime_error(photoPath + " is " + std::to_string(photo.width) + "x" + std::to_string(photo.height) +
                                     ", the camera " + std::to_string(camera.width) + "x" + std::to_string(camera.height));
        rad::ImageF scaled = r.image;
        for (float& x : scaled.rgb) x *= static_cast<float>(exposure);
        std::printf("against %s:\n", photoPath.c_str());
        printErrors("  pixels fully covered by the mesh", rad::compareImages(scaled, photo, r.mask(255)));
        printErrors("  whole image", rad::compareImages(scaled, photo));
        if (!sideBySide.empty()) {
            const int W = camera.width, H = camera.height;
            rad::Image8 panel(3 * W, H);
            for (int y = 0; y < H; ++y)
                for (int x = 0; x < W; ++x) {
                    const std::uint8_t* p = photo.rgb.data() + (std::size_t(y) * W + x) * 3;
                    const std::uint8_t* q = encoded.rgb.data() + (std::size_t(y) * W + x) * 3;
                    for (int c = 0; c < 3; ++c) {
                        panel.pixel(x, y)[c] = p[c];
                        panel.pixel(W + x, y)[c] = q[c];
                        panel.pixel(2 * W + x, y)[c] = static_cast<std::uint8_t>(std::min(255, 4 * std::abs(int(p[c]) - int(q[c]))));
                    }
                }
            rad::writePng(sideBySide, panel);
            std::printf("wrote %s (photograph | rendering | 4 x |difference|)\n", sideBySide.c_str());
        }
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) { return radtools::runTool("render_radiance", argc, argv, run, usage); }
