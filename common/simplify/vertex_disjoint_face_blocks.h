// The faces of a CollapseMesh cut into blocks of consecutive faces, and the blocks split into classes
// in which no two blocks share a vertex (a greedy colouring of the blocks, two blocks conflicting
// when a face of one and a face of the other have a corner in common). A loop that adds each face's
// terms to its three corners can then run one class at a time, its blocks in parallel: no two
// threads ever write the same vertex, each thread walks consecutive faces (which share corners, so
// the corners' data stays in cache), and each vertex receives its faces in the same order whatever
// the thread count.
#pragma once

#include "simplify/collapse_mesh.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace rad {

struct VertexDisjointFaceBlocks {
    std::size_t blockSize = 0;           // block b holds faces [b * blockSize, (b + 1) * blockSize)
    std::vector<std::uint32_t> blocks;   // block indices, grouped by class, increasing within one
    std::vector<std::size_t> offsets;    // class c is blocks[offsets[c] .. offsets[c + 1])
    std::size_t classCount() const { return offsets.empty() ? 0 : offsets.size() - 1; }
};

// Deterministic: blocks are coloured in index order, each with the smallest class that no block
// already coloured and sharing a vertex with it has. Dead faces count for nothing.
VertexDisjointFaceBlocks vertexDisjointFaceBlocks(const CollapseMesh& mesh, std::size_t blockSize = 128);

}  // namespace rad
