// Real spherical harmonics Y_l^m in the global frame, orthonormal on the unit sphere
// (integral of Y_l^m Y_l'^m' over the sphere = delta). Index l*l + l + m (basis.h harmonicIndex).
#pragma once

namespace rad {

// out[0 .. (degree+1)^2) = Y_l^m(x, y, z) for the unit direction (x, y, z), 0 <= degree <= kMaxHarmonicDegree.
void evaluateSphericalHarmonics(int degree, double x, double y, double z, double* out);
void evaluateSphericalHarmonics(int degree, float x, float y, float z, float* out);

}  // namespace rad
