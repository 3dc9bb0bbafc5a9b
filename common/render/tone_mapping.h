// From linear radiance to the 8-bit sRGB codes a display (and a screenshot) holds: the tone mapping
// of the "Radiance Field" decoration (parameters RadianceExposure and RadianceToneMap), on the CPU so
// that a reference rendering can be compared with a screenshot of MeshLab code for code. Per channel:
//   1. exposure: x = 2^stops * L;
//   2. curve: Clamp, min(max(x, 0), 1), or Reinhard, max(x, 0) / (1 + max(x, 0)) (Reinhard et al.
//      2002, per channel as the shader does); NaN becomes 0;
//   3. encoding: the IEC 61966-2-1 sRGB curve, then round(255 * code).
// The decoration's GLSL implements the same formulas in float: the two may differ by one code.
// Details: docs/decorate-radiance.md, "`common/render/tone_mapping.h`: how it works".
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
