// 1-to-4 midpoint subdivision of a triangle mesh: each midpoint is created once per edge and shared,
// so a watertight mesh stays watertight, and the shape does not change (no smoothing, unlike Loop).
// It makes dense meshes of a real scan's exact shape for benchmarks at the scale of Vanhoey et al.
// 2015's acquisitions (e.g. 1.66M vertices from the 26k-vertex armadillo with 3 levels). Original
// vertices keep their indices; normals are recomputed, or interpolated at the midpoints.
// Details: docs/fitting.md, "`common/geometry/midpoint_subdivision.h`: how it works".
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
