// compute_irradiance_grid: the irradiance vector grid of Granier et al. 2007 for a scene made of
// mesh files (merged, as the filter merges the visible layers), written as an .ivg file
// (common/lighting/irradiance_vector_grid.h, docs/irradiance-vector-grid.md).
//   compute_irradiance_grid SCENE.ply [MORE.off ...] [-o OUT.ivg] [--resolution 16] [--bounces 1]
//       [--rays 256] (--envmap MAP.exr [--lights 64] [--env-scale 1] | --sun X,Y,Z[,E] | --point X,Y,Z,I)
// Albedo: the PLY's vertex colours (sRGB codes decoded to linear reflectance, as the filter does);
// files without colours get the default grey 0.5. Output: OUT.ivg, or the first file's name with .ivg.
#include "image/rgb_image.h"
#include "io/obj_mesh.h"
#include "io/off_reader.h"
#include "io/radiance_ply.h"
#include "lighting/environment_map.h"
#include "lighting/irradiance_vector_grid.h"
#include "lighting/irradiance_vector_grid_compute.h"

#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "command_line.h"

namespace {

using radtools::UsageError;
using radtools::toInt;
using radtools::toNumber;

void usage(std::ostream& out) {
    out << "usage: compute_irradiance_grid MESH [MESH ...] [options]   (binary PLY, OFF or OBJ; merged into one scene)\n"
           "  -o OUT.ivg               output [first mesh's name with .ivg]\n"
           "  --resolution N           cells along the longest side of the scene's box [16]\n"
           "  --bounces B              diffuse bounces of the direct light, >= 1 [1]\n"
           "  --rays R                 rays per grid vertex and direction [256]\n"
           "  --envmap MAP             HDR environment map (.exr or .hdr) as direct light\n"
           "  --lights N               median-cut lights for the map [64]\n"
           "  --env-scale S            multiplies the map's radiance [1]\n"
           "  --sun X,Y,Z[,E]          directional light toward (X,Y,Z), irradiance E [1]\n"
           "  --point X,Y,Z,I          point light at (X,Y,Z), intensity I\n"
           "  --light-samples K        lights drawn per path vertex when there are more (0 = all) [8]\n"
           "  --padding F              box padding, fraction of its longest side [0.02]\n"
           "  --threads N              worker threads [all]\n";
}

bool endsWith(const std::string& s, const std::string& tail) {
    if (s.size() < tail.size()) return false;
    for (std::size_t i = 0; i < tail.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(s[s.size() - tail.size() + i])) != tail[i]) return false;
    return true;
}

// Appends one file's triangles and albedo (3 per vertex) to the scene.
void appendMesh(const std::string& path, rad::TriangleMesh& scene, std::vector<float>& albedo) {
    rad::TriangleMesh mesh;
    std::vector<float> rho;
    if (endsWith(path, ".off")) {
        mesh = rad::readOff(path);
    } else if (endsWith(path, ".obj")) {
        mesh = rad::readObj(path).mesh;
    } else {
        rad::RadianceMesh r = rad::readRadiancePly(path);
        mesh.positions = std::move(r.positions);
        mesh.faces = std::move(r.faces);
        if (!r.colors.empty())
            for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
                for (int c = 0; c < 3; ++c) rho.push_back(rad::srgbToLinear(r.colors[4 * v + c]));
    }
    if (rho.empty()) rho.assign(3 * mesh.vertexCount(), rad::kDefaultIndirectAlbedo);
    const auto base = static_cast<std::uint32_t>(scene.vertexCount());
    scene.positions.insert(scene.positions.end(), mesh.positions.begin(), mesh.positions.end());
    for (std::uint32_t i : mesh.faces) scene.faces.push_back(base + i);
    albedo.insert(albedo.end(), rho.begin(), rho.end());
}

