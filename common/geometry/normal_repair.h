// Usable unit vertex normals for real scans, whose normals are often zero, tiny or not finite
// (slivers, folds, collinear corners in float, isolated vertices, NaN from a broken export):
// radiance functions, PRT transfer and the bake all live on the hemisphere around the normal, and
// refusing a whole scan for a handful of vertices helps nobody. Per vertex, in this order (counted):
//   1. a finite, non-zero normal is kept, normalised in double;
//   2. otherwise the angle-weighted normal of its faces (Thürmer and Wüthrich 1998);
//   3. otherwise the average of its neighbours' normals, ring by ring (independent of vertex order);
//   4. otherwise +Z, counted as defaulted: the caller decides whether that is acceptable.
// Details: docs/robustness.md, "`common/geometry/normal_repair.h`: how it works".
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
