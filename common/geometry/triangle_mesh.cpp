#include "geometry/triangle_mesh.h"

#include "geometry/coordinate_range.h"
#include "parallel/parallel_sort.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>

namespace rad {

std::string TriangleMesh::validate() const {
    std::ostringstream why;
    if (positions.size() % 3 != 0) {
        why << "mesh positions hold " << positions.size() << " floats, not a whole number of vertices";
        return why.str();
    }
    if (faces.size() % 3 != 0) {
        why << "mesh faces hold " << faces.size() << " indices, not a whole number of triangles";
        return why.str();
    }
    if (!normals.empty() && normals.size() != positions.size()) {
        why << "mesh has " << normals.size() / 3 << " normals for " << vertexCount() << " vertices";
        return why.str();
    }
    for (std::size_t i = 0; i < positions.size(); ++i)
        if (!std::isfinite(positions[i])) {
            why << "vertex " << i / 3 << " has a non-finite coordinate";
            return why.str();
        }
    if (std::string range = coordinateRangeProblem(positions.data(), vertexCount()); !range.empty()) return range;
    for (std::size_t i = 0; i < normals.size(); ++i)
        if (!std::isfinite(normals[i])) {
            why << "vertex " << i / 3 << " has a non-finite normal";
            return why.str();
        }
    const std::size_t n = vertexCount();
    for (std::size_t i = 0; i < faces.size(); ++i)
        if (faces[i] >= n) {
            why << "face " << i / 3 << " refers to vertex " << faces[i] << " but the mesh has " << n
                << " vertices";
            return why.str();
        }
    return {};
}

EdgeCensus countEdgesByFaces(std::vector<std::uint64_t>& undirectedEdgeKeys) {
    sortInParallel(undirectedEdgeKeys.begin(), undirectedEdgeKeys.end(), std::less<std::uint64_t>());
    EdgeCensus census;
    for (std::size_t i = 0; i < undirectedEdgeKeys.size();) {
        std::size_t j = i;
        while (j < undirectedEdgeKeys.size() && undirectedEdgeKeys[j] == undirectedEdgeKeys[i]) ++j;
        if (j - i > 2) ++census.nonManifold;
        if (j - i == 1) ++census.boundary;
        i = j;
    }
    return census;
}

std::size_t countNonManifoldEdges(std::vector<std::uint64_t>& undirectedEdgeKeys) {
    return countEdgesByFaces(undirectedEdgeKeys).nonManifold;
}

}  // namespace rad
