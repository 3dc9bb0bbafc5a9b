// Usable unit vertex normals for real scans, whose normals are often zero, tiny or not finite: a
// vertex used only by a sliver triangle (MeshLab stores the unnormalised area-weighted sum, ~1e-10
// long there), faces that cancel out around a fold, triangles whose corners are collinear in float,
// isolated vertices, NaN from a broken export. Radiance functions, PRT transfer and the bake all live
// on the hemisphere around the normal, so every such vertex needs one; refusing the whole scan for a
// handful of them (as our filters did) helps nobody, and MeshLab's own "Re-Compute Vertex Normals"
// cannot repair a vertex whose only face is degenerate.
//
// For each vertex, in this order (each step counted):
//   1. a finite, non-zero normal is kept and normalised in double, however short it is;
//   2. otherwise the angle-weighted normal of its incident faces (Thürmer and Wüthrich 1998: each
//      face's unit normal weighted by the corner angle at the vertex), in double, so that a sliver
//      of area 1e-11 still gives its plane;
//   3. otherwise (every incident face degenerate, or they cancel out) the normalised average of the
//      normals of its edge neighbours known so far, ring by ring (a round reads only normals known
//      before it, so the result does not depend on the vertex order);
//   4. otherwise (an isolated vertex, or a component with no usable face at all) +Z, counted as
//      defaulted: the caller decides whether that is acceptable (it is not when every vertex is).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace rad {

struct NormalRepairCounts {
    std::size_t kept = 0;            // step 1 (normalised in place)
    std::size_t fromFaces = 0;       // step 2
    std::size_t fromNeighbours = 0;  // step 3
    std::size_t defaulted = 0;       // step 4
    std::size_t repaired() const { return fromFaces + fromNeighbours + defaulted; }
    // "12 vertex normals repaired (10 from their faces, 2 from their neighbours)", empty when none.
    std::string describe() const;
};

// positions: 3 floats per vertex; faces: 3 indices per face, each < vertexCount (not checked here:
// TriangleMesh::validate()); normals: 3 floats per vertex, replaced by unit normals (resized to
// 3 * vertexCount when it is empty or of another size, every vertex then being repaired).
NormalRepairCounts repairVertexNormals(const std::vector<float>& positions, const std::vector<std::uint32_t>& faces,
                                       std::vector<float>& normals);

}  // namespace rad
