// A radiance mesh with known ground truth straight from a scan and a sample material, no
// photographs: the exact outgoing radiance of the sample scene (virtual_scene.h: sample material and
// lighting around the mesh) projected on a basis at every vertex (scene_radiance_field.h). What
// tools/make_radiance_mesh writes and what the simplification benchmarks simplify.
#pragma once

#include "acquisition/virtual_scene.h"
#include "geometry/triangle_mesh.h"
#include "io/radiance_mesh.h"
#include "progress/progress_callback.h"
#include "radiance/basis.h"

#include <Eigen/Core>

namespace rad {

// Where the sample lighting's fill light goes (makeSampleLighting's radius): both choices are in
// use and move the figures made with them, so the caller states which.
enum class SampleLightRadius {
    FarthestVertex,   // largest distance of a vertex from the bounding-box centre (the tools)
    HalfBoxDiagonal,  // half the bounding-box diagonal (the simplification benchmarks)
};

struct SampleSceneRadianceOptions {
    SampleMaterial material = SampleMaterial::Glossy;
    Eigen::Vector3d up = Eigen::Vector3d::UnitY();
    bool castShadows = true;
    bool variation = true;   // SmoothVariation of the material over position
    bool reflected = false;  // reflected radiance functions (Vanhoey et al. 2015, sec. 3.1)
    SampleLightRadius lightRadius = SampleLightRadius::FarthestVertex;
};

// The mesh's bounding box and the light radius of `kind` for it.
void sampleSceneBounds(const TriangleMesh& mesh, SampleLightRadius kind, Eigen::AlignedBox3d& box, double& radius);

// Positions and faces of `mesh`, radiance of the sample scene at every vertex (area-weighted normals
// are computed first when the mesh has none). No colours: the caller sets them if it wants them.
RadianceMesh sampleSceneRadianceMesh(TriangleMesh mesh, const BasisSpec& basis, const SampleSceneRadianceOptions& options,
                                     const ProgressCallback& progress = {});

}  // namespace rad
