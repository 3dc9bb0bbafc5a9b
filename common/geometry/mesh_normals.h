// Per-vertex normals of a triangle mesh, for meshes that come without them (OFF scans).
//
// Area-weighted average: each vertex's normal is the normalised sum of the (unnormalised) cross
// products (b - a) x (c - a) of its incident triangles, i.e. of their unit normals weighted by twice
// their areas. This is MeshLab's default weighting: vcg::tri::UpdateNormal<>::PerVertexNormalized
// sums the unnormalised vcg::TriangleNormal of the incident faces, then normalises.
#pragma once

#include "geometry/triangle_mesh.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace rad {

// Writes 3 * vertexCount floats into `normals` (resized). A vertex whose incident faces cancel
// out or have zero area, or that no face uses, receives (0, 0, 0): the return value counts such
// vertices, so a caller that needs unit normals everywhere can refuse the mesh or repair them.
// Accumulates in double. Faces must index valid vertices (TriangleMesh::validate()).
std::size_t computeAreaWeightedNormals(const std::vector<float>& positions,
                                       const std::vector<std::uint32_t>& faces,
                                       std::vector<float>& normals);

// Same, replacing mesh.normals.
std::size_t computeAreaWeightedNormals(TriangleMesh& mesh);

// Unit normal of triangle f (zero vector for a degenerate triangle), and its area.
void faceNormal(const TriangleMesh& mesh, std::size_t f, float out[3]);
double faceArea(const TriangleMesh& mesh, std::size_t f);

}  // namespace rad
