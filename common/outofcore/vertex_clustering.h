// Simplification by uniform vertex clustering with quadrics (Lindstrom 2000), the simplification
// Granier et al. 2007 use for scans that do not fit in memory: one pass over the triangles, in any
// order, streamed. A uniform grid of cubic cells (its size given, or chosen from a target triangle
// count) accumulates area-weighted plane quadrics per cell; a triangle survives when its vertices
// fall in three different cells, and each cell's vertex minimises its quadric. The caller's vertices
// are kept (12 bytes each plus a 4-byte cell id); triangles are never stored.
// Details: docs/out-of-core.md, "`common/outofcore/vertex_clustering.h`: how it works".
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
