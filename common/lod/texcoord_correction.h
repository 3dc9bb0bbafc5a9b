// Texture-coordinate correction for vertex clustering (Weber & Stamminger, eq. 1-3 and Alg. 1).
//
// Snapping a vertex to a grid moves it across the surface while its texture coordinates stay, so the
// texture (a diffuse or a baked normal map) slides with it and "pops" when the level changes. Each
// triangle's tangent space [T B N] maps differences of texture coordinates to differences of
// positions (eq. 1, solved per triangle from its edges in eq. 3); its inverse maps a positional move
// to a move in texture space (eq. 2). A vertex's tangent spaces are averaged over its triangles, and
// the vertex's texture coordinates are shifted by the first two rows of the inverse times its move
// (Alg. 1): exact for a planar, linearly mapped surface (the texture is where it was), a first-order
// correction elsewhere.
//
// Texture coordinates are per corner (wedge: 6 floats per face, u and v of its three corners), so a
// vertex on a texture seam has one texture vertex per chart; the averaging runs over the triangles
// that share the vertex *and* the (u, v) of that corner, never across a seam.
#pragma once

#include "geometry/triangle_mesh.h"
#include "progress/progress_callback.h"

#include <cstddef>
#include <vector>

namespace rad {

struct TexCoordDerivatives {
    // d(u, v)/d(x, y, z) of every corner (3 f + k): 6 floats, the row of u (3) then the row of v (3).
    // Corners of one texture vertex hold the same values; zero where no tangent space could be formed.
    std::vector<float> perCorner;
    std::size_t textureVertices = 0;
    // Texture vertices whose triangles are all degenerate in space or in texture space (or whose
    // averaged tangent space is singular): they keep their coordinates when moved.
    std::size_t withoutTangentSpace = 0;
};

// The per-texture-vertex derivatives of `mesh` with wedge coordinates `wedgeUv` (6 per face).
// \throw std::invalid_argument for a mesh without faces, a bad mesh (non-finite, index out of range),
//        a `wedgeUv` of the wrong size or with a non-finite value.
TexCoordDerivatives computeTexCoordDerivatives(const TriangleMesh& mesh, const std::vector<float>& wedgeUv,
                                               const ProgressCallback& progress = {});

// Alg. 1 for one corner: uv + D (moved - original), D the corner's 2x3 derivative (6 floats).
inline void correctTexCoord(const float* derivative, const double original[3], const double moved[3], double uv[2]) {
    const double d[3] = {moved[0] - original[0], moved[1] - original[1], moved[2] - original[2]};
    uv[0] += derivative[0] * d[0] + derivative[1] * d[1] + derivative[2] * d[2];
    uv[1] += derivative[3] * d[0] + derivative[4] * d[1] + derivative[5] * d[2];
}

}  // namespace rad
