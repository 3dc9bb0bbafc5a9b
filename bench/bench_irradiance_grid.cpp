// bench_irradiance_grid: the irradiance vector grid (Granier et al. 2007) against a CPU reference
// and against per-vertex irradiance at equal memory, on a Cornell-box-like room and on a real scan
// on a plinth in a room. Prints, per grid resolution: the grid's image error (paper's n^2
// directional weights and the |n| variant), the per-vertex image error at equal memory, and the
// grid's computation time per million samples. Not a test: figures only (README, section
// "Irradiance vector grid").
//   bench_irradiance_grid [--scene cornell|scan|both] [--resolutions 4,8,16,32] [--rays 256]
//       [--reference-rays 1024] [--bounces 1] [--size 160] [--scan PATH] [--threads N]
//       [--images DIR]  (PNG of the reference, the grid and the per-vertex images, exposed alike)
//
// Memory (what "equal memory" means): the grid, uncompressed, 54 floats per grid vertex; the
// per-vertex alternative 3 floats (RGB irradiance) per vertex of its mesh, the mesh's own positions
// and faces NOT counted (favouring the alternative: a viewer has the mesh anyway). So the
// per-vertex mesh gets 18 vertices per grid vertex. Also given: the paper's compressed grid
// (12 half-float RGB 3D textures = 36 halves = 18 floats per vertex) against 6 vertices per grid
// vertex. Rays: R per grid vertex and direction (6 R per grid vertex), R per vertex of the
// per-vertex mesh (cosine-distributed).
// The per-vertex mesh: the room's walls re-subdivided uniformly and the blocks/plinth likewise,
// at the subdivision whose vertex count is nearest below the budget, and (scan room) the scan
// simplified by memoryless QEM (Garland and Heckbert 1997, common/simplify) to the rest.
#include "geometry/box_rooms.h"
#include "geometry/mesh_normals.h"
#include "geometry/primitive_meshes.h"
#include "image/image_io.h"
#include "io/off_reader.h"
#include "lighting/irradiance_vector_grid_compute.h"
#include "render/indirect_light_reference.h"
#include "simplify/radiance_simplification.h"

#include <algorithm>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {

struct SceneSetup {
    std::string name;
    rad::AlbedoMesh full;
    rad::AnalyticLighting lights;
    rad::PinholeCamera camera;
    rad::TriangleMesh scan;  // scan room only: the input scan
};

rad::AnalyticLighting pointLight(double x, double y, double z, double intensity) {
    rad::AnalyticLighting l;
    rad::PointLight p;
    p.position = Eigen::Vector3d(x, y, z);
    p.intensity = rad::Rgb::Constant(intensity);
    l.points.push_back(p);
    return l;
}

// The scene's per-vertex mesh with at most `budget` vertices (see the file comment), vertex
// normals area-weighted. Scan room: the room (walls, plinth) takes at most half of the budget, at
// the finest uniform subdivision that fits, the scan the rest (simplified once).
rad::TriangleMesh perVertexMesh(const SceneSetup& s, std::size_t budget) {
    const bool scanRoom = s.scan.vertexCount() != 0;
    const std::size_t roomBudget = scanRoom ? budget / 2 : budget;
    rad::AlbedoMesh room;
    for (int n = 1; n <= 512; ++n) {
        rad::AlbedoMesh candidate = scanRoom ? rad::makeScanRoom(rad::makeIcosphere(0), 0.9f, n, true) : rad::makeCornellBox(n);
        if (scanRoom) {  // drop the placeholder's 12 vertices and 20 faces
            candidate.mesh.positions.resize(candidate.mesh.positions.size() - 36);
            candidate.mesh.faces.resize(candidate.mesh.faces.size() - 60);
        }
        if (n > 1 && candidate.mesh.vertexCount() > roomBudget) break;
        room = candidate;
    }
    rad::TriangleMesh mesh = room.mesh;
    if (scanRoom) {
        const std::size_t scanBudget = budget > mesh.vertexCount() ? budget - mesh.vertexCount() : 16;
        // The scan placed as in the full scene: the full scene's vertices after its room's.
        const rad::AlbedoMesh placed = rad::makeScanRoom(s.scan, 0.9f, 1, true);
        const std::size_t placedRoom = placed.mesh.vertexCount() - s.scan.vertexCount();
        rad::RadianceMesh scanOnly;
        scanOnly.positions.assign(placed.mesh.positions.begin() + 3 * placedRoom, placed.mesh.positions.end());
        for (std::size_t f = 0; f < placed.mesh.faceCount(); ++f)
            if (placed.mesh.faces[3 * f] >= placedRoom)
                for (int k = 0; k < 3; ++k) scanOnly.faces.push_back(placed.mesh.faces[3 * f + k] - std::uint32_t(placedRoom));
        if (scanBudget < s.scan.vertexCount()) {
            rad::RadianceSimplificationOptions o;
            o.metric = rad::SimplificationMetric::GeometryOnly;
            o.collapse.targetFaceCount = 2 * scanBudget;
            rad::RadianceSimplificationResult r = rad::simplifyRadianceMesh(scanOnly, o);
            scanOnly = r.progressive.extract(r.progressive.stepsForFaceCount(2 * scanBudget));
        }
        const auto base = std::uint32_t(mesh.vertexCount());
        mesh.positions.insert(mesh.positions.end(), scanOnly.positions.begin(), scanOnly.positions.end());
        for (std::uint32_t i : scanOnly.faces) mesh.faces.push_back(base + i);
    }
    mesh.normals.clear();
    rad::computeAreaWeightedNormals(mesh);
    return mesh;
}

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

}  // namespace

