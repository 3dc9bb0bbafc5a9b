#include "lod/texcoord_correction.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <string>

namespace rad {
namespace {

std::uint32_t bitsOf(float x) {
    if (x == 0.0f) x = 0.0f;  // -0 and +0 are one coordinate
    std::uint32_t b;
    std::memcpy(&b, &x, sizeof b);
    return b;
}

struct CornerKey {
    std::uint32_t vertex, u, v, corner;
    bool sameTextureVertex(const CornerKey& o) const { return vertex == o.vertex && u == o.u && v == o.v; }
};

}  // namespace

TexCoordDerivatives computeTexCoordDerivatives(const TriangleMesh& mesh, const std::vector<float>& wedgeUv,
                                               const ProgressCallback& progress) {
    if (mesh.faceCount() == 0)
        throw std::invalid_argument("The mesh has no faces: texture coordinates are corrected over triangles.");
    if (std::string why = mesh.validate(); !why.empty())
        throw std::invalid_argument("The mesh cannot be used for texture-coordinate correction: " + why +
                                    ". Remove the bad vertices or faces first.");
    const std::size_t m = mesh.faceCount();
    if (wedgeUv.size() != 6 * m)
        throw std::invalid_argument("The texture coordinates hold " + std::to_string(wedgeUv.size()) +
                                    " values for " + std::to_string(m) + " faces (6 per face expected): give the "
                                    "mesh texture coordinates (wedge or per vertex) first.");
    for (std::size_t i = 0; i < wedgeUv.size(); ++i)
        if (!std::isfinite(wedgeUv[i]))
            throw std::invalid_argument("Face " + std::to_string(i / 6) + " has a non-finite texture coordinate: "
                                        "repair or recompute the parametrisation first.");

    // Tangent space of every triangle (eq. 3): T = dP/du, B = dP/dv from the edges, N the unit normal.
    // A triangle degenerate in space or in texture space has none (valid = 0).
    std::vector<double> frames(9 * m);
    std::vector<std::uint8_t> valid(m);
#pragma omp parallel for schedule(static)
    for (long long f = 0; f < (long long)m; ++f) {
        const float* p[3];
        for (int k = 0; k < 3; ++k) p[k] = &mesh.positions[3 * std::size_t(mesh.faces[3 * f + k])];
        const float* uv = &wedgeUv[6 * f];
        const Eigen::Vector3d p0(p[0][0], p[0][1], p[0][2]);
        const Eigen::Vector3d e1 = Eigen::Vector3d(p[1][0], p[1][1], p[1][2]) - p0;
        const Eigen::Vector3d e2 = Eigen::Vector3d(p[2][0], p[2][1], p[2][2]) - p0;
        const double du1 = double(uv[2]) - uv[0], dv1 = double(uv[3]) - uv[1];
        const double du2 = double(uv[4]) - uv[0], dv2 = double(uv[5]) - uv[1];
        const double det = du1 * dv2 - du2 * dv1;
        const Eigen::Vector3d n = e1.cross(e2);
        const double uvScale = std::max({std::fabs(du1), std::fabs(dv1), std::fabs(du2), std::fabs(dv2)});
        valid[f] = 0;
        if (!(std::fabs(det) > 1e-12 * uvScale * uvScale) || !(n.norm() > 0)) continue;
        const Eigen::Vector3d t = (e1 * dv2 - e2 * dv1) / det;
        const Eigen::Vector3d b = (e2 * du1 - e1 * du2) / det;
        const Eigen::Vector3d nn = n.normalized();
        double* out = &frames[9 * f];
        for (int k = 0; k < 3; ++k) {
            out[k] = t[k];
            out[3 + k] = b[k];
            out[6 + k] = nn[k];
        }
        valid[f] = 1;
    }
    reportProgress(progress, 0.3, "Tangent spaces of the triangles");

    // Texture vertices: corners sharing a vertex and its (u, v).
    std::vector<CornerKey> corners(3 * m);
    for (std::size_t c = 0; c < 3 * m; ++c)
        corners[c] = {mesh.faces[c], bitsOf(wedgeUv[2 * c]), bitsOf(wedgeUv[2 * c + 1]), std::uint32_t(c)};
    std::sort(corners.begin(), corners.end(), [](const CornerKey& a, const CornerKey& b) {
        if (a.vertex != b.vertex) return a.vertex < b.vertex;
        if (a.u != b.u) return a.u < b.u;
        if (a.v != b.v) return a.v < b.v;
        return a.corner < b.corner;
    });
    reportProgress(progress, 0.6, "Grouping corners into texture vertices");

    TexCoordDerivatives out;
    out.perCorner.assign(6 * 3 * m, 0.0f);
    for (std::size_t i = 0; i < corners.size();) {
        std::size_t j = i;
        // Averaged tangent space of the texture vertex (each triangle once, even if two of its corners
        // are the same texture vertex).
        Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();  // columns T, B, N
        int count = 0;
        std::uint32_t lastFace = 0xffffffffu;
        while (j < corners.size() && corners[j].sameTextureVertex(corners[i])) {
            const std::uint32_t f = corners[j].corner / 3;
            if (valid[f] && f != lastFace) {
                for (int k = 0; k < 3; ++k)
                    for (int r = 0; r < 3; ++r) sum(r, k) += frames[9 * f + 3 * k + r];
                ++count;
            }
            lastFace = f;
            ++j;
        }
        ++out.textureVertices;
        bool ok = false;
        if (count > 0) {
            const Eigen::Matrix3d tbn = sum / double(count);
            const double scale = tbn.col(0).norm() * tbn.col(1).norm() * tbn.col(2).norm();
            const double det = tbn.determinant();
            if (scale > 0 && std::fabs(det) > 1e-9 * scale) {
                // Eq. 2: the inverse tangent space; its first two rows are d(u, v)/d(x, y, z).
                const Eigen::Matrix3d inv = tbn.inverse();
                if (inv.allFinite()) {
                    for (std::size_t c = i; c < j; ++c) {
                        float* d = &out.perCorner[6 * std::size_t(corners[c].corner)];
                        for (int k = 0; k < 3; ++k) {
                            d[k] = float(inv(0, k));
                            d[3 + k] = float(inv(1, k));
                        }
                    }
                    ok = true;
                }
            }
        }
        if (!ok) ++out.withoutTangentSpace;
        i = j;
    }
    reportProgress(progress, 1.0, "Averaging tangent spaces");
    return out;
}

}  // namespace rad
