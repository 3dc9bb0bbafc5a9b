// GLSL sources of the normal-map renderer (normal_map_gl_renderer.h), GLSL 1.50 compatibility
// profile like radiance_shaders.h: one program whose mode a uniform chooses (NormalMapShading):
// Blinn-Phong with the vertex normals, with the normal map (object space, or tangent space decoded
// in the frame of normal_baker.h), or LEAN (Weber and Stamminger Alg. 3-4, common/bake/lean_maps.h);
// plus, or instead, the indirect light of an irradiance vector grid; then the tone mapping of
// radiance_shaders.h.
// Details: docs/normal-map-baking.md, "`render_gl/normal_map_shaders.h`: how it works".
#pragma once

#include <string>

namespace radgl {

// Indirect light from an irradiance vector grid (Granier et al. 2007, irradiance_grid_shaders.h),
// evaluated at the fragment's object position with the shading normal n (the mapped normal in the
// map modes, so that a simplified mesh with its normal map receives the scan's detail of indirect
// light): None: the direct light above only; Indirect: rho / pi <I_n, n> alone (no ambient, no
// direct light); DirectAndIndirect: the direct light above (no shadows) plus the indirect term.
// rho: the diffuse map when the renderer has one, else the per-vertex albedo when it has vertex
// colours, else the albedo uniform (for the direct light too).
enum class IndirectLight {
    None = 0,
    Indirect = 1,
    DirectAndIndirect = 2,
};

enum class NormalMapShading {
    VertexNormals = 0,
    NormalMap = 1,
    Lean = 2,
};

std::string normalMapVertexShaderSource();
std::string normalMapFragmentShaderSource();

}  // namespace radgl
