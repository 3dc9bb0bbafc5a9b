#include "radiance_gl_renderer.h"

#include "gl_helpers.h"

#include "radiance/radiance_evaluation.h"
#include "radiance/radiance_frame.h"
#include "radiance/view_colors.h"

#include <GL/glew.h>

#include <cmath>
#include <sstream>

namespace radgl {
namespace {

// Uploads `bytes` into a new buffer object bound to `target` (left unbound afterwards).
unsigned makeBuffer(GLenum target, const void* data, std::size_t bytes, GLenum usage = GL_STATIC_DRAW) {
    GLuint id = 0;
    glGenBuffers(1, &id);
    glBindBuffer(target, id);
    glBufferData(target, static_cast<GLsizeiptr>(bytes), data, usage);
    glBindBuffer(target, 0);
    return id;
}

unsigned makeTextureBuffer(unsigned buffer, GLenum format) {
    GLuint tex = 0;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_BUFFER, tex);
    glTexBuffer(GL_TEXTURE_BUFFER, format, buffer);
    glBindTexture(GL_TEXTURE_BUFFER, 0);
    return tex;
}

}  // namespace

RadianceGlRenderer::RadianceGlRenderer(const GlCapabilities& caps) : caps_(caps) {
    if (caps_.supportsShaders()) buildPrograms();
    else shaderProblem_ = caps_.missingForShaders();
    checkGl("shader setup");
}

void RadianceGlRenderer::buildPrograms() {
    auto link = [this](GlShading shading, Program& p) {
        p.id = buildGlProgram(vertexShaderSource(shading), fragmentShaderSource(shading), "radiance", shaderProblem_,
                              [shading](unsigned program) {
                                  glBindAttribLocation(program, 1, "aLinear");
                                  if (shading == GlShading::PerVertex) {
                                      // The per-vertex colours are evaluated once per vertex into a
                                      // buffer (transform feedback over GL_POINTS) instead of once
                                      // per triangle corner: see draw().
                                      const char* varyings[] = {"vLinear"};
                                      glTransformFeedbackVaryings(program, 1, varyings, GL_INTERLEAVED_ATTRIBS);
                                  }
                              });
        if (!p.id) return;
        p.frames = glGetUniformLocation(p.id, "uFrames");
        p.coefficients = glGetUniformLocation(p.id, "uCoefficients");
        p.faces = glGetUniformLocation(p.id, "uFaces");
        p.basisKind = glGetUniformLocation(p.id, "uBasisKind");
        p.degree = glGetUniformLocation(p.id, "uDegree");
        p.coefficientCount = glGetUniformLocation(p.id, "uCoefficientCount");
        p.shNorm = glGetUniformLocation(p.id, "uShNorm");
        p.eye = glGetUniformLocation(p.id, "uEye");
        p.exposureScale = glGetUniformLocation(p.id, "uExposureScale");
        p.toneCurve = glGetUniformLocation(p.id, "uToneCurve");
    };
    link(GlShading::PerVertex, perVertex_);
    link(GlShading::PerFragment, perFragment_);
    link(GlShading::VertexColors, vertexColours_);
}

RadianceGlRenderer::~RadianceGlRenderer() {
    releaseRadiance();
    deleteGlBuffer(positionBuffer_);
    deleteGlBuffer(indexBuffer_);
    deleteGlBuffer(linearColourBuffer_);
    deleteGlBuffer(byteColourBuffer_);
    for (Program* p : {&perVertex_, &perFragment_, &vertexColours_})
        if (p->id) glDeleteProgram(p->id);
    while (glGetError() != GL_NO_ERROR) {
    }
}

void RadianceGlRenderer::releaseRadiance() {
    deleteGlTexture(frameTexture_);
    deleteGlTexture(coefficientTexture_);
    deleteGlTexture(faceTexture_);
    deleteGlBuffer(frameBuffer_);
    deleteGlBuffer(coefficientBuffer_);
    deleteGlBuffer(feedbackBuffer_);
    feedbackValid_ = false;
    gpuRadiance_ = false;
    radianceVertexCount_ = 0;
    cpuField_ = rad::RadianceField();
    if (byteContent_ == ByteContent::CpuRadiance) byteContent_ = ByteContent::None;
}

