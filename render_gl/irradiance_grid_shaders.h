// GLSL of the irradiance vector grid (Granier et al. 2007, "Hardware Implementation"): the function
// ivgReflected(p, n, rho) that the normal-map renderer's fragment shader calls, evaluating per
// fragment what common/lighting/irradiance_vector_grid.h's reflectedRadianceCompressed() computes on
// the CPU, from the twelve RGB16F 3D textures of irradiance_grid_textures.h (a colour and a
// direction texture per main direction, hardware trilinear filtering). GLSL 1.50.
// Details: docs/irradiance-vector-grid.md, "`render_gl/irradiance_grid_shaders.h`: how it works".
#pragma once

#include <string>

namespace radgl {

std::string irradianceGridGlsl();

// Sampler uniform names, in the order of IrradianceVectorGrid's directions.
const char* irradianceGridColourSampler(int direction);
const char* irradianceGridDirectionSampler(int direction);

}  // namespace radgl
