#include "gl_capabilities.h"

#include <GL/glew.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>

namespace radgl {
namespace {
std::string glString(GLenum name) {
    const GLubyte* s = glGetString(name);
    return s ? reinterpret_cast<const char*>(s) : std::string();
}

bool atLeast(int major, int minor, int wantMajor, int wantMinor) {
    return major > wantMajor || (major == wantMajor && minor >= wantMinor);
}

bool hasExtension(const char* name) {
    GLint count = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &count);
    for (GLint i = 0; i < count; ++i) {
        const GLubyte* e = glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i));
        if (e && std::strcmp(reinterpret_cast<const char*>(e), name) == 0) return true;
    }
    return false;
}
}  // namespace

bool GlCapabilities::supportsShaders() const { return missingForShaders().empty(); }

std::string GlCapabilities::missingForShaders() const {
    std::ostringstream why;
    if (!atLeast(glMajor, glMinor, 3, 2))
        why << "OpenGL " << glMajor << "." << glMinor << " < 3.2 (texture buffers and gl_PrimitiveID)";
    if (!atLeast(glslMajor, glslMinor, 1, 50)) {
        if (why.tellp() > 0) why << "; ";
        why << "GLSL " << glslMajor << "." << glslMinor << " < 1.50";
    }
    if (!compatibilityProfile) {
        if (why.tellp() > 0) why << "; ";
        why << "core-profile context (MeshLab's fixed-function matrices are not visible to shaders)";
    }
    return why.str();
}

std::string GlCapabilities::describe() const {
    std::ostringstream s;
    s << "OpenGL " << glMajor << "." << glMinor << " (" << version << "), GLSL " << glslMajor << "."
      << (glslMinor < 10 ? "0" : "") << glslMinor << ", " << renderer;
    return s.str();
}

GlCapabilities queryGlCapabilities() {
    GlCapabilities caps;
    caps.vendor = glString(GL_VENDOR);
    caps.renderer = glString(GL_RENDERER);
    caps.version = glString(GL_VERSION);
    if (std::sscanf(caps.version.c_str(), "%d.%d", &caps.glMajor, &caps.glMinor) != 2) caps.glMajor = caps.glMinor = 0;
    const std::string glsl = glString(GL_SHADING_LANGUAGE_VERSION);
    if (std::sscanf(glsl.c_str(), "%d.%d", &caps.glslMajor, &caps.glslMinor) != 2) caps.glslMajor = caps.glslMinor = 0;
    // "4.50 ..." and "1.50 ..." parse as (4, 50) and (1, 50): minor is in hundredths, as in #version 450.
    if (atLeast(caps.glMajor, caps.glMinor, 3, 2)) {
        GLint mask = 0;
        glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &mask);
        caps.compatibilityProfile = (mask & GL_CONTEXT_CORE_PROFILE_BIT) == 0 || (mask & GL_CONTEXT_COMPATIBILITY_PROFILE_BIT);
    }
    if (atLeast(caps.glMajor, caps.glMinor, 3, 1)) {
        GLint texels = 0;
        glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &texels);
        caps.maxTextureBufferTexels = texels;
        caps.rgb32TextureBuffer =
            atLeast(caps.glMajor, caps.glMinor, 4, 0) || hasExtension("GL_ARB_texture_buffer_object_rgb32");
    }
    {
        GLint size = 0, units = 0;
        glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &size);
        glGetIntegerv(GL_MAX_TEXTURE_IMAGE_UNITS, &units);
        caps.max3dTextureSize = size;
        caps.maxFragmentTextureUnits = units;
    }
    while (glGetError() != GL_NO_ERROR) {
    }
    return caps;
}

void capGlVersion(GlCapabilities& caps, int major, int minor) {
    if (atLeast(major, minor, caps.glMajor, caps.glMinor)) return;
    caps.glMajor = major;
    caps.glMinor = minor;
    // GLSL versions by GL version (GL 2.0: 1.10, 2.1: 1.20, 3.0: 1.30, 3.1: 1.40, 3.2: 1.50, 3.3+: same).
    if (atLeast(major, minor, 3, 3)) {
        caps.glslMajor = major;
        caps.glslMinor = minor * 10;
    } else if (major == 3) {
        caps.glslMajor = 1;
        caps.glslMinor = 30 + 10 * minor;
    } else if (major == 2) {
        caps.glslMajor = 1;
        caps.glslMinor = 10 + 10 * minor;
    } else {
        caps.glslMajor = caps.glslMinor = 0;
    }
    if (!atLeast(major, minor, 4, 0)) caps.rgb32TextureBuffer = false;
    if (!atLeast(major, minor, 3, 1)) caps.maxTextureBufferTexels = 0;
}

void capGlVersionFromEnvironment(GlCapabilities& caps) {
    const char* cap = std::getenv("RADIANCE_DECORATE_MAX_GL");
    int major = 0, minor = 0;
    if (cap && std::sscanf(cap, "%d.%d", &major, &minor) == 2) capGlVersion(caps, major, minor);
}

}  // namespace radgl
