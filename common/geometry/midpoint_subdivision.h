// 1-to-4 midpoint subdivision of a triangle mesh: each triangle (a, b, c) becomes
//   (a, m_ab, m_ca), (m_ab, b, m_bc), (m_ca, m_bc, c), (m_ab, m_bc, m_ca)
// where m_xy is the midpoint of edge xy, created ONCE per undirected edge and shared by the
// triangles on both sides (no cracks, no duplicated vertices), so a watertight mesh stays
// watertight and orientations are kept. The shape does not change (no smoothing, unlike Loop):
// this makes dense meshes of a real scan's exact shape, e.g. 1.66M vertices from the 26k-vertex
// armadillo with 3 levels, for benchmarks at the scale of Vanhoey et al. 2015's acquisitions.
//
// Counts per level: V' = V + E, F' = 4 F, E' = 2 E + 3 F. Vertex order: the original vertices
// first (same indices), then one midpoint per edge in increasing (min index, max index) order.
//
// Normals: recomputed after the last level with computeAreaWeightedNormals (geometry/mesh_normals.h),
// as asked for by the fitting issue. Since every original triangle stays flat, the recomputed normals
// are constant across the interior of each original triangle and only vary near its edges: shading
// with them looks faceted at the original resolution. NormalMode::Interpolate instead gives each
// midpoint normalize(n_a + n_b) of its edge's end normals (original vertices keep theirs), which
// keeps the original's smooth (Phong-like) shading.
#pragma once

#include "geometry/triangle_mesh.h"

namespace rad {

enum class SubdivisionNormals {
    Recompute,    // computeAreaWeightedNormals of the subdivided mesh (default)
    Interpolate,  // normalize(n_a + n_b) at midpoints (needs input normals)
};

// levels >= 0 (0 returns a copy, normals recomputed or kept as per the mode). Throws
// std::invalid_argument when the mesh is invalid, levels is negative, Interpolate is asked for a
// mesh without normals, or the result would exceed 2^32 - 1 vertices.
TriangleMesh subdivideMidpoint(const TriangleMesh& mesh, int levels,
                               SubdivisionNormals normals = SubdivisionNormals::Recompute);

}  // namespace rad
