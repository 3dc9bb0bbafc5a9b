// Real spherical harmonics Y_l^m in the global frame, orthonormal on the unit sphere
// (integral of Y_l^m Y_l'^m' over the sphere = delta). Index l*l + l + m (basis.h harmonicIndex).
//
// Convention (fixed: stored coefficients depend on it).
// With (x, y, z) = (sin t cos p, sin t sin p, cos t), K_l^m = sqrt((2l+1)/(4 pi) (l-|m|)!/(l+|m|)!)
// and P_l^m the associated Legendre function WITHOUT the Condon-Shortley phase (-1)^m,
// i.e. P_l^m(cos t) = (1 - z^2)^(m/2) d^m/dz^m P_l(z), so P_1^1 = +sin t:
//     Y_l^0  = K_l^0 P_l^0(z)
//     Y_l^m  = sqrt(2) K_l^m P_l^m(z) cos(m p)     m > 0
//     Y_l^-m = sqrt(2) K_l^m P_l^m(z) sin(m p)     m > 0
// Hence every band-1 constant is positive:
//     Y_0^0 = 0.2820947917738781,  Y_1^-1 = 0.4886025119029199 y,
//     Y_1^0 = 0.4886025119029199 z, Y_1^1 = 0.4886025119029199 x,
//     Y_2^-2 = 1.0925484305920792 x y, Y_2^1 = 1.0925484305920792 x z, ...
// Note: the code of P.-P. Sloan, "Stupid Spherical Harmonics (SH) Tricks" (GDC 2008) and many
// graphics and physics codes (and std::sph_legendre) INCLUDE the Condon-Shortley phase (their
// Y_1^1 = -0.4886 x, Y_1^-1 = -0.4886 y); their coefficients convert to ours by multiplying the
// coefficient of Y_l^m by (-1)^m. Magnitudes and the m ordering are the same. We leave the phase
// out so that the band-1 functions are exactly (y, z, x) times one positive constant, which makes
// the band-1 rotation block a permutation of R (sh_rotation.h).
//
// Evaluation: no trigonometric call, no pow, no allocation. cos(m p) sin^m t and sin(m p) sin^m t are
// the real and imaginary parts of (x + i y)^m, obtained by complex multiplication; the z part is the
// normalised associated Legendre three-term recurrence in l at fixed m, whose coefficients are
// tabulated once. This recurrence is the numerically stable direction (forward in l), see
// W. H. Press et al., Numerical Recipes 3rd ed., sec. 6.7.
#pragma once

namespace rad {

// out[0 .. (degree+1)^2) = Y_l^m(x, y, z) for the unit direction (x, y, z),
// 0 <= degree <= kMaxHarmonicDegree (throws std::out_of_range otherwise).
// The direction is not normalised here (callers pass unit vectors; normalising would cost a sqrt
// per call); for a non-unit vector the values are not those of Y at the normalised direction.
void evaluateSphericalHarmonics(int degree, double x, double y, double z, double* out);
void evaluateSphericalHarmonics(int degree, float x, float y, float z, float* out);

}  // namespace rad
