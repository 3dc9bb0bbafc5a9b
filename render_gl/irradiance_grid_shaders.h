// GLSL of the irradiance vector grid (Granier et al. 2007, "Hardware Implementation"): the function
// ivgReflected(p, n, rho) that the normal-map renderer's fragment shader calls, evaluating per
// fragment what common/lighting/irradiance_vector_grid.h's reflectedRadianceCompressed() computes
// on the CPU:
//   - the textures (irradiance_grid_textures.h): per direction delta (+x, -x, +y, -y, +z, -z) a
//     colour texture (|I_R|, |I_G|, |I_B|) and a direction texture (normalise(I_R + I_G + I_B)),
//     RGB16F, one texel per grid vertex, trilinear (GL_LINEAR), clamped to the edge;
//   - the texture coordinate of object point p: ((p - origin) / cellSize + 0.5) / vertexCounts, so
//     that texel centres are the grid vertices, hardware trilinear filtering is the paper's spatial
//     interpolation, and a point outside the box takes the value at the nearest point of the box
//     (clamp to edge), as the CPU does;
//   - per axis a, the +a or -a textures by the sign of n_a (n_a = 0 counts as +, as on the CPU),
//     I_c += n_a^2 colour_c * direction (colour and direction filtered separately, direction not
//     renormalised: the CPU form);
//   - L = rho / pi <I_c, n> per channel, never negative.
// Samplers uIvgColor0..5 and uIvgDirection0..5 (index = direction), uniforms uIvgOrigin,
// uIvgCellSize, uIvgVertexCounts. GLSL 1.50 (sampler arrays could only be indexed by constants, hence
// twelve names and a branch per axis; textureLod level 0, the textures have no mipmaps).
#pragma once

#include <string>

namespace radgl {

std::string irradianceGridGlsl();

// Sampler uniform names, in the order of IrradianceVectorGrid's directions.
const char* irradianceGridColourSampler(int direction);
const char* irradianceGridDirectionSampler(int direction);

}  // namespace radgl
