// From the conventions of a 3D Gaussian Splatting scene (Kerbl et al. 2023, as its reference code
// writes `point_cloud.ply`) to ours (radiance/spherical_harmonics.h, radiance/view_colors.h). Its
// colour is max(0, SH + 0.5), display-referred, with real SH WITH the Condon-Shortley phase evaluated
// at the direction camera -> splat; ours are linear radiance, without the phase, at the direction
// surface -> viewer. Hence coefficients convert exactly by (-1)^(l+m), and the colour by sRGB
// decoding, applied to colours, never to coefficients.
// Details: docs/gaussian-splats.md, "Conventions, from the splats' to ours".
#pragma once

#include <Eigen/Core>

namespace rad {

// Y_0^0 of both conventions: a colour c with no view dependence is the DC coefficient (c - 0.5) / SH_C0.
inline constexpr double kSplatShC0 = 0.28209479177387814;
// The offset the reference rasteriser adds to the SH sum before clamping at 0.
inline constexpr double kSplatColorOffset = 0.5;

// (-1)^(l+m) for the SH index l*l + l + m: the factor from a 3DGS coefficient to ours (see above).
inline double splatToViewerShSign(int index) {
    int l = 0;
    while ((l + 1) * (l + 1) <= index) ++l;
    const int m = index - l * l - l;
    return ((l + m) % 2 == 0) ? 1.0 : -1.0;
}

// Our coefficients (count (degree+1)^2) of  w -> [3DGS SH sum](-w)  from one channel's 3DGS coefficients.
void toViewerShCoefficients(int degree, const float* splatChannel, double* out);

// IEC 61966-2-1 sRGB decoding of a display-referred colour value, clamped to [0, 1] first.
double displayToLinear(double display);

// sigmoid(logit).
double splatOpacity(double logit);

// Covariance R S S^T R^T of a splat from its stored log-scales (3) and quaternion (4, w first,
// normalised here). Scales are exponentiated in double: a stored log-scale above ~700 gives infinity,
// which the caller must treat as a splat of unbounded extent.
Eigen::Matrix3d splatCovariance(const float* logScale, const float* quaternion);

}  // namespace rad
