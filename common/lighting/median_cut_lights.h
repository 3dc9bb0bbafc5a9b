// Directional lights that stand in for an environment map under diffuse (and moderately glossy)
// reflection, by the median cut of Debevec 2005 ("A Median Cut Algorithm for Light Probe Sampling"):
// the map, weighted by luminance times solid angle, is cut recursively into regions of equal
// weight, and each region becomes one light at its luminance-weighted mean direction whose
// irradiance is the region's radiance integral, so the lights' total equals the map's integral.
// The lights are in the world frame (the map's rotation applied).
// Details: docs/irradiance-vector-grid.md, "`common/lighting/median_cut_lights.h`: how it works".
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
