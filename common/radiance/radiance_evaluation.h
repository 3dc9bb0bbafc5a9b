// Evaluation of per-vertex radiance functions (RF) at world directions, with the border extension
// of Vanhoey et al. 2015 sec. 7, and conversion between plain and reflected storage (sec. 3.1).
// L(w) is meaningful on the hemisphere n.w >= 0; L~(w) = L(R_n w) is the reflected RF. Below the
// hemisphere an RF takes the value of the border direction with the same azimuth,
// normalize(w - (n.w) n), and the frame's tangent t at the exact opposite pole. PB coefficients are in
// the local frame (t, b = n x t, n), SH coefficients in the global frame.
// Details: docs/architecture.md, "`common/radiance/radiance_evaluation.h`: how it works".
#pragma once

#include "radiance/basis.h"
#include "radiance/radiance_field.h"
#include "radiance/radiance_frame.h"

#include <Eigen/Core>

#include <cmath>
#include <cstddef>

namespace rad {

// Largest coefficientCount() over every supported basis (SH10: 121; PB8: 45). Scratch buffers of
// this size work for any basis.
inline constexpr int kMaxCoefficientsPerChannel = (kMaxHarmonicDegree + 1) * (kMaxHarmonicDegree + 1);

// One vertex's RF as a function of world directions: a view on kColorChannels * K coefficients
// (channel c at coefficients + c * K, the layout of one vertex in radiance_field.h) and its frame.
// Scalar is float (coefficients inside a RadianceField) or double (computed coefficients, e.g. the
// coefficient-level SH interpolation of radiance_interpolation.h).
template <typename Scalar>
struct VertexRadianceT {
    BasisSpec basis;
    const Scalar* coefficients = nullptr;
    Frame frame;
    bool reflected = false;  // true: `coefficients` encode L~ (sec. 3.1), false: L
};
using VertexRadiance = VertexRadianceT<float>;
using VertexRadianceD = VertexRadianceT<double>;

// |w - (n.w) n| below which w is taken as the opposite pole (where border() is the tangent t).
inline constexpr double kOppositePoleRadius = 1e-12;

// border() of sec. 7 on the LOCAL coordinates (x, y, z) = (t.w, b.w, n.w) of a unit direction: for
// z < 0 the direction becomes (x, y, 0) normalised, or the tangent (1, 0, 0) at the opposite pole;
// unchanged for z >= 0. The flat-array kernels (fit, collapse pricing) call it per direction.
inline void borderExtendLocal(double& x, double& y, double& z) {
    if (z >= 0.0) return;
    const double r = std::sqrt(x * x + y * y);
    if (r < kOppositePoleRadius) {
        x = 1.0;
        y = 0.0;
    } else {
        x /= r;
        y /= r;
    }
    z = 0.0;
}

// View on vertex v of the field (frame re-orthonormalised in double, see frameFromStored).
VertexRadiance vertexRadiance(const RadianceField& field, std::size_t v);

// border(w) of sec. 7 for a direction below the frame's tangent plane: normalize(w - (n.w) n),
// or the tangent t at the opposite pole. Directions with n.w >= 0 are returned unchanged.
Eigen::Vector3d borderExtendedDirection(const Frame& frame, const Eigen::Vector3d& w);

// The unit direction, in the basis's own frame (local for PB, global for SH), at which coefficients
// stored for (basis, frame, reflectedStorage) must be evaluated to give L(w): border-extended
// below the tangent plane (sec. 7), then reflected about n for reflected storage
// (L(w) = L~(R_n w), sec. 3.1). Evaluating plain storage here with reflectedStorage = true gives
// L~(w) instead.
Eigen::Vector3d basisDirection(const BasisSpec& basis, const Frame& frame, const Eigen::Vector3d& w,
                               bool reflectedStorage);

// sum_k c[c*K + k] B_k(d) for every channel c, where d is a unit direction in the basis's own frame
// (local for PB, global for SH), without any border extension. scratch: >= K doubles.
template <typename Scalar>
Eigen::Vector3d evaluateCoefficients(const BasisSpec& basis, const Scalar* coefficients,
                                     const Eigen::Vector3d& basisDirection, double* scratch);

// L(w) for a unit world direction w, border-extended below the tangent plane, whatever the
// storage. scratch: >= basis.coefficientCount() doubles (reuse it over many directions).
template <typename Scalar>
Eigen::Vector3d evaluateRadiance(const VertexRadianceT<Scalar>& rf, const Eigen::Vector3d& w, double* scratch);
// L~(w) = L(R_n w), border-extended, whatever the storage.
template <typename Scalar>
Eigen::Vector3d evaluateReflectedRadiance(const VertexRadianceT<Scalar>& rf, const Eigen::Vector3d& w,
                                          double* scratch);

// Conveniences with an internal stack scratch buffer.
Eigen::Vector3d evaluateRadiance(const RadianceField& field, std::size_t v, const Eigen::Vector3d& w);
Eigen::Vector3d evaluateReflectedRadiance(const RadianceField& field, std::size_t v, const Eigen::Vector3d& w);

// Coefficients of the reflected function g(w) = f(R_n w) from those of f, for one vertex (all
// channels, kColorChannels * K values). The map is an involution, so it converts plain -> reflected
// and reflected -> plain alike. PB (local frame): R_n maps local (u, v, z) to (-u, -v, z), so the
// monomial u^i v^j gets the sign (-1)^(i+j). SH (global frame): rotation of the coefficient vector
// by pi about n (sh_rotation.h). `in` and `out` may be the same array.
template <typename Scalar>
void reflectCoefficients(const BasisSpec& basis, const Frame& frame, const Scalar* in, Scalar* out);

// Coefficients (double, kColorChannels * K) of L~ (reflected = true) or L (reflected = false) of
// vertex v, whatever the field's storage.
void vertexCoefficients(const RadianceField& field, std::size_t v, bool reflected, double* out);

// Converts the whole field to reflected (true) or plain (false) storage; no-op when it already is.
// Parallel over vertices (OpenMP). The coefficients are rounded to float once (PB: exact).
void setReflectedStorage(RadianceField& field, bool reflected);

}  // namespace rad
