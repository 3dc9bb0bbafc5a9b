// CMeshO <-> plain arrays (rad::RadianceMesh), the bridge between MeshLab layers and the cores.
#pragma once

#include "io/radiance_ply.h"

#include "meshlab_mesh.h"

#include <string>
#include <vector>

namespace radml {

struct ExportChoice {
    bool normals = true;
    bool colors = true;
    bool quality = true;
    bool radiance = true;
    bool transfer = true;  // PRT transfer vectors as the extra block "prt" (transfer_attribute.h)
    // The other extra blocks kept from an opened file (extra_blocks_attribute.h): only saving needs them.
    bool extraBlocks = false;
};

// Copies the live vertices/faces of `mesh` (deleted elements skipped, indices compacted) into `out`.
// Returns false with `why` when the radiance data is requested but inconsistent with the mesh.
// Extra blocks that cannot be exported are left out with a sentence each in `leftOut` (the caller
// must show them: nothing is dropped silently).
bool exportPlainMesh(CMeshO& mesh, const ExportChoice& choice, rad::RadianceMesh& out, std::string& why,
                     std::vector<std::string>* leftOut = nullptr);

// The wedge texture coordinates (u, v) of the live faces, 6 floats per face, in the face order of
// exportPlainMesh. The caller checks that the mesh has them (MeshModel::MM_WEDGTEXCOORD).
std::vector<float> exportWedgeTexCoords(const CMeshO& mesh);

// Per-vertex texture coordinates (a PLY's texture_u/texture_v, as photogrammetry tools write them)
// as wedge coordinates of the live faces, same layout. The caller checks MM_VERTTEXCOORD.
std::vector<float> exportVertexTexCoordsAsWedges(const CMeshO& mesh);

// Replaces the content of `mesh` with `in` (positions, normals, colours, quality, faces, radiance,
// the PRT transfer block "prt", every other extra block as it is). Returns the vcg::tri::io::Mask bits
// describing what was loaded. A "prt" block that does not describe a transfer field is kept as an
// uninterpreted block (saved again unchanged), with a sentence in `warning`.
int importPlainMesh(const rad::RadianceMesh& in, CMeshO& mesh, std::string* warning = nullptr);

}  // namespace radml
