// make_radiance_mesh: a radiance mesh (.rply) with known ground truth, straight from a scan and a
// sample material (no photographs): the exact outgoing radiance of the virtual scene of
// acquisition/virtual_scene.h (same presets as virtual_acquisition) projected onto a basis at every
// vertex. Input of the simplification benchmarks and of the main job's simplification step.
#include "acquisition/sample_scene_radiance_mesh.h"
#include "geometry/mesh_normals.h"
#include "geometry/midpoint_subdivision.h"
#include "io/radiance_ply.h"
#include "radiance/material_radiance.h"

#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>
#include <utility>

#include "command_line.h"
#include "scene_setup.h"

namespace {

using radtools::UsageError;
using radtools::toInt;

void usage(std::ostream& out) {
    out << "usage: make_radiance_mesh MESH.{off,ply} -o OUT.rply [options]\n"
           "  --basis PB4|SH6|...      basis of the radiance functions [PB4]\n"
           "  --reflected              store reflected functions (Vanhoey et al. 2015 sec. 3.1)\n"
           "  --material glossy|diffuse|stripes   sample material of virtual_acquisition [glossy]\n"
           "  --up x|y|z|-x|-y|-z      world up axis (lights, stripes) [y]\n"
           "  --subdivide L            midpoint-subdivide L times first (normals interpolated) [0]\n"
           "  --no-shadows             lights reach every point facing them\n"
           "  --no-variation           no smooth spatial variation of the material\n";
}

int run(int argc, char** argv) {
    std::string input, output, basisName = "PB4", materialName = "glossy", upName = "y";
    int subdivide = 0;
    bool reflected = false, shadows = true, variation = true;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "-h" || a == "--help") {
            usage(std::cout);
            return 0;
        }
        if (a == "--reflected") { reflected = true; continue; }
        if (a == "--no-shadows") { shadows = false; continue; }
        if (a == "--no-variation") { variation = false; continue; }
        if (a.rfind("-", 0) != 0) {
            if (!input.empty()) throw UsageError("more than one mesh given: " + input + ", " + a);
            input = a;
            continue;
        }
        if (i + 1 >= argc) throw UsageError("option " + a + " needs a value");
        const std::string v = argv[++i];
        if (a == "-o" || a == "--output") output = v;
        else if (a == "--basis") basisName = v;
        else if (a == "--material") materialName = v;
        else if (a == "--up") upName = v;
        else if (a == "--subdivide") subdivide = toInt(a, v);
        else throw UsageError("unknown option " + a);
    }
    if (input.empty() || output.empty()) throw UsageError("a mesh and -o OUT.rply are required");
    if (subdivide < 0 || subdivide > 6) throw UsageError("--subdivide must lie in 0..6");
    const auto basis = rad::BasisSpec::parse(basisName);
    if (!basis) throw UsageError("--basis needs PB1..PB8 or SH0..SH10, got '" + basisName + "'");
    const Eigen::Vector3d up = radtools::parseAxis(upName);
    rad::SampleMaterial materialKind;
    try {
        materialKind = rad::parseSampleMaterial(materialName);
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }

    const auto t0 = std::chrono::steady_clock::now();
    rad::TriangleMesh mesh = radtools::loadMesh(input);
    if (const std::string problem = mesh.validate(); !problem.empty()) throw std::runtime_error(input + ": " + problem);
    if (!mesh.hasNormals()) rad::computeAreaWeightedNormals(mesh);
    if (subdivide > 0) mesh = rad::subdivideMidpoint(mesh, subdivide, rad::SubdivisionNormals::Interpolate);

    rad::SampleSceneRadianceOptions sceneOptions;
    sceneOptions.material = materialKind;
    sceneOptions.up = up;
    sceneOptions.castShadows = shadows;
    sceneOptions.variation = variation;
    sceneOptions.reflected = reflected;
    sceneOptions.lightRadius = rad::SampleLightRadius::FarthestVertex;
    rad::RadianceMesh out = rad::sampleSceneRadianceMesh(std::move(mesh), *basis, sceneOptions);
    radtools::setMeanColors(out);
    rad::writeRadiancePly(output, out);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("%s: %zu vertices, %zu faces, %s%s radiance of the %s material%s, %.1f s\n", output.c_str(),
                out.vertexCount(), out.faceCount(), basis->name().c_str(), reflected ? " reflected" : "",
                materialName.c_str(), shadows ? " with cast shadows" : "", seconds);
    return 0;
}

}  // namespace

int main(int argc, char** argv) { return radtools::runTool("make_radiance_mesh", argc, argv, run, usage); }
