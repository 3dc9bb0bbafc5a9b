// Vertex colours from radiance functions: L(p, w) toward a viewpoint (per-vertex evaluation, the
// "Gouraud-like" mode of Vanhoey et al. 2015 sec. 5), and the linear -> 8-bit sRGB encoding used whenever
// linear radiance becomes a displayable colour.
#pragma once

#include "radiance/radiance_field.h"

#include <cstddef>
#include <cstdint>

namespace rad {

// IEC 61966-2-1 sRGB transfer function of a linear value (clamped to [0, 1]) to 0..255, rounded.
std::uint8_t encodeSrgb8(float linear);

// rgbOut[3 v + c] = exposure * L_v(normalize(eye - p_v)) for every vertex (border-extended below
// the horizon, Vanhoey et al. 2015 sec. 7). A vertex at the eye gets its normal direction. Parallel (OpenMP).
// Throws std::invalid_argument (a sentence for the user) for a non-finite eye or an exposure that is
// negative or not finite.
void radianceTowardViewpoint(const RadianceField& field, const float* positions, const double eye[3],
                             float exposure, float* rgbOut);

}  // namespace rad
