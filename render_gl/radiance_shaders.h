// GLSL sources of the radiance decoration (GLSL 1.50, compatibility profile; ftransform() keeps the
// positions invariant with the fixed-function pass that drew the mesh underneath). They shade per
// vertex (sec. 5) or per fragment (eq. 8) of Vanhoey et al. 2015 from the frames, REFLECTED RF
// coefficients and triangles that radiance_gl_renderer.h uploads as texture buffers, with the same
// recurrences as the CPU code and the same tone mapping as render/tone_mapping.h.
// Details: docs/decorate-radiance.md, "`render_gl/radiance_shaders.h`: how it works".
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
