// GL chores shared by the decoration's renderers: compiling and linking a GLSL program, collecting
// glGetError reports, deleting objects. GLEW must be initialised and a context current.
#pragma once
#include <functional>
#include <string>

namespace radgl {

// The linked program's id, or 0 with the compiler's or linker's message appended to `log`, prefixed
// by `label` (e.g. "normal-map"). beforeLink, when given, runs on the program id after the shaders
// are attached and before linking (attribute locations, transform-feedback varyings). The shader
// objects are always deleted; a failed program too.
unsigned buildGlProgram(const std::string& vertexSource, const std::string& fragmentSource, const std::string& label,
                        std::string& log, const std::function<void(unsigned)>& beforeLink = {});

// Reads every pending glGetError and appends "GL error 0x0500 (GL_INVALID_ENUM) in <where>" to
// `errors` ("; "-separated). Stops at GL_OUT_OF_MEMORY, which glGetError may keep returning.
void appendGlErrors(std::string& errors, const char* where);

// Delete the object when there is one, and zero the id.
void deleteGlBuffer(unsigned& id);
void deleteGlTexture(unsigned& id);

}  // namespace radgl
