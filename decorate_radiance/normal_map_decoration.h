// The "Baked Normal Map" decoration: draws a layer with the normal map of the "Bake Normal Map"
// filter, with Blinn-Phong or with the LEAN Gaussian lobe (Weber and Stamminger, Alg. 3-4;
// render_gl/normal_map_gl_renderer.h), so that the highlight's behaviour at a distance can be
// compared (docs/normal-map-baking.md), optionally as a POP buffer level of detail (Limper et al. 2013).
#pragma once

#include "decoration.h"

#include <memory>

namespace raddecorate {

std::unique_ptr<Decoration> makeNormalMapDecoration();

}  // namespace raddecorate
