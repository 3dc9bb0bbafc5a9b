// virtual_acquisition: "virtually acquired photographs" (Vanhoey et al. 2015 sec. 7) of a mesh, written as a
// MeshLab project, so that radiance fitting is exercised exactly as on a user's calibrated
// photographs loaded as raster layers.
//
//   virtual_acquisition MESH.{off,ply} -o OUTDIR [options]
//
// writes
//   OUTDIR/images/view_000.png ...  8-bit sRGB photographs (acquisition/virtual_photographs.h)
//   OUTDIR/project.mlp              the rasters with their cameras, EMPTY MeshGroup (meshlabserver
//                                   needs the mesh via -i and the rasters via -p; see
//                                   io/meshlab_project.h)
//   OUTDIR/mesh.ply                 the exact mesh photographed (after --subdivide), positions,
//                                   unit normals and faces, binary PLY MeshLab opens with -i
//   OUTDIR/scene.txt                the options used, to rebuild the ground truth (VirtualScene with
//                                   makeSampleMaterial / makeSampleLighting and these values)
// and prints timings. Photographs are rendered with the cameras exactly as the project stores them
// (float32 values, storedCamera()), so photographs and project agree bit for bit.
#include "acquisition/sample_scene_radiance_mesh.h"
#include "acquisition/camera_rig.h"
#include "acquisition/virtual_photographs.h"
#include "acquisition/virtual_scene.h"
#include "geometry/mesh_normals.h"
#include "geometry/midpoint_subdivision.h"
#include "image/image_io.h"
#include "io/meshlab_project.h"
#include "io/off_reader.h"
#include "io/radiance_ply.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "command_line.h"
#include "scene_setup.h"

