// The POP buffer of Limper et al. 2013 ("The POP Buffer: Rapid Progressive Clustering by Geometry
// Quantization"), the level-of-detail scheme Weber & Stamminger build on: at level L (1..16) every
// position is snapped to a grid of 2^L cells per axis over the mesh's bounding box, which clusters
// vertices without any connectivity change. A triangle whose three vertices fall in three distinct
// cells at level L is drawn; one with two vertices in the same cell has collapsed and is not. A
// triangle that is drawn at L is drawn at every finer level, so sorting the triangles by the first
// level at which they are drawn makes the triangles of level L a prefix of the index buffer: a
// renderer draws `levelEnd[L]` indices and keeps no state between frames.
//
// The grid is exact integer arithmetic: a coordinate's level-16 cell c16 = floor(t * 65536) with t
// its position in [0, 1] across the box (65535 for t = 1), and its level-L cell is c16 >> (16 - L),
// the same as floor(t * 2^L). A snapped coordinate is the centre of its cell, so the clustered mesh
// stays centred on the original. An axis along which the box is flat (a planar mesh) is not snapped.
#pragma once

#include "geometry/triangle_mesh.h"
#include "progress/progress_callback.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rad {

constexpr int kPopMinLevel = 1;
constexpr int kPopMaxLevel = 16;
// The "level" of a triangle that stays collapsed at level 16 (two vertices closer than 1/65536 of
// the box, or the same vertex twice): it is drawn only by the unquantized mesh.
constexpr int kPopNeverDrawn = kPopMaxLevel + 1;

struct PopBuffer {
    std::array<double, 3> boxMin{};
    std::array<double, 3> boxExtent{};  // max - min per axis (0 for a flat axis)
    // Level-16 cell of every vertex, 3 per vertex (x, y, z).
    std::vector<std::uint16_t> cells;
    // The triangles sorted by level (stable: the input order within a level), 3 indices each.
    std::vector<std::uint32_t> faces;
    // Input index of every sorted triangle.
    std::vector<std::uint32_t> faceOrder;
    // Level of every sorted triangle: 1..16, or kPopNeverDrawn.
    std::vector<std::uint8_t> faceLevel;
    // levelEnd[L] = number of triangles drawn at level L (L = 1..16), a prefix of `faces`;
    // levelEnd[0] = 0 and levelEnd[kPopNeverDrawn] = all triangles.
    std::array<std::size_t, kPopNeverDrawn + 1> levelEnd{};

    std::size_t vertexCount() const { return cells.size() / 3; }
    std::size_t faceCount() const { return faces.size() / 3; }
    // Cell of vertex v along `axis` at `level` (1..16).
    std::uint32_t cell(std::size_t v, int axis, int level) const {
        return std::uint32_t(cells[3 * v + axis]) >> (kPopMaxLevel - level);
    }
    // The snapped coordinate of vertex v along `axis` at `level`: the centre of its cell; the box's
    // coordinate itself along a flat axis.
    double quantizedCoordinate(std::size_t v, int axis, int level) const;
};

// Orders `mesh`'s triangles into a POP buffer (normals are not used).
// \throw std::invalid_argument (a sentence saying what is wrong and how to fix it) for a mesh without
//        vertices or faces, with a non-finite coordinate or an index out of range.
// \throw OperationCancelled when `progress` asks to stop.
PopBuffer buildPopBuffer(const TriangleMesh& mesh, const ProgressCallback& progress = {});

// The level a renderer draws when the bounding box's diagonal covers `boxPixels` pixels on screen
// and a snapped vertex may move by at most `tolerancePixels`: the coarsest L whose half cell
// diagonal (the largest move) is within the tolerance, clamped to 1..16.
int popLevelForScreenSize(double boxPixels, double tolerancePixels);

}  // namespace rad
