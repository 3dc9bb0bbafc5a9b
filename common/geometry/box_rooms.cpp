#include "geometry/box_rooms.h"

#include <algorithm>
#include <stdexcept>

namespace rad {

void AlbedoMesh::addQuad(const std::array<float, 3>& corner, const std::array<float, 3>& u,
                         const std::array<float, 3>& v, int n, const std::array<float, 3>& rho) {
    if (n < 1) throw std::invalid_argument("A wall needs at least one subdivision.");
    const auto base = static_cast<std::uint32_t>(mesh.vertexCount());
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const float s = float(i) / n, t = float(j) / n;
            for (int c = 0; c < 3; ++c) {
                mesh.positions.push_back(corner[c] + s * u[c] + t * v[c]);
                albedo.push_back(rho[c]);
            }
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const std::uint32_t a = base + std::uint32_t(j * (n + 1) + i), b = a + 1, c = a + std::uint32_t(n + 1) + 1,
                                d = a + std::uint32_t(n + 1);
            mesh.faces.insert(mesh.faces.end(), {a, b, c, a, c, d});  // counter-clockwise about u x v
        }
}

void AlbedoMesh::addBox(const std::array<float, 3>& lo, const std::array<float, 3>& hi, int n,
                        const std::array<float, 3>& rho) {
    const float dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    addQuad({lo[0], lo[1], lo[2]}, {0, dy, 0}, {dx, 0, 0}, n, rho);   // bottom, -z
    addQuad({lo[0], lo[1], hi[2]}, {dx, 0, 0}, {0, dy, 0}, n, rho);   // top, +z
    addQuad({lo[0], lo[1], lo[2]}, {dx, 0, 0}, {0, 0, dz}, n, rho);   // front, -y
    addQuad({lo[0], hi[1], lo[2]}, {0, 0, dz}, {dx, 0, 0}, n, rho);   // back, +y
    addQuad({lo[0], lo[1], lo[2]}, {0, 0, dz}, {0, dy, 0}, n, rho);   // left, -x
    addQuad({hi[0], lo[1], lo[2]}, {0, dy, 0}, {0, 0, dz}, n, rho);   // right, +x
}

void AlbedoMesh::addMesh(const TriangleMesh& other, const std::array<float, 3>& rho) {
    const auto base = static_cast<std::uint32_t>(mesh.vertexCount());
    mesh.positions.insert(mesh.positions.end(), other.positions.begin(), other.positions.end());
    for (std::uint32_t i : other.faces) mesh.faces.push_back(base + i);
    for (std::size_t v = 0; v < other.vertexCount(); ++v) albedo.insert(albedo.end(), rho.begin(), rho.end());
}

AlbedoMesh makeCornellBox(int n) {
    AlbedoMesh s;
    const std::array<float, 3> white{{0.73f, 0.73f, 0.73f}}, red{{0.63f, 0.065f, 0.05f}}, green{{0.14f, 0.45f, 0.091f}};
    s.addQuad({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, n, white);  // floor, +z
    s.addQuad({0, 0, 1}, {0, 1, 0}, {1, 0, 0}, n, white);  // ceiling, -z
    s.addQuad({0, 1, 0}, {1, 0, 0}, {0, 0, 1}, n, white);  // back, -y
    s.addQuad({0, 0, 0}, {0, 1, 0}, {0, 0, 1}, n, red);    // left, +x
    s.addQuad({1, 0, 0}, {0, 0, 1}, {0, 1, 0}, n, green);  // right, -x
    const int b = std::max(1, n / 4);
    s.addBox({0.55f, 0.15f, 0.0f}, {0.85f, 0.45f, 0.30f}, b, white);  // short block
    s.addBox({0.15f, 0.50f, 0.0f}, {0.45f, 0.80f, 0.60f}, b, white);  // tall block
    return s;
}

AlbedoMesh makeScanRoom(const TriangleMesh& input, float height, int n, bool yUp) {
    if (input.vertexCount() == 0) throw std::invalid_argument("The scan has no vertices.");
    TriangleMesh scan = input;
    if (yUp)
        for (std::size_t v = 0; v < scan.vertexCount(); ++v) {
            float* p = &scan.positions[3 * v];
            const float y = p[1], z = p[2];
            p[1] = -z;  // (x, y, z) -> (x, -z, y): a rotation, the winding is kept
            p[2] = y;
        }
    AlbedoMesh s;
    const std::array<float, 3> wall{{0.7f, 0.7f, 0.7f}}, floor{{0.6f, 0.45f, 0.3f}}, blue{{0.2f, 0.3f, 0.7f}},
        plinth{{0.8f, 0.8f, 0.8f}}, grey{{0.75f, 0.75f, 0.75f}};
    s.addQuad({-1, -1, 0}, {2, 0, 0}, {0, 2, 0}, n, floor);  // floor, +z
    s.addQuad({-1, -1, 2}, {0, 2, 0}, {2, 0, 0}, n, wall);   // ceiling, -z
    s.addQuad({-1, 1, 0}, {2, 0, 0}, {0, 0, 2}, n, wall);    // back, -y
    s.addQuad({-1, -1, 0}, {0, 2, 0}, {0, 0, 2}, n, wall);   // left, +x
    s.addQuad({1, -1, 0}, {0, 0, 2}, {0, 2, 0}, n, blue);    // right, -x
    const float plinthTop = 0.5f;
    s.addBox({-0.3f, -0.3f, 0.0f}, {0.3f, 0.3f, plinthTop}, std::max(1, n / 4), plinth);
    // The scan: its box's bottom centre on the plinth's top, its height `height`.
    float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
    for (std::size_t v = 0; v < scan.vertexCount(); ++v)
        for (int c = 0; c < 3; ++c) {
            lo[c] = std::min(lo[c], scan.positions[3 * v + c]);
            hi[c] = std::max(hi[c], scan.positions[3 * v + c]);
        }
    const float extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    if (!(extent > 0.0f)) throw std::invalid_argument("The scan has no extent.");
    const float scale = height / std::max(hi[2] - lo[2], 0.25f * extent);
    TriangleMesh placed = scan;
    placed.normals.clear();
    for (std::size_t v = 0; v < placed.vertexCount(); ++v) {
        float* p = &placed.positions[3 * v];
        p[0] = (p[0] - 0.5f * (lo[0] + hi[0])) * scale;
        p[1] = (p[1] - 0.5f * (lo[1] + hi[1])) * scale;
        p[2] = (p[2] - lo[2]) * scale + plinthTop + 1e-3f;
    }
    s.addMesh(placed, grey);
    return s;
}

}  // namespace rad
