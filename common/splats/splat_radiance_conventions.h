// From the conventions of a 3D Gaussian Splatting scene (Kerbl et al. 2023, as its reference code
// writes `point_cloud.ply`) to ours (radiance/spherical_harmonics.h, radiance/view_colors.h).
//
// A splat's colour seen from a camera at c is, in the reference rasteriser,
//     colour(d) = max(0, sum_k g_k Y3dgs_k(d) + 0.5),   d = normalize(mu - c)  (camera -> splat)
// where Y3dgs are real SH WITH the Condon-Shortley phase (its Y_0^0 = 0.28209479 = SH_C0, its
// Y_1^-1 = -0.48860251 y, Y_1^0 = +0.48860251 z, Y_1^1 = -0.48860251 x, ...), and the colour is
// display-referred: the training compared it with the photographs' 8-bit sRGB values divided by 255.
//
// Ours: L(w) = sum_k a_k Y_k(w), w = normalize(c - mu) (surface -> viewer), Y without that phase,
// L linear radiance. Hence, with w = -d:
//   - direction flip:  Y_l^m(-w) = (-1)^l Y_l^m(w);
//   - phase:           Y3dgs_l^m = (-1)^m Y_l^m;
//   so the display-referred colour minus 0.5 is, as a function of our w, the SH with coefficients
//       a_lm = (-1)^(l+m) g_lm                           (exact; see toViewerShCoefficients);
//   - colour space:    linear = sRGB decoding (IEC 61966-2-1) of the display colour clamped to [0, 1]
//     (the rasteriser clamps each splat at 0; the images it was trained on, and those it renders to,
//     end at 1). The decoding is not linear: it is applied to colours, never to coefficients
//     (splat_radiance_transfer.h projects the decoded colours onto our basis).
// A splat's opacity is sigmoid(opacity), its covariance R S S^T R^T with S = diag(exp(scale_i)) and R
// the rotation of the normalised quaternion (rot_0 = w, rot_1..3 = x, y, z).
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