void RadianceGlRenderer::checkGl(const char* where) { appendGlErrors(errors_, where); }

std::string RadianceGlRenderer::takeGlErrors() {
    std::string out;
    out.swap(errors_);
    return out;
}

void RadianceGlRenderer::setMesh(const float* positions, std::size_t vertexCount, const std::uint32_t* faces,
                                 std::size_t faceCount) {
    if (vertexCount == 0 || faceCount == 0) throw GlRendererError("the mesh has no vertices or no faces to draw");
    for (std::size_t i = 0; i < 3 * faceCount; ++i)
        if (faces[i] >= vertexCount) throw GlRendererError("a face refers to a vertex that does not exist");
    releaseRadiance();
    deleteGlBuffer(positionBuffer_);
    deleteGlBuffer(indexBuffer_);
    deleteGlBuffer(linearColourBuffer_);
    deleteGlBuffer(byteColourBuffer_);
    linearColours_.clear();
    hasVertexColours_ = false;
    byteContent_ = ByteContent::None;
    vertexCount_ = vertexCount;
    faceCount_ = faceCount;
    positions_.assign(positions, positions + 3 * vertexCount);
    positionBuffer_ = makeBuffer(GL_ARRAY_BUFFER, positions, 3 * vertexCount * sizeof(float));
    indexBuffer_ = makeBuffer(GL_ARRAY_BUFFER, faces, 3 * faceCount * sizeof(std::uint32_t));
    gpuBytes_ = 3 * vertexCount * sizeof(float) + 3 * faceCount * sizeof(std::uint32_t);
    checkGl("mesh upload");
}

std::string RadianceGlRenderer::setRadiance(const rad::RadianceField& field) {
    if (field.vertexCount() != vertexCount_)
        throw GlRendererError("the radiance field has " + std::to_string(field.vertexCount()) + " functions for " +
                              std::to_string(vertexCount_) + " vertices");
    const std::string invalid = field.validate();
    if (!invalid.empty()) throw GlRendererError("invalid radiance field: " + invalid);
    releaseRadiance();
    radianceVertexCount_ = vertexCount_;
    basis_ = field.basis;

    std::string why;
    const int K = field.coefficientsPerChannel();
    const bool rgb = caps_.rgb32TextureBuffer;
    const std::size_t texelWidth = rgb ? 3 : 4;
    const long long coefficientTexels = static_cast<long long>(vertexCount_) * K;
    // The per-vertex mode draws through the vertex-colour program (transform feedback, see draw()).
    if (!caps_.supportsShaders() || !perVertex_.id || !perFragment_.id || !vertexColours_.id) {
        why = shaderProblem_.empty() ? "no shader programs" : shaderProblem_;
    } else if (coefficientTexels > caps_.maxTextureBufferTexels ||
               static_cast<long long>(3 * vertexCount_) > caps_.maxTextureBufferTexels ||
               static_cast<long long>(3 * faceCount_) > caps_.maxTextureBufferTexels) {
        std::ostringstream s;
        s << "the coefficients need " << coefficientTexels << " texture-buffer texels, the GL allows "
          << caps_.maxTextureBufferTexels;
        why = s.str();
    }
    if (!why.empty()) {
        cpuField_ = field;  // the CPU per-vertex path draws it
        return why;
    }

    // Frames: position, normal, tangent per vertex.
    std::vector<float> frames(vertexCount_ * 3 * texelWidth, 0.0f);
    std::vector<float> coefficients(static_cast<std::size_t>(coefficientTexels) * texelWidth, 0.0f);
    std::vector<double> reflected(static_cast<std::size_t>(3 * K));
#pragma omp parallel for schedule(static) firstprivate(reflected)
    for (long long v = 0; v < static_cast<long long>(vertexCount_); ++v) {
        const std::size_t vi = static_cast<std::size_t>(v);
        const rad::Frame frame = rad::frameFromStored(field.frame(vi));
        float* f = frames.data() + vi * 3 * texelWidth;
        for (int a = 0; a < 3; ++a) {
            f[a] = positions_[3 * vi + a];
            f[texelWidth + a] = static_cast<float>(frame.n[a]);
            f[2 * texelWidth + a] = static_cast<float>(frame.t[a]);
        }
        rad::vertexCoefficients(field, vi, true, reflected.data());  // L~ whatever the storage
        float* c = coefficients.data() + vi * K * texelWidth;
        for (int k = 0; k < K; ++k)
            for (int ch = 0; ch < 3; ++ch) c[k * texelWidth + ch] = static_cast<float>(reflected[ch * K + k]);
    }
    const GLenum format = rgb ? GL_RGB32F : GL_RGBA32F;
    frameBuffer_ = makeBuffer(GL_TEXTURE_BUFFER, frames.data(), frames.size() * sizeof(float));
    frameTexture_ = makeTextureBuffer(frameBuffer_, format);
    coefficientBuffer_ = makeBuffer(GL_TEXTURE_BUFFER, coefficients.data(), coefficients.size() * sizeof(float));
    coefficientTexture_ = makeTextureBuffer(coefficientBuffer_, format);
    faceTexture_ = makeTextureBuffer(indexBuffer_, GL_R32UI);
    gpuBytes_ += (frames.size() + coefficients.size()) * sizeof(float);
    shNorm_ = shNormalisationConstants(basis_.kind == rad::BasisKind::SphericalHarmonics ? basis_.degree : 0);
    checkGl("radiance upload");
    gpuRadiance_ = errors_.empty();
    if (!gpuRadiance_) {
        cpuField_ = field;
        return "the GL refused the upload (" + errors_ + ")";
    }
    return {};
}

