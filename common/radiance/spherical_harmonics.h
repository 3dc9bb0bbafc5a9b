// Real spherical harmonics Y_l^m in the global frame, orthonormal on the unit sphere, index
// l*l + l + m (basis.h harmonicIndex). Convention, fixed because stored coefficients depend on it:
// WITHOUT the Condon-Shortley phase (-1)^m, so every band-1 constant is positive
// (Y_1^-1, Y_1^0, Y_1^1 = 0.4886 (y, z, x)); coefficients of codes that include the phase (Sloan's
// "Stupid SH Tricks", std::sph_legendre) convert to ours by (-1)^m. Evaluated by recurrences: no
// trigonometric call, no pow, no allocation.
// Details: docs/architecture.md, "`common/radiance/spherical_harmonics.h`: how it works".
#pragma once

namespace rad {

// out[0 .. (degree+1)^2) = Y_l^m(x, y, z) for the unit direction (x, y, z),
// 0 <= degree <= kMaxHarmonicDegree (throws std::out_of_range otherwise).
// The direction is not normalised here (callers pass unit vectors; normalising would cost a sqrt
// per call); for a non-unit vector the values are not those of Y at the normalised direction.
void evaluateSphericalHarmonics(int degree, double x, double y, double z, double* out);
void evaluateSphericalHarmonics(int degree, float x, float y, float z, float* out);

}  // namespace rad
