#include "acquisition/sample_scene_radiance_mesh.h"

#include "acquisition/scene_radiance_field.h"
#include "geometry/mesh_bounds.h"
#include "geometry/mesh_normals.h"

#include <algorithm>

namespace rad {

void sampleSceneBounds(const TriangleMesh& mesh, SampleLightRadius kind, Eigen::AlignedBox3d& box, double& radius) {
    const MeshBounds bounds = meshBounds(mesh.positions);
    box = bounds.box;
    radius = kind == SampleLightRadius::HalfBoxDiagonal ? 0.5 * box.diagonal().norm() : bounds.farthestFromCentre;
}

RadianceMesh sampleSceneRadianceMesh(TriangleMesh mesh, const BasisSpec& basis, const SampleSceneRadianceOptions& options,
                                     const ProgressCallback& progress) {
    if (!mesh.hasNormals()) computeAreaWeightedNormals(mesh);
    Eigen::AlignedBox3d box;
    double radius = 0.0;
    sampleSceneBounds(mesh, options.lightRadius, box, radius);
    VirtualSceneOptions sceneOptions;
    sceneOptions.castShadows = options.castShadows;
    sceneOptions.variation.enabled = options.variation;
    VirtualScene scene(mesh, makeSampleMaterial(options.material, box, options.up),
                       makeSampleLighting(box.center(), radius, options.up), sceneOptions);
    RadianceMesh out;
    out.radiance = sceneRadianceField(scene, basis, options.reflected, progress);
    out.positions = scene.mesh().positions;
    out.faces = scene.mesh().faces;
    return out;
}

}  // namespace rad
