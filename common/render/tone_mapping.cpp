#include "render/tone_mapping.h"

#include <algorithm>
#include <cmath>

namespace rad {

Eigen::Vector3d toneMap(const ToneMapping& mapping, const Eigen::Vector3d& linear) {
    const double scale = std::exp2(mapping.exposureStops);
    Eigen::Vector3d out;
    for (int c = 0; c < 3; ++c) {
        double x = scale * linear[c];
        if (!(x > 0.0)) x = 0.0;  // negatives and NaN
        out[c] = mapping.curve == ToneCurve::Reinhard ? (std::isinf(x) ? 1.0 : x / (1.0 + x)) : std::min(x, 1.0);
    }
    return out;
}

double srgbEncode(double d) {
    return d <= 0.0031308 ? 12.92 * d : 1.055 * std::pow(d, 1.0 / 2.4) - 0.055;
}

std::uint8_t toSrgb8(double d) {
    if (!(d > 0.0)) d = 0.0;
    if (d > 1.0) d = 1.0;
    return static_cast<std::uint8_t>(std::lround(255.0 * srgbEncode(d)));
}

Image8 toneMapToSrgb8(const ImageF& linear, const ToneMapping& mapping) {
    Image8 out(linear.width, linear.height);
    const std::size_t n = static_cast<std::size_t>(linear.width) * linear.height;
    for (std::size_t i = 0; i < n; ++i) {
        const Eigen::Vector3d d =
            toneMap(mapping, Eigen::Vector3d(linear.rgb[3 * i], linear.rgb[3 * i + 1], linear.rgb[3 * i + 2]));
        for (int c = 0; c < 3; ++c) out.rgb[3 * i + c] = toSrgb8(d[c]);
    }
    return out;
}

}  // namespace rad
