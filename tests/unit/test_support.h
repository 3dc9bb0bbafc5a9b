// Small helpers shared by the unit tests (not a core unit: no test file of its own).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "geometry/triangle_mesh.h"
#include "radiance/basis.h"
#include "radiance/radiance_frame.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

namespace radtest {

// A uniformly distributed unit vector (normalised Gaussian triple, degenerate draws rejected).
inline Eigen::Vector3d randomUnit(std::mt19937& rng) {
    std::normal_distribution<double> g;
    Eigen::Vector3d v;
    do v = Eigen::Vector3d(g(rng), g(rng), g(rng));
    while (v.norm() < 1e-3);
    return v.normalized();
}

// Brute-force (1/2pi) integral of g over the hemisphere around unit n: midpoint rule in
// (theta, phi) with the sin(theta) weight, in a frame built here, independent of the quadrature
// rules and of radiance_frame under test.
template <typename G>
double bruteHemisphere(const Eigen::Vector3d& n, int thetaSteps, int phiSteps, G g) {
    const double pi = 3.14159265358979323846;
    const Eigen::Vector3d helper = std::fabs(n.x()) < 0.9 ? Eigen::Vector3d(1, 0, 0) : Eigen::Vector3d(0, 1, 0);
    const Eigen::Vector3d a = n.cross(helper).normalized(), b = n.cross(a);
    const double dt = 0.5 * pi / thetaSteps, dp = 2 * pi / phiSteps;
    double sum = 0;
    for (int i = 0; i < thetaSteps; ++i) {
        const double t = (i + 0.5) * dt, st = std::sin(t), ct = std::cos(t);
        double ring = 0;
        for (int j = 0; j < phiSteps; ++j) {
            const double p = (j + 0.5) * dp;
            ring += g(Eigen::Vector3d(st * std::cos(p) * a + st * std::sin(p) * b + ct * n));
        }
        sum += ring * st;
    }
    return sum * dt * dp / (2 * pi);
}

// Moller-Trumbore against every face, no acceleration structure (an oracle for the Embree-based
// visibility): is anything hit by o + t d for t in [tNear, tFar]?
inline bool bruteOccluded(const rad::TriangleMesh& mesh, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double tNear, double tFar) {
    for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
        Eigen::Vector3d p[3];
        for (int k = 0; k < 3; ++k) {
            const float* q = mesh.positions.data() + 3 * mesh.faces[3 * f + k];
            p[k] = Eigen::Vector3d(q[0], q[1], q[2]);
        }
        const Eigen::Vector3d e1 = p[1] - p[0], e2 = p[2] - p[0], h = d.cross(e2);
        const double det = e1.dot(h);
        if (std::abs(det) < 1e-14) continue;
        const Eigen::Vector3d s = o - p[0];
        const double a = s.dot(h) / det;
        if (a < 0 || a > 1) continue;
        const Eigen::Vector3d q = s.cross(e1);
        const double b = d.dot(q) / det;
        if (b < 0 || a + b > 1) continue;
        const double t = e2.dot(q) / det;
        if (t >= tNear && t <= tFar) return true;
    }
    return false;
}

