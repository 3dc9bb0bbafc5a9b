// Texture coordinates for baking: the per-triangle atlas made when the target mesh has none, and
// the checks a user-supplied layout must pass before anything is baked into it.
//
// Texture convention (MeshLab's and OpenGL's): wedge coordinates (u, v) in [0, 1]^2, u to the
// right, v UP. The image is stored rows top to bottom, so texel (column c, row r) of a W x H image
// covers u in [c / W, (c + 1) / W] and v in [1 - (r + 1) / H, 1 - r / H]; its centre is
// (u, v) = ((c + 0.5) / W, 1 - (r + 0.5) / H).
//
// Wedge arrays: 6 floats per face, (u0, v0, u1, v1, u2, v2) for the face's corners in the order
// of its vertex indices.
#pragma once

#include "bake/bake_input_error.h"

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace rad {

struct PerTriangleAtlas {
    std::vector<float> wedgeUv;  // 6 floats per face
    int cellSize = 0;            // texels per side of the square cell holding two triangles
    int cellsPerRow = 0;
    int gutterTexels = 0;        // the smallest distance, in texels, between two charts
};

// Per-triangle atlas, as MeshLab's "Parametrization: Trivial Per-Triangle" lays it out: faces are
// paired into square cells of a regular grid; in a cell, face 2k takes the lower-left right
// triangle and face 2k + 1 the upper-right one, each corner on texel centres, so that the two
// triangles of a cell and the triangles of neighbouring cells are at least gutterTexels apart
// (every texel a chart covers, even partly, is at least gutterTexels - 1 texels from any texel of
// another chart). The largest cell that fits is used. Throws BakeInputError when
// faceCount == 0 or when the texture is too small for cells that leave each triangle at least
// 2 texels along its legs (the message gives the smallest texture size that would do).
PerTriangleAtlas makePerTriangleAtlas(std::size_t faceCount, int textureSize, int gutterTexels = 4);

// The largest face count makePerTriangleAtlas lays out in a textureSize^2 texture with this gutter
// (0 when not even one cell fits or the gutter is outside 1..64).
std::size_t perTriangleAtlasCapacity(int textureSize, int gutterTexels);

struct UvLayoutReport {
    std::size_t faceCount = 0;
    std::size_t nonFiniteFaces = 0;      // a coordinate is NaN or infinite
    std::size_t outOfRangeFaces = 0;     // a coordinate outside [0, 1] by more than 1e-5 (rounding)
    std::size_t degenerateFaces = 0;     // UV area below a hundredth of a texel
    std::size_t overlappingTexels = 0;   // texel centres strictly inside two or more faces
    // Empty when the layout can be baked into; otherwise one sentence naming the first problem
    // and the MeshLab filter that fixes it (e.g. "Parametrization: Trivial Per-Triangle").
    std::string problem() const;
};

// Rasterises the layout at textureSize x textureSize: a texel centre strictly inside two faces
// (beyond a small tolerance, so that shared edges do not count) is an overlap. Linear in the
// number of covered texels.
UvLayoutReport checkUvLayout(const float* wedgeUv, std::size_t faceCount, int textureSize);

// Whether size is a power of two in [minSize, maxSize]; otherwise the refusal message.
std::string textureSizeProblem(int size, int minSize = 16, int maxSize = 16384);

}  // namespace rad
