#include "gl_helpers.h"

#include <cstdio>

#include <GL/glew.h>

namespace radgl {
namespace {

const char* glErrorName(GLenum e) {
    switch (e) {
        case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
        case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
        case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
        case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
        case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
        case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
        case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
        default: return "unknown";
    }
}

unsigned compileShader(GLenum type, const std::string& source, const std::string& label, std::string& log) {
    const GLuint shader = glCreateShader(type);
    const char* text = source.c_str();
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        GLint length = 0;
        glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
        std::string info(static_cast<std::size_t>(length > 0 ? length : 1), '\0');
        glGetShaderInfoLog(shader, length, nullptr, &info[0]);
        log += label + (type == GL_VERTEX_SHADER ? " vertex shader: " : " fragment shader: ") + info;
        glDeleteShader(shader);
        return 0;
    }
    return shader;
}

}  // namespace

unsigned buildGlProgram(const std::string& vertexSource, const std::string& fragmentSource, const std::string& label,
                        std::string& log, const std::function<void(unsigned)>& beforeLink) {
    const unsigned vs = compileShader(GL_VERTEX_SHADER, vertexSource, label, log);
    const unsigned fs = compileShader(GL_FRAGMENT_SHADER, fragmentSource, label, log);
    if (!vs || !fs) {
        if (vs) glDeleteShader(vs);
        if (fs) glDeleteShader(fs);
        return 0;
    }
    const GLuint program = glCreateProgram();
    glAttachShader(program, vs);
    glAttachShader(program, fs);
    if (beforeLink) beforeLink(program);
    glLinkProgram(program);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = GL_FALSE;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint length = 0;
        glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
        std::string info(static_cast<std::size_t>(length > 0 ? length : 1), '\0');
        glGetProgramInfoLog(program, length, nullptr, &info[0]);
        log += label + " link: " + info;
        glDeleteProgram(program);
        return 0;
    }
    return program;
}

void appendGlErrors(std::string& errors, const char* where) {
    for (GLenum e = glGetError(); e != GL_NO_ERROR; e = glGetError()) {
        char buffer[128];
        std::snprintf(buffer, sizeof buffer, "GL error 0x%x (%s) in %s", static_cast<unsigned>(e), glErrorName(e), where);
        if (!errors.empty()) errors += "; ";
        errors += buffer;
        if (e == GL_OUT_OF_MEMORY) break;  // glGetError may keep returning it
    }
}

void deleteGlBuffer(unsigned& id) {
    if (id) glDeleteBuffers(1, &id);
    id = 0;
}

void deleteGlTexture(unsigned& id) {
    if (id) glDeleteTextures(1, &id);
    id = 0;
}

}  // namespace radgl