int main(int argc, char** argv) {
    std::string which = "both", scanPath = std::string(RADIANCE_SOURCE_DIR) + "/data-cache/meshes/armadillo.off";
    std::vector<int> resolutions = {4, 8, 16, 32};
    std::string imageDir;
    int rays = 256, referenceRays = 1024, bounces = 1, size = 160, threads = 0;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string a = argv[i], v = argv[i + 1];
        if (a == "--scene") which = v;
        else if (a == "--rays") rays = std::stoi(v);
        else if (a == "--reference-rays") referenceRays = std::stoi(v);
        else if (a == "--bounces") bounces = std::stoi(v);
        else if (a == "--size") size = std::stoi(v);
        else if (a == "--scan") scanPath = v;
        else if (a == "--threads") threads = std::stoi(v);
        else if (a == "--images") imageDir = v;
        else if (a == "--resolutions") {
            resolutions.clear();
            std::size_t start = 0;
            while (start < v.size()) {
                const std::size_t comma = v.find(',', start);
                resolutions.push_back(std::stoi(v.substr(start, comma - start)));
                if (comma == std::string::npos) break;
                start = comma + 1;
            }
        } else {
            std::fprintf(stderr, "unknown option %s\n", a.c_str());
            return 2;
        }
    }

    std::vector<SceneSetup> scenes;
    if (which == "cornell" || which == "both") {
        SceneSetup s;
        s.name = "Cornell box (sun through the open side)";
        s.full = rad::makeCornellBox(32);
        rad::DirectionalLight sun;
        sun.direction = Eigen::Vector3d(0.3, -1.0, 0.8);
        sun.irradiance = rad::Rgb::Ones();
        s.lights.directional.push_back(sun);
        s.camera = rad::PinholeCamera::lookAt(Eigen::Vector3d(0.5, -1.1, 0.5), Eigen::Vector3d(0.5, 0.5, 0.5),
                                              Eigen::Vector3d(0, 0, 1), 50.0, size, size);
        scenes.push_back(s);
    }
    if (which == "scan" || which == "both") {
        SceneSetup s;
        s.name = "scan on a plinth in a room (" + scanPath.substr(scanPath.find_last_of('/') + 1) + ", point light)";
        s.scan = rad::readOff(scanPath);
        s.scan.normals.clear();
        s.full = rad::makeScanRoom(s.scan, 0.9f, 32, true);
        s.lights = pointLight(-0.5, -0.4, 1.4, 2.0);
        s.camera = rad::PinholeCamera::lookAt(Eigen::Vector3d(0.2, -2.9, 1.1), Eigen::Vector3d(0, 0, 0.8),
                                              Eigen::Vector3d(0, 0, 1), 60.0, size, size * 3 / 4);
        scenes.push_back(s);
    }

    for (const SceneSetup& s : scenes) {
        rad::IndirectLightSetup setup;
        setup.bounces = bounces;
        rad::IndirectLightTracer tracer(s.full.mesh, s.full.albedo, s.lights, setup);
        const rad::VisibleSurface surface = rad::traceVisibleSurface(tracer, s.camera);
        double t0 = now();
        const rad::ImageF reference = rad::renderIndirectReference(tracer, surface, referenceRays, 7, {}, threads);
        const double referenceSeconds = now() - t0;
        // The reference's own noise: a second reference with another seed.
        const rad::ImageF reference2 = rad::renderIndirectReference(tracer, surface, referenceRays, 99, {}, threads);
        const rad::IndirectImageError noise = rad::indirectImageError(reference2, reference, surface.mask);
        const float exposure = float(0.5 / std::max(1e-12, rad::indirectImageError(reference, reference, surface.mask).meanReference));
        const std::string prefix = imageDir.empty() ? "" : imageDir + "/" + (s.scan.vertexCount() ? "scan" : "cornell");
        if (!prefix.empty()) rad::writePng(prefix + "_reference.png", rad::encodeToSrgb8(reference, exposure));
        std::printf("\n== %s: %zu faces, %d bounce(s), %dx%d image, %zu visible pixels\n", s.name.c_str(),
                    s.full.mesh.faceCount(), bounces, s.camera.width, s.camera.height, surface.visiblePixels());
        // Two independent references differ by sqrt(2) times the reference's own noise sigma; every
        // error below is measured against the first one, and includes sigma (in quadrature).
        std::printf("reference: %d cosine rays per pixel, %.1f s; mean indirect radiance %.4g; its own noise "
                    "(relative RMSE, sigma) %.2f %%\n",
                    referenceRays, referenceSeconds, noise.meanReference, 100.0 * noise.relativeRmse() / std::sqrt(2.0));
        std::printf("%-6s %-12s %8s %8s %9s %9s | %9s %9s %9s | %9s %9s\n", "res", "cells", "vertices", "MB",
                    "s/Msampl", "invalid", "grid n^2", "grid |n|", "compr.n^2", "pv 18x", "pv 6x");
        std::printf("%-6s %-12s %8s %8s %9s %9s | %9s %9s %9s | %9s %9s\n", "", "", "", "", "", "", "rel.RMSE",
                    "rel.RMSE", "rel.RMSE", "rel.RMSE", "rel.RMSE");
        for (int resolution : resolutions) {
            rad::IrradianceGridOptions options;
            options.resolution = resolution;
            options.raysPerDirection = rays;
            options.light = setup;
            options.threads = threads;
            // Box of the scene, as computeIrradianceVectorGrid places it.
            std::array<float, 3> lo{{1e30f, 1e30f, 1e30f}}, hi{{-1e30f, -1e30f, -1e30f}};
            for (std::size_t v = 0; v < s.full.mesh.vertexCount(); ++v)
                for (int c = 0; c < 3; ++c) {
                    lo[c] = std::min(lo[c], s.full.mesh.positions[3 * v + c]);
                    hi[c] = std::max(hi[c], s.full.mesh.positions[3 * v + c]);
                }
            rad::IrradianceVectorGrid grid = rad::placeIrradianceGrid(lo, hi, resolution, options.padding);
            rad::IrradianceGridReport report;
            rad::computeIrradianceVectors(tracer, grid, options, {}, report);
            const rad::ImageF paper = rad::renderIndirectFromGrid(grid, surface, rad::DirectionalWeights::Squared);
            const rad::ImageF absolute = rad::renderIndirectFromGrid(grid, surface, rad::DirectionalWeights::Absolute);
            // The paper's GPU compression, evaluated per pixel.
            const std::vector<float> compressed = rad::gpuCompressed(grid);
            rad::ImageF compressedImage(surface.width, surface.height);
            for (std::size_t i = 0; i < surface.mask.size(); ++i)
                if (surface.mask[i])
                    rad::reflectedRadianceCompressed(grid, compressed, &surface.points[3 * i], &surface.normals[3 * i],
                                                     &surface.albedo[3 * i], &compressedImage.rgb[3 * i]);
            double perVertexError[2] = {0, 0};
            std::size_t perVertexVertices[2] = {0, 0};
            const std::size_t budgets[2] = {18 * grid.vertexCount(), 6 * grid.vertexCount()};
            if (!prefix.empty()) {
                rad::writePng(prefix + "_grid" + std::to_string(resolution) + ".png", rad::encodeToSrgb8(paper, exposure));
                rad::ImageF difference = paper;  // |grid - reference|, same exposure
                for (std::size_t q = 0; q < difference.rgb.size(); ++q) difference.rgb[q] = std::fabs(paper.rgb[q] - reference.rgb[q]);
                rad::writePng(prefix + "_grid" + std::to_string(resolution) + "_error.png", rad::encodeToSrgb8(difference, exposure));
            }
            double perVertexSeconds = 0.0;
            for (int b = 0; b < 2; ++b) {
                const rad::TriangleMesh pv = perVertexMesh(s, budgets[b]);
                const double start = now();
                const std::vector<float> E = rad::computeVertexIndirectIrradiance(tracer, pv, rays, 1e-3, 5, {}, threads);
                if (b == 0) perVertexSeconds = now() - start;
                if (b == 0 && !prefix.empty())
                    rad::writePng(prefix + "_pervertex" + std::to_string(resolution) + ".png",
                                  rad::encodeToSrgb8(rad::renderIndirectFromVertexIrradiance(pv, E, surface), exposure));
                const rad::ImageF image = rad::renderIndirectFromVertexIrradiance(pv, E, surface);
                perVertexError[b] = rad::indirectImageError(image, reference, surface.mask).relativeRmse();
                perVertexVertices[b] = pv.vertexCount();
            }
            char cells[32];
            std::snprintf(cells, sizeof cells, "%dx%dx%d", grid.cells[0], grid.cells[1], grid.cells[2]);
            std::printf("%-6d %-12s %8zu %8.3f %9.3f %9zu | %8.2f%% %8.2f%% %8.2f%% | %8.2f%% %8.2f%%   (grid %.1f s; per-vertex meshes "
                        "%zu and %zu vertices, the first %.1f s)\n",
                        resolution, cells, grid.vertexCount(), report.memoryBytes / 1e6, report.secondsPerMillionSamples(),
                        report.invalidVertices, 100.0 * rad::indirectImageError(paper, reference, surface.mask).relativeRmse(),
                        100.0 * rad::indirectImageError(absolute, reference, surface.mask).relativeRmse(),
                        100.0 * rad::indirectImageError(compressedImage, reference, surface.mask).relativeRmse(),
                        100.0 * perVertexError[0], 100.0 * perVertexError[1], report.traceSeconds, perVertexVertices[0],
                        perVertexVertices[1], perVertexSeconds);
            std::fflush(stdout);
        }
    }
    return 0;
}
