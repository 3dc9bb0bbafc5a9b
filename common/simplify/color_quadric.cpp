#include "simplify/color_quadric.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace rad {

namespace {
// Per vertex: the upper triangle of the symmetric A (21 values, row by row), b (6), c (1). Half the
// memory of a full 6x6 + 6 + 1, which matters at a million vertices.
constexpr int kUpper = 21;
constexpr int kPacked = kUpper + 6 + 1;

void unpackAdd(const double* packed, ColorQuadric& q) {
    int k = 0;
    for (int i = 0; i < 6; ++i)
        for (int j = i; j < 6; ++j, ++k) {
            q.A(i, j) += packed[k];
            if (j != i) q.A(j, i) += packed[k];
        }
    for (int i = 0; i < 6; ++i) q.b[i] += packed[kUpper + i];
    q.c += packed[kUpper + 6];
}

// The half-edge case of collapse_metric.h.
bool isHalfEdge(const EdgeQuery& query) { return query.halfEdge; }
}  // namespace

ColorQuadric ColorQuadric::triangle(const Vector6d& p, const Vector6d& q, const Vector6d& r) {
    ColorQuadric out;
    const Vector6d u = q - p, w = r - p;
    const double lu = u.norm();
    if (!(lu > 0.0) || !std::isfinite(lu)) return out;
    const Vector6d e1 = u / lu;
    Vector6d e2 = w - e1.dot(w) * e1;  // Gram-Schmidt
    const double l2 = e2.norm();
    if (!(l2 > 1e-12 * std::max(lu, w.norm())) || !std::isfinite(l2)) return out;
    e2 /= l2;
    const double pe1 = p.dot(e1), pe2 = p.dot(e2);
    out.A = Matrix6d::Identity() - e1 * e1.transpose() - e2 * e2.transpose();
    out.b = pe1 * e1 + pe2 * e2 - p;
    out.c = p.dot(p) - pe1 * pe1 - pe2 * pe2;
    return out;
}

Eigen::Vector3d ColorQuadric::optimalColor(const Eigen::Vector3d& x, const Eigen::Vector3d& fallback) const {
    const Eigen::Matrix3d Acc = A.bottomRightCorner<3, 3>();
    const Eigen::Vector3d rhs = -(A.bottomLeftCorner<3, 3>() * x + b.tail<3>());
    // Minimum-norm correction delta of the fallback: Acc (fallback + delta) = rhs in the range of
    // Acc, delta = 0 in its null space. For a regular Acc this is just Acc^-1 rhs.
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(Acc);
    const Eigen::Vector3d lambda = eigen.eigenvalues();  // increasing
    if (eigen.info() != Eigen::Success || !(lambda(2) > 0.0)) return fallback;
    const Eigen::Vector3d residual = eigen.eigenvectors().transpose() * (rhs - Acc * fallback);
    Eigen::Vector3d delta = Eigen::Vector3d::Zero();
    for (int i = 0; i < 3; ++i)
        if (lambda(i) > 1e-12 * lambda(2)) delta(i) = residual(i) / lambda(i);
    const Eigen::Vector3d c = fallback + eigen.eigenvectors() * delta;
    return c.allFinite() ? c : fallback;
}

