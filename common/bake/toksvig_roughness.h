// A glTF metallic-roughness texture from LEAN moments, so that renderers without LEAN mapping
// (Olano and Baker 2010) still widen the highlight where the baked normals vary within a texel's
// footprint, the effect Toksvig 2005 obtains from the shortening of averaged normals.
//
// A Beckmann / GGX lobe of roughness alpha has a slope variance of alpha^2 / 2 per axis; a spread
// of normals with covariance Sigma (slopes in the averaged normal's frame: the LEAN second moments
// about it, lean_maps.h) adds trace(Sigma) / 2 per axis on average, so
//     alpha'^2 = alpha0^2 + trace(Sigma) = alpha0^2 + E[x^2] + E[y^2],
// and with glTF's perceptual roughness r (alpha = r^2, glTF 2.0 appendix B):
//     r' = (r0^4 + E[x^2] + E[y^2])^(1/4), clamped to [0, 1].
// Texture channels (glTF 2.0 sec. 3.9.2): R unused (written as 255), G roughness, B metallic;
// 8 bit, linear.
#pragma once
#include "bake/lean_maps.h"
#include "image/rgb_image.h"

namespace rad {

float toksvigRoughness(float baseRoughness, float momentXX, float momentYY);

// One texel per texel of `moments` (a LEAN level: channels xx, yy, xy). Non-finite or negative
// moments count as zero. Throws std::invalid_argument for a base roughness or metallic value
// outside [0, 1] or an image that does not have 3 channels.
Image8 metallicRoughnessFromLean(const MipImage& moments, float baseRoughness, float metallic);

}  // namespace rad
