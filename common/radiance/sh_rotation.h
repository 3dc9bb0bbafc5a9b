// Rotation of real spherical-harmonic expansions (spherical_harmonics.h convention). For a 3x3
// rotation R, ShRotation(degree, R).apply(c, c') gives the coefficients of g(w) = f(R^T w): f ROTATED
// BY R (what f shows in direction d, g shows in direction R d); ShRotation(R1 * R2) =
// ShRotation(R1) o ShRotation(R2). Block diagonal, one orthogonal block per band, built by the
// recurrences of Ivanic and Ruedenberg 1996 (with their 1998 corrections): no trigonometry, no
// allocation. Mirror reflections (det = -1) are accepted too.
// Details: docs/architecture.md, "`common/radiance/sh_rotation.h`: how it works".
#pragma once

#include "radiance/basis.h"

#include <Eigen/Core>

#include <array>

namespace rad {

namespace detail {
// Start of band l in the block storage: sum_{k<l} (2k+1)^2 = l (2l-1)(2l+1) / 3.
constexpr int shRotationBlockOffset(int l) { return l * (2 * l - 1) * (2 * l + 1) / 3; }
}  // namespace detail

class ShRotation {
public:
    // Identity rotation of the given degree.
    explicit ShRotation(int degree = 0);
    // R must be orthogonal (a rotation, or a rotation times -1); 0 <= degree <= kMaxHarmonicDegree
    // (std::out_of_range otherwise). R is not re-orthogonalised: pass an orthonormal matrix.
    ShRotation(int degree, const Eigen::Matrix3d& R);

    int degree() const { return degree_; }
    int coefficientCount() const { return (degree_ + 1) * (degree_ + 1); }

    // out[0 .. (degree+1)^2) = D in[0 .. (degree+1)^2). in == out is allowed (band by band through a
    // small stack buffer). Apply once per colour channel. The float overload accumulates in double.
    void apply(const double* in, double* out) const;
    void apply(const float* in, float* out) const;

    // D^l_{m, m'}: the coefficient of input Y_l^m' in output Y_l^m, |m|, |m'| <= l <= degree.
    double element(int l, int m, int mPrime) const { return blocks_[offset(l) + (m + l) * (2 * l + 1) + (mPrime + l)]; }
    // Row-major (2l+1) x (2l+1) block of band l.
    const double* block(int l) const { return blocks_.data() + offset(l); }

private:
    static constexpr int offset(int l) { return detail::shRotationBlockOffset(l); }
    static constexpr int kStorage = detail::shRotationBlockOffset(kMaxHarmonicDegree + 1);

    int degree_ = 0;
    // Fixed storage (about 14 KB at degree 10) so that building one per vertex in a parallel loop
    // does not touch the heap.
    std::array<double, kStorage> blocks_;  // bands 0..degree_ set; the rest unused

    template <typename Real>
    void applyImpl(const Real* in, Real* out) const;
};

// The reflection about the axis n of Vanhoey et al. 2015 sec. 3.1: w -> 2 (n.w) n - w, i.e. the matrix
// 2 n n^T - I. It is the rotation by pi about n (det +1), its own inverse and symmetric, so
// "rotate f by it" and "by its transpose" coincide. n is normalised here.
Eigen::Matrix3d reflectionAbout(const Eigen::Vector3d& n);

// SH operator of that reflection: c' of g(w) = f(2 (n.w) n - w). It maps n to n and every vector
// t orthogonal to n to -t.
ShRotation reflectionAboutAxisSH(const Eigen::Vector3d& n, int degree = kMaxHarmonicDegree);

}  // namespace rad
