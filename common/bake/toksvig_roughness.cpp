#include "bake/toksvig_roughness.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rad {

float toksvigRoughness(float baseRoughness, float momentXX, float momentYY) {
    const auto usable = [](float m) { return std::isfinite(m) && m > 0.0f ? m : 0.0f; };
    const double r0 = std::clamp(double(baseRoughness), 0.0, 1.0);
    // alpha'^2 = alpha0^2 + trace(Sigma), alpha = r^2 (toksvig_roughness.h).
    const double alphaSquared = r0 * r0 * r0 * r0 + double(usable(momentXX)) + double(usable(momentYY));
    return float(std::min(1.0, std::pow(alphaSquared, 0.25)));
}

Image8 metallicRoughnessFromLean(const MipImage& moments, float baseRoughness, float metallic) {
    if (!(baseRoughness >= 0.0f && baseRoughness <= 1.0f) || !(metallic >= 0.0f && metallic <= 1.0f))
        throw std::invalid_argument("The base roughness and the metallic value must lie in [0, 1] (glTF's range).");
    if (moments.channels != 3 || moments.data.size() != std::size_t(moments.width) * moments.height * 3)
        throw std::invalid_argument("LEAN moments need 3 channels (xx, yy, xy) per texel.");
    Image8 image(moments.width, moments.height);
    const std::uint8_t metal = static_cast<std::uint8_t>(std::lround(metallic * 255.0f));
    const std::size_t texels = std::size_t(moments.width) * moments.height;
    for (std::size_t t = 0; t < texels; ++t) {
        const float r = toksvigRoughness(baseRoughness, moments.data[3 * t], moments.data[3 * t + 1]);
        image.rgb[3 * t] = 255;
        image.rgb[3 * t + 1] = static_cast<std::uint8_t>(std::lround(r * 255.0f));
        image.rgb[3 * t + 2] = metal;
    }
    return image;
}

}  // namespace rad
