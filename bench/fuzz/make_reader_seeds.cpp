// Seed corpora for bench/fuzz/progressive_mesh_fuzzer.cpp and irradiance_grid_fuzzer.cpp, written by
// our own writers into the folders given as arguments:
//   RPM_FOLDER/base.rply, half-edge.rpm, full.rpm   (a simplified icosphere with SH radiance; both
//                                                     .rpm files name base.rply)
//   IVG_FOLDER/small.ivg, flat.ivg                  (grids with smooth and constant vectors)
#include "geometry/mesh_normals.h"
#include "geometry/primitive_meshes.h"
#include "lighting/irradiance_vector_grid.h"
#include "radiance/material_radiance.h"
#include "simplify/progressive_mesh.h"
#include "simplify/radiance_simplification.h"

#include <cmath>
#include <cstdio>
#include <string>

namespace {

rad::RadianceMesh sphereWithRadiance() {
    rad::TriangleMesh sphere = rad::makeIcosphere(2);
    rad::computeAreaWeightedNormals(sphere);
    rad::AnalyticMaterial material;
    rad::AnalyticLighting lighting;
    lighting.directional.push_back({Eigen::Vector3d(0.3, 0.5, 1.0), rad::Rgb(1.0, 0.9, 0.8)});
    rad::MaterialRadianceOptions options;
    options.basis = {rad::BasisKind::SphericalHarmonics, 2};
    rad::RadianceMesh mesh;
    mesh.positions = sphere.positions;
    mesh.faces = sphere.faces;
    mesh.radiance = rad::makeMaterialRadiance(sphere.positions.data(), sphere.normals.data(), sphere.vertexCount(),
                                              material, lighting, options);
    return mesh;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: make_reader_seeds RPM_FOLDER IVG_FOLDER\n");
        return 2;
    }
    const std::string rpm = argv[1], ivg = argv[2];
    for (rad::CollapseKind kind : {rad::CollapseKind::HalfEdge, rad::CollapseKind::Full}) {
        rad::RadianceSimplificationOptions options;
        options.metric = rad::SimplificationMetric::GeometryOnly;
        options.collapse.kind = kind;
        options.collapse.targetFaceCount = 40;
        const rad::RadianceSimplificationResult r = rad::simplifyRadianceMesh(sphereWithRadiance(), options);
        const std::string name = kind == rad::CollapseKind::Full ? "full" : "half-edge";
        rad::writeProgressiveMesh(rpm + "/" + name + ".rpm", rpm + "/base.rply", r.progressive);
    }
    for (int flat = 0; flat < 2; ++flat) {
        rad::IrradianceVectorGrid grid = rad::IrradianceVectorGrid::covering({{-1, -1, -1}}, {{1, 1, 2}}, {{3, 2, 4}});
        for (std::size_t i = 0; i < grid.vectors.size(); ++i) grid.vectors[i] = flat ? 0.25f : std::sin(0.37f * i);
        rad::writeIrradianceVectorGrid(ivg + (flat ? "/flat.ivg" : "/small.ivg"), grid);
    }
    return 0;
}
