#include "geometry/midpoint_subdivision.h"

#include "geometry/mesh_normals.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

namespace rad {

namespace {

// One level. Edges are found by sorting the 3F half-edge keys (min << 32 | max): deterministic,
// O(F log F), no hash table; the sorted order numbers the midpoints.
void subdivideOnce(TriangleMesh& m, bool interpolateNormals) {
    const std::size_t V = m.vertexCount(), F = m.faceCount();
    std::vector<std::pair<std::uint64_t, std::uint32_t>> halfEdges(3 * F);  // (edge key, 3 f + k)
    for (std::size_t f = 0; f < F; ++f)
        for (int k = 0; k < 3; ++k) {
            const std::uint64_t a = m.faces[3 * f + k], b = m.faces[3 * f + (k + 1) % 3];
            halfEdges[3 * f + k] = {(std::min(a, b) << 32) | std::max(a, b), static_cast<std::uint32_t>(3 * f + k)};
        }
    std::sort(halfEdges.begin(), halfEdges.end());
    std::size_t edges = 0;
    for (std::size_t i = 0; i < halfEdges.size(); ++i)
        if (i == 0 || halfEdges[i].first != halfEdges[i - 1].first) ++edges;
    if (V + edges > std::numeric_limits<std::uint32_t>::max())
        throw std::invalid_argument("midpoint subdivision: the result would have more than 2^32 - 1 vertices");

    std::vector<std::uint32_t> midpointOf(3 * F);  // midpoint vertex of half-edge 3 f + k
    m.positions.resize(3 * (V + edges));
    if (interpolateNormals) m.normals.resize(3 * (V + edges));
    std::uint32_t next = static_cast<std::uint32_t>(V);
    for (std::size_t i = 0; i < halfEdges.size(); ++i) {
        if (i > 0 && halfEdges[i].first == halfEdges[i - 1].first) {
            midpointOf[halfEdges[i].second] = next - 1;
            continue;
        }
        const std::size_t a = halfEdges[i].first >> 32, b = halfEdges[i].first & 0xFFFFFFFFu;
        for (int c = 0; c < 3; ++c)
            m.positions[3 * std::size_t(next) + c] = 0.5f * (m.positions[3 * a + c] + m.positions[3 * b + c]);
        if (interpolateNormals) {
            double n[3], len2 = 0.0;
            for (int c = 0; c < 3; ++c) {
                n[c] = double(m.normals[3 * a + c]) + double(m.normals[3 * b + c]);
                len2 += n[c] * n[c];
            }
            // Opposite end normals: zero here, repaired from the geometry after the last level.
            const double inv = len2 > 0.0 ? 1.0 / std::sqrt(len2) : 0.0;
            for (int c = 0; c < 3; ++c) m.normals[3 * std::size_t(next) + c] = static_cast<float>(n[c] * inv);
        }
        midpointOf[halfEdges[i].second] = next++;
    }

    std::vector<std::uint32_t> faces(12 * F);
    for (std::size_t f = 0; f < F; ++f) {
        const std::uint32_t a = m.faces[3 * f], b = m.faces[3 * f + 1], c = m.faces[3 * f + 2];
        const std::uint32_t ab = midpointOf[3 * f], bc = midpointOf[3 * f + 1], ca = midpointOf[3 * f + 2];
        const std::uint32_t quad[12] = {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca};
        std::copy(quad, quad + 12, faces.begin() + 12 * f);
    }
    m.faces = std::move(faces);
}

}  // namespace

TriangleMesh subdivideMidpoint(const TriangleMesh& mesh, int levels, SubdivisionNormals normals) {
    const std::string problem = mesh.validate();
    if (!problem.empty()) throw std::invalid_argument("midpoint subdivision: " + problem);
    if (levels < 0) throw std::invalid_argument("midpoint subdivision: the number of levels must be >= 0");
    const bool interpolate = normals == SubdivisionNormals::Interpolate;
    if (interpolate && !mesh.hasNormals())
        throw std::invalid_argument("midpoint subdivision: interpolated normals need a mesh with normals");
    TriangleMesh m = mesh;
    for (int level = 0; level < levels; ++level) subdivideOnce(m, interpolate);
    if (!interpolate) {
        computeAreaWeightedNormals(m);
    } else {
        std::vector<float> geometric;
        bool needed = false;
        for (std::size_t v = 0; v < m.vertexCount() && !needed; ++v)
            needed = m.normals[3 * v] == 0.0f && m.normals[3 * v + 1] == 0.0f && m.normals[3 * v + 2] == 0.0f;
        if (needed) {
            computeAreaWeightedNormals(m.positions, m.faces, geometric);
            for (std::size_t v = 0; v < m.vertexCount(); ++v)
                if (m.normals[3 * v] == 0.0f && m.normals[3 * v + 1] == 0.0f && m.normals[3 * v + 2] == 0.0f)
                    for (int c = 0; c < 3; ++c) m.normals[3 * v + c] = geometric[3 * v + c];
        }
    }
    return m;
}

}  // namespace rad
