#include "geometry/primitive_meshes.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace rad {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Appends a vertex with position p and normal n (given in double, stored as float).
void pushVertex(TriangleMesh& m, double px, double py, double pz, double nx, double ny, double nz) {
    m.positions.push_back(static_cast<float>(px));
    m.positions.push_back(static_cast<float>(py));
    m.positions.push_back(static_cast<float>(pz));
    m.normals.push_back(static_cast<float>(nx));
    m.normals.push_back(static_cast<float>(ny));
    m.normals.push_back(static_cast<float>(nz));
}

void pushFace(TriangleMesh& m, std::size_t a, std::size_t b, std::size_t c) {
    m.faces.push_back(static_cast<std::uint32_t>(a));
    m.faces.push_back(static_cast<std::uint32_t>(b));
    m.faces.push_back(static_cast<std::uint32_t>(c));
}

void require(bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument(what);
}

}  // namespace

std::size_t icosphereVertexCount(int level) { return 10 * (std::size_t{1} << (2 * level)) + 2; }
std::size_t icosphereFaceCount(int level) { return 20 * (std::size_t{1} << (2 * level)); }

TriangleMesh makeIcosphere(int level, float radius) {
    require(level >= 0 && level <= 9, "icosphere level must be in 0..9, got " + std::to_string(level));
    require(radius > 0.0f && std::isfinite(radius), "icosphere radius must be positive");

    // Unit directions in double; converted to floats at the end.
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<double> dirs = {-1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, 0, 0, -1, t, 0, 1, t,
                                0, -1, -t, 0, 1, -t, t, 0, -1, t, 0, 1, -t, 0, -1, -t, 0, 1};
    std::vector<std::uint32_t> faces = {0, 11, 5,  0, 5,  1, 0, 1, 7, 0, 7, 10, 0, 10, 11,
                                        1, 5,  9,  5, 11, 4, 11, 10, 2, 10, 7, 6, 7, 1, 8,
                                        3, 9,  4,  3, 4,  2, 3, 2, 6, 3, 6, 8, 3, 8, 9,
                                        4, 9,  5,  2, 4,  11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
    auto normalizeLast = [&dirs]() {
        const std::size_t i = dirs.size() - 3;
        const double len = std::sqrt(dirs[i] * dirs[i] + dirs[i + 1] * dirs[i + 1] + dirs[i + 2] * dirs[i + 2]);
        dirs[i] /= len;
        dirs[i + 1] /= len;
        dirs[i + 2] /= len;
    };
    {
        std::vector<double> raw;
        raw.swap(dirs);
        for (std::size_t i = 0; i < raw.size(); i += 3) {
            dirs.insert(dirs.end(), {raw[i], raw[i + 1], raw[i + 2]});
            normalizeLast();
        }
    }

    dirs.reserve(3 * icosphereVertexCount(level));
    for (int l = 0; l < level; ++l) {
        std::unordered_map<std::uint64_t, std::uint32_t> midpoints;
        midpoints.reserve(faces.size());
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) -> std::uint32_t {
            const std::uint64_t key = a < b ? (std::uint64_t{a} << 32) | b : (std::uint64_t{b} << 32) | a;
            auto it = midpoints.find(key);
            if (it != midpoints.end()) return it->second;
            const auto index = static_cast<std::uint32_t>(dirs.size() / 3);
            dirs.insert(dirs.end(), {dirs[3 * a] + dirs[3 * b], dirs[3 * a + 1] + dirs[3 * b + 1],
                                     dirs[3 * a + 2] + dirs[3 * b + 2]});
            normalizeLast();
            midpoints.emplace(key, index);
            return index;
        };
        std::vector<std::uint32_t> next;
        next.reserve(faces.size() * 4);
        for (std::size_t f = 0; f < faces.size(); f += 3) {
            const std::uint32_t a = faces[f], b = faces[f + 1], c = faces[f + 2];
            const std::uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
            next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        faces.swap(next);
    }

    TriangleMesh mesh;
    const std::size_t n = dirs.size() / 3;
    mesh.positions.reserve(3 * n);
    mesh.normals.reserve(3 * n);
    for (std::size_t v = 0; v < n; ++v) {
        const double x = dirs[3 * v], y = dirs[3 * v + 1], z = dirs[3 * v + 2];
        pushVertex(mesh, radius * x, radius * y, radius * z, x, y, z);
    }
    mesh.faces = std::move(faces);
    return mesh;
}

TriangleMesh makeUvSphere(int stacks, int slices, float radius) {
    require(stacks >= 2, "UV sphere needs at least 2 stacks, got " + std::to_string(stacks));
    require(slices >= 3, "UV sphere needs at least 3 slices, got " + std::to_string(slices));
    require(radius > 0.0f && std::isfinite(radius), "UV sphere radius must be positive");

    TriangleMesh mesh;
    const std::size_t rings = static_cast<std::size_t>(stacks - 1);
    const std::size_t s = static_cast<std::size_t>(slices);
    mesh.positions.reserve(3 * (rings * s + 2));
    mesh.normals.reserve(3 * (rings * s + 2));
    pushVertex(mesh, 0, 0, radius, 0, 0, 1);  // north pole, vertex 0
    for (std::size_t i = 1; i <= rings; ++i) {
        const double theta = kPi * static_cast<double>(i) / stacks;
        for (std::size_t j = 0; j < s; ++j) {
            const double phi = 2.0 * kPi * static_cast<double>(j) / slices;
            const double x = std::sin(theta) * std::cos(phi), y = std::sin(theta) * std::sin(phi),
                         z = std::cos(theta);
            pushVertex(mesh, radius * x, radius * y, radius * z, x, y, z);
        }
    }
    const std::size_t south = rings * s + 1;
    pushVertex(mesh, 0, 0, -radius, 0, 0, -1);

    auto ring = [s](std::size_t i, std::size_t j) { return 1 + (i - 1) * s + j % s; };
    for (std::size_t j = 0; j < s; ++j) pushFace(mesh, 0, ring(1, j), ring(1, j + 1));
    for (std::size_t i = 1; i < rings; ++i)
        for (std::size_t j = 0; j < s; ++j) {
            const std::size_t a = ring(i, j), b = ring(i, j + 1), c = ring(i + 1, j), d = ring(i + 1, j + 1);
            pushFace(mesh, a, c, d);
            pushFace(mesh, a, d, b);
        }
    for (std::size_t j = 0; j < s; ++j) pushFace(mesh, ring(rings, j), south, ring(rings, j + 1));
    return mesh;
}

TriangleMesh makeDivergingQuad(float tiltRadians, float halfSize) {
    require(std::isfinite(tiltRadians) && std::fabs(tiltRadians) < kPi / 2,
            "quad normal tilt must be within (-pi/2, pi/2) radians");
    require(halfSize > 0.0f && std::isfinite(halfSize), "quad half size must be positive");
    TriangleMesh mesh;
    const double corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    const double s = std::sin(static_cast<double>(tiltRadians)) / std::sqrt(2.0);
    const double c = std::cos(static_cast<double>(tiltRadians));
    for (const auto& k : corners)
        pushVertex(mesh, halfSize * k[0], halfSize * k[1], 0.0, s * k[0], s * k[1], c);
    pushFace(mesh, 0, 1, 2);
    pushFace(mesh, 0, 2, 3);
    return mesh;
}

namespace {
void checkColumnOptions(const ColumnSceneOptions& o) {
    require(o.segments >= 3, "column needs at least 3 segments");
    require(o.heightRings >= 1, "column needs at least 1 height ring");
    require(o.groundResolution >= 1, "ground needs at least 1 cell per side");
    require(o.radius > 0.0f && o.height > 0.0f && o.groundHalfSize > 0.0f && std::isfinite(o.radius) &&
                std::isfinite(o.height) && std::isfinite(o.groundHalfSize),
            "column radius, height and ground size must be positive");
}
}  // namespace

std::size_t columnOnPlaneVertexCount(const ColumnSceneOptions& o) {
    const std::size_t s = static_cast<std::size_t>(o.segments);
    const std::size_t g = static_cast<std::size_t>(o.groundResolution) + 1;
    return s * static_cast<std::size_t>(o.heightRings + 1) + 2 * (s + 1) + g * g;
}

std::size_t columnOnPlaneFaceCount(const ColumnSceneOptions& o) {
    const std::size_t s = static_cast<std::size_t>(o.segments);
    const std::size_t g = static_cast<std::size_t>(o.groundResolution);
    return 2 * s * static_cast<std::size_t>(o.heightRings) + 2 * s + 2 * g * g;
}

TriangleMesh makeColumnOnPlane(const ColumnSceneOptions& o) {
    checkColumnOptions(o);
    TriangleMesh mesh;
    const std::size_t s = static_cast<std::size_t>(o.segments);
    const std::size_t h = static_cast<std::size_t>(o.heightRings);
    mesh.positions.reserve(3 * columnOnPlaneVertexCount(o));
    mesh.normals.reserve(3 * columnOnPlaneVertexCount(o));
    mesh.faces.reserve(3 * columnOnPlaneFaceCount(o));

    // Side: ring k at z = height * k / heightRings, normal radial.
    for (std::size_t k = 0; k <= h; ++k) {
        const double z = o.height * static_cast<double>(k) / static_cast<double>(h);
        for (std::size_t j = 0; j < s; ++j) {
            const double phi = 2.0 * kPi * static_cast<double>(j) / static_cast<double>(s);
            const double c = std::cos(phi), sn = std::sin(phi);
            pushVertex(mesh, o.radius * c, o.radius * sn, z, c, sn, 0.0);
        }
    }
    auto side = [s](std::size_t k, std::size_t j) { return k * s + j % s; };
    for (std::size_t k = 0; k < h; ++k)
        for (std::size_t j = 0; j < s; ++j) {
            const std::size_t a = side(k, j), b = side(k, j + 1), c = side(k + 1, j), d = side(k + 1, j + 1);
            pushFace(mesh, a, b, d);
            pushFace(mesh, a, d, c);
        }

    // Caps: centre then rim, normal +z on top, -z at the bottom.
    for (int cap = 0; cap < 2; ++cap) {
        const bool top = cap == 0;
        const double z = top ? o.height : 0.0;
        const double nz = top ? 1.0 : -1.0;
        const std::size_t centre = mesh.vertexCount();
        pushVertex(mesh, 0.0, 0.0, z, 0.0, 0.0, nz);
        for (std::size_t j = 0; j < s; ++j) {
            const double phi = 2.0 * kPi * static_cast<double>(j) / static_cast<double>(s);
            pushVertex(mesh, o.radius * std::cos(phi), o.radius * std::sin(phi), z, 0.0, 0.0, nz);
        }
        for (std::size_t j = 0; j < s; ++j) {
            const std::size_t a = centre + 1 + j, b = centre + 1 + (j + 1) % s;
            if (top)
                pushFace(mesh, centre, a, b);
            else
                pushFace(mesh, centre, b, a);
        }
    }

    // Ground: a regular grid at z = 0, normal +z.
    const std::size_t g = static_cast<std::size_t>(o.groundResolution);
    const std::size_t first = mesh.vertexCount();
    for (std::size_t r = 0; r <= g; ++r)
        for (std::size_t c = 0; c <= g; ++c) {
            const double x = -o.groundHalfSize + 2.0 * o.groundHalfSize * static_cast<double>(c) / g;
            const double y = -o.groundHalfSize + 2.0 * o.groundHalfSize * static_cast<double>(r) / g;
            pushVertex(mesh, x, y, 0.0, 0.0, 0.0, 1.0);
        }
    for (std::size_t r = 0; r < g; ++r)
        for (std::size_t c = 0; c < g; ++c) {
            const std::size_t a = first + r * (g + 1) + c, b = a + 1, cc = a + g + 1, d = cc + 1;
            pushFace(mesh, a, b, d);
            pushFace(mesh, a, d, cc);
        }
    return mesh;
}

TriangleMesh makeTorus(float majorRadius, float minorRadius, int majorSegments, int minorSegments) {
    require(majorSegments >= 3 && minorSegments >= 3, "torus needs at least 3 segments each way");
    require(minorRadius > 0.0f && majorRadius > minorRadius && std::isfinite(majorRadius),
            "torus radii must satisfy 0 < minorRadius < majorRadius");
    TriangleMesh mesh;
    const std::size_t M = static_cast<std::size_t>(majorSegments), m = static_cast<std::size_t>(minorSegments);
    mesh.positions.reserve(3 * M * m);
    mesh.normals.reserve(3 * M * m);
    for (std::size_t i = 0; i < M; ++i) {
        const double u = 2.0 * kPi * static_cast<double>(i) / static_cast<double>(M);
        for (std::size_t j = 0; j < m; ++j) {
            const double v = 2.0 * kPi * static_cast<double>(j) / static_cast<double>(m);
            const double nx = std::cos(v) * std::cos(u), ny = std::cos(v) * std::sin(u), nz = std::sin(v);
            pushVertex(mesh, majorRadius * std::cos(u) + minorRadius * nx,
                       majorRadius * std::sin(u) + minorRadius * ny, minorRadius * nz, nx, ny, nz);
        }
    }
    auto idx = [M, m](std::size_t i, std::size_t j) { return (i % M) * m + j % m; };
    for (std::size_t i = 0; i < M; ++i)
        for (std::size_t j = 0; j < m; ++j) {
            const std::size_t a = idx(i, j), b = idx(i + 1, j), c = idx(i, j + 1), d = idx(i + 1, j + 1);
            pushFace(mesh, a, b, d);
            pushFace(mesh, a, d, c);
        }
    return mesh;
}

}  // namespace rad
