// Frame time of the POP-buffer level of detail (Limper et al. 2013) in the normal-map renderer of
// the "Baked Normal Map" decoration (render_gl/normal_map_gl_renderer.h), per level against the whole
// mesh, with the texture-coordinate correction of Weber & Stamminger (Alg. 1) in the vertex shader;
// and the wall time of the draw call (uniforms and one glDrawArrays of a prefix: the scheme keeps no
// state between frames; on llvmpipe the call itself does the vertex work, on a GPU it only queues). Offscreen compatibility context (under Xvfb: Mesa llvmpipe, like MeshLab's
// window here); `frames` frames orbiting the mesh, glFinish after each; median and mean.
//
// Usage: bench_pop_frames MESH.off [--subdivide L] [--frames N] [--size WxH]
// e.g. (README): xvfb-run -a -s "-screen 0 1280x1024x24" build/bench/bench_pop_frames \
//          data-cache/meshes/armadillo.off --subdivide 2
#include "normal_map_gl_renderer.h"
#include "offscreen_gl.h"

#include "bake/lean_maps.h"
#include "bake/texture_atlas.h"
#include "camera/pinhole_camera.h"
#include "geometry/mesh_normals.h"
#include "geometry/midpoint_subdivision.h"
#include "io/off_reader.h"
#include "lod/pop_buffer.h"
#include "lod/texcoord_correction.h"

#include <GL/glew.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {
using Clock = std::chrono::steady_clock;
double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }
}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s MESH.off [--subdivide L] [--frames N] [--size WxH]\n", argv[0]);
        return 2;
    }
    int subdivide = 0, frames = 30, width = 1024, height = 768;
    for (int i = 2; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--subdivide")) subdivide = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--frames")) frames = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--size")) std::sscanf(argv[i + 1], "%dx%d", &width, &height);
    }
    try {
        rad::TriangleMesh mesh = rad::readOff(argv[1]);
        if (subdivide > 0) mesh = rad::subdivideMidpoint(mesh, subdivide);
        rad::computeAreaWeightedNormals(mesh);
        const rad::PerTriangleAtlas atlas = rad::makePerTriangleAtlas(mesh.faceCount(), 4096, 1);
        const rad::PopBuffer pop = rad::buildPopBuffer(mesh);
        const rad::TexCoordDerivatives derivatives = rad::computeTexCoordDerivatives(mesh, atlas.wedgeUv);

        radgl::OffscreenGl gl(width, height);
        radgl::NormalMapGlRenderer renderer(radgl::queryGlCapabilities());
        if (!renderer.shaderProblem().empty()) throw std::runtime_error(renderer.shaderProblem());
        const auto t0 = Clock::now();
        std::string problem = renderer.setPopMesh(mesh.positions.data(), mesh.normals.data(), mesh.vertexCount(),
                                                  mesh.faces.data(), mesh.faceCount(), atlas.wedgeUv.data(), pop,
                                                  &derivatives);
        std::vector<float> flat(512 * 512 * 3);
        for (std::size_t i = 0; i < flat.size(); ++i) flat[i] = i % 3 == 2 ? 1.0f : 0.0f;
        if (problem.empty()) problem = renderer.setNormalMap(rad::buildNormalPyramid(flat.data(), 512, 512), false);
        if (!problem.empty()) throw std::runtime_error(problem);
        glFinish();
        const double upload = seconds(t0, Clock::now());

        Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e30), hi = -lo;
        for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
            for (int k = 0; k < 3; ++k) {
                lo[k] = std::min(lo[k], double(mesh.positions[3 * v + k]));
                hi[k] = std::max(hi[k], double(mesh.positions[3 * v + k]));
            }
        const Eigen::Vector3d center = 0.5 * (lo + hi);
        const double radius = 0.5 * (hi - lo).norm();
        std::printf("bench_pop_frames: %s, %zu vertices, %zu faces, %dx%d, %d frames per level; upload %.2f s "
                    "(17 floats per corner: %.0f MB)\n",
                    argv[1], mesh.vertexCount(), mesh.faceCount(), width, height, frames, upload,
                    3.0 * mesh.faceCount() * 17 * 4 / 1048576.0);
        std::printf("%8s %10s %12s %12s %14s\n", "level", "triangles", "median ms", "mean ms", "draw() wall us");
        radgl::NormalMapLighting lighting;
        lighting.lightDirection = Eigen::Vector3d(0.4, 0.5, 1.0);
        for (int level : {0, 16, 12, 10, 9, 8, 7, 6}) {
            problem = renderer.setPopLevel(level, level > 0);
            if (!problem.empty()) throw std::runtime_error(problem);
            std::vector<double> times, cpu;
            for (int f = 0; f < frames + 2; ++f) {
                const double angle = 2 * 3.14159265358979 * f / frames;
                const Eigen::Vector3d eye = center + 2.5 * radius * Eigen::Vector3d(std::sin(angle), 0.2, std::cos(angle));
                const rad::PinholeCamera camera =
                    rad::PinholeCamera::lookAt(eye, center, {0, 1, 0}, 40.0, width, height);
                const auto a = Clock::now();
                gl.beginFrame(camera, 0.1 * radius, 10 * radius);
                const auto b = Clock::now();
                problem = renderer.draw(radgl::NormalMapShading::NormalMap, lighting, {}, eye);
                const auto c = Clock::now();
                glFinish();
                const auto d = Clock::now();
                if (!problem.empty()) throw std::runtime_error(problem);
                if (f >= 2) {  // the first frames compile and warm up
                    times.push_back(seconds(a, d) * 1e3);
                    cpu.push_back(seconds(b, c) * 1e6);
                }
            }
            std::sort(times.begin(), times.end());
            std::sort(cpu.begin(), cpu.end());
            double mean = 0;
            for (double t : times) mean += t / times.size();
            std::printf("%8s %10zu %12.2f %12.2f %14.1f\n", level == 0 ? "full" : std::to_string(level).c_str(),
                        renderer.drawnFaceCount(), times[times.size() / 2], mean, cpu[cpu.size() / 2]);
        }
        const std::string errors = renderer.takeGlErrors();
        if (!errors.empty()) std::printf("GL errors: %s\n", errors.c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_pop_frames: %s\n", e.what());
        return 1;
    }
    return 0;
}
