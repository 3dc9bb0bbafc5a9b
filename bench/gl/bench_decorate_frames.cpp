// Frame time of the decoration's GL renderer (render_gl/radiance_gl_renderer.h) per shading mode, on
// a mesh of the size a museum scan has after simplification (100k vertices) and before (1M+).
// Runs the decoration's own code in an offscreen compatibility context (under Xvfb: Mesa llvmpipe,
// like MeshLab's window here), draws `frames` frames orbiting the mesh, glFinish after each, and
// prints the median and mean frame time per mode, plus the one-off upload time and the GPU memory.
//
// Usage: bench_decorate_frames MESH.off [--subdivide L] [--basis PB4] [--frames N] [--size WxH]
// e.g. (README): xvfb-run -a -s "-screen 0 1280x1024x24" build/bench/bench_decorate_frames \
//          data-cache/meshes/armadillo.off --subdivide 1      (104k vertices)
//          ... --subdivide 3                                   (1.66M vertices)
#include "bench_mesh.h"
#include "offscreen_gl.h"
#include "radiance_gl_renderer.h"

#include "radiance/material_radiance.h"
#include "radiance/view_colors.h"

#include <GL/glew.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

namespace {
double seconds(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
}
}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s MESH.off [--subdivide L] [--basis PB4] [--frames N] [--size WxH]\n", argv[0]);
        return 2;
    }
    std::string path = argv[1];
    int levels = 0, frames = 20, width = 1024, height = 768;
    rad::BasisSpec basis{rad::BasisKind::HemisphericalPolynomial, 4};
    for (int i = 2; i + 1 < argc; i += 2) {
        const std::string key = argv[i];
        if (key == "--subdivide") levels = std::atoi(argv[i + 1]);
        else if (key == "--frames") frames = std::max(1, std::atoi(argv[i + 1]));
        else if (key == "--size") std::sscanf(argv[i + 1], "%dx%d", &width, &height);
        else if (key == "--basis") {
            const auto b = rad::BasisSpec::parse(argv[i + 1]);
            if (!b) {
                std::fprintf(stderr, "bad basis %s\n", argv[i + 1]);
                return 2;
            }
            basis = *b;
        } else {
            std::fprintf(stderr, "unknown option %s\n", key.c_str());
            return 2;
        }
    }
    rad::TriangleMesh mesh = radbench::loadBenchMesh(path, levels);

    rad::AnalyticMaterial material;
    material.exponent = 30.0;
    rad::AnalyticLighting lighting;
    lighting.directional.push_back({Eigen::Vector3d(0.3, 0.6, 1.0), rad::Rgb(2.0, 2.0, 2.0)});
    rad::MaterialRadianceOptions options;
    options.basis = basis;
    const rad::RadianceField field =
        rad::makeMaterialRadiance(mesh.positions.data(), mesh.normals.data(), mesh.vertexCount(), material, lighting, options);
    std::printf("mesh %s: %zu vertices, %zu faces, %s, viewport %dx%d, %d frames per mode\n", path.c_str(),
                mesh.vertexCount(), mesh.faceCount(), basis.name().c_str(), width, height, frames);

    radgl::OffscreenGl context(width, height);
    const radgl::GlCapabilities caps = radgl::queryGlCapabilities();
    std::printf("GL: %s\n", caps.describe().c_str());
    struct Mode {
        const char* name;
        radgl::GlShading shading;
        bool cpu;
    };
    const Mode modes[] = {{"per-vertex (GPU)", radgl::GlShading::PerVertex, false},
                          {"per-fragment eq. 8 (GPU)", radgl::GlShading::PerFragment, false},
                          {"vertex colours (PRT)", radgl::GlShading::VertexColors, false},
                          {"per-vertex CPU fallback (GL 2.1)", radgl::GlShading::PerVertex, true}};
    // MeshLab draws the mesh itself before the decoration draws over it (depth test GL_LEQUAL with a
    // polygon offset): the decoration's fragments behind the visible surface are then rejected before
    // shading. A plain depth-only draw of the same mesh stands for MeshLab's own pass here; its time
    // is part of every frame (printed once below).
    radgl::RadianceGlRenderer prepass(caps);
    prepass.setMesh(mesh.positions.data(), mesh.vertexCount(), mesh.faces.data(), mesh.faceCount());
    {
        const std::vector<float> grey(3 * mesh.vertexCount(), 0.2f);
        prepass.setVertexColors(grey.data());
    }
    auto meshlabPass = [&](const Eigen::Vector3d& eye) {
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        glDisable(GL_POLYGON_OFFSET_FILL);
        prepass.draw(radgl::GlShading::VertexColors, {}, eye);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    };
    // Frame times (seconds, sorted) of `frames` frames orbiting the mesh; the first frame is dropped
    // (shader compilation, caches).
    auto orbitFrameTimes = [&](const std::function<void(const Eigen::Vector3d&)>& drawFrame) {
        std::vector<double> times;
        for (int f = 0; f <= frames; ++f) {
            const double angle = 2.0 * 3.14159265358979 * f / frames;
            const Eigen::Vector3d eye(3.0 * std::sin(angle), 0.8, 3.0 * std::cos(angle));
            const rad::PinholeCamera camera =
                rad::PinholeCamera::lookAt(eye, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), 45.0, width, height);
            const auto a = std::chrono::steady_clock::now();
            context.beginFrame(camera, 0.1, 10.0, 40);
            meshlabPass(eye);
            drawFrame(eye);
            context.finish();
            if (f > 0) times.push_back(seconds(a, std::chrono::steady_clock::now()));
        }
        std::sort(times.begin(), times.end());
        return times;
    };
    const std::vector<double> depthOnly = orbitFrameTimes([](const Eigen::Vector3d&) {});
    std::printf("%-34s frame median %7.1f ms (included in every line below)\n", "depth-only pass (MeshLab's own draw)",
                1e3 * depthOnly[depthOnly.size() / 2]);
    for (const Mode& mode : modes) {
        radgl::GlCapabilities modeCaps = caps;
        if (mode.cpu) radgl::capGlVersion(modeCaps, 2, 1);
        const auto t0 = std::chrono::steady_clock::now();
        radgl::RadianceGlRenderer renderer(modeCaps);
        renderer.setMesh(mesh.positions.data(), mesh.vertexCount(), mesh.faces.data(), mesh.faceCount());
        if (mode.shading == radgl::GlShading::VertexColors) {
            std::vector<float> colours(3 * mesh.vertexCount());
            const double eye[3] = {0, 0, 3};
            rad::radianceTowardViewpoint(field, mesh.positions.data(), eye, 1.0f, colours.data());
            renderer.setVertexColors(colours.data());
        } else {
            renderer.setRadiance(field);
        }
        context.finish();
        const auto t1 = std::chrono::steady_clock::now();
        const std::vector<double> sorted =
            orbitFrameTimes([&](const Eigen::Vector3d& eye) { renderer.draw(mode.shading, {}, eye); });
        const std::string errors = renderer.takeGlErrors();
        double mean = 0;
        for (double t : sorted) mean += t;
        mean /= sorted.size();
        std::printf("%-34s upload %6.2f s  frame median %7.1f ms  mean %7.1f ms  (%.1f fps)  GPU memory %.0f MB%s%s\n",
                    mode.name, seconds(t0, t1), 1e3 * sorted[sorted.size() / 2], 1e3 * mean, 1.0 / sorted[sorted.size() / 2],
                    renderer.gpuBytes() / 1048576.0, errors.empty() ? "" : "  ", errors.c_str());
    }
    return 0;
}
