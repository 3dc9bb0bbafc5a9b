// The mutable triangle mesh the edge-collapse engine (edge_collapse.h) works on: flat arrays plus
// the vertex -> incident faces lists that collapses update. Dead faces and vertices keep their
// slots (indices never move during a simplification); compacting is done once at the end.
//
// Layout:
//   positions[3 * v + 0..2]   double, so that repeated QEM placements do not drift
//   faces[3 * f + 0..2]       counter-clockwise seen from outside
//   vertexFaces[v]            the alive faces incident to v, unordered
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace rad {

// A face (v0, a, b) of the star of v0, counter-clockwise, v0 implied.
struct StarFace {
    std::uint32_t a, b;
};

class CollapseMesh {
public:
    CollapseMesh() = default;
    // Copies the arrays and builds the incidence lists. Throws std::invalid_argument when an index
    // is out of range or a face repeats a vertex.
    CollapseMesh(const float* positions, std::size_t vertexCount, const std::uint32_t* faces, std::size_t faceCount);

    std::size_t vertexCount() const { return positions_.size() / 3; }
    std::size_t faceCount() const { return faces_.size() / 3; }  // slots, alive or not
    std::size_t aliveFaceCount() const { return aliveFaces_; }
    std::size_t aliveVertexCount() const { return aliveVertices_; }

    Eigen::Vector3d position(std::uint32_t v) const {
        return {positions_[3 * v], positions_[3 * v + 1], positions_[3 * v + 2]};
    }
    void setPosition(std::uint32_t v, const Eigen::Vector3d& p);
    const double* positionData() const { return positions_.data(); }

    const std::uint32_t* face(std::uint32_t f) const { return faces_.data() + 3 * f; }
    bool faceAlive(std::uint32_t f) const { return faceAlive_[f] != 0; }
    bool vertexAlive(std::uint32_t v) const { return vertexAlive_[v] != 0; }
    const std::vector<std::uint32_t>& incidentFaces(std::uint32_t v) const { return vertexFaces_[v]; }

    // The faces around v as (a, b) with (v, a, b) counter-clockwise (any order of faces).
    void star(std::uint32_t v, std::vector<StarFace>& out) const;
    // The distinct neighbours of v (any order).
    void neighbours(std::uint32_t v, std::vector<std::uint32_t>& out) const;
    // Number of alive faces containing both u and v (1 on a boundary edge, 2 inside a manifold).
    int edgeFaceCount(std::uint32_t u, std::uint32_t v) const;
    // True when v lies on a boundary edge (an edge with exactly one face) or a non-manifold edge.
    bool onBoundary(std::uint32_t v) const;
    // The same test on a star already at hand: the fan is closed when every neighbour appears once
    // as an 'a' and once as a 'b'.
    static bool isOpenStar(const std::vector<StarFace>& star);
    // What an open star is: one open fan (a vertex on a manifold boundary), or anything else (an
    // edge on more than two faces, several fans meeting at the vertex). isOpenStar(star) is
    // starShape(star) != ClosedFan; this one costs twice as many comparisons.
    enum class StarShape : std::uint8_t { ClosedFan, OneOpenFan, Other };  // ordered: the more constrained last
    static StarShape starShape(const std::vector<StarFace>& star);

    // Replaces v0 by v1 in every face around v0, kills the faces that contained both, kills v0.
    // Used for half-edge collapses (v1 keeps its position) and full ones (the caller moves v1
    // first). Appends the killed faces to `killedFaces` when given. The caller checks validity.
    void collapse(std::uint32_t v0, std::uint32_t v1, std::vector<std::uint32_t>* killedFaces = nullptr);

    // The alive part, re-indexed: positions (float), faces, and old -> new vertex index
    // (UINT32_MAX for dead vertices).
    void compact(std::vector<float>& positions, std::vector<std::uint32_t>& faces,
                 std::vector<std::uint32_t>& vertexMap) const;

private:
    std::vector<double> positions_;
    std::vector<std::uint32_t> faces_;
    std::vector<std::uint8_t> faceAlive_, vertexAlive_;
    std::vector<std::vector<std::uint32_t>> vertexFaces_;
    std::size_t aliveFaces_ = 0, aliveVertices_ = 0;
};

}  // namespace rad