// Appends the square [x0, x1] x [y0, y1] at height z, normals +z, counter-clockwise from above.
inline void addQuad(rad::TriangleMesh& m, float x0, float x1, float y0, float y1, float z) {
    const auto base = static_cast<std::uint32_t>(m.vertexCount());
    const float corners[4][2] = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
    for (const auto& c : corners) {
        m.positions.insert(m.positions.end(), {c[0], c[1], z});
        m.normals.insert(m.normals.end(), {0.0f, 0.0f, 1.0f});
    }
    m.faces.insert(m.faces.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

// Appends a grid of n x n vertices over [lo, hi]^2 at z = 0, normals +z, each square split along
// its diagonal into two triangles counter-clockwise from +z.
// The vertices renumbered at random (positions: 3 per vertex; faces: their indices), the same
// surface: the corners of most faces end far apart in the numbering, as in subdivided or merged
// scans.
inline void renumberVerticesAtRandom(std::vector<float>& positions, std::vector<std::uint32_t>& faces, unsigned seed) {
    std::vector<std::uint32_t> order(positions.size() / 3);
    for (std::uint32_t v = 0; v < order.size(); ++v) order[v] = v;
    std::shuffle(order.begin(), order.end(), std::mt19937(seed));
    std::vector<float> moved(positions.size());
    for (std::size_t v = 0; v < order.size(); ++v)
        for (int k = 0; k < 3; ++k) moved[3 * order[v] + k] = positions[3 * v + k];
    positions.swap(moved);
    for (std::uint32_t& i : faces) i = order[i];
}

inline void addGrid(rad::TriangleMesh& mesh, int n, float lo = -1.0f, float hi = 1.0f) {
    const auto base = static_cast<std::uint32_t>(mesh.vertexCount());
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            mesh.positions.insert(mesh.positions.end(),
                                  {lo + (hi - lo) * i / (n - 1), lo + (hi - lo) * j / (n - 1), 0.0f});
            mesh.normals.insert(mesh.normals.end(), {0.0f, 0.0f, 1.0f});
        }
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            const std::uint32_t a = base + j * n + i, b = a + 1, c = a + n + 1, d = a + n;
            mesh.faces.insert(mesh.faces.end(), {a, b, c, a, c, d});
        }
}

// The message of the Error that call() throws, or "" when it returns: for tests of refusals.
template <class Error, class Call>
std::string refusalMessage(Call&& call) {
    try {
        call();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

// Whole files as bytes (for tests that truncate or corrupt files).
inline std::vector<char> readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::vector<char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}
inline void writeBytes(const std::string& path, const std::vector<char>& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size()));
}

// Independent PB function: sum c_ij u^i v^j with (u, v) = (t.w, (n x t).w), std::pow (not the
// basis code under test). c: 3 channel-major blocks of K coefficients.
inline Eigen::Vector3d polynomialValue(const rad::BasisSpec& basis, const std::vector<double>& c, const rad::Frame& f,
                                       const Eigen::Vector3d& w) {
    const double u = f.t.dot(w), v = f.n.cross(f.t).dot(w);
    const int K = basis.coefficientCount();
    Eigen::Vector3d out = Eigen::Vector3d::Zero();
    for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i <= basis.degree; ++i)
            for (int j = 0; i + j <= basis.degree; ++j)
                out[ch] += c[ch * K + rad::polynomialIndex(i, j)] * std::pow(u, i) * std::pow(v, j);
    return out;
}

// SH function through evaluateBasis (the SH evaluation is tested in spherical_harmonics_test).
inline Eigen::Vector3d harmonicValue(const rad::BasisSpec& basis, const std::vector<double>& c, const Eigen::Vector3d& w) {
    std::vector<double> y(basis.coefficientCount());
    rad::evaluateBasis(basis, w.x(), w.y(), w.z(), y.data());
    Eigen::Vector3d out = Eigen::Vector3d::Zero();
    for (int ch = 0; ch < 3; ++ch)
        for (int k = 0; k < basis.coefficientCount(); ++k) out[ch] += c[ch * basis.coefficientCount() + k] * y[k];
    return out;
}

// A fresh, empty folder under the system's temporary directory, removed with its content at the
// end of the scope.
struct TemporaryFolder {
    std::filesystem::path path;
    explicit TemporaryFolder(const std::string& name) : path(std::filesystem::temp_directory_path() / name) {
        std::filesystem::remove_all(path);
        std::filesystem::create_directories(path);
    }
    ~TemporaryFolder() { std::filesystem::remove_all(path); }
    TemporaryFolder(const TemporaryFolder&) = delete;
    TemporaryFolder& operator=(const TemporaryFolder&) = delete;
    bool empty() const { return std::filesystem::is_empty(path); }
    std::size_t files() const {
        return std::size_t(std::distance(std::filesystem::directory_iterator(path), std::filesystem::directory_iterator()));
    }
};

// The square [-a, a]^2 at z = 0 facing +z, two triangles.
inline rad::TriangleMesh floorSquare(float a) {
    rad::TriangleMesh m;
    m.positions = {-a, -a, 0, a, -a, 0, a, a, 0, -a, a, 0};
    m.faces = {0, 1, 2, 0, 2, 3};
    return m;
}

}  // namespace radtest
