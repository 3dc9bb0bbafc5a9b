#include "simplify/collapse_mesh.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace rad {

CollapseMesh::CollapseMesh(const float* positions, std::size_t vertexCount, const std::uint32_t* faces,
                           std::size_t faceCount)
    : positions_(positions, positions + 3 * vertexCount),
      faces_(faces, faces + 3 * faceCount),
      faceAlive_(faceCount, 1),
      vertexAlive_(vertexCount, 1),
      vertexFaces_(vertexCount),
      aliveFaces_(faceCount),
      aliveVertices_(vertexCount) {
    std::vector<std::uint32_t> valence(vertexCount, 0);
    for (std::size_t f = 0; f < faceCount; ++f) {
        const std::uint32_t* t = faces + 3 * f;
        for (int k = 0; k < 3; ++k) {
            if (t[k] >= vertexCount)
                throw std::invalid_argument("face " + std::to_string(f) + " refers to vertex " + std::to_string(t[k]) +
                                            " of a mesh with " + std::to_string(vertexCount) + " vertices");
        }
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
            throw std::invalid_argument("face " + std::to_string(f) + " repeats a vertex");
        for (int k = 0; k < 3; ++k) ++valence[t[k]];
    }
    for (std::size_t v = 0; v < vertexCount; ++v) vertexFaces_[v].reserve(valence[v]);
    for (std::size_t f = 0; f < faceCount; ++f)
        for (int k = 0; k < 3; ++k) vertexFaces_[faces[3 * f + k]].push_back(static_cast<std::uint32_t>(f));
}

void CollapseMesh::setPosition(std::uint32_t v, const Eigen::Vector3d& p) {
    positions_[3 * v] = p.x();
    positions_[3 * v + 1] = p.y();
    positions_[3 * v + 2] = p.z();
}

void CollapseMesh::star(std::uint32_t v, std::vector<StarFace>& out) const {
    out.clear();
    for (std::uint32_t f : vertexFaces_[v]) {
        const std::uint32_t* t = face(f);
        if (t[0] == v) out.push_back({t[1], t[2]});
        else if (t[1] == v) out.push_back({t[2], t[0]});
        else out.push_back({t[0], t[1]});
    }
}

void CollapseMesh::neighbours(std::uint32_t v, std::vector<std::uint32_t>& out) const {
    out.clear();
    for (std::uint32_t f : vertexFaces_[v]) {
        const std::uint32_t* t = face(f);
        for (int k = 0; k < 3; ++k) {
            if (t[k] != v && std::find(out.begin(), out.end(), t[k]) == out.end()) out.push_back(t[k]);
        }
    }
}

int CollapseMesh::edgeFaceCount(std::uint32_t u, std::uint32_t v) const {
    int count = 0;
    for (std::uint32_t f : vertexFaces_[u]) {
        const std::uint32_t* t = face(f);
        if (t[0] == v || t[1] == v || t[2] == v) ++count;
    }
    return count;
}

bool CollapseMesh::isOpenStar(const std::vector<StarFace>& star) {
    for (const StarFace& f : star) {
        int asB = 0, asA = 0;
        for (const StarFace& g : star) {
            asB += g.b == f.a;
            asA += g.a == f.b;
        }
        if (asB != 1 || asA != 1) return true;
    }
    return false;
}

// In a fan each neighbour is the 'a' of at most one face and the 'b' of at most one; a closed fan has
// every neighbour as both, an open one exactly one neighbour as an 'a' only (and one as a 'b' only).
CollapseMesh::StarShape CollapseMesh::starShape(const std::vector<StarFace>& star) {
    int onlyA = 0, onlyB = 0;
    for (const StarFace& f : star) {
        int aAsA = 0, aAsB = 0, bAsA = 0, bAsB = 0;
        for (const StarFace& g : star) {
            aAsA += g.a == f.a;
            aAsB += g.b == f.a;
            bAsA += g.a == f.b;
            bAsB += g.b == f.b;
        }
        if (aAsA > 1 || aAsB > 1 || bAsA > 1 || bAsB > 1) return StarShape::Other;
        onlyA += aAsB == 0;
        onlyB += bAsA == 0;
    }
    if (onlyA == 0 && onlyB == 0) return StarShape::ClosedFan;
    return onlyA == 1 && onlyB == 1 ? StarShape::OneOpenFan : StarShape::Other;
}

bool CollapseMesh::onBoundary(std::uint32_t v) const {
    std::vector<StarFace> around;
    star(v, around);
    return isOpenStar(around);
}

void CollapseMesh::collapse(std::uint32_t v0, std::uint32_t v1, std::vector<std::uint32_t>* killedFaces) {
    auto& faces0 = vertexFaces_[v0];
    auto& faces1 = vertexFaces_[v1];
    for (std::uint32_t f : faces0) {
        std::uint32_t* t = faces_.data() + 3 * f;
        const bool hasV1 = t[0] == v1 || t[1] == v1 || t[2] == v1;
        if (hasV1) {
            // The face dies: detach it from its other vertices.
            faceAlive_[f] = 0;
            --aliveFaces_;
            if (killedFaces) killedFaces->push_back(f);
            for (int k = 0; k < 3; ++k) {
                if (t[k] == v0) continue;
                auto& list = vertexFaces_[t[k]];
                auto it = std::find(list.begin(), list.end(), f);
                if (it != list.end()) {
                    *it = list.back();
                    list.pop_back();
                }
            }
        } else {
            for (int k = 0; k < 3; ++k)
                if (t[k] == v0) t[k] = v1;
            faces1.push_back(f);
        }
    }
    faces0.clear();
    faces0.shrink_to_fit();
    vertexAlive_[v0] = 0;
    --aliveVertices_;
}

void CollapseMesh::compact(std::vector<float>& positions, std::vector<std::uint32_t>& faces,
                           std::vector<std::uint32_t>& vertexMap) const {
    const std::size_t nv = vertexCount();
    vertexMap.assign(nv, std::numeric_limits<std::uint32_t>::max());
    positions.clear();
    positions.reserve(3 * aliveVertices_);
    std::uint32_t next = 0;
    for (std::size_t v = 0; v < nv; ++v) {
        if (!vertexAlive_[v]) continue;
        vertexMap[v] = next++;
        for (int k = 0; k < 3; ++k) positions.push_back(static_cast<float>(positions_[3 * v + k]));
    }
    faces.clear();
    faces.reserve(3 * aliveFaces_);
    for (std::size_t f = 0; f < faceCount(); ++f) {
        if (!faceAlive_[f]) continue;
        for (int k = 0; k < 3; ++k) faces.push_back(vertexMap[faces_[3 * f + k]]);
    }
}

}  // namespace rad
