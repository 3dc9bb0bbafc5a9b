// The mesh a POP buffer (Limper et al. 2013) draws at one level, evaluated on the CPU: the prefix of
// triangles drawn at that level, positions snapped to the level's grid, texture coordinates as they
// were or corrected by Alg. 1 of Weber & Stamminger (texcoord_correction.h). What a vertex shader
// does per frame, written out: the reference of the tests and of the benchmark, and what the
// "Write Level of Detail" filter exports as a plain mesh.
#pragma once

#include "geometry/triangle_mesh.h"
#include "lod/pop_buffer.h"
#include "lod/texcoord_correction.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace rad {

struct PopLevelRequest {
    const TriangleMesh* mesh = nullptr;     // the mesh the POP buffer was built from
    const PopBuffer* pop = nullptr;
    int level = kPopMaxLevel;               // 1..16
    // Wedge texture coordinates of the mesh's faces (6 per face, input order), or null.
    const std::vector<float>* wedgeUv = nullptr;
    // Per-corner derivatives of `wedgeUv` (computeTexCoordDerivatives), or null for no correction.
    const TexCoordDerivatives* correction = nullptr;
};

struct PopLevelMesh {
    // The vertices used by the level's triangles (in input order), snapped; faces index them.
    TriangleMesh mesh;
    std::vector<float> wedgeUv;              // 6 per face, when the request has coordinates
    std::vector<std::uint32_t> sourceVertex; // input vertex of every output vertex
    std::vector<std::uint32_t> sourceFace;   // input face of every output face
    std::size_t movedVertices = 0;           // output vertices whose position changed
    double maxDisplacement = 0;              // largest move, in the mesh's units
};

// \throw std::invalid_argument for a level outside 1..16, a missing mesh or POP buffer, a POP buffer
//        not built from this mesh, coordinates or derivatives of the wrong size, or a correction
//        asked without texture coordinates.
PopLevelMesh evaluatePopLevel(const PopLevelRequest& request);

}  // namespace rad
