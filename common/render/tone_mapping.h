// From linear radiance to the 8-bit sRGB codes a display (and a screenshot) holds: the tone mapping
// of the "Radiance Field" decoration (docs/decorate-radiance.md, parameters RadianceExposure and
// RadianceToneMap), on the CPU so that a reference rendering (render/radiance_renderer.h) can be
// compared with a screenshot of MeshLab code for code.
//
// Per channel, for a linear value L:
//   1. exposure:  x = 2^stops * L                                   (stops = RadianceExposure)
//   2. curve:     Clamp:    d = min(max(x, 0), 1)
//                 Reinhard: d = max(x, 0) / (1 + max(x, 0))         (E. Reinhard et al., "Photographic
//                           tone reproduction for digital images", SIGGRAPH 2002, eq. 3, applied per
//                           channel rather than to luminance: the decoration's fragment shader does so)
//      NaN becomes 0 here, so that one broken value cannot poison a comparison (GLSL leaves
//      max(NaN, 0) undefined: do not compare pixels whose RF is not finite).
//   3. encoding:  the IEC 61966-2-1 sRGB curve: 12.92 d for d <= 0.0031308, else 1.055 d^(1/2.4) - 0.055,
//      then round(255 * code) into the framebuffer's 8 bits.
// The decoration's GLSL (function displayColor, render_gl/radiance_shaders.cpp) implements exactly
// these formulas in float; the framebuffer's conversion of [0, 1] to 8 bits is the same rounding
// (GL spec, "conversion to fixed point": round(255 f)). The two may differ by one code where float
// and double straddle a rounding boundary.
#pragma once

#include "image/rgb_image.h"

#include <Eigen/Core>

#include <cstdint>

namespace rad {

enum class ToneCurve {
    Clamp,     // RadianceToneMap 0
    Reinhard,  // RadianceToneMap 1
};

struct ToneMapping {
    double exposureStops = 0.0;  // displayed = curve(2^stops * L)
    ToneCurve curve = ToneCurve::Clamp;
};

// Steps 1 and 2: display-linear values in [0, 1] (negatives and NaN -> 0).
Eigen::Vector3d toneMap(const ToneMapping& mapping, const Eigen::Vector3d& linear);

// Step 3 without the quantisation: the sRGB-encoded value of a display-linear value in [0, 1]
// (not clamped here: the curve itself, extended as 12.92 d below 0).
double srgbEncode(double displayLinear);

// round(255 * srgbEncode(d)) with d clamped to [0, 1] first (NaN -> 0).
std::uint8_t toSrgb8(double displayLinear);

// The whole chain on every pixel of a linear image.
Image8 toneMapToSrgb8(const ImageF& linear, const ToneMapping& mapping);

}  // namespace rad