ColorQuadricMetric::ColorQuadricMetric(const CollapseMesh& mesh, const std::vector<float>& colors,
                                       ColorQuadricOptions options) {
    const std::size_t n = mesh.vertexCount();
    if (colors.size() != 3 * n)
        throw std::invalid_argument("colour quadric: " + std::to_string(colors.size()) + " colour values for " +
                                    std::to_string(n) + " vertices (3 per vertex expected)");
    if (!(options.geometryScale >= 0.0) || !std::isfinite(options.geometryScale))
        throw std::invalid_argument("colour quadric: geometry scale must be finite and >= 0");
    colors_.resize(3 * n);
    for (std::size_t i = 0; i < colors.size(); ++i) {
        if (!std::isfinite(colors[i]))
            throw std::invalid_argument("colour quadric: colour of vertex " + std::to_string(i / 3) + " is not finite");
        colors_[i] = colors[i];
    }

    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (std::uint32_t v = 0; v < n; ++v) {
        if (!mesh.vertexAlive(v)) continue;
        lo = lo.cwiseMin(mesh.position(v));
        hi = hi.cwiseMax(mesh.position(v));
    }
    if (lo.allFinite() && hi.allFinite()) centre_ = 0.5 * (lo + hi);
    const double diagonal = lo.allFinite() && hi.allFinite() ? (hi - lo).norm() : 0.0;
    scale_ = options.geometryScale > 0.0 ? options.geometryScale : (diagonal > 0.0 ? 1.0 / diagonal : 1.0);

    quadrics_.assign(kPacked * n, 0.0);
    for (std::uint32_t f = 0; f < mesh.faceCount(); ++f) {
        if (!mesh.faceAlive(f)) continue;
        const std::uint32_t* t = mesh.face(f);
        Vector6d p[3];
        for (int k = 0; k < 3; ++k) p[k] << normalizedPosition(mesh.position(t[k])), color(t[k]);
        ColorQuadric q = ColorQuadric::triangle(p[0], p[1], p[2]);
        if (options.areaWeighted) {
            const Eigen::Vector3d e1 = (p[1] - p[0]).head<3>(), e2 = (p[2] - p[0]).head<3>();
            q *= 0.5 * e1.cross(e2).norm();
        }
        for (int k = 0; k < 3; ++k) addQuadric(t[k], q);
    }
}

void ColorQuadricMetric::addQuadric(std::uint32_t v, const ColorQuadric& q) {
    double* packed = quadrics_.data() + std::size_t(kPacked) * v;
    int k = 0;
    for (int i = 0; i < 6; ++i)
        for (int j = i; j < 6; ++j, ++k) packed[k] += q.A(i, j);
    for (int i = 0; i < 6; ++i) packed[kUpper + i] += q.b[i];
    packed[kUpper + 6] += q.c;
}

ColorQuadric ColorQuadricMetric::quadric(std::uint32_t v) const {
    ColorQuadric q;
    unpackAdd(quadrics_.data() + std::size_t(kPacked) * v, q);
    return q;
}

ColorQuadric ColorQuadricMetric::sum(std::uint32_t v0, std::uint32_t v1) const {
    ColorQuadric q;
    unpackAdd(quadrics_.data() + std::size_t(kPacked) * v0, q);
    unpackAdd(quadrics_.data() + std::size_t(kPacked) * v1, q);
    return q;
}

void ColorQuadricMetric::priceHalfEdges(const CollapseMesh& mesh, const HalfEdgeQuery& query, double* costs) const {
    for (int i = 0; i < query.targetCount; ++i) {
        const std::uint32_t v1 = query.targets[i];
        const ColorQuadric q = sum(query.source, v1);
        // The rounding of the expanded form can dip below 0 on an exact fit.
        costs[i] = std::max(0.0, q.evaluate(normalizedPosition(mesh.position(v1)), color(v1)));
    }
}

Eigen::Vector3d ColorQuadricMetric::survivorColor(const ColorQuadric& q, const EdgeQuery& query,
                                                  const Eigen::Vector3d& x) const {
    if (isHalfEdge(query)) return color(query.v1);
    const double s = std::clamp(query.s, 0.0, 1.0);
    return q.optimalColor(x, (1.0 - s) * color(query.v0) + s * color(query.v1));
}

double ColorQuadricMetric::priceEdge(const CollapseMesh& mesh, const EdgeQuery& query) const {
    const ColorQuadric q = sum(query.v0, query.v1);
    // Half-edge: the engine's position is p1, and the survivor keeps c1.
    const Eigen::Vector3d x = normalizedPosition(query.position);
    return std::max(0.0, q.evaluate(x, survivorColor(q, query, x)));
}

void ColorQuadricMetric::onCollapse(const CollapseMesh& mesh, const EdgeQuery& query) {
    const ColorQuadric q = sum(query.v0, query.v1);
    const Eigen::Vector3d c = survivorColor(q, query, normalizedPosition(query.position));
    for (int k = 0; k < 3; ++k) colors_[3 * query.v1 + k] = c[k];
    // GH98's accumulation: Q1 += Q0 (componentwise on the packed form).
    const double* q0 = quadrics_.data() + std::size_t(kPacked) * query.v0;
    double* q1 = quadrics_.data() + std::size_t(kPacked) * query.v1;
    for (int k = 0; k < kPacked; ++k) q1[k] += q0[k];
}

}  // namespace rad
