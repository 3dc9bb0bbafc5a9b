#include "radiance/radiance_interpolation.h"

#include <Eigen/Geometry>

#include <cmath>

namespace rad {

namespace {
bool isFinite(const Eigen::Vector3d& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

template <typename Scalar>
bool sameShBasis(const TriangleRadianceT<Scalar>& tri) {
    const BasisSpec& b = tri.vertices[0].basis;
    return b.kind == BasisKind::SphericalHarmonics && b.isValid() && tri.vertices[1].basis == b &&
           tri.vertices[2].basis == b;
}

// The three L~ coefficient vectors, count = kColorChannels * K each.
template <typename Scalar>
void reflectedTriangleSh(const TriangleRadianceT<Scalar>& tri, double (*c)[kColorChannels * kMaxCoefficientsPerChannel]) {
    for (int i = 0; i < 3; ++i) reflectedShCoefficients(tri.vertices[i], c[i]);
}
}  // namespace

// ---- TriangleGradient -----------------------------------------------------------------------

std::optional<TriangleGradient> TriangleGradient::create(const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                                                         const Eigen::Vector3d& p3) {
    if (!isFinite(p1) || !isFinite(p2) || !isFinite(p3)) return std::nullopt;
    const Eigen::Vector3d e1 = p2 - p1, e2 = p3 - p1;
    const Eigen::Vector3d cross = e1.cross(e2);
    const double a = e1.squaredNorm(), b = e1.dot(e2), c = e2.squaredNorm();
    const double det = cross.squaredNorm();  // = a c - b^2 = det(J^T J), without cancellation
    if (!(det > 1e-20 * a * c) || !std::isfinite(det)) return std::nullopt;
    Eigen::Matrix<double, 3, 2> J;
    J.col(0) = e1;
    J.col(1) = e2;
    Eigen::Matrix2d inv;  // (J^T J)^{-1}
    inv << c, -b, -b, a;
    inv /= det;
    TriangleGradient g;
    g.p1_ = p1;
    g.M_ = J * inv;
    g.normal_ = cross / std::sqrt(det);
    return g;
}

Eigen::Vector3d TriangleGradient::gradient(double v1, double v2, double v3) const {
    return M_ * Eigen::Vector2d(v2 - v1, v3 - v1);
}

Eigen::Matrix3d TriangleGradient::gradient(const Eigen::Vector3d& L1, const Eigen::Vector3d& L2,
                                           const Eigen::Vector3d& L3) const {
    Eigen::Matrix<double, 2, 3> d;  // rows: L2 - L1, L3 - L1; columns: channels
    d.row(0) = (L2 - L1).transpose();
    d.row(1) = (L3 - L1).transpose();
    return (M_ * d).transpose();  // row c = M [d2_c; d3_c]
}

Eigen::Vector3d TriangleGradient::extrapolationWeights(const Eigen::Vector3d& p) const {
    // grad . (p - p1) = (p - p1)^T M [d2; d3]  =>  (a2, a3) = M^T (p - p1)
    const Eigen::Vector2d a = M_.transpose() * (p - p1_);
    return {1.0 - a.x() - a.y(), a.x(), a.y()};
}

// ---- Function level -------------------------------------------------------------------------

TriangleRadiance triangleRadiance(const RadianceField& field, std::size_t v1, std::size_t v2, std::size_t v3,
                                  const Eigen::Vector3d& p1, const Eigen::Vector3d& p2, const Eigen::Vector3d& p3) {
    TriangleRadiance tri;
    tri.vertices = {vertexRadiance(field, v1), vertexRadiance(field, v2), vertexRadiance(field, v3)};
    tri.positions = {p1, p2, p3};
    return tri;
}

template <typename Scalar>
std::optional<Eigen::Vector3d> interpolatedNormal(const TriangleRadianceT<Scalar>& tri, const Eigen::Vector3d& alpha) {
    const Eigen::Vector3d n =
        alpha[0] * tri.vertices[0].frame.n + alpha[1] * tri.vertices[1].frame.n + alpha[2] * tri.vertices[2].frame.n;
    const double len = n.norm();
    if (!(len >= 1e-12) || !std::isfinite(len)) return std::nullopt;
    return Eigen::Vector3d(n / len);
}

template <typename Scalar>
Eigen::Vector3d interpolateReflectedRadiance(const TriangleRadianceT<Scalar>& tri, const Eigen::Vector3d& alpha,
                                             const Eigen::Vector3d& w) {
    double scratch[kMaxCoefficientsPerChannel];
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int i = 0; i < 3; ++i) sum += alpha[i] * evaluateReflectedRadiance(tri.vertices[i], w, scratch);
    return sum;
}

template <typename Scalar>
std::optional<Eigen::Vector3d> interpolateRadiance(const TriangleRadianceT<Scalar>& tri, const Eigen::Vector3d& alpha,
                                                   const Eigen::Vector3d& w) {
    const std::optional<Eigen::Vector3d> n = interpolatedNormal(tri, alpha);
    if (!n) return std::nullopt;
    return interpolateReflectedRadiance(tri, alpha, reflect(*n, w));  // eq. (8)
}

template <typename Scalar>
std::optional<Eigen::Matrix3d> reflectedRadianceGradient(const TriangleRadianceT<Scalar>& tri,
                                                         const Eigen::Vector3d& w) {
    const std::optional<TriangleGradient> g = TriangleGradient::create(tri.positions[0], tri.positions[1], tri.positions[2]);
    if (!g) return std::nullopt;
    double scratch[kMaxCoefficientsPerChannel];
    Eigen::Vector3d L[3];
    for (int i = 0; i < 3; ++i) L[i] = evaluateReflectedRadiance(tri.vertices[i], w, scratch);
    return g->gradient(L[0], L[1], L[2]);
}

template <typename Scalar>
std::optional<Eigen::Vector3d> extrapolateReflectedRadiance(const TriangleRadianceT<Scalar>& tri,
                                                            const Eigen::Vector3d& p, const Eigen::Vector3d& w) {
    const std::optional<TriangleGradient> g = TriangleGradient::create(tri.positions[0], tri.positions[1], tri.positions[2]);
    if (!g || !isFinite(p)) return std::nullopt;
    double scratch[kMaxCoefficientsPerChannel];
    Eigen::Vector3d L[3];
    for (int i = 0; i < 3; ++i) L[i] = evaluateReflectedRadiance(tri.vertices[i], w, scratch);
    return extrapolate(L[0], g->gradient(L[0], L[1], L[2]), tri.positions[0], p);  // eq. (4)
}

// ---- SH coefficient level -------------------------------------------------------------------

template <typename Scalar>
bool reflectedShCoefficients(const VertexRadianceT<Scalar>& rf, double* out) {
    if (rf.basis.kind != BasisKind::SphericalHarmonics || !rf.basis.isValid() || rf.coefficients == nullptr)
        return false;
    const int count = kColorChannels * rf.basis.coefficientCount();
    for (int k = 0; k < count; ++k) out[k] = static_cast<double>(rf.coefficients[k]);
    if (!rf.reflected) reflectCoefficients(rf.basis, rf.frame, out, out);
    return true;
}

template <typename Scalar>
bool interpolateReflectedSh(const TriangleRadianceT<Scalar>& tri, const Eigen::Vector3d& alpha, double* out) {
    if (!sameShBasis(tri) || !isFinite(alpha)) return false;
    double c[3][kColorChannels * kMaxCoefficientsPerChannel];
    reflectedTriangleSh(tri, c);
    const int count = kColorChannels * tri.vertices[0].basis.coefficientCount();
    for (int k = 0; k < count; ++k) out[k] = alpha[0] * c[0][k] + alpha[1] * c[1][k] + alpha[2] * c[2][k];
    return true;
}

template <typename Scalar>
bool reflectedShGradient(const TriangleRadianceT<Scalar>& tri, double* out) {
    if (!sameShBasis(tri)) return false;
    const std::optional<TriangleGradient> g = TriangleGradient::create(tri.positions[0], tri.positions[1], tri.positions[2]);
    if (!g) return false;
    double c[3][kColorChannels * kMaxCoefficientsPerChannel];
    reflectedTriangleSh(tri, c);
    const int count = kColorChannels * tri.vertices[0].basis.coefficientCount();
    for (int k = 0; k < count; ++k) {
        const Eigen::Vector3d grad = g->gradient(c[0][k], c[1][k], c[2][k]);
        for (int axis = 0; axis < 3; ++axis) out[k * 3 + axis] = grad[axis];
    }
    return true;
}

template <typename Scalar>
bool extrapolateReflectedSh(const TriangleRadianceT<Scalar>& tri, const Eigen::Vector3d& p, double* out) {
    if (!sameShBasis(tri) || !isFinite(p)) return false;
    const std::optional<TriangleGradient> g = TriangleGradient::create(tri.positions[0], tri.positions[1], tri.positions[2]);
    if (!g) return false;
    double c[3][kColorChannels * kMaxCoefficientsPerChannel];
    reflectedTriangleSh(tri, c);
    const int count = kColorChannels * tri.vertices[0].basis.coefficientCount();
    const Eigen::Vector3d d = p - tri.positions[0];
    for (int k = 0; k < count; ++k) out[k] = c[0][k] + g->gradient(c[0][k], c[1][k], c[2][k]).dot(d);  // eq. (4)
    return true;
}

#define RAD_INSTANTIATE(S)                                                                                           \
    template std::optional<Eigen::Vector3d> interpolatedNormal<S>(const TriangleRadianceT<S>&, const Eigen::Vector3d&); \
    template Eigen::Vector3d interpolateReflectedRadiance<S>(const TriangleRadianceT<S>&, const Eigen::Vector3d&,      \
                                                             const Eigen::Vector3d&);                                 \
    template std::optional<Eigen::Vector3d> interpolateRadiance<S>(const TriangleRadianceT<S>&, const Eigen::Vector3d&, \
                                                                   const Eigen::Vector3d&);                           \
    template std::optional<Eigen::Matrix3d> reflectedRadianceGradient<S>(const TriangleRadianceT<S>&,                  \
                                                                         const Eigen::Vector3d&);                     \
    template std::optional<Eigen::Vector3d> extrapolateReflectedRadiance<S>(                                          \
        const TriangleRadianceT<S>&, const Eigen::Vector3d&, const Eigen::Vector3d&);                                 \
    template bool reflectedShCoefficients<S>(const VertexRadianceT<S>&, double*);                                     \
    template bool interpolateReflectedSh<S>(const TriangleRadianceT<S>&, const Eigen::Vector3d&, double*);            \
    template bool reflectedShGradient<S>(const TriangleRadianceT<S>&, double*);                                       \
    template bool extrapolateReflectedSh<S>(const TriangleRadianceT<S>&, const Eigen::Vector3d&, double*);

RAD_INSTANTIATE(float)
RAD_INSTANTIATE(double)
#undef RAD_INSTANTIATE

}  // namespace rad
