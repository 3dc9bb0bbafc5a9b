// A plain-array triangle mesh: the smallest common currency between the generated scenes
// (primitive_meshes.h), the OFF reader (io/off_reader.h), the tools and the tests. No topology, no
// attributes beyond per-vertex normals; algorithms that need more build it from these arrays.
//
// Layout:
//   positions[3 * v + 0..2]  vertex v
//   normals[3 * v + 0..2]    unit normal of vertex v (or empty when the mesh has none)
//   faces[3 * f + 0..2]      vertex indices of triangle f, counter-clockwise seen from outside
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace rad {

struct TriangleMesh {
    std::vector<float> positions;
    std::vector<float> normals;
    std::vector<std::uint32_t> faces;

    std::size_t vertexCount() const { return positions.size() / 3; }
    std::size_t faceCount() const { return faces.size() / 3; }
    bool hasNormals() const { return !normals.empty(); }

    // Empty string when the arrays are whole triples, normals (if any) match the vertices, every
    // index is in range and every value is finite; otherwise a sentence saying what is wrong.
    std::string validate() const;
};

// Key of the undirected edge {a, b}: the same for (a, b) and (b, a), ordered like (min, max).
inline std::uint64_t undirectedEdgeKey(std::uint64_t a, std::uint64_t b) {
    return a < b ? (a << 32) | b : (b << 32) | a;
}

// Distinct edges by how many faces share them: more than two (the input checks' "non-manifold
// edge") and exactly one (a boundary edge). Sorts the keys in place.
struct EdgeCensus {
    std::size_t nonManifold = 0, boundary = 0;
};
EdgeCensus countEdgesByFaces(std::vector<std::uint64_t>& undirectedEdgeKeys);
// countEdgesByFaces(...).nonManifold.
std::size_t countNonManifoldEdges(std::vector<std::uint64_t>& undirectedEdgeKeys);

}  // namespace rad
