// Directional lights that stand in for an environment map under diffuse (and moderately glossy)
// reflection, by the median cut of
//   P. Debevec, "A Median Cut Algorithm for Light Probe Sampling", SIGGRAPH 2005 poster / Technical
//   Report ICT-TR-02-2005 (sec. 2, "The Median Cut Algorithm").
//
// The latitude-longitude map (lighting/environment_map.h) is weighted per texel by its luminance
// (Rec. 709: 0.2126 R + 0.7152 G + 0.0722 B) times its exact solid angle -- Debevec's
// "cos(latitude)" scaling of the image. Starting from the whole image as one region, every level
// cuts every region in two along its longer side, at the texel boundary that splits the region's
// weighted luminance most evenly (a summed-area table makes each cut O(log n)). The "length" of
// a side is angular: a region's width counts its columns times their longitude step times
// sin(theta) at the region's middle, its height its rows times the latitude step, so regions near
// the poles are not cut into ever thinner longitude slivers (Debevec sec. 2, step 2).
// After k levels there are up to 2^k regions (a single texel is never cut, so at most
// width * height).
//
// One DirectionalLight per region (radiance/analytic_material.h):
//  - irradiance = the region's radiance integral, sum of texel RGB * solid angle: what the region
//    contributes to the irradiance of a surface facing it when the region is small. The lights'
//    irradiances therefore sum exactly to EnvironmentMap::sphereIntegral() (power is preserved).
//  - direction = the region's luminance-weighted mean direction (the 3D centroid of its texel
//    directions weighted by luminance * solid angle, normalised; Debevec puts the light at the
//    region's energy centroid in the image, the 3D mean is the same for small regions and
//    stays meaningful across the poles); the region's centre direction if that mean vanishes.
//   Both in the world frame: the map's rotation is applied.
// A diffuse surface with normal n then receives sum_i E_i max(0, n.d_i), which approximates the
// map's irradiance integral of L(w) max(0, n.w) dw; the error comes from the regions the horizon
// of n cuts (and from large regions, whose light overstates their cosine-weighted contribution)
// and shrinks as the lights multiply. Measured on the 10 maps of data-cache/hdr
// (tests/unit/median_cut_lights_test.cpp): at most 3.1 % of the brightest normal's irradiance at
// 64 lights, 1.0 % at 256.
// Cost: one summed-area table and one pass over the texels, ~2 ms for 1024 x 512 and 64 lights.
#pragma once

#include "lighting/environment_map.h"
#include "radiance/analytic_material.h"

#include <vector>

namespace rad {

struct MedianCutRegion {
    int column0 = 0, column1 = 0;  // texel columns [column0, column1)
    int row0 = 0, row1 = 0;        // texel rows [row0, row1), from the top
    DirectionalLight light;        // irradiance zero when the region is black
};

// The 2^levels regions (fewer only when regions shrink to single texels), in no particular
// order; 0 <= levels <= 24, std::invalid_argument otherwise; empty for an empty map.
std::vector<MedianCutRegion> medianCutRegions(const EnvironmentMap& map, int levels);

// The lights of medianCutRegions(), black regions left out. Sorted by decreasing luminance of
// their irradiance, so a caller can keep the strongest few.
std::vector<DirectionalLight> medianCutLights(const EnvironmentMap& map, int levels);

// Rec. 709 luminance of linear RGB, the weight of the cut.
inline double luminanceRec709(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

}  // namespace rad
