#include "simplify/vertex_disjoint_face_blocks.h"

#include <algorithm>
#include <stdexcept>

namespace rad {

VertexDisjointFaceBlocks vertexDisjointFaceBlocks(const CollapseMesh& mesh, std::size_t blockSize) {
    if (blockSize == 0) throw std::invalid_argument("vertexDisjointFaceBlocks: the block size must be at least 1");
    constexpr std::uint32_t kUncoloured = UINT32_MAX;
    const std::size_t nf = mesh.faceCount(), blockCount = (nf + blockSize - 1) / blockSize;
    std::vector<std::uint32_t> colour(blockCount, kUncoloured);
    // taken[c] == b + 1 while colouring block b: class c is used by a block sharing a vertex with b.
    std::vector<std::size_t> taken;
    std::size_t classes = 0;
    for (std::size_t b = 0; b < blockCount; ++b) {
        const std::size_t first = b * blockSize, last = std::min(nf, first + blockSize);
        for (std::size_t f = first; f < last; ++f) {
            if (!mesh.faceAlive(static_cast<std::uint32_t>(f))) continue;
            const std::uint32_t* t = mesh.face(static_cast<std::uint32_t>(f));
            for (int corner = 0; corner < 3; ++corner)
                for (std::uint32_t g : mesh.incidentFaces(t[corner])) {
                    const std::uint32_t c = colour[g / blockSize];
                    if (c != kUncoloured) taken[c] = b + 1;
                }
        }
        std::uint32_t c = 0;
        while (c < classes && taken[c] == b + 1) ++c;
        if (c == classes) {
            ++classes;
            taken.push_back(0);
        }
        colour[b] = c;
    }
    // Counting sort by class, blocks in index order within a class.
    VertexDisjointFaceBlocks out;
    out.blockSize = blockSize;
    out.offsets.assign(classes + 1, 0);
    for (std::size_t b = 0; b < blockCount; ++b) ++out.offsets[colour[b] + 1];
    for (std::size_t c = 0; c < classes; ++c) out.offsets[c + 1] += out.offsets[c];
    out.blocks.resize(blockCount);
    std::vector<std::size_t> next(out.offsets.begin(), out.offsets.end() - 1);
    for (std::size_t b = 0; b < blockCount; ++b) out.blocks[next[colour[b]]++] = static_cast<std::uint32_t>(b);
    return out;
}

}  // namespace rad
