// Simplification by uniform vertex clustering with quadrics (Lindstrom 2000, "Out-of-core
// simplification of large polygonal models"), the simplification Granier et al. 2007 use for scans
// that do not fit in memory: one pass over the triangles, in any order, streamed.
//
//  - A uniform grid of cubic cells covers the bounding box of the vertices. Its cell size is given,
//    or chosen from a target triangle count: a closed surface has about twice as many triangles as
//    vertices, so the grid is refined until about target / 2 cells hold a vertex (counted on the
//    vertices themselves, at most 4 M of them sampled evenly, before the triangles come).
//  - Every triangle adds its plane's quadric, weighted by its area, to the cells of its three
//    vertices (Garland and Heckbert 1997's fundamental quadric, as Lindstrom does).
//  - A triangle whose three vertices fall in three different cells is kept, as a triangle of those
//    cells (the same cell triple in the same orientation is kept once); the others collapse.
//  - Each cell's representative vertex minimises its quadric. The 3 x 3 system is solved through its
//    eigen-decomposition about the mean of the cell's vertices, dropping directions whose
//    eigenvalue is below 1e-3 of the largest (Lindstrom 2000, sec. 3.2: the pseudo-inverse keeps the
//    point at the mean along directions the quadric does not constrain, e.g. along a flat region or
//    an edge), then clamped to the cell grown by half a cell on every side.
//
// Memory model (docs/out-of-core.md): the caller's vertices are kept, 12 bytes each, plus a 4-byte
// cell id per vertex while the triangles stream; per occupied cell about 120 bytes; per kept
// triangle about 40 bytes. Triangles are never stored.
#pragma once

#include "geometry/triangle_mesh.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace rad {

struct ClusteringOptions {
    std::size_t targetTriangles = 0;  // used when cellSize <= 0
    double cellSize = 0.0;            // edge of a cubic cell, in model units; > 0 wins over the target
    std::size_t sampledVertices = 4000000;  // at most this many evenly spaced vertices count the occupied cells
    // One flag per vertex (1 = some triangle uses it), or null: every vertex counts. With it, the
    // grid is placed on the used vertices only: a stray unreferenced vertex far away no longer
    // stretches the grid (one such vertex 1e6 away turned a 400-triangle target into 36).
    const std::vector<std::uint8_t>* referenced = nullptr;
};

struct ClusteringStats {
    std::array<int, 3> gridCells{{0, 0, 0}};
    double cellSize = 0.0;
    std::size_t occupiedCells = 0;
    std::size_t inputTriangles = 0;
    std::size_t keptTriangles = 0;        // after deduplication
    std::size_t duplicateTriangles = 0;   // same cell triple seen again
    std::size_t clampedVertices = 0;      // representatives moved back into the grown cell
    std::size_t meanFallbacks = 0;        // cells whose quadric constrained no direction
};

// Feed the vertices (all of them, in index order), then the triangles, then finish().
class VertexClustering {
public:
    explicit VertexClustering(const ClusteringOptions& options);
    ~VertexClustering();
    VertexClustering(const VertexClustering&) = delete;
    VertexClustering& operator=(const VertexClustering&) = delete;

    // Room for `count` vertices in all (a PLY header announces them: no reallocation, no doubling).
    void reserveVertices(std::size_t count) { positions_.reserve(3 * count); }
    // Appends vertices (3 floats each, finite). Throws std::invalid_argument after the first
    // triangles or for more than 2^32 - 1 vertices.
    void addVertices(const float* positions, std::size_t count);
    // Chooses the grid (first call only, then nothing). Throws std::invalid_argument without vertices
    // or with neither a target nor a cell size.
    void beginTriangles();
    // Triangles as vertex indices (3 each, < vertex count: checked, std::out_of_range otherwise).
    // When accumulatedNormals is not null, each triangle's (b - a) x (c - a) is added to the normals
    // of its three vertices (3 floats per vertex, the caller's array; area-weighted vertex normals
    // once normalised, geometry/mesh_normals.h).
    void addTriangles(const std::uint32_t* indices, std::size_t count, float* accumulatedNormals = nullptr);
    // The simplified mesh: representatives of the cells some kept triangle uses, the kept triangles,
    // area-weighted vertex normals. Releases the per-vertex cell ids.
    TriangleMesh finish();

    const ClusteringStats& stats() const { return stats_; }
    // The vertices fed so far (the caller may move them out after finish()).
    std::vector<float>& positions() { return positions_; }

private:
    struct Cells;
    ClusteringOptions options_;
    ClusteringStats stats_;
    std::vector<float> positions_;
    std::vector<std::uint32_t> cellOfVertex_;
    std::unique_ptr<Cells> cells_;
    double origin_[3] = {0, 0, 0};
};

// The whole algorithm on a mesh in memory (tests, small inputs).
TriangleMesh clusterVertices(const TriangleMesh& mesh, const ClusteringOptions& options, ClusteringStats* stats = nullptr);

}  // namespace rad