int run(int argc, char** argv) {
    std::vector<std::string> inputs;
    std::string output, envmap;
    int lightCount = 64;
    double envScale = 1.0;
    rad::AnalyticLighting lights;
    rad::IrradianceGridOptions options;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "-h" || a == "--help") {
            usage(std::cout);
            return 0;
        }
        if (!a.empty() && a[0] != '-') {
            inputs.push_back(a);
            continue;
        }
        if (i + 1 >= argc) throw UsageError(a + " needs a value");
        const std::string v = argv[++i];
        if (a == "-o") output = v;
        else if (a == "--resolution") options.resolution = toInt(a, v);
        else if (a == "--bounces") options.light.bounces = toInt(a, v);
        else if (a == "--rays") options.raysPerDirection = toInt(a, v);
        else if (a == "--envmap") envmap = v;
        else if (a == "--lights") lightCount = toInt(a, v);
        else if (a == "--env-scale") envScale = toNumber(a, v);
        else if (a == "--light-samples") options.light.lightSamples = toInt(a, v);
        else if (a == "--padding") options.padding = toNumber(a, v);
        else if (a == "--threads") options.threads = toInt(a, v);
        else if (a == "--sun") {
            const std::vector<double> n = radtools::numberList(a, v, ',');
            if (n.size() != 3 && n.size() != 4) throw UsageError("--sun needs X,Y,Z or X,Y,Z,E");
            rad::DirectionalLight l;
            l.direction = Eigen::Vector3d(n[0], n[1], n[2]);
            l.irradiance = rad::Rgb::Constant(n.size() == 4 ? n[3] : 1.0);
            lights.directional.push_back(l);
        } else if (a == "--point") {
            const std::vector<double> n = radtools::numberList(a, v, ',');
            if (n.size() != 4) throw UsageError("--point needs X,Y,Z,I");
            rad::PointLight l;
            l.position = Eigen::Vector3d(n[0], n[1], n[2]);
            l.intensity = rad::Rgb::Constant(n[3]);
            lights.points.push_back(l);
        } else throw UsageError("unknown option " + a);
    }
    if (inputs.empty()) throw UsageError("give at least one mesh file");
    if (!envmap.empty()) {
        const rad::AnalyticLighting env = rad::environmentLights(rad::readEnvironmentMap(envmap), lightCount, envScale);
        lights.directional.insert(lights.directional.end(), env.directional.begin(), env.directional.end());
    }
    if (lights.directional.empty() && lights.points.empty())
        throw UsageError("no light: give --envmap, --sun or --point (the grid holds the bounce of the direct light)");
    if (output.empty()) {
        const std::string& first = inputs.front();
        const std::size_t slash = first.find_last_of('/'), dot = first.find_last_of('.');
        output = (dot != std::string::npos && (slash == std::string::npos || dot > slash) ? first.substr(0, dot) : first) +
                 ".ivg";
    }

    rad::TriangleMesh scene;
    std::vector<float> albedo;
    for (const std::string& path : inputs) appendMesh(path, scene, albedo);
    std::printf("scene: %zu vertices, %zu faces from %zu file(s); %zu directional and %zu point light(s)\n",
                scene.vertexCount(), scene.faceCount(), inputs.size(), lights.directional.size(), lights.points.size());

    int lastPercent = -1;
    const rad::ProgressCallback progress = [&](double fraction, const char*) {
        const int percent = static_cast<int>(100 * fraction);
        if (percent / 10 != lastPercent / 10) {
            std::fprintf(stderr, "\r%3d %%", percent);
            lastPercent = percent;
        }
        return true;
    };
    rad::IrradianceGridReport report;
    const rad::IrradianceVectorGrid grid = rad::computeIrradianceVectorGrid(scene, albedo, lights, options, progress, &report);
    std::fprintf(stderr, "\n");
    rad::writeIrradianceVectorGrid(output, grid);
    std::printf("grid: %d x %d x %d cells, %zu vertices, %.2f MB (54 floats per vertex)\n", grid.cells[0], grid.cells[1],
                grid.cells[2], report.vertices, report.memoryBytes / 1e6);
    std::printf("rays: %llu samples (%d per vertex and direction), %llu rays in all, %d bounce(s)\n",
                static_cast<unsigned long long>(report.samples), options.raysPerDirection,
                static_cast<unsigned long long>(report.rays), options.light.bounces);
    std::printf("time: %.2f s (setup %.2f, trace %.2f, repair %.3f), %.3f s per million samples\n", report.totalSeconds,
                report.setupSeconds, report.traceSeconds, report.repairSeconds, report.secondsPerMillionSamples());
    std::printf("vertices inside objects or behind walls: %zu (%zu repaired from their neighbours, %zu left zero)\n",
                report.invalidVertices, report.repairedVertices, report.unreachableVertices);
    std::printf("wrote %s\n", output.c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) { return radtools::runTool("compute_irradiance_grid", argc, argv, run, usage); }
