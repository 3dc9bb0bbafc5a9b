#include "lod/pop_buffer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rad {
namespace {

// The first level at which vertices a and b lie in different cells: 16 - (the highest bit in which
// their level-16 cells differ, over the three axes); kPopNeverDrawn when they share a level-16 cell.
int separationLevel(const std::uint16_t* a, const std::uint16_t* b) {
    unsigned differing = 0;
    for (int k = 0; k < 3; ++k) differing |= unsigned(a[k] ^ b[k]);
    if (differing == 0) return kPopNeverDrawn;
    int highest = 0;
    while ((differing >> (highest + 1)) != 0) ++highest;
    return kPopMaxLevel - highest;
}

}  // namespace

double PopBuffer::quantizedCoordinate(std::size_t v, int axis, int level) const {
    const double extent = boxExtent[axis];
    if (!(extent > 0)) return boxMin[axis];
    const double cellSize = extent / double(1u << level);
    return boxMin[axis] + (double(cell(v, axis, level)) + 0.5) * cellSize;
}

PopBuffer buildPopBuffer(const TriangleMesh& mesh, const ProgressCallback& progress) {
    if (mesh.vertexCount() == 0 || mesh.faceCount() == 0)
        throw std::invalid_argument("The mesh has no " + std::string(mesh.vertexCount() == 0 ? "vertices" : "faces") +
                                    ": a POP buffer orders triangles; choose a layer with faces.");
    if (std::string why = mesh.validate(); !why.empty())
        throw std::invalid_argument("The mesh cannot be ordered into a POP buffer: " + why +
                                    ". Remove the bad vertices or faces first (e.g. MeshLab's cleaning filters).");
    if (mesh.faceCount() > 0xffffffffull || mesh.vertexCount() > 0xffffffffull)
        throw std::invalid_argument("The mesh has more than 2^32 vertices or faces: split it into parts first.");

    PopBuffer pop;
    const std::size_t n = mesh.vertexCount(), m = mesh.faceCount();
    std::array<double, 3> lo, hi;
    for (int k = 0; k < 3; ++k) lo[k] = hi[k] = mesh.positions[k];
    for (std::size_t v = 0; v < n; ++v)
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], double(mesh.positions[3 * v + k]));
            hi[k] = std::max(hi[k], double(mesh.positions[3 * v + k]));
        }
    for (int k = 0; k < 3; ++k) {
        pop.boxMin[k] = lo[k];
        pop.boxExtent[k] = hi[k] - lo[k];
    }

    pop.cells.resize(3 * n);
#pragma omp parallel for schedule(static)
    for (long long v = 0; v < (long long)n; ++v)
        for (int k = 0; k < 3; ++k) {
            const double extent = pop.boxExtent[k];
            double cell = 0;
            if (extent > 0) cell = std::floor((double(mesh.positions[3 * v + k]) - lo[k]) / extent * 65536.0);
            pop.cells[3 * v + k] = std::uint16_t(std::clamp(cell, 0.0, 65535.0));
        }
    reportProgress(progress, 0.3, "Quantizing positions");

    std::vector<std::uint8_t> level(m);
#pragma omp parallel for schedule(static)
    for (long long f = 0; f < (long long)m; ++f) {
        const std::uint16_t* a = &pop.cells[3 * std::size_t(mesh.faces[3 * f])];
        const std::uint16_t* b = &pop.cells[3 * std::size_t(mesh.faces[3 * f + 1])];
        const std::uint16_t* c = &pop.cells[3 * std::size_t(mesh.faces[3 * f + 2])];
        level[f] = std::uint8_t(std::max({separationLevel(a, b), separationLevel(b, c), separationLevel(a, c)}));
    }
    reportProgress(progress, 0.6, "Finding the level of every triangle");

    // Stable counting sort by level.
    std::array<std::size_t, kPopNeverDrawn + 2> start{};
    for (std::size_t f = 0; f < m; ++f) ++start[level[f] + 1];
    for (int l = 1; l <= kPopNeverDrawn + 1; ++l) start[l] += start[l - 1];
    for (int l = 0; l <= kPopNeverDrawn; ++l) pop.levelEnd[l] = start[l + 1];
    pop.faces.resize(3 * m);
    pop.faceOrder.resize(m);
    pop.faceLevel.resize(m);
    for (std::size_t f = 0; f < m; ++f) {
        const std::size_t at = start[level[f]]++;
        pop.faceOrder[at] = std::uint32_t(f);
        pop.faceLevel[at] = level[f];
        for (int k = 0; k < 3; ++k) pop.faces[3 * at + k] = mesh.faces[3 * f + k];
    }
    reportProgress(progress, 1.0, "Sorting triangles by level");
    return pop;
}

int popLevelForScreenSize(double boxPixels, double tolerancePixels) {
    if (!(tolerancePixels > 0) || !std::isfinite(tolerancePixels))
        throw std::invalid_argument("The screen-space tolerance must be a positive number of pixels.");
    if (!(boxPixels > 0) || !std::isfinite(boxPixels)) return kPopMinLevel;
    // Largest move at level L: half a cell diagonal = boxPixels / 2^(L + 1).
    for (int level = kPopMinLevel; level <= kPopMaxLevel; ++level)
        if (boxPixels / double(1u << (level + 1)) <= tolerancePixels) return level;
    return kPopMaxLevel;
}

}  // namespace rad
