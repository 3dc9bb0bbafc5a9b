// PLACEHOLDER (replaced by the helper's version)
#pragma once
#include "image/rgb_image.h"
#include <Eigen/Core>
#include <cstdint>
namespace rad {
enum class ToneCurve { Clamp, Reinhard };
struct ToneMapping { double exposureStops = 0; ToneCurve curve = ToneCurve::Clamp; };
Eigen::Vector3d toneMap(const ToneMapping&, const Eigen::Vector3d& linear);
double srgbEncode(double displayLinear);
std::uint8_t toSrgb8(double displayLinear);
Image8 toneMapToSrgb8(const ImageF& linear, const ToneMapping&);
}
