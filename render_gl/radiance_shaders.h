// GLSL sources of the radiance decoration (GLSL 1.50, compatibility profile: the vertex position goes
// through MeshLab's fixed-function matrices with ftransform(), which is invariant with the
// fixed-function pipeline that drew the mesh underneath).
//
// Data the shaders read (uploaded once per mesh by radiance_gl_renderer.h):
//  - uFrames  (samplerBuffer, RGB32F or RGBA32F): texel 3v = position p_v, 3v+1 = RF normal n_v,
//    3v+2 = RF tangent t_v (radiance_field.h frames; bitangent b = n x t);
//  - uCoefficients (samplerBuffer): texel v*K + k = (r, g, b) coefficient k of vertex v's REFLECTED
//    RF L~_v (Vanhoey et al. 2015 sec. 3.1; plain storage is converted at upload);
//  - uFaces (usamplerBuffer, R32UI): the three vertex indices of triangle f at 3f .. 3f+2, fetched
//    with gl_PrimitiveID (the triangle's index in the draw call).
//
// evalReflected(v, d) = L~_v(d), border-extended about n_v below its hemisphere (Vanhoey et al. 2015 sec. 7),
// in the basis of the field (radiance/basis.h): PB(d) monomials u^i v^j of the local coordinates
// (t.d, b.d), or real SH in the global frame (radiance/spherical_harmonics.h, no Condon-Shortley
// phase), evaluated with the same recurrences as the CPU code:
//  - per vertex (sec. 5, "Gouraud-like"): colour_v = L_v(w_v) = L~_v(R_{n_v} w_v), w_v = normalize(eye - p_v),
//    interpolated linearly over the triangle;
//  - per fragment, eq. (8): L(p, w) = sum_i alpha_i L~_i(R_n w), n = normalize(sum_i alpha_i n_i),
//    alpha = barycentrics of the fragment's object-space position in its triangle.
// Both end with the same tone mapping as render/tone_mapping.h: 2^stops * L, clamp or Reinhard,
// then the sRGB curve (the framebuffer is plain 8-bit).
#pragma once

#include <string>
#include <vector>

namespace radgl {

enum class GlShading {
    PerVertex,     // RF evaluated toward the eye in the vertex shader, colours interpolated
    PerFragment,   // eq. (8) in the fragment shader
    VertexColors,  // linear colours given per vertex (PRT relighting, CPU fallback), tone-mapped per fragment
};

std::string vertexShaderSource(GlShading shading);
std::string fragmentShaderSource(GlShading shading);

// The tone mapping of render/tone_mapping.h in GLSL, for any fragment shader (no #version line):
// uniforms uExposureScale (2^stops) and uToneCurve (0: clamp, 1: Reinhard), and
// vec3 displayColor(vec3 linear) returning the sRGB-encoded display value.
std::string toneMappingGlsl();

// uShNorm[l*l + l + m]: K_l^0 for m = 0, sqrt(2) K_l^|m| otherwise (spherical_harmonics.h), for
// l <= degree, so that Y_l^m = uShNorm * Q_l^|m|(z) * Re/Im (x + i y)^|m|, Q the associated
// Legendre function divided by sin^|m|.
std::vector<float> shNormalisationConstants(int degree);

}  // namespace radgl
