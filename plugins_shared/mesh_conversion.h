// CMeshO <-> plain arrays (rad::RadianceMesh), the bridge between MeshLab layers and the cores.
#pragma once

#include "io/radiance_ply.h"

#include <common/ml_mesh_type.h>

#include <string>

namespace radml {

struct ExportChoice {
    bool normals = true;
    bool colors = true;
    bool quality = true;
    bool radiance = true;
};

// Copies the live vertices/faces of `mesh` (deleted elements skipped, indices compacted) into `out`.
// Returns false with `why` when the radiance data is requested but inconsistent with the mesh.
bool exportPlainMesh(CMeshO& mesh, const ExportChoice& choice, rad::RadianceMesh& out, std::string& why);

// Replaces the content of `mesh` with `in` (positions, normals, colours, quality, faces, radiance).
// Returns the vcg::tri::io::Mask bits describing what was loaded.
int importPlainMesh(const rad::RadianceMesh& in, CMeshO& mesh);

}  // namespace radml
