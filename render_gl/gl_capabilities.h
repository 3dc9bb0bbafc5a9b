// What the current OpenGL context can do for the radiance decoration, asked once when the decoration
// starts (MeshLab's context is current in startDecorate).
//
// The shaded modes (per-vertex evaluation on the GPU and per-fragment eq. 8) need:
//  - OpenGL 3.2 and GLSL 1.50: texture buffer objects (samplerBuffer, texelFetch: GL 3.1) and
//    gl_PrimitiveID in the fragment shader (GLSL 1.50), in a compatibility profile (MeshLab 2020.09
//    sets its matrices with the fixed-function stack; the shaders read them as built-ins);
//  - the RF coefficients fitting in one texture buffer (GL_MAX_TEXTURE_BUFFER_SIZE texels).
// RGB32F texture buffers (GL 4.0 or ARB_texture_buffer_object_rgb32) save a quarter of the memory;
// without them the coefficients are padded to RGBA32F.
// Anything missing: the decoration falls back to per-vertex colours computed on the CPU and drawn
// with the fixed-function pipeline (works on any GL with vertex buffer objects, 1.5).
#pragma once

#include <string>

namespace radgl {

struct GlCapabilities {
    int glMajor = 0, glMinor = 0;
    int glslMajor = 0, glslMinor = 0;
    bool compatibilityProfile = true;   // false for a core-profile context (no built-in matrices)
    bool rgb32TextureBuffer = false;
    long long maxTextureBufferTexels = 0;
    // The irradiance vector grid (irradiance_grid_textures.h): 3D textures per axis and the
    // fragment shader's texture units (the grid's 12 plus the normal map's 2).
    int max3dTextureSize = 0;
    int maxFragmentTextureUnits = 0;
    std::string vendor, renderer, version;

    // GL >= 3.2, GLSL >= 1.50, compatibility profile.
    bool supportsShaders() const;
    // Empty when supportsShaders(); otherwise what is missing, for MeshLab's log.
    std::string missingForShaders() const;
    // "OpenGL 4.5 (Mesa ...), GLSL 4.50, llvmpipe"
    std::string describe() const;
};

// Queries the current context (GLEW must be initialised). Never throws.
GlCapabilities queryGlCapabilities();

// Pretends the context offers at most OpenGL major.minor (tests of the fallback, and the
// RADIANCE_DECORATE_MAX_GL environment variable of the plugin): lowers the reported GL and GLSL
// versions and drops the features the lower version lacks.
void capGlVersion(GlCapabilities& caps, int major, int minor);

// capGlVersion with the "major.minor" of the environment variable RADIANCE_DECORATE_MAX_GL when it is
// set (the decorations' way to show their fallbacks in the GUI); otherwise nothing.
void capGlVersionFromEnvironment(GlCapabilities& caps);

}  // namespace radgl
