// The "Irradiance Vector Grid" decoration: the layer lit by the indirect light of an irradiance
// vector grid (Granier et al. 2007), evaluated per fragment on the GPU (render_gl/irradiance_grid_*:
// the paper's 12 16-bit 3D textures, trilinear, squared-normal weights, L = rho / pi <I_n, n>), alone
// or added to one directional light that follows the camera (Lambert, no shadows). The grid is the
// layer's file with the extension .ivg (as the grid computation writes it) or a file named in the
// options; rho is the diffuse map of the layer's normal-map bake (B_diffuse.png) when there is one,
// else the layer's vertex colour (sRGB decoded) when it has colours, else the albedo option; when
// the layer carries a normal map baked by 'Bake Normal Map', the grid is evaluated with the mapped
// normal (the paper's simplified mesh + normal map + grid). A thin adapter: parameters,
// files, log; the drawing is render_gl/normal_map_gl_renderer.h.
#pragma once

#include "decoration.h"

#include <memory>

namespace raddecorate {

std::unique_ptr<Decoration> makeIrradianceGridDecoration();

}  // namespace raddecorate
