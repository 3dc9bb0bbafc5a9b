#include "lod/pop_level.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace rad {

PopLevelMesh evaluatePopLevel(const PopLevelRequest& r) {
    if (r.mesh == nullptr || r.pop == nullptr)
        throw std::invalid_argument("A level of detail needs the mesh and its POP buffer.");
    if (r.level < kPopMinLevel || r.level > kPopMaxLevel)
        throw std::invalid_argument("Level " + std::to_string(r.level) + " does not exist: POP-buffer levels are " +
                                    std::to_string(kPopMinLevel) + " to " + std::to_string(kPopMaxLevel) + ".");
    const TriangleMesh& mesh = *r.mesh;
    const PopBuffer& pop = *r.pop;
    const std::size_t m = mesh.faceCount();
    if (pop.vertexCount() != mesh.vertexCount() || pop.faceCount() != m)
        throw std::invalid_argument("The POP buffer was built from another mesh: build it again from this one.");
    if (r.correction != nullptr && r.wedgeUv == nullptr)
        throw std::invalid_argument("Texture-coordinate correction needs texture coordinates: give the mesh wedge "
                                    "or per-vertex texture coordinates, or turn the correction off.");
    if (r.wedgeUv != nullptr && r.wedgeUv->size() != 6 * m)
        throw std::invalid_argument("The texture coordinates hold " + std::to_string(r.wedgeUv->size()) +
                                    " values for " + std::to_string(m) + " faces (6 per face expected).");
    if (r.correction != nullptr && r.correction->perCorner.size() != 18 * m)
        throw std::invalid_argument("The texture-coordinate derivatives were computed for another mesh: compute "
                                    "them again from this one.");

    PopLevelMesh out;
    const std::size_t drawn = pop.levelEnd[r.level];
    std::vector<std::uint32_t> remap(mesh.vertexCount(), 0xffffffffu);
    out.mesh.faces.resize(3 * drawn);
    out.sourceFace.assign(pop.faceOrder.begin(), pop.faceOrder.begin() + drawn);
    for (std::size_t i = 0; i < 3 * drawn; ++i) {
        std::uint32_t& id = remap[pop.faces[i]];
        if (id == 0xffffffffu) {
            id = std::uint32_t(out.sourceVertex.size());
            out.sourceVertex.push_back(pop.faces[i]);
        }
        out.mesh.faces[i] = id;
    }
    const std::size_t n = out.sourceVertex.size();
    out.mesh.positions.resize(3 * n);
    for (std::size_t v = 0; v < n; ++v) {
        const std::size_t s = out.sourceVertex[v];
        double move2 = 0;
        for (int k = 0; k < 3; ++k) {
            const double q = pop.quantizedCoordinate(s, k, r.level);
            out.mesh.positions[3 * v + k] = float(q);
            const double d = double(float(q)) - double(mesh.positions[3 * s + k]);
            move2 += d * d;
        }
        if (move2 > 0) ++out.movedVertices;
        out.maxDisplacement = std::max(out.maxDisplacement, std::sqrt(move2));
    }

    if (r.wedgeUv != nullptr) {
        out.wedgeUv.resize(6 * drawn);
        for (std::size_t f = 0; f < drawn; ++f) {
            const std::size_t src = out.sourceFace[f];
            for (int k = 0; k < 3; ++k) {
                double uv[2] = {(*r.wedgeUv)[6 * src + 2 * k], (*r.wedgeUv)[6 * src + 2 * k + 1]};
                if (r.correction != nullptr) {
                    const std::size_t s = mesh.faces[3 * src + k];
                    const std::size_t v = out.mesh.faces[3 * f + k];
                    const double original[3] = {mesh.positions[3 * s], mesh.positions[3 * s + 1],
                                                mesh.positions[3 * s + 2]};
                    const double moved[3] = {out.mesh.positions[3 * v], out.mesh.positions[3 * v + 1],
                                             out.mesh.positions[3 * v + 2]};
                    correctTexCoord(&r.correction->perCorner[6 * (3 * src + k)], original, moved, uv);
                }
                out.wedgeUv[6 * f + 2 * k] = float(uv[0]);
                out.wedgeUv[6 * f + 2 * k + 1] = float(uv[1]);
            }
        }
    }
    return out;
}

}  // namespace rad