void RadianceGlRenderer::setVertexColors(const float* linearRgb) {
    if (vertexCount_ == 0) throw GlRendererError("no mesh to colour");
    hasVertexColours_ = true;
    if (byteContent_ == ByteContent::VertexColours) byteContent_ = ByteContent::None;
    if (!vertexColours_.id) {
        // No vertex-colour program: the colours are tone-mapped on the CPU at draw time, keep them.
        linearColours_.assign(linearRgb, linearRgb + 3 * vertexCount_);
    } else if (!linearColourBuffer_) {
        linearColourBuffer_ = makeBuffer(GL_ARRAY_BUFFER, linearRgb, 3 * vertexCount_ * sizeof(float), GL_DYNAMIC_DRAW);
        gpuBytes_ += 3 * vertexCount_ * sizeof(float);
    } else {
        glBindBuffer(GL_ARRAY_BUFFER, linearColourBuffer_);
        glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(3 * vertexCount_ * sizeof(float)), linearRgb);
        glBindBuffer(GL_ARRAY_BUFFER, 0);
    }
    checkGl("vertex colour upload");
}

GlShading RadianceGlRenderer::activeShading(GlShading requested) const {
    if (requested == GlShading::VertexColors || gpuRadiance_) return requested;
    return GlShading::PerVertex;
}

namespace {
bool sameToneMapping(const rad::ToneMapping& a, const rad::ToneMapping& b) {
    return a.exposureStops == b.exposureStops && a.curve == b.curve;
}
}  // namespace

