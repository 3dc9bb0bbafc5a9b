#include "image/rgb_image.h"

#include "radiance/view_colors.h"

#include <array>
#include <cmath>

namespace rad {

namespace {
std::array<float, 256> makeSrgbTable() {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) {
        const double c = i / 255.0;
        t[i] = static_cast<float>(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
    }
    return t;
}
const std::array<float, 256> kSrgbTable = makeSrgbTable();
}  // namespace

float srgbToLinear(std::uint8_t code) { return kSrgbTable[code]; }
const float* srgbToLinearTable() { return kSrgbTable.data(); }

bool sampleBilinearLinear(const ImageView8& image, double u, double v, float out[3]) {
    if (image.empty() || !std::isfinite(u) || !std::isfinite(v)) return false;
    if (u < 0.0 || v < 0.0 || u > image.width || v > image.height) return false;
    // Continuous pixel-centre coordinates, clamped to the centres of the border pixels.
    double x = std::min(std::max(u - 0.5, 0.0), double(image.width - 1));
    double y = std::min(std::max(v - 0.5, 0.0), double(image.height - 1));
    const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
    const int x1 = std::min(x0 + 1, image.width - 1), y1 = std::min(y0 + 1, image.height - 1);
    const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
    const std::uint8_t* p00 = image.pixel(x0, y0);
    const std::uint8_t* p10 = image.pixel(x1, y0);
    const std::uint8_t* p01 = image.pixel(x0, y1);
    const std::uint8_t* p11 = image.pixel(x1, y1);
    const float* lut = kSrgbTable.data();
    for (int c = 0; c < 3; ++c) {
        const int o = image.channelOffset[c];
        const float top = lut[p00[o]] + fx * (lut[p10[o]] - lut[p00[o]]);
        const float bottom = lut[p01[o]] + fx * (lut[p11[o]] - lut[p01[o]]);
        out[c] = top + fy * (bottom - top);
    }
    return true;
}

Image8 encodeToSrgb8(const ImageF& linear, float exposure) {
    Image8 out(linear.width, linear.height);
    for (std::size_t i = 0; i < linear.rgb.size(); ++i) out.rgb[i] = encodeSrgb8(exposure * linear.rgb[i]);
    return out;
}

}  // namespace rad
