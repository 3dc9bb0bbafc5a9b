// Tests of vertex_disjoint_face_blocks.h: blocks of consecutive faces coloured so that no two blocks
// of one class share a vertex.
#include "simplify/vertex_disjoint_face_blocks.h"

#include "geometry/primitive_meshes.h"
#include "simplify/collapse_mesh.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <set>
#include <stdexcept>
#include <vector>

namespace {

// An icosphere whose vertices are numbered at random (radtest::renumberVerticesAtRandom).
rad::CollapseMesh shuffledIcosphere(int level, unsigned seed) {
    rad::TriangleMesh sphere = rad::makeIcosphere(level);
    radtest::renumberVerticesAtRandom(sphere.positions, sphere.faces, seed);
    return rad::CollapseMesh(sphere.positions.data(), sphere.vertexCount(), sphere.faces.data(), sphere.faceCount());
}

// The alive vertices of one block.
std::set<std::uint32_t> blockVertices(const rad::CollapseMesh& mesh, const rad::VertexDisjointFaceBlocks& b,
                                      std::uint32_t block) {
    std::set<std::uint32_t> out;
    const std::size_t first = std::size_t(block) * b.blockSize, last = std::min(mesh.faceCount(), first + b.blockSize);
    for (std::size_t f = first; f < last; ++f)
        if (mesh.faceAlive(std::uint32_t(f))) out.insert(mesh.face(std::uint32_t(f)), mesh.face(std::uint32_t(f)) + 3);
    return out;
}

void expectVertexDisjointCover(const rad::CollapseMesh& mesh, const rad::VertexDisjointFaceBlocks& b) {
    const std::size_t blockCount = (mesh.faceCount() + b.blockSize - 1) / b.blockSize;
    std::vector<std::uint32_t> all(b.blocks);
    std::sort(all.begin(), all.end());
    std::vector<std::uint32_t> expected(blockCount);
    std::iota(expected.begin(), expected.end(), 0u);
    EXPECT_EQ(all, expected);  // every block exactly once
    ASSERT_EQ(b.offsets.front(), 0u);
    ASSERT_EQ(b.offsets.back(), b.blocks.size());
    for (std::size_t c = 0; c < b.classCount(); ++c) {
        std::vector<int> owner(mesh.vertexCount(), -1);
        for (std::size_t i = b.offsets[c]; i < b.offsets[c + 1]; ++i)
            for (std::uint32_t v : blockVertices(mesh, b, b.blocks[i])) {
                EXPECT_EQ(owner[v], -1) << "class " << c << " has two blocks at vertex " << v;
                owner[v] = int(i);
            }
    }
}

TEST(VertexDisjointFaceBlocks, NoTwoBlocksOfAClassShareAVertexOnAShuffledScan) {
    const rad::CollapseMesh mesh = shuffledIcosphere(4, 7);  // 5120 faces
    for (std::size_t size : {std::size_t(1), std::size_t(16), std::size_t(128)}) {
        const rad::VertexDisjointFaceBlocks b = rad::vertexDisjointFaceBlocks(mesh, size);
        EXPECT_EQ(b.blockSize, size);
        expectVertexDisjointCover(mesh, b);
        EXPECT_GT(b.classCount(), 1u);
    }
}

TEST(VertexDisjointFaceBlocks, AFanNeedsOneClassPerFace) {
    // Six faces around vertex 0: each conflicts with every other one.
    std::vector<float> p = {0, 0, 0};
    for (int i = 0; i < 6; ++i) p.insert(p.end(), {std::cos(i * 1.0472f), std::sin(i * 1.0472f), 0.0f});
    std::vector<std::uint32_t> f;
    for (std::uint32_t i = 0; i < 6; ++i) f.insert(f.end(), {0u, 1 + i, 1 + (i + 1) % 6});
    const rad::CollapseMesh mesh(p.data(), 7, f.data(), 6);
    const rad::VertexDisjointFaceBlocks b = rad::vertexDisjointFaceBlocks(mesh, 1);
    EXPECT_EQ(b.classCount(), 6u);
    expectVertexDisjointCover(mesh, b);
}

TEST(VertexDisjointFaceBlocks, DeadFacesShareNothing) {
    // Two triangles sharing the edge (1, 2), one face per block: they conflict until the first dies.
    const float p[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    const std::uint32_t f[6] = {0, 1, 2, 2, 1, 3};
    rad::CollapseMesh mesh(p, 4, f, 2);
    EXPECT_EQ(rad::vertexDisjointFaceBlocks(mesh, 1).classCount(), 2u);
    mesh.collapse(0, 1);  // kills face 0 only
    ASSERT_FALSE(mesh.faceAlive(0));
    ASSERT_TRUE(mesh.faceAlive(1));
    EXPECT_EQ(rad::vertexDisjointFaceBlocks(mesh, 1).classCount(), 1u);
}

TEST(VertexDisjointFaceBlocks, IsTheSameOnEveryCall) {
    const rad::CollapseMesh mesh = shuffledIcosphere(3, 11);
    const rad::VertexDisjointFaceBlocks a = rad::vertexDisjointFaceBlocks(mesh, 8), b = rad::vertexDisjointFaceBlocks(mesh, 8);
    EXPECT_EQ(a.blocks, b.blocks);
    EXPECT_EQ(a.offsets, b.offsets);
}

TEST(VertexDisjointFaceBlocks, RefusesEmptyBlocks) {
    const rad::CollapseMesh mesh = shuffledIcosphere(1, 3);
    EXPECT_THROW(rad::vertexDisjointFaceBlocks(mesh, 0), std::invalid_argument);
}

}  // namespace
