#include "render/tone_mapping.h"
#include <algorithm>
#include <cmath>
namespace rad {
Eigen::Vector3d toneMap(const ToneMapping& t, const Eigen::Vector3d& L) {
    Eigen::Vector3d v;
    const double s = std::exp2(t.exposureStops);
    for (int c = 0; c < 3; ++c) {
        double x = L[c] * s;
        if (!(x > 0)) x = 0;
        v[c] = t.curve == ToneCurve::Reinhard ? x / (1 + x) : std::min(x, 1.0);
    }
    return v;
}
double srgbEncode(double v) { return v < 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055; }
std::uint8_t toSrgb8(double v) { v = std::clamp(v, 0.0, 1.0); return static_cast<std::uint8_t>(std::lround(255 * srgbEncode(v))); }
Image8 toneMapToSrgb8(const ImageF& linear, const ToneMapping& t) {
    Image8 out(linear.width, linear.height);
    for (int y = 0; y < linear.height; ++y)
        for (int x = 0; x < linear.width; ++x) {
            const float* p = linear.pixel(x, y);
            const Eigen::Vector3d d = toneMap(t, Eigen::Vector3d(p[0], p[1], p[2]));
            std::uint8_t* q = out.pixel(x, y);
            for (int c = 0; c < 3; ++c) q[c] = toSrgb8(d[c]);
        }
    return out;
}
}
