// Compiling and linking a GLSL program (vertex + fragment shader), shared by the decoration's
// renderers. GLEW must be initialised and a context current.
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

}  // namespace radgl
