// Image-space quality of radiance-aware simplification against the paper's comparisons
// (Vanhoey et al. 2015, Vanhoey et al. 2015), in numbers rather than pictures:
//  [1] Fig. 8: a sphere with alternating diffuse and specular stripes (PB4, 10,242 vertices),
//      half-edge collapse to 50 % of the faces with the radiance metric (eq. 7), the colour QEM
//      (Garland-Heckbert 1998 on the mean colour), the 2010 light-field metric and geometry alone.
//      Target: mean image RMSE of the radiance metric <= 0.6 x that of the colour QEM.
//  [2] Fig. 7: a real scan (CGAL's refined elephant, the paper's Fig. 7 subject) with a glossy SH(6)
//      radiance field, simplified to 25 % of its faces (half-edge and full collapse) versus the
//      field reduced to SH(2) / SH(3) on the full mesh (directional reduction). Target:
//      simplification has the lower image error at comparable memory.
// Every render: 16 views around the object, 512 x 512, per-fragment eq. 8 shading, error over the
// pixels either mesh covers (render/image_space_error.h).
//  [1b] Fig. 8 rebuilt as the paper describes it: glossy and matte stripes with equal mean colours.
//   bench_simplify_quality [--views N] [--size S] [--lazy 0|1] [--level L (fig. 8 icosphere, 5)] [--only fig8|fig8b|fig7]
#include "acquisition/sample_scene_radiance_mesh.h"
#include "acquisition/virtual_scene.h"
#include "geometry/mesh_normals.h"
#include "geometry/primitive_meshes.h"
#include "io/off_reader.h"
#include "radiance/material_radiance.h"
#include "render/image_space_error.h"
#include "simplify/directional_reduction.h"
#include "simplify/radiance_simplification.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#ifndef RADIANCE_SOURCE_DIR
#define RADIANCE_SOURCE_DIR "."
#endif