namespace {

using radtools::UsageError;
using radtools::toInt;
using radtools::toNumber;
using radtools::numberList;
using radtools::loadMesh;
using radtools::parseAxis;

void usage(std::ostream& out) {
    out << "usage: virtual_acquisition MESH.{off,ply} -o OUTDIR [options]\n"
           "options (defaults in brackets):\n"
           "  --views N            number of photographs [50]\n"
           "  --size WxH           image size in pixels [1024x768]\n"
           "  --fov DEG            horizontal field of view [40]\n"
           "  --fill F             bounding-sphere diameter / smaller image side [0.9]\n"
           "  --elevation MIN,MAX  elevation band of the viewpoints in degrees [-60,80]\n"
           "  --seed S             jitter of the viewpoints [1]\n"
           "  --up x|y|z|-x|-y|-z  world up axis (lights, elevation, image up) [y]\n"
           "  --material glossy|diffuse|stripes   [glossy]\n"
           "  --light dir:X,Y,Z[:E]      directional light towards (X,Y,Z) (world), irradiance E\n"
           "                             (one value or R,G,B) [default key + fill lights]\n"
           "  --light point:X,Y,Z[:E]    point light at centre + radius * (X,Y,Z), giving irradiance E\n"
           "                             at the centre (repeat --light for several lights)\n"
           "  --ambient A          ambient radiance (unshadowed) [0.06 with the default lights, else 0]\n"
           "  --no-shadows         no cast shadows\n"
           "  --no-variation       no smooth spatial variation of albedo and specular strength\n"
           "  --supersampling N    N x N rays per pixel [2]\n"
           "  --subdivide L        midpoint-subdivide the mesh L times first [0]\n"
           "  --normals recompute|interpolate  normals after --subdivide: area-weighted normals of the\n"
           "                       subdivided mesh (faceted look at the original resolution) or midpoint\n"
           "                       normals interpolated from the original's (smooth) [recompute]\n"
           "  --exposure E         linear scale before sRGB encoding [1]\n";
}



struct LightSpec {
    bool directional = true;
    Eigen::Vector3d vector;
    Eigen::Vector3d value = Eigen::Vector3d::Ones();
};

LightSpec parseLight(const std::string& text) {
    const std::size_t c1 = text.find(':');
    if (c1 == std::string::npos) throw UsageError("--light needs dir:X,Y,Z[:E] or point:X,Y,Z[:E], got '" + text + "'");
    LightSpec l;
    const std::string kind = text.substr(0, c1);
    if (kind == "dir") l.directional = true;
    else if (kind == "point") l.directional = false;
    else throw UsageError("--light kind must be dir or point, got '" + kind + "'");
    const std::size_t c2 = text.find(':', c1 + 1);
    const std::vector<double> xyz = numberList("--light", text.substr(c1 + 1, c2 == std::string::npos ? std::string::npos : c2 - c1 - 1), ',');
    if (xyz.size() != 3) throw UsageError("--light needs three coordinates, got '" + text + "'");
    l.vector = Eigen::Vector3d(xyz[0], xyz[1], xyz[2]);
    if (l.vector.norm() == 0.0) throw UsageError("--light needs a non-zero vector: '" + text + "'");
    if (c2 != std::string::npos) {
        const std::vector<double> e = numberList("--light", text.substr(c2 + 1), ',');
        if (e.size() == 1) l.value = Eigen::Vector3d::Constant(e[0]);
        else if (e.size() == 3) l.value = Eigen::Vector3d(e[0], e[1], e[2]);
        else throw UsageError("--light intensity needs one or three values: '" + text + "'");
        if (l.value.minCoeff() < 0.0) throw UsageError("--light intensity must not be negative: '" + text + "'");
    }
    return l;
}

std::string vec(const Eigen::Vector3d& v) {
    std::ostringstream s;
    s.precision(9);
    s << v.x() << ' ' << v.y() << ' ' << v.z();
    return s.str();
}

int run(int argc, char** argv) {
    std::string input, outdir, materialName = "glossy", upName = "y", normalsName = "recompute";
    int views = 50, width = 1024, height = 768, supersampling = 2, subdivide = 0;
    double fov = 40.0, fill = 0.9, minElevation = -60.0, maxElevation = 80.0, exposure = 1.0;
    double ambient = -1.0;  // < 0: default
    unsigned long long seed = 1;
    bool shadows = true, variation = true;
    std::vector<LightSpec> lightSpecs;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "-h" || a == "--help") {
            usage(std::cout);
            return 0;
        }
        if (a == "--no-shadows") {
            shadows = false;
            continue;
        }
        if (a == "--no-variation") {
            variation = false;
            continue;
        }
        if (a.rfind("-", 0) != 0) {
            if (!input.empty()) throw UsageError("more than one mesh given: " + input + ", " + a);
            input = a;
            continue;
        }
        if (i + 1 >= argc) throw UsageError("option " + a + " needs a value");
        const std::string v = argv[++i];
        if (a == "-o" || a == "--output") outdir = v;
        else if (a == "--views") views = toInt(a, v);
        else if (a == "--size") {
            const std::size_t x = v.find('x');
            if (x == std::string::npos) throw UsageError("--size needs WxH, got '" + v + "'");
            width = toInt(a, v.substr(0, x));
            height = toInt(a, v.substr(x + 1));
        } else if (a == "--fov") fov = toNumber(a, v);
        else if (a == "--fill") fill = toNumber(a, v);
        else if (a == "--elevation") {
            const std::vector<double> e = numberList(a, v, ',');
            if (e.size() != 2) throw UsageError("--elevation needs MIN,MAX, got '" + v + "'");
            minElevation = e[0];
            maxElevation = e[1];
        } else if (a == "--seed") {
            const int s = toInt(a, v);
            if (s < 0) throw UsageError("--seed must not be negative");
            seed = static_cast<unsigned long long>(s);
        } else if (a == "--up") upName = v;
        else if (a == "--material") materialName = v;
        else if (a == "--light") lightSpecs.push_back(parseLight(v));
        else if (a == "--ambient") ambient = toNumber(a, v);
        else if (a == "--supersampling") supersampling = toInt(a, v);
        else if (a == "--subdivide") subdivide = toInt(a, v);
        else if (a == "--normals") normalsName = v;
        else if (a == "--exposure") exposure = toNumber(a, v);
        else throw UsageError("unknown option '" + a + "'");
    }
    if (input.empty()) throw UsageError("no mesh given");
    if (outdir.empty()) throw UsageError("no output folder (-o OUTDIR)");
    if (width < 1 || height < 1) throw UsageError("--size must be positive");
    if (subdivide < 0 || subdivide > 6) throw UsageError("--subdivide must lie in 0..6");
    if (!(exposure > 0.0)) throw UsageError("--exposure must be positive");
    if (normalsName != "recompute" && normalsName != "interpolate")
        throw UsageError("--normals must be recompute or interpolate, got '" + normalsName + "'");
    const Eigen::Vector3d up = parseAxis(upName);
    const rad::SampleMaterial materialKind = rad::parseSampleMaterial(materialName);

    using Clock = std::chrono::steady_clock;
    auto seconds = [](Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); };
    const auto t0 = Clock::now();

    rad::TriangleMesh mesh = loadMesh(input);
    const std::string problem = mesh.validate();
    if (!problem.empty()) throw std::runtime_error(input + ": " + problem);
    if (normalsName == "interpolate") {
        if (!mesh.hasNormals()) rad::computeAreaWeightedNormals(mesh);
        mesh = rad::subdivideMidpoint(mesh, subdivide, rad::SubdivisionNormals::Interpolate);
    } else if (!mesh.hasNormals() || subdivide > 0) {
        mesh = rad::subdivideMidpoint(mesh, subdivide);  // level 0: area-weighted normals only
    }
    const auto tMesh = Clock::now();
    std::printf("mesh %s: %zu vertices, %zu faces%s (%.2f s)\n", input.c_str(), mesh.vertexCount(), mesh.faceCount(),
                subdivide > 0 ? (", after " + std::to_string(subdivide) + " midpoint subdivision(s)").c_str() : "",
                seconds(t0, tMesh));

    Eigen::AlignedBox3d box;
    double radius = 0.0;  // bounding sphere around the box centre
    rad::sampleSceneBounds(mesh, rad::SampleLightRadius::FarthestVertex, box, radius);
    const Eigen::Vector3d centre = box.center();

    rad::AnalyticLighting lighting;
    if (lightSpecs.empty()) {
        lighting = rad::makeSampleLighting(centre, radius, up);
        if (ambient >= 0.0) lighting.ambient = Eigen::Vector3d::Constant(ambient);
    } else {
        for (const LightSpec& l : lightSpecs) {
            if (l.directional) {
                lighting.directional.push_back({l.vector.normalized(), l.value});
            } else {
                const Eigen::Vector3d q = centre + radius * l.vector;
                lighting.points.push_back({q, l.value * (q - centre).squaredNorm()});
            }
        }
        lighting.ambient = Eigen::Vector3d::Constant(std::max(0.0, ambient));
    }
    rad::VirtualSceneOptions sceneOptions;
    sceneOptions.castShadows = shadows;
    sceneOptions.variation.enabled = variation;
    const rad::AnalyticMaterial material = rad::makeSampleMaterial(materialKind, box, up);
    rad::VirtualScene scene(mesh, material, lighting, sceneOptions);
    const auto tScene = Clock::now();
    std::printf("Embree scene built in %.2f s\n", seconds(tMesh, tScene));

    rad::CameraRigOptions rig;
    rig.count = views;
    rig.width = width;
    rig.height = height;
    rig.horizontalFovDegrees = fov;
    rig.fillFraction = fill;
    rig.minElevationDegrees = minElevation;
    rig.maxElevationDegrees = maxElevation;
    rig.up = up;
    rig.seed = seed;
    const std::vector<rad::PinholeCamera> cameras = rad::makeCameraRig(centre, radius, rig);

    const std::filesystem::path out(outdir);
    std::filesystem::create_directories(out / "images");
    rad::RadianceMesh plyMesh;
    plyMesh.positions = scene.mesh().positions;
    plyMesh.normals = scene.mesh().normals;
    plyMesh.faces = scene.mesh().faces;
    rad::writeRadiancePly((out / "mesh.ply").string(), plyMesh);

    const int digits = std::max(3, static_cast<int>(std::to_string(std::max(0, views - 1)).size()));
    rad::MeshLabProject project;
    rad::PhotographOptions photo;
    photo.supersampling = supersampling;
    double renderSeconds = 0.0, writeSeconds = 0.0;
    std::size_t clipped = 0, covered = 0;
    std::future<void> pendingWrite;  // PNG encoding of view k overlaps the rendering of view k + 1
    for (int k = 0; k < views; ++k) {
        char name[32];
        std::snprintf(name, sizeof name, "view_%0*d.png", digits, k);
        rad::ProjectRaster raster;
        raster.label = name;
        raster.imageFile = std::string("images/") + name;
        raster.camera = rad::roundedToFloat(rad::toVcgCamera(cameras[k]));
        const rad::PinholeCamera stored = rad::fromVcgCamera(raster.camera);  // exactly what readers see
        const auto a = Clock::now();
        rad::ImageF image = rad::renderPhotograph(scene, stored, photo);
        const auto b = Clock::now();
        renderSeconds += seconds(a, b);
        for (std::size_t i = 0; i < image.rgb.size(); i += 3) {
            const float m = std::max({image.rgb[i], image.rgb[i + 1], image.rgb[i + 2]});
            covered += m > 0.0f;
            clipped += exposure * m > 1.0f;
        }
        if (pendingWrite.valid()) pendingWrite.get();
        const std::string path = (out / raster.imageFile).string();
        pendingWrite = std::async(std::launch::async, [path, img = std::move(image), exposure]() {
            rad::writePhotographPng(path, img, static_cast<float>(exposure));
        });
        writeSeconds += seconds(b, Clock::now());
        project.rasters.push_back(raster);
        std::printf("\r%d/%d photographs", k + 1, views);
        std::fflush(stdout);
    }
    if (pendingWrite.valid()) pendingWrite.get();
    std::printf("\n");
    rad::writeMeshLabProject((out / "project.mlp").string(), project);

    {
        std::ofstream s(out / "scene.txt");
        s.precision(9);
        s << "# virtual_acquisition scene: rebuild the ground truth with rad::VirtualScene(mesh.ply,\n"
          << "# makeSampleMaterial(material, bbox, up), the lights below, options below)\n"
          << "mesh_source " << input << "\nsubdivide " << subdivide << "\nnormals " << normalsName << "\nup " << vec(up) << "\nmaterial "
          << materialName << "\nvariation " << (variation ? 1 : 0) << "\nshadows " << (shadows ? 1 : 0)
          << "\nbbox_min " << vec(box.min()) << "\nbbox_max " << vec(box.max()) << "\nbounding_radius " << radius
          << "\nexposure " << exposure << "\nsupersampling " << supersampling << "\nviews " << views << "\nseed "
          << seed << "\nambient " << vec(lighting.ambient) << "\n";
        for (const auto& l : lighting.directional) s << "directional " << vec(l.direction) << " irradiance " << vec(l.irradiance) << "\n";
        for (const auto& l : lighting.points) s << "point " << vec(l.position) << " intensity " << vec(l.intensity) << "\n";
        if (!s) throw std::runtime_error("cannot write " + (out / "scene.txt").string());
    }
    const auto tEnd = Clock::now();
    const double primaryRays = double(views) * width * height * supersampling * supersampling;
    std::printf("wrote %s: %d photographs %dx%d (%dx%d rays per pixel), project.mlp, mesh.ply, scene.txt\n",
                outdir.c_str(), views, width, height, supersampling, supersampling);
    std::printf("rendering %.2f s (%.2f s per photograph, %.2f M primary rays/s incl. shading and shadow rays), "
                "waiting for PNG writes %.2f s, total %.2f s\n",
                renderSeconds, renderSeconds / views, primaryRays / renderSeconds / 1e6, writeSeconds,
                seconds(t0, tEnd));
    if (covered > 0)
        std::printf("object pixels above 1 before encoding (clipped to white): %.3f %%\n", 100.0 * clipped / covered);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    return radtools::runTool("virtual_acquisition", argc, argv, run, usage, /*invalidArgumentIsUsage=*/true);
}
