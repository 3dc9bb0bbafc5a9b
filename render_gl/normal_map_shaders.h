// GLSL sources of the normal-map renderer (normal_map_gl_renderer.h): GLSL 1.50, compatibility
// profile, like radiance_shaders.h (ftransform(), the built-in vertex attributes gl_Vertex,
// gl_Normal, gl_MultiTexCoord0).
//
// One program, the mode chosen by a uniform (NormalMapShading):
//  - VertexNormals: Blinn-Phong with the interpolated vertex normal;
//  - NormalMap: Blinn-Phong with the normal map, trilinear (textureLod at lambda, below), renormalised;
//    a tangent-space map is decoded as n = t.x T + t.y B + t.z N in the frame of normal_baker.h:
//    MikkTSpace (Mikkelsen 2008: T and the sign s are per-corner attributes, gl_MultiTexCoord1,
//    interpolated with N, B = s N x T, none renormalised) or the per-face frame (N the
//    interpolated vertex normal, T = dP/du made orthogonal to N, B = s N x T, s = the sign of
//    (dP/du x dP/dv) . N);
//  - Lean: Weber and Stamminger Alg. 3-4 (common/bake/lean_maps.h): N = the trilinear averaged normal,
//    mu2 = textureLod(moments, uv, max(lambda - 1, 0)), times clamp(lambda, 0, 1) below
//    lambda = 1; frame T = dP/du orthogonalised against N, B = N x T; the 2D Gaussian of leanSpecular.
// lambda = log2 of the larger screen-space footprint of a level-0 texel,
//   max(|d(uv * size)/dx|, |d(uv * size)/dy|), computed in the shader (the normal map is read with
//   the same lambda in both map modes, so that they agree exactly when the covariance is 0).
// dP/du, dP/dv come from the screen-space derivatives of the object position and of uv.
// Lighting (object space): linear = ambient * albedo + light * (albedo * max(n.L, 0) + specular * spec),
// spec = 0 where n.L <= 0, albedo = rho below; plus or instead the indirect light of an irradiance
// vector grid (IndirectLight); then displayColor() of radiance_shaders.h (toneMappingGlsl()).
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