void RadianceGlRenderer::uploadBytes(const std::vector<float>& linear, const rad::ToneMapping& toneMapping) {
    std::vector<std::uint8_t> bytes(3 * vertexCount_);
#pragma omp parallel for schedule(static)
    for (long long v = 0; v < static_cast<long long>(vertexCount_); ++v) {
        const std::size_t i = 3 * static_cast<std::size_t>(v);
        const Eigen::Vector3d display = rad::toneMap(toneMapping, Eigen::Vector3d(linear[i], linear[i + 1], linear[i + 2]));
        for (int c = 0; c < 3; ++c) bytes[i + c] = rad::toSrgb8(display[c]);
    }
    if (!byteColourBuffer_) {
        byteColourBuffer_ = makeBuffer(GL_ARRAY_BUFFER, bytes.data(), bytes.size(), GL_DYNAMIC_DRAW);
        gpuBytes_ += bytes.size();
    } else {
        glBindBuffer(GL_ARRAY_BUFFER, byteColourBuffer_);
        glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(bytes.size()), bytes.data());
        glBindBuffer(GL_ARRAY_BUFFER, 0);
    }
    byteToneMapping_ = toneMapping;
}

void RadianceGlRenderer::draw(GlShading shading, const rad::ToneMapping& toneMapping, const Eigen::Vector3d& eyeObject) {
    if (vertexCount_ == 0) return;
    const GlShading mode = activeShading(shading);
    const Program* program = nullptr;
    if (mode == GlShading::VertexColors) {
        if (!hasVertexColours_) return;
        if (vertexColours_.id) {
            program = &vertexColours_;
        } else if (byteContent_ != ByteContent::VertexColours || !sameToneMapping(byteToneMapping_, toneMapping)) {
            uploadBytes(linearColours_, toneMapping);
            byteContent_ = ByteContent::VertexColours;
        }
    } else if (gpuRadiance_) {
        program = mode == GlShading::PerVertex ? &perVertex_ : &perFragment_;
    } else if (radianceVertexCount_ > 0) {
        // CPU per-vertex path: re-evaluate when the eye or the tone mapping changed.
        if (byteContent_ != ByteContent::CpuRadiance || byteEye_ != eyeObject ||
            !sameToneMapping(byteToneMapping_, toneMapping)) {
            std::vector<float> linear(3 * vertexCount_);
            const double eye[3] = {eyeObject.x(), eyeObject.y(), eyeObject.z()};
            rad::radianceTowardViewpoint(cpuField_, positions_.data(), eye, 1.0f, linear.data());
            uploadBytes(linear, toneMapping);
            byteContent_ = ByteContent::CpuRadiance;
            byteEye_ = eyeObject;
        }
    } else {
        return;  // nothing to show
    }

    GLint previousProgram = 0, previousArray = 0, previousElements = 0, previousActiveTexture = 0;
    glGetIntegerv(GL_CURRENT_PROGRAM, &previousProgram);
    glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &previousArray);
    glGetIntegerv(GL_ELEMENT_ARRAY_BUFFER_BINDING, &previousElements);
    glGetIntegerv(GL_ACTIVE_TEXTURE, &previousActiveTexture);
    glPushAttrib(GL_ENABLE_BIT | GL_DEPTH_BUFFER_BIT | GL_POLYGON_BIT | GL_LIGHTING_BIT | GL_CURRENT_BIT);
    glPushClientAttrib(GL_CLIENT_VERTEX_ARRAY_BIT);

    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glEnable(GL_POLYGON_OFFSET_FILL);  // win over MeshLab's own drawing of the same triangles
    glPolygonOffset(-1.0f, -1.0f);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glDisable(GL_LIGHTING);
    glDisable(GL_BLEND);
    glDisable(GL_TEXTURE_2D);
    glDisable(GL_COLOR_MATERIAL);

    glBindBuffer(GL_ARRAY_BUFFER, positionBuffer_);
    glEnableClientState(GL_VERTEX_ARRAY);
    glVertexPointer(3, GL_FLOAT, 0, nullptr);
    glDisableClientState(GL_NORMAL_ARRAY);
    glDisableClientState(GL_TEXTURE_COORD_ARRAY);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, indexBuffer_);

    auto bindRadiance = [&](const Program& p) {
        glUseProgram(p.id);
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_BUFFER, frameTexture_);
        glActiveTexture(GL_TEXTURE1);
        glBindTexture(GL_TEXTURE_BUFFER, coefficientTexture_);
        glActiveTexture(GL_TEXTURE2);
        glBindTexture(GL_TEXTURE_BUFFER, faceTexture_);
        glUniform1i(p.frames, 0);
        glUniform1i(p.coefficients, 1);
        if (p.faces >= 0) glUniform1i(p.faces, 2);
        glUniform1i(p.basisKind, basis_.kind == rad::BasisKind::SphericalHarmonics ? 1 : 0);
        glUniform1i(p.degree, basis_.degree);
        glUniform1i(p.coefficientCount, basis_.coefficientCount());
        if (p.shNorm >= 0) glUniform1fv(p.shNorm, static_cast<GLsizei>(shNorm_.size()), shNorm_.data());
        glUniform3f(p.eye, static_cast<float>(eyeObject.x()), static_cast<float>(eyeObject.y()),
                    static_cast<float>(eyeObject.z()));
    };
    unsigned colourBuffer = linearColourBuffer_;
    if (program == &perVertex_) {
        // Per-vertex RF: evaluate each vertex once toward the eye into feedbackBuffer_ (only when the
        // eye moved), then draw the triangles with those linear colours. Indexed triangles would run
        // the vertex shader once per corner (about 6 times per vertex on a software rasteriser).
        if (!feedbackBuffer_) {
            feedbackBuffer_ = makeBuffer(GL_ARRAY_BUFFER, nullptr, 3 * vertexCount_ * sizeof(float), GL_DYNAMIC_COPY);
            gpuBytes_ += 3 * vertexCount_ * sizeof(float);
            feedbackValid_ = false;
        }
        if (!feedbackValid_ || feedbackEye_ != eyeObject) {
            bindRadiance(perVertex_);
            glEnable(GL_RASTERIZER_DISCARD);
            glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, feedbackBuffer_);
            glBeginTransformFeedback(GL_POINTS);
            glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(vertexCount_));
            glEndTransformFeedback();
            glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, 0);
            glDisable(GL_RASTERIZER_DISCARD);
            feedbackValid_ = true;
            feedbackEye_ = eyeObject;
        }
        program = &vertexColours_;
        colourBuffer = feedbackBuffer_;
    }
    const bool colourProgram = program == &vertexColours_;
    if (program) {
        if (colourProgram) {
            glUseProgram(program->id);
            glBindBuffer(GL_ARRAY_BUFFER, colourBuffer);
            glEnableVertexAttribArray(1);
            glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
        } else {
            bindRadiance(*program);
        }
        glUniform1f(program->exposureScale, static_cast<float>(std::exp2(toneMapping.exposureStops)));
        glUniform1i(program->toneCurve, toneMapping.curve == rad::ToneCurve::Reinhard ? 1 : 0);
    } else {
        if (previousProgram) glUseProgram(0);
        glBindBuffer(GL_ARRAY_BUFFER, byteColourBuffer_);
        glEnableClientState(GL_COLOR_ARRAY);
        glColorPointer(3, GL_UNSIGNED_BYTE, 0, nullptr);
    }

    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(3 * faceCount_), GL_UNSIGNED_INT, nullptr);

    if (colourProgram) glDisableVertexAttribArray(1);
    if (gpuRadiance_ && mode != GlShading::VertexColors) {
        for (GLenum unit : {GL_TEXTURE2, GL_TEXTURE1, GL_TEXTURE0}) {
            glActiveTexture(unit);
            glBindTexture(GL_TEXTURE_BUFFER, 0);
        }
    }
    glUseProgram(static_cast<GLuint>(previousProgram));
    glActiveTexture(static_cast<GLenum>(previousActiveTexture));
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLuint>(previousElements));
    glBindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(previousArray));
    glPopClientAttrib();
    glPopAttrib();
    checkGl("draw");
}

}  // namespace radgl
