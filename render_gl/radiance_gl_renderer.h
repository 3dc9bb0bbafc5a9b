// Draws a mesh carrying per-vertex radiance functions (RF) with OpenGL, for MeshLab's decoration, the
// frame-time benchmark and the GL tests (no Qt, no MeshLab headers: a current context with GLEW
// initialised is all it needs). Upload once (setMesh, setRadiance), draw many: draw() only sets
// uniforms and issues one glDrawElements over the mesh MeshLab drew, with the current GL matrices,
// and restores every binding and state it touches. Without shaders (or beyond the texture buffer
// limit) the per-vertex mode is evaluated on the CPU; activeShading() says what is drawn.
// Details: docs/decorate-radiance.md, "Where it draws" and "Decisions".
#pragma once

#include "gl_capabilities.h"
#include "radiance_shaders.h"

#include "radiance/radiance_field.h"
#include "render/tone_mapping.h"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace radgl {

struct GlRendererError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

class RadianceGlRenderer {
public:
    // The context must be current. Compiles the shader programs when caps.supportsShaders(); a
    // compile or link failure is not thrown but reported by shaderProblem() (the CPU path is used).
    explicit RadianceGlRenderer(const GlCapabilities& caps);
    // Releases the GL objects: the context that created them must be current.
    ~RadianceGlRenderer();
    RadianceGlRenderer(const RadianceGlRenderer&) = delete;
    RadianceGlRenderer& operator=(const RadianceGlRenderer&) = delete;

    // Geometry: 3 floats per vertex, 3 indices per triangle (all < vertexCount). Drops the RF and
    // colours of a previous mesh. Throws GlRendererError on inconsistent input or a GL error.
    void setMesh(const float* positions, std::size_t vertexCount, const std::uint32_t* faces, std::size_t faceCount);

    // RF of the mesh's vertices (field.vertexCount() == vertexCount, validated). Returns an empty
    // string when the GPU modes can draw it, otherwise why not (texture buffer limit, no shaders):
    // the CPU per-vertex path is then used. Throws GlRendererError on a size mismatch.
    std::string setRadiance(const rad::RadianceField& field);
    bool hasRadiance() const { return radianceVertexCount_ > 0; }

    // Linear RGB per vertex (3 floats each), for GlShading::VertexColors (PRT relighting).
    void setVertexColors(const float* linearRgb);

    // The mode draw() will really use for the requested one (PerFragment falls back to PerVertex
    // when the GPU path is unavailable).
    GlShading activeShading(GlShading requested) const;
    bool gpuRadiance() const { return gpuRadiance_; }
    const std::string& shaderProblem() const { return shaderProblem_; }

    // Draws the mesh. eyeObject: the eye in the mesh's object coordinates (inverse modelview * 0).
    void draw(GlShading shading, const rad::ToneMapping& toneMapping, const Eigen::Vector3d& eyeObject);

    // GL errors seen since the last call ("GL error 0x502 (GL_INVALID_OPERATION) in draw"), or empty.
    std::string takeGlErrors();

    std::size_t vertexCount() const { return vertexCount_; }
    std::size_t faceCount() const { return faceCount_; }
    // Bytes of buffer storage the renderer holds on the GL side.
    std::size_t gpuBytes() const { return gpuBytes_; }

private:
    struct Program {
        unsigned id = 0;
        int frames = -1, coefficients = -1, faces = -1, basisKind = -1, degree = -1, coefficientCount = -1,
            shNorm = -1, eye = -1, exposureScale = -1, toneCurve = -1;
    };
    void buildPrograms();
    void releaseRadiance();
    void checkGl(const char* where);

    GlCapabilities caps_;
    std::string shaderProblem_;
    std::string errors_;
    Program perVertex_, perFragment_, vertexColours_;

    std::size_t vertexCount_ = 0, faceCount_ = 0, gpuBytes_ = 0;
    std::vector<float> positions_;  // kept for the CPU path
    unsigned positionBuffer_ = 0, indexBuffer_ = 0;

    // GPU radiance
    bool gpuRadiance_ = false;
    std::size_t radianceVertexCount_ = 0;
    rad::BasisSpec basis_;
    std::vector<float> shNorm_;
    unsigned feedbackBuffer_ = 0;  // per-vertex mode: linear colours toward feedbackEye_
    bool feedbackValid_ = false;
    Eigen::Vector3d feedbackEye_{0, 0, 0};
    unsigned frameBuffer_ = 0, frameTexture_ = 0, coefficientBuffer_ = 0, coefficientTexture_ = 0,
             faceTexture_ = 0;

    // CPU paths: the RF evaluated per vertex (fallback), and linear vertex colours kept for a
    // fixed-function draw; both end as sRGB bytes in byteColourBuffer_.
    enum class ByteContent { None, VertexColours, CpuRadiance };
    void uploadBytes(const std::vector<float>& linear, const rad::ToneMapping& toneMapping);
    rad::RadianceField cpuField_;
    bool hasVertexColours_ = false;
    std::vector<float> linearColours_;  // only without the vertex-colour program
    unsigned linearColourBuffer_ = 0;  // floats, for the VertexColors program
    unsigned byteColourBuffer_ = 0;    // sRGB bytes, for the fixed-function path
    ByteContent byteContent_ = ByteContent::None;
    rad::ToneMapping byteToneMapping_;
    Eigen::Vector3d byteEye_{0, 0, 0};
};

}  // namespace radgl
