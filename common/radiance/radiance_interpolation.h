// Interpolation, gradient and extrapolation of radiance functions (RF) over a triangle, Vanhoey et
// al. 2015 sec. 3.2-3.4 and 5: eq. (1) r-RF interpolation, eq. (2)/(8) RF interpolation about the
// interpolated normal, eq. (3) the spatial gradient, eq. (4) extrapolation to any 3D point, which is
// linear in the vertices' r-RF (extrapolationWeights: what makes eq. 7 cheap). The *Sh* functions do
// the same on the coefficient vectors of SH in the global frame (sec. 6). Degenerate input (zero-area
// triangle, zero interpolated normal, non-finite data) gives an empty std::optional / false, never NaN.
// Details: docs/architecture.md, "`common/radiance/radiance_interpolation.h`: how it works".
#pragma once

#include "radiance/radiance_evaluation.h"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <optional>

namespace rad {

// The triangle geometry of eq. (3)-(4): the 3x2 operator M = J (J^T J)^{-1}.
class TriangleGradient {
public:
    // Empty when the triangle is degenerate: non-finite positions or
    // |e1 x e2|^2 <= 1e-20 |e1|^2 |e2|^2 (sine of the angle at p1 below 1e-10, or a zero edge),
    // e1 = p2 - p1, e2 = p3 - p1.
    static std::optional<TriangleGradient> create(const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                                                  const Eigen::Vector3d& p3);

    // Eq. (3) for one scalar channel with values v_i at the vertices.
    Eigen::Vector3d gradient(double v1, double v2, double v3) const;
    // Eq. (3) for RGB values: row c is the gradient (a 3-vector) of channel c.
    Eigen::Matrix3d gradient(const Eigen::Vector3d& L1, const Eigen::Vector3d& L2, const Eigen::Vector3d& L3) const;
    // beta(p) such that eq. (4) = sum_i beta_i L~_i (docs/architecture.md). Sums to 1; equals the
    // barycentrics for p in the triangle's plane; constant along the triangle's normal.
    Eigen::Vector3d extrapolationWeights(const Eigen::Vector3d& p) const;

    const Eigen::Vector3d& p1() const { return p1_; }
    const Eigen::Matrix<double, 3, 2>& op() const { return M_; }  // J (J^T J)^{-1}
    // Unit normal of the triangle, (p2 - p1) x (p3 - p1) normalised.
    const Eigen::Vector3d& normal() const { return normal_; }

private:
    Eigen::Vector3d p1_;
    Eigen::Matrix<double, 3, 2> M_;
    Eigen::Vector3d normal_;
};

// Eq. (4) from the value at p1, the gradient (rows = channels) and the point.
inline Eigen::Vector3d extrapolate(const Eigen::Vector3d& L1, const Eigen::Matrix3d& gradient,
                                   const Eigen::Vector3d& p1, const Eigen::Vector3d& p) {
    return L1 + gradient * (p - p1);
}

// The three RF and positions of a triangle. Scalar: float (field views) or double.
template <typename Scalar>
struct TriangleRadianceT {
    std::array<VertexRadianceT<Scalar>, 3> vertices;
    std::array<Eigen::Vector3d, 3> positions;
};
using TriangleRadiance = TriangleRadianceT<float>;

// Views on vertices (v1, v2, v3) of the field, with their positions (which the field does not hold).
TriangleRadiance triangleRadiance(const RadianceField& field, std::size_t v1, std::size_t v2, std::size_t v3,
                                  const Eigen::Vector3d& p1, const Eigen::Vector3d& p2, const Eigen::Vector3d& p3);

// n = normalize(sum_i alpha_i n_i); empty when its length is below 1e-12 or not finite.
template <typename Scalar>
std::optional<Eigen::Vector3d> interpolatedNormal(const TriangleRadianceT<Scalar>& tri, const Eigen::Vector3d& alpha);

// Eq. (1): sum_i alpha_i L~_i(w). (Needs no normal: always defined.)
template <typename Scalar>
Eigen::Vector3d interpolateReflectedRadiance(const TriangleRadianceT<Scalar>& tri, const Eigen::Vector3d& alpha,
                                             const Eigen::Vector3d& w);

// Eq. (2) = eq. (8): sum_i alpha_i L~_i(R_n w) with the interpolated normal n. Empty when n is.
template <typename Scalar>
std::optional<Eigen::Vector3d> interpolateRadiance(const TriangleRadianceT<Scalar>& tri, const Eigen::Vector3d& alpha,
                                                   const Eigen::Vector3d& w);

// Eq. (3) at direction w: row c = gradient of channel c of L~_t. Empty for a degenerate triangle.
template <typename Scalar>
std::optional<Eigen::Matrix3d> reflectedRadianceGradient(const TriangleRadianceT<Scalar>& tri,
                                                         const Eigen::Vector3d& w);

// Eq. (4): L~_t(p, w) at any 3D point p. Empty for a degenerate triangle.
template <typename Scalar>
std::optional<Eigen::Vector3d> extrapolateReflectedRadiance(const TriangleRadianceT<Scalar>& tri,
                                                            const Eigen::Vector3d& p, const Eigen::Vector3d& w);

// ---- SH coefficient level (sec. 6). Coefficient vectors: kColorChannels * K doubles, channel-major,
// encoding the r-RF L~ in the global frame. All return false for a non-SH basis, mismatched bases
// between the three vertices, or degenerate input (out untouched).

// out = L~ coefficients of vertex `rf` (reflecting plain storage about its normal).
template <typename Scalar>
bool reflectedShCoefficients(const VertexRadianceT<Scalar>& rf, double* out);

// Eq. (1) on coefficients: out = sum_i alpha_i c~_i.
template <typename Scalar>
bool interpolateReflectedSh(const TriangleRadianceT<Scalar>& tri, const Eigen::Vector3d& alpha, double* out);

// Eq. (3) on coefficients: out[j * 3 + axis], j < kColorChannels * K: the gradient (3-vector) of every
// coefficient of L~_t. sum_j grad_j Y_j(w) is the gradient of L~_t(w) (for w in all hemispheres).
template <typename Scalar>
bool reflectedShGradient(const TriangleRadianceT<Scalar>& tri, double* out);

// Eq. (4) on coefficients: out = c~_1 + grad . (p - p1) = sum_i beta_i(p) c~_i.
template <typename Scalar>
bool extrapolateReflectedSh(const TriangleRadianceT<Scalar>& tri, const Eigen::Vector3d& p, double* out);

}  // namespace rad