namespace {

rad::ImageSpaceOptions imageOptions;
bool lazy = true;
int sphereLevel = 5;  // 10,242 vertices; --level L for others

// The sample scene's exact radiance on the mesh, the lights placed at half the box diagonal.
rad::RadianceMesh radianceMesh(rad::TriangleMesh mesh, rad::SampleMaterial material, rad::BasisSpec basis,
                               const Eigen::Vector3d& up, bool shadows) {
    rad::SampleSceneRadianceOptions options;
    options.material = material;
    options.up = up;
    options.castShadows = shadows;
    options.lightRadius = rad::SampleLightRadius::HalfBoxDiagonal;
    return rad::sampleSceneRadianceMesh(std::move(mesh), basis, options);
}

rad::RadianceMesh simplified(const rad::RadianceMesh& mesh, rad::SimplificationMetric metric, rad::CollapseKind kind,
                             double ratio, double* seconds = nullptr) {
    rad::RadianceSimplificationOptions options;
    options.metric = metric;
    options.collapse.kind = kind;
    options.collapse.lazyRepricing = lazy;
    options.collapse.targetFaceCount = static_cast<std::size_t>(ratio * mesh.faceCount());
    if (metric == rad::SimplificationMetric::ColorQuadric) {
        // Garland-Heckbert's 6D quadric already holds the geometric distance.
        options.collapse.geometryWeight = 0.0;
        options.collapse.attributeWeight = 1.0;
    }
    rad::RadianceSimplificationResult r = rad::simplifyRadianceMesh(mesh, options);
    if (seconds) *seconds = r.seconds;
    return r.progressive.extract(r.progressive.stepsForFaceCount(options.collapse.targetFaceCount));
}

void printRow(const char* name, const rad::RadianceMesh& mesh, const rad::ImageSpaceError& e) {
    std::printf("  %-34s %8zu %8zu %6s %9.3f %10.5f %8.2f %8.3f %8.2f\n", name, mesh.vertexCount(), mesh.faceCount(),
                mesh.radiance->basis.name().c_str(), e.otherMemoryBytes / 1e6, e.meanRmseLinear, e.meanPsnrLinear,
                e.meanRmseSrgb8, e.meanPsnrSrgb8);
}

void header() {
    std::printf("  %-34s %8s %8s %6s %9s %10s %8s %8s %8s\n", "representation", "vertices", "faces", "basis", "memory MB",
                "RMSE lin", "PSNR dB", "RMSE 8b", "PSNR 8b");
}

void fig8() {
    std::printf("[1] Fig. 8: striped sphere, PB4, half-edge collapse to 50 %% of the faces\n");
    rad::TriangleMesh sphere = rad::makeIcosphere(sphereLevel);
    const rad::RadianceMesh original =
        radianceMesh(sphere, rad::SampleMaterial::Stripes, {rad::BasisKind::HemisphericalPolynomial, 4},
                     Eigen::Vector3d::UnitZ(), false);
    header();
    struct Run {
        const char* name;
        rad::SimplificationMetric metric;
    };
    const Run runs[] = {{"radiance (eq. 7)", rad::SimplificationMetric::Radiance},
                        {"colour QEM (GH98, mean colour)", rad::SimplificationMetric::ColorQuadric},
                        {"light field 2010 (Vanhoey et al. 2010)", rad::SimplificationMetric::LightField2010},
                        {"geometry only (memoryless QEM)", rad::SimplificationMetric::GeometryOnly}};
    double radianceRmse = 0.0, colorRmse = 0.0;
    for (const Run& run : runs) {
        double seconds = 0.0;
        const rad::RadianceMesh s = simplified(original, run.metric, rad::CollapseKind::HalfEdge, 0.5, &seconds);
        const rad::ImageSpaceError e = rad::compareRadianceMeshes(original, s, imageOptions);
        printRow(run.name, s, e);
        if (run.metric == rad::SimplificationMetric::Radiance) radianceRmse = e.meanRmseLinear;
        if (run.metric == rad::SimplificationMetric::ColorQuadric) colorRmse = e.meanRmseLinear;
    }
    std::printf("  radiance / colour QEM mean linear RMSE: %.3f (target <= 0.6)\n\n", radianceRmse / colorRmse);
}

// Fig. 8 as the paper describes its scene: stripes that differ in their directional behaviour only,
// with mean colours a colour metric cannot tell apart. The glossy material's field everywhere, then
// every other of 8 stripes along the up axis made matte: each of its vertices' functions replaced by
// the constant equal to that function's own hemispherical mean (PB: the constant term). The mean-colour
// field is then the same continuous field on both kinds of stripe; only the directional behaviour
// changes at the stripe borders.
void fig8EqualMeans() {
    std::printf("[1b] Fig. 8 rebuilt: glossy and matte stripes of equal mean colour, PB4, half-edge to 50 %%\n");
    rad::TriangleMesh sphere = rad::makeIcosphere(sphereLevel);
    rad::RadianceMesh original =
        radianceMesh(sphere, rad::SampleMaterial::Glossy, {rad::BasisKind::HemisphericalPolynomial, 4},
                     Eigen::Vector3d::UnitZ(), false);
    // The error no metric avoids here: the same sphere glossy everywhere, simplified by the radiance
    // metric (the highlight interpolated over half the vertices).
    {
        const rad::RadianceMesh s = simplified(original, rad::SimplificationMetric::Radiance, rad::CollapseKind::HalfEdge, 0.5);
        std::printf("  glossy everywhere (no stripes), radiance metric: mean linear RMSE %.5f\n",
                    rad::compareRadianceMeshes(original, s, imageOptions).meanRmseLinear);
    }
    rad::RadianceField& field = *original.radiance;
    std::vector<float> means(3 * field.vertexCount());
    rad::meanHemisphereColors(field, means.data());
    std::size_t matte = 0;
    for (std::size_t v = 0; v < field.vertexCount(); ++v) {
        const double z = original.positions[3 * v + 2];  // the unit sphere: z in [-1, 1]
        const int stripe = std::min(7, static_cast<int>((z + 1.0) * 4.0));
        if (stripe % 2 != 0) continue;
        ++matte;
        for (int c = 0; c < 3; ++c) {
            float* k = field.channelCoefficients(v, c);
            std::fill(k, k + field.coefficientsPerChannel(), 0.0f);
            k[0] = means[3 * v + c];  // u^0 v^0 = 1
        }
    }
    std::vector<float> check(means.size());
    rad::meanHemisphereColors(field, check.data());
    double worst = 0.0;
    for (std::size_t i = 0; i < means.size(); ++i) worst = std::max(worst, double(std::fabs(check[i] - means[i])));
    std::printf("  %zu of %zu vertices matte; largest change of a vertex's mean colour: %.2g\n", matte,
                field.vertexCount(), worst);
    header();
    double radianceRmse = 0.0, colorRmse = 0.0;
    for (const rad::SimplificationMetric metric :
         {rad::SimplificationMetric::Radiance, rad::SimplificationMetric::ColorQuadric,
          rad::SimplificationMetric::GeometryOnly}) {
        const rad::RadianceMesh s = simplified(original, metric, rad::CollapseKind::HalfEdge, 0.5);
        const rad::ImageSpaceError e = rad::compareRadianceMeshes(original, s, imageOptions);
        printRow(rad::describe(metric).c_str(), s, e);
        if (metric == rad::SimplificationMetric::Radiance) radianceRmse = e.meanRmseLinear;
        if (metric == rad::SimplificationMetric::ColorQuadric) colorRmse = e.meanRmseLinear;
    }
    std::printf("  radiance / colour QEM mean linear RMSE: %.3f (target <= 0.6)\n\n", radianceRmse / colorRmse);
}

void fig7() {
    const std::string path = std::string(RADIANCE_SOURCE_DIR) + "/data-cache/meshes/refined_elephant.off";
    rad::TriangleMesh scan;
    try {
        scan = rad::readOff(path);
    } catch (const std::exception& e) {
        std::printf("[2] skipped: %s (run samples/fetch_data.sh)\n", e.what());
        return;
    }
    std::printf("[2] Fig. 7: refined elephant scan, glossy SH6, 25 %% of the faces vs directional reduction\n");
    const rad::RadianceMesh original =
        radianceMesh(scan, rad::SampleMaterial::Glossy, {rad::BasisKind::SphericalHarmonics, 6}, Eigen::Vector3d::UnitY(), true);
    std::printf("  original: %zu vertices, %zu faces, SH6, %.3f MB\n", original.vertexCount(), original.faceCount(),
                rad::radianceMeshMemoryBytes(original) / 1e6);
    header();
    double bestSimplified = 1e30, bestReduced = 1e30;
    for (rad::CollapseKind kind : {rad::CollapseKind::HalfEdge, rad::CollapseKind::Full}) {
        const rad::RadianceMesh s = simplified(original, rad::SimplificationMetric::Radiance, kind, 0.25);
        const rad::ImageSpaceError e = rad::compareRadianceMeshes(original, s, imageOptions);
        printRow(kind == rad::CollapseKind::HalfEdge ? "simplified 25 %, half-edge, eq. 7" : "simplified 25 %, full, sec. 4.3",
                 s, e);
        bestSimplified = std::min(bestSimplified, e.meanRmseLinear);
    }
    for (int degree : {3, 2}) {
        rad::RadianceMesh reduced = original;
        reduced.radiance = rad::reduceDirectionalDegree(*original.radiance, {rad::BasisKind::SphericalHarmonics, degree});
        const rad::ImageSpaceError e = rad::compareRadianceMeshes(original, reduced, imageOptions);
        printRow(degree == 3 ? "directional reduction to SH3" : "directional reduction to SH2", reduced, e);
        bestReduced = std::min(bestReduced, e.meanRmseLinear);
    }
    std::printf("  best simplification / best directional reduction mean linear RMSE: %.3f (target < 1)\n",
                bestSimplified / bestReduced);
}

}  // namespace

int main(int argc, char** argv) {
    std::string only;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string a = argv[i], v = argv[i + 1];
        if (a == "--views") imageOptions.viewCount = std::atoi(v.c_str());
        else if (a == "--size") imageOptions.width = imageOptions.height = std::atoi(v.c_str());
        else if (a == "--lazy") lazy = v != "0";
        else if (a == "--only") only = v;
        else if (a == "--level") sphereLevel = std::atoi(v.c_str());
    }
    const auto t0 = std::chrono::steady_clock::now();
    if (only.empty() || only == "fig8") fig8();
    if (only.empty() || only == "fig8" || only == "fig8b") fig8EqualMeans();
    if (only.empty() || only == "fig7") {
        imageOptions.up = Eigen::Vector3d::UnitY();
        fig7();
    }
    std::printf("total %.1f s\n", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    return 0;
}
