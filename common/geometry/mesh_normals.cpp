#include "geometry/mesh_normals.h"

#include <cmath>

namespace rad {

namespace {

// Unnormalised (b - a) x (c - a) of the triangle (ia, ib, ic), in double.
void crossOf(const std::vector<float>& p, std::uint32_t ia, std::uint32_t ib, std::uint32_t ic, double out[3]) {
    const double ax = p[3 * ia], ay = p[3 * ia + 1], az = p[3 * ia + 2];
    const double ux = p[3 * ib] - ax, uy = p[3 * ib + 1] - ay, uz = p[3 * ib + 2] - az;
    const double vx = p[3 * ic] - ax, vy = p[3 * ic + 1] - ay, vz = p[3 * ic + 2] - az;
    out[0] = uy * vz - uz * vy;
    out[1] = uz * vx - ux * vz;
    out[2] = ux * vy - uy * vx;
}

}  // namespace

std::size_t computeAreaWeightedNormals(const std::vector<float>& positions,
                                       const std::vector<std::uint32_t>& faces,
                                       std::vector<float>& normals) {
    const std::size_t n = positions.size() / 3;
    std::vector<double> sum(3 * n, 0.0);
    for (std::size_t f = 0; f + 2 < faces.size(); f += 3) {
        double c[3];
        crossOf(positions, faces[f], faces[f + 1], faces[f + 2], c);
        for (int k = 0; k < 3; ++k) {
            const std::size_t v = faces[f + k];
            sum[3 * v] += c[0];
            sum[3 * v + 1] += c[1];
            sum[3 * v + 2] += c[2];
        }
    }
    normals.assign(3 * n, 0.0f);
    std::size_t undetermined = 0;
    for (std::size_t v = 0; v < n; ++v) {
        const double x = sum[3 * v], y = sum[3 * v + 1], z = sum[3 * v + 2];
        const double len = std::sqrt(x * x + y * y + z * z);
        // A sum that is tiny relative to nothing is still a direction; only an exact zero (or a
        // non-finite value from overflow) leaves the normal undetermined.
        if (!(len > 0.0) || !std::isfinite(len)) {
            ++undetermined;
            continue;
        }
        normals[3 * v] = static_cast<float>(x / len);
        normals[3 * v + 1] = static_cast<float>(y / len);
        normals[3 * v + 2] = static_cast<float>(z / len);
    }
    return undetermined;
}

std::size_t computeAreaWeightedNormals(TriangleMesh& mesh) {
    return computeAreaWeightedNormals(mesh.positions, mesh.faces, mesh.normals);
}

void faceNormal(const TriangleMesh& mesh, std::size_t f, float out[3]) {
    double c[3];
    crossOf(mesh.positions, mesh.faces[3 * f], mesh.faces[3 * f + 1], mesh.faces[3 * f + 2], c);
    const double len = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    for (int k = 0; k < 3; ++k) out[k] = len > 0.0 ? static_cast<float>(c[k] / len) : 0.0f;
}

double faceArea(const TriangleMesh& mesh, std::size_t f) {
    double c[3];
    crossOf(mesh.positions, mesh.faces[3 * f], mesh.faces[3 * f + 1], mesh.faces[3 * f + 2], c);
    return 0.5 * std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
}

}  // namespace rad
