// Frame time of the irradiance vector grid's display (Granier et al. 2007; render_gl/
// irradiance_grid_textures.h, irradiance_grid_shaders.h through the normal-map renderer, what the
// "Irradiance Vector Grid" decoration draws): direct light only (the same shader without the grid),
// indirect light alone, direct + indirect, per grid resolution, on a mesh the size of a simplified
// scan; plus the grid's upload time and texture memory. Offscreen compatibility context (under Xvfb:
// Mesa llvmpipe, like MeshLab's window here), `frames` frames orbiting the mesh, glFinish after each;
// median and mean printed. The grid holds an analytic field (its values do not change the cost).
//
// Usage: bench_ivg_frames MESH.off [--subdivide L] [--frames N] [--size WxH] [--cells N,N,...]
// e.g. (README): xvfb-run -a -s "-screen 0 1280x1024x24" build/bench/bench_ivg_frames \
//          data-cache/meshes/armadillo.off --subdivide 1 --cells 8,32,64
#include "bench_mesh.h"
#include "normal_map_gl_renderer.h"
#include "offscreen_gl.h"

#include "lighting/irradiance_vector_grid.h"

#include <GL/glew.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace {
double seconds(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
}
}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s MESH.off [--subdivide L] [--frames N] [--size WxH] [--cells N,N,...]\n", argv[0]);
        return 2;
    }
    const std::string path = argv[1];
    int levels = 0, frames = 20, width = 1024, height = 768;
    std::vector<int> resolutions{8, 32, 64};
    for (int i = 2; i + 1 < argc; i += 2) {
        const std::string key = argv[i];
        if (key == "--subdivide") levels = std::atoi(argv[i + 1]);
        else if (key == "--frames") frames = std::max(1, std::atoi(argv[i + 1]));
        else if (key == "--size") std::sscanf(argv[i + 1], "%dx%d", &width, &height);
        else if (key == "--cells") {
            resolutions.clear();
            std::stringstream list(argv[i + 1]);
            std::string item;
            while (std::getline(list, item, ',')) resolutions.push_back(std::max(1, std::atoi(item.c_str())));
        } else {
            std::fprintf(stderr, "unknown option %s\n", key.c_str());
            return 2;
        }
    }
    rad::TriangleMesh mesh = radbench::loadBenchMesh(path, levels);
    std::printf("mesh %s: %zu vertices, %zu faces, viewport %dx%d, %d frames per mode\n", path.c_str(), mesh.vertexCount(),
                mesh.faceCount(), width, height, frames);

    radgl::OffscreenGl context(width, height);
    const radgl::GlCapabilities caps = radgl::queryGlCapabilities();
    std::printf("GL: %s\n", caps.describe().c_str());
    radgl::NormalMapGlRenderer renderer(caps);
    if (!renderer.shaderProblem().empty()) {
        std::fprintf(stderr, "no shaders: %s\n", renderer.shaderProblem().c_str());
        return 1;
    }
    const std::vector<float> uv(6 * mesh.faceCount(), 0.0f);
    renderer.setMesh(mesh.positions.data(), mesh.normals.data(), mesh.vertexCount(), mesh.faces.data(), mesh.faceCount(),
                     uv.data());

    auto orbitFrameTimes = [&](const std::function<void(const Eigen::Vector3d&)>& drawFrame) {
        std::vector<double> times;
        for (int f = 0; f <= frames; ++f) {
            const double angle = 2.0 * 3.14159265358979 * f / frames;
            const Eigen::Vector3d eye(3.0 * std::sin(angle), 0.8, 3.0 * std::cos(angle));
            const rad::PinholeCamera camera =
                rad::PinholeCamera::lookAt(eye, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), 45.0, width, height);
            const auto a = std::chrono::steady_clock::now();
            context.beginFrame(camera, 0.1, 10.0, 40);
            drawFrame(eye);
            context.finish();
            if (f > 0) times.push_back(seconds(a, std::chrono::steady_clock::now()));
        }
        std::sort(times.begin(), times.end());
        return times;
    };
    auto report = [&](const std::string& name, const std::vector<double>& sorted) {
        double mean = 0;
        for (double t : sorted) mean += t;
        mean /= sorted.size();
        std::printf("  %-28s frame median %7.1f ms  mean %7.1f ms  (%.1f fps)\n", name.c_str(), 1e3 * sorted[sorted.size() / 2],
                    1e3 * mean, 1.0 / sorted[sorted.size() / 2]);
    };
    radgl::NormalMapLighting lighting;
    lighting.specular.setZero();
    lighting.albedo = Eigen::Vector3d(0.7, 0.6, 0.5);
    lighting.lightDirection = Eigen::Vector3d(0.3, 0.6, 1.0);
    const auto draw = [&](radgl::IndirectLight indirect) {
        return [&, indirect](const Eigen::Vector3d& eye) {
            radgl::NormalMapLighting l = lighting;
            l.indirect = indirect;
            renderer.draw(radgl::NormalMapShading::VertexNormals, l, {}, eye);
        };
    };
    report("direct light only (no grid)", orbitFrameTimes(draw(radgl::IndirectLight::None)));
    for (int n : resolutions) {
        rad::IrradianceVectorGrid grid = rad::IrradianceVectorGrid::covering({{-1.1f, -1.1f, -1.1f}}, {{1.1f, 1.1f, 1.1f}}, {{n, n, n}});
        for (int k = 0; k <= n; ++k)
            for (int j = 0; j <= n; ++j)
                for (int i = 0; i <= n; ++i) {
                    const auto p = grid.vertexPosition(i, j, k);
                    for (int d = 0; d < 6; ++d) {
                        const auto delta = rad::gridDirection(d);
                        float* out = grid.at(grid.vertexIndex(i, j, k), d);
                        for (int c = 0; c < 3; ++c)
                            for (int a = 0; a < 3; ++a) out[3 * c + a] = (1.5f + 0.5f * p[0] - 0.3f * c * p[1]) * delta[a];
                    }
                }
        const auto t0 = std::chrono::steady_clock::now();
        std::string note;
        const std::string problem = renderer.setIrradianceGrid(grid, note);
        context.finish();
        const auto t1 = std::chrono::steady_clock::now();
        if (!problem.empty()) {
            std::printf("grid %d^3 refused: %s\n", n, problem.c_str());
            continue;
        }
        std::printf("grid %d^3 cells (%zu vertices, file %.1f MB): upload %.3f s, 3D textures %.2f MB\n", n, grid.vertexCount(),
                    grid.memoryBytes() / 1048576.0, seconds(t0, t1), renderer.irradianceGridBytes() / 1048576.0);
        report("indirect only", orbitFrameTimes(draw(radgl::IndirectLight::Indirect)));
        report("direct + indirect", orbitFrameTimes(draw(radgl::IndirectLight::DirectAndIndirect)));
    }
    const std::string errors = renderer.takeGlErrors();
    if (!errors.empty()) std::printf("GL errors: %s\n", errors.c_str());
    return 0;
}
