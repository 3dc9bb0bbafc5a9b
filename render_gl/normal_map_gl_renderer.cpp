#include "normal_map_gl_renderer.h"

#include "gl_helpers.h"
#include "irradiance_grid_shaders.h"

#include "geometry/mikktspace_tangents.h"

#include <GL/glew.h>

#include <cmath>

namespace radgl {

namespace {
constexpr int kDiffuseUnit = 2;    // units 0 and 1: the normal map and the LEAN moments
constexpr int kGridFirstUnit = 3;  // then the irradiance vector grid's 12 3D textures
constexpr int kCornerFloats = 12;  // position, normal, uv, MikkTSpace tangent and sign
// POP buffer: position, normal, uv, level-16 cell, d(u)/dxyz, d(v)/dxyz, then the tangent and sign.
constexpr int kPopCornerFloats = 21;
int tangentOffset(int floatsPerCorner) { return floatsPerCorner == kPopCornerFloats ? 17 : 8; }

// The MikkTSpace tangents of a mesh's corners (for maps baked in MikkTSpace): the very ones the baker
// used, as both compute them from the same positions, normals and wedge UVs.
rad::CornerTangents cornerTangents(const float* positions, const float* normals, std::size_t vertexCount,
                                   const std::uint32_t* faces, std::size_t faceCount, const float* wedgeUv) {
    rad::TangentSpaceInput input;
    input.positions = positions;
    input.vertexCount = vertexCount;
    input.faces = faces;
    input.faceCount = faceCount;
    input.normals = normals;
    input.uv = wedgeUv;
    rad::CornerTangents tangents = rad::computeMikkTSpaceTangents(input);
    rad::completeTangents(tangents, input);
    return tangents;
}
}
namespace {

// Empty when levels form a mip chain w >> k x h >> k down to 1 x 1 with 3 channels.
std::string chainProblem(const std::vector<rad::MipImage>& levels, int w, int h, const char* what) {
    if (levels.empty()) return std::string(what) + ": no levels";
    for (std::size_t k = 0; k < levels.size(); ++k) {
        const rad::MipImage& m = levels[k];
        const int ew = std::max(1, w >> k), eh = std::max(1, h >> k);
        if (m.width != ew || m.height != eh || m.channels != 3 ||
            m.data.size() != static_cast<std::size_t>(m.width) * m.height * 3)
            return std::string(what) + ": level " + std::to_string(k) + " is " + std::to_string(m.width) + " x " +
                   std::to_string(m.height) + " x " + std::to_string(m.channels) + ", expected " + std::to_string(ew) +
                   " x " + std::to_string(eh) + " x 3";
    }
    if (std::max(levels.back().width, levels.back().height) != 1) return std::string(what) + ": the levels stop before 1 x 1";
    return {};
}

}  // namespace

NormalMapGlRenderer::NormalMapGlRenderer(const GlCapabilities& caps) : caps_(caps) {
    if (caps_.supportsShaders()) buildProgram();
    else shaderProblem_ = caps_.missingForShaders();
    checkGl("normal-map shader setup");
}

void NormalMapGlRenderer::buildProgram() {
    std::string log;
    program_ = buildGlProgram(normalMapVertexShaderSource(), normalMapFragmentShaderSource(), "normal-map", log);
    if (!program_) {
        shaderProblem_ = log;
        return;
    }
    auto loc = [this](const char* name) { return glGetUniformLocation(program_, name); };
    u_.normalMap = loc("uNormalMap");
    u_.moments = loc("uMoments");
    u_.mode = loc("uMode");
    u_.tangentSpace = loc("uTangentSpace");
    u_.mikkTSpace = loc("uMikkTSpace");
    u_.textureSize = loc("uTextureSize");
    u_.eye = loc("uEye");
    u_.lightDirection = loc("uLightDirection");
    u_.lightColor = loc("uLightColor");
    u_.albedo = loc("uAlbedo");
    u_.specular = loc("uSpecular");
    u_.ambient = loc("uAmbient");
    u_.shininess = loc("uShininess");
    u_.exposureScale = loc("uExposureScale");
    u_.toneCurve = loc("uToneCurve");
    u_.popLevel = loc("uPopLevel");
    u_.popCorrection = loc("uPopCorrection");
    u_.boxMin = loc("uBoxMin");
    u_.boxExtent = loc("uBoxExtent");
    u_.indirect = loc("uIndirect");
    u_.vertexAlbedo = loc("uVertexAlbedo");
    u_.diffuseMap = loc("uDiffuseMap");
    u_.useDiffuseMap = loc("uUseDiffuseMap");
    u_.gridOrigin = loc("uIvgOrigin");
    u_.gridCellSize = loc("uIvgCellSize");
    u_.gridVertexCounts = loc("uIvgVertexCounts");
    u_.gridAbsoluteWeights = loc("uIvgAbsoluteWeights");
    for (int d = 0; d < 6; ++d) {
        u_.gridSamplers[2 * d] = loc(irradianceGridColourSampler(d));
        u_.gridSamplers[2 * d + 1] = loc(irradianceGridDirectionSampler(d));
    }

    // The erase pass: MeshLab's background gradient (raw 8-bit colours, interpolated in window y) and
    // optionally the far depth.
    const char* eraseVertex = "#version 150 compatibility\nvoid main() { gl_Position = ftransform(); }\n";
    const char* eraseFragment = "#version 150 compatibility\n"
                                "uniform vec3 uTop; uniform vec3 uBottom; uniform float uHeight; uniform int uFarDepth;\n"
                                "void main() {\n"
                                "    gl_FragColor = vec4(mix(uBottom, uTop, clamp(gl_FragCoord.y / uHeight, 0.0, 1.0)), 1.0);\n"
                                "    gl_FragDepth = uFarDepth == 1 ? 1.0 : gl_FragCoord.z;\n"
                                "}\n";
    std::string eraseLog;
    eraseProgram_ = buildGlProgram(eraseVertex, eraseFragment, "normal-map erase", eraseLog);
    if (eraseProgram_) {
        eraseTop_ = glGetUniformLocation(eraseProgram_, "uTop");
        eraseBottom_ = glGetUniformLocation(eraseProgram_, "uBottom");
        eraseHeight_ = glGetUniformLocation(eraseProgram_, "uHeight");
        eraseDepth_ = glGetUniformLocation(eraseProgram_, "uFarDepth");
    }
}

std::string NormalMapGlRenderer::eraseFullMesh(const Eigen::Vector3f& top, const Eigen::Vector3f& bottom) {
    if (!program_) return shaderProblem_;
    if (!eraseProgram_) return "the erase shader did not build";
    if (!cornerCount_) return "no mesh";
    GLint previousProgram = 0, previousArray = 0, viewport[4] = {0, 0, 1, 1}, stencilBits = 0;
    glGetIntegerv(GL_CURRENT_PROGRAM, &previousProgram);
    glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &previousArray);
    glGetIntegerv(GL_VIEWPORT, viewport);
    glGetIntegerv(GL_STENCIL_BITS, &stencilBits);
    glPushAttrib(GL_ENABLE_BIT | GL_DEPTH_BUFFER_BIT | GL_POLYGON_BIT | GL_COLOR_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
    glPushClientAttrib(GL_CLIENT_VERTEX_ARRAY_BIT);
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(-1.0f, -1.0f);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glUseProgram(eraseProgram_);
    glUniform3f(eraseTop_, top.x(), top.y(), top.z());
    glUniform3f(eraseBottom_, bottom.x(), bottom.y(), bottom.z());
    glUniform1f(eraseHeight_, static_cast<float>(std::max(1, viewport[3])));
    glBindBuffer(GL_ARRAY_BUFFER, vertexBuffer_);
    glEnableClientState(GL_VERTEX_ARRAY);
    glVertexPointer(3, GL_FLOAT, floatsPerCorner_ * sizeof(float), nullptr);
    const GLsizei count = static_cast<GLsizei>(cornerCount_);
    // Pass 1: the background colour where the mesh is the visible surface (no depth write, so the
    // mesh does not hide itself), marking those pixels in the stencil.
    if (stencilBits > 0) {
        glEnable(GL_STENCIL_TEST);
        glClearStencil(0);
        glClear(GL_STENCIL_BUFFER_BIT);
        glStencilFunc(GL_ALWAYS, 1, 0xff);
        glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
    }
    glDepthFunc(GL_LEQUAL);
    glDepthMask(GL_FALSE);
    glUniform1i(eraseDepth_, 0);
    glDrawArrays(GL_TRIANGLES, 0, count);
    // Pass 2: the far depth on the marked pixels (on the whole projection without a stencil).
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_ALWAYS);
    if (stencilBits > 0) {
        glStencilFunc(GL_EQUAL, 1, 0xff);
        glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    }
    glUniform1i(eraseDepth_, 1);
    glDrawArrays(GL_TRIANGLES, 0, count);
    glUseProgram(static_cast<GLuint>(previousProgram));
    glBindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(previousArray));
    glPopClientAttrib();
    glPopAttrib();
    checkGl("normal-map erase");
    return {};
}

NormalMapGlRenderer::~NormalMapGlRenderer() {
    deleteGlBuffer(vertexBuffer_);
    deleteGlBuffer(colorBuffer_);
    deleteGlTexture(diffuseTexture_);
    grid_.release();
    deleteGlTexture(normalTexture_);
    deleteGlTexture(momentTexture_);
    if (program_) glDeleteProgram(program_);
    if (eraseProgram_) glDeleteProgram(eraseProgram_);
    while (glGetError() != GL_NO_ERROR) {
    }
}

void NormalMapGlRenderer::checkGl(const char* where) { appendGlErrors(errors_, where); }

std::string NormalMapGlRenderer::takeGlErrors() {
    std::string out;
    out.swap(errors_);
    return out;
}

std::string NormalMapGlRenderer::setMesh(const float* positions, const float* normals, std::size_t vertexCount,
                                         const std::uint32_t* faces, std::size_t faceCount, const float* wedgeUv) {
    if (vertexCount == 0 || faceCount == 0) throw GlRendererError("the mesh has no vertices or no faces to draw");
    if (!positions || !normals || !faces || !wedgeUv) throw GlRendererError("the mesh needs positions, normals, faces and wedge UVs");
    for (std::size_t i = 0; i < 3 * faceCount; ++i)
        if (faces[i] >= vertexCount) throw GlRendererError("a face refers to a vertex that does not exist");
    if (!program_) return shaderProblem_;
    const rad::CornerTangents tangents = cornerTangents(positions, normals, vertexCount, faces, faceCount, wedgeUv);
    // 12 floats per corner: position, normal, uv, tangent (x, y, z, sign).
    std::vector<float> corners(3 * faceCount * kCornerFloats);
    for (std::size_t f = 0; f < faceCount; ++f)
        for (int k = 0; k < 3; ++k) {
            const std::size_t v = faces[3 * f + k];
            float* c = corners.data() + (3 * f + k) * kCornerFloats;
            for (int a = 0; a < 3; ++a) {
                c[a] = positions[3 * v + a];
                c[3 + a] = normals[3 * v + a];
            }
            c[6] = wedgeUv[6 * f + 2 * k];
            c[7] = wedgeUv[6 * f + 2 * k + 1];
            for (int a = 0; a < 4; ++a) c[8 + a] = tangents.tangents[4 * (3 * f + k) + a];
        }
    cornerVertex_.assign(faces, faces + 3 * faceCount);
    meshVertexCount_ = vertexCount;
    popLevelEnd_.clear();
    popDerivatives_ = false;
    popLevel_ = 0;
    popCorrect_ = false;
    uploadCorners(corners, kCornerFloats);
    return {};
}

void NormalMapGlRenderer::uploadCorners(const std::vector<float>& corners, int floatsPerCorner) {
    GLint previousArray = 0;
    glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &previousArray);
    if (!vertexBuffer_) glGenBuffers(1, &vertexBuffer_);
    glBindBuffer(GL_ARRAY_BUFFER, vertexBuffer_);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(corners.size() * sizeof(float)), corners.data(), GL_STATIC_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(previousArray));
    cornerCount_ = corners.size() / floatsPerCorner;
    floatsPerCorner_ = floatsPerCorner;
    deleteGlBuffer(colorBuffer_);  // colours belong to the previous mesh
    checkGl("normal-map mesh upload");
}

std::string NormalMapGlRenderer::setPopMesh(const float* positions, const float* normals, std::size_t vertexCount,
                                            const std::uint32_t* faces, std::size_t faceCount, const float* wedgeUv,
                                            const rad::PopBuffer& pop, const rad::TexCoordDerivatives* correction) {
    if (vertexCount == 0 || faceCount == 0) throw GlRendererError("the mesh has no vertices or no faces to draw");
    if (!positions || !normals || !faces || !wedgeUv) throw GlRendererError("the mesh needs positions, normals, faces and wedge UVs");
    if (pop.vertexCount() != vertexCount || pop.faceCount() != faceCount)
        throw GlRendererError("the POP buffer was built from another mesh");
    if (correction && correction->perCorner.size() != 18 * faceCount)
        throw GlRendererError("the texture-coordinate derivatives were computed for another mesh");
    for (std::size_t i = 0; i < 3 * faceCount; ++i)
        if (faces[i] >= vertexCount) throw GlRendererError("a face refers to a vertex that does not exist");
    if (!program_) return shaderProblem_;
    const rad::CornerTangents tangents = cornerTangents(positions, normals, vertexCount, faces, faceCount, wedgeUv);
    // 21 floats per corner: position, normal, uv, level-16 cell (exact in float), d(u)/dxyz, d(v)/dxyz,
    // MikkTSpace tangent and sign.
    std::vector<float> corners(3 * faceCount * kPopCornerFloats, 0.0f);
    for (std::size_t i = 0; i < faceCount; ++i) {
        const std::size_t f = pop.faceOrder[i];
        for (int k = 0; k < 3; ++k) {
            const std::size_t v = faces[3 * f + k];
            float* c = corners.data() + (3 * i + k) * kPopCornerFloats;
            for (int a = 0; a < 3; ++a) {
                c[a] = positions[3 * v + a];
                c[3 + a] = normals[3 * v + a];
                c[8 + a] = static_cast<float>(pop.cells[3 * v + a]);
            }
            c[6] = wedgeUv[6 * f + 2 * k];
            c[7] = wedgeUv[6 * f + 2 * k + 1];
            if (correction)
                for (int a = 0; a < 6; ++a) c[11 + a] = correction->perCorner[6 * (3 * f + k) + a];
            for (int a = 0; a < 4; ++a) c[17 + a] = tangents.tangents[4 * (3 * f + k) + a];
        }
    }
    cornerVertex_.resize(3 * faceCount);
    for (std::size_t i = 0; i < faceCount; ++i)
        for (int k = 0; k < 3; ++k) cornerVertex_[3 * i + k] = faces[3 * pop.faceOrder[i] + k];
    meshVertexCount_ = vertexCount;
    popLevelEnd_.assign(pop.levelEnd.begin(), pop.levelEnd.end());
    for (int a = 0; a < 3; ++a) {
        boxMin_[a] = static_cast<float>(pop.boxMin[a]);
        boxExtent_[a] = static_cast<float>(pop.boxExtent[a]);
    }
    popDerivatives_ = correction != nullptr;
    popLevel_ = 0;
    popCorrect_ = false;
    uploadCorners(corners, kPopCornerFloats);
    return {};
}

std::string NormalMapGlRenderer::setPopLevel(int level, bool correct) {
    if (level == 0) {
        popLevel_ = 0;
        popCorrect_ = false;
        return {};
    }
    if (popLevelEnd_.empty()) return "no POP buffer uploaded (setPopMesh)";
    if (level < rad::kPopMinLevel || level > rad::kPopMaxLevel)
        return "POP-buffer levels are " + std::to_string(rad::kPopMinLevel) + " to " + std::to_string(rad::kPopMaxLevel);
    if (correct && !popDerivatives_) return "no texture-coordinate derivatives uploaded: the correction needs them";
    popLevel_ = level;
    popCorrect_ = correct;
    return {};
}

std::size_t NormalMapGlRenderer::drawnFaceCount() const {
    return popLevel_ > 0 ? popLevelEnd_[popLevel_] : cornerCount_ / 3;
}

unsigned NormalMapGlRenderer::uploadPyramid(const std::vector<rad::MipImage>& levels) {
    GLint previousTexture = 0;
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &previousTexture);
    glPushClientAttrib(GL_CLIENT_PIXEL_STORE_BIT);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    glPixelStorei(GL_UNPACK_SKIP_ROWS, 0);
    glPixelStorei(GL_UNPACK_SKIP_PIXELS, 0);
    GLint previousUnpackBuffer = 0;
    glGetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &previousUnpackBuffer);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    GLuint tex = 0;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    std::vector<float> flipped;
    for (std::size_t k = 0; k < levels.size(); ++k) {
        const rad::MipImage& m = levels[k];
        const std::size_t row = static_cast<std::size_t>(m.width) * 3;
        flipped.resize(row * m.height);
        for (int r = 0; r < m.height; ++r)
            std::copy(m.data.begin() + static_cast<std::ptrdiff_t>(row * (m.height - 1 - r)),
                      m.data.begin() + static_cast<std::ptrdiff_t>(row * (m.height - r)), flipped.begin() + static_cast<std::ptrdiff_t>(row * r));
        glTexImage2D(GL_TEXTURE_2D, static_cast<GLint>(k), GL_RGB32F, m.width, m.height, 0, GL_RGB, GL_FLOAT, flipped.data());
    }
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, 0);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, static_cast<GLint>(levels.size() - 1));
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glBindTexture(GL_TEXTURE_2D, static_cast<GLuint>(previousTexture));
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, static_cast<GLuint>(previousUnpackBuffer));
    glPopClientAttrib();
    return tex;
}

std::string NormalMapGlRenderer::setNormalMap(const std::vector<rad::MipImage>& pyramid, bool tangentSpace,
                                              rad::TangentFrame frame) {
    if (!program_) return shaderProblem_;
    if (pyramid.empty()) return "the normal map has no levels";
    const std::string problem = chainProblem(pyramid, pyramid[0].width, pyramid[0].height, "normal map");
    if (!problem.empty()) return problem;
    deleteGlTexture(normalTexture_);
    deleteGlTexture(momentTexture_);
    normalTexture_ = uploadPyramid(pyramid);
    mapWidth_ = pyramid[0].width;
    mapHeight_ = pyramid[0].height;
    mapLevels_ = static_cast<int>(pyramid.size());
    tangentSpace_ = tangentSpace;
    mikkTSpace_ = tangentSpace && frame == rad::TangentFrame::MikkTSpace;
    checkGl("normal map upload");
    return {};
}

std::string NormalMapGlRenderer::setLeanMoments(const std::vector<rad::MipImage>& levels1toK) {
    if (!program_) return shaderProblem_;
    if (!normalTexture_) return "set the normal map before its LEAN moments";
    if (tangentSpace_)
        return "LEAN mapping needs an object-space normal map (it filters object-space normals, Weber and Stamminger); this one is in "
               "tangent space";
    if (mapLevels_ < 2) return "a 1 x 1 normal map has no LEAN moments";
    if (static_cast<int>(levels1toK.size()) != mapLevels_ - 1)
        return "expected " + std::to_string(mapLevels_ - 1) + " LEAN moment levels (MIP levels 1.." +
               std::to_string(mapLevels_ - 1) + "), got " + std::to_string(levels1toK.size());
    const std::string problem =
        chainProblem(levels1toK, std::max(1, mapWidth_ >> 1), std::max(1, mapHeight_ >> 1), "LEAN moments");
    if (!problem.empty()) return problem;
    deleteGlTexture(momentTexture_);
    momentTexture_ = uploadPyramid(levels1toK);
    checkGl("LEAN moment upload");
    return {};
}

std::string NormalMapGlRenderer::setVertexColors(const float* rgb, std::size_t vertexCount) {
    if (!program_) return shaderProblem_;
    if (!cornerCount_) return "no mesh";
    if (!rgb || vertexCount != meshVertexCount_)
        return "vertex colours for " + std::to_string(vertexCount) + " vertices, the mesh has " + std::to_string(meshVertexCount_);
    std::vector<float> corners(3 * cornerVertex_.size());
    for (std::size_t c = 0; c < cornerVertex_.size(); ++c)
        for (int a = 0; a < 3; ++a) corners[3 * c + a] = rgb[3 * std::size_t(cornerVertex_[c]) + a];
    GLint previousArray = 0;
    glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &previousArray);
    if (!colorBuffer_) glGenBuffers(1, &colorBuffer_);
    glBindBuffer(GL_ARRAY_BUFFER, colorBuffer_);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(corners.size() * sizeof(float)), corners.data(), GL_STATIC_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(previousArray));
    checkGl("vertex colour upload");
    return {};
}

std::string NormalMapGlRenderer::setDiffuseMap(const rad::Image8& image) {
    if (!program_) return shaderProblem_;
    if (image.width <= 0 || image.height <= 0 || image.rgb.size() != std::size_t(image.width) * image.height * 3)
        return "the diffuse map is empty or its size does not match its data";
    GLint previousTexture = 0, previousUnpackBuffer = 0;
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &previousTexture);
    glGetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &previousUnpackBuffer);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    glPushClientAttrib(GL_CLIENT_PIXEL_STORE_BIT);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    glPixelStorei(GL_UNPACK_SKIP_ROWS, 0);
    glPixelStorei(GL_UNPACK_SKIP_PIXELS, 0);
    // Rows flipped (images are stored top to bottom, GL's first row is v = 0); GL_SRGB8: the
    // sampler returns linear values, filtered after decoding.
    const std::size_t row = std::size_t(image.width) * 3;
    std::vector<std::uint8_t> flipped(image.rgb.size());
    for (int r = 0; r < image.height; ++r)
        std::copy(image.rgb.begin() + std::ptrdiff_t(row * (image.height - 1 - r)),
                  image.rgb.begin() + std::ptrdiff_t(row * (image.height - r)), flipped.begin() + std::ptrdiff_t(row * r));
    if (!diffuseTexture_) glGenTextures(1, &diffuseTexture_);
    glBindTexture(GL_TEXTURE_2D, diffuseTexture_);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_SRGB8, image.width, image.height, 0, GL_RGB, GL_UNSIGNED_BYTE, flipped.data());
    glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glPopClientAttrib();
    glBindTexture(GL_TEXTURE_2D, static_cast<GLuint>(previousTexture));
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, static_cast<GLuint>(previousUnpackBuffer));
    checkGl("diffuse map upload");
    return {};
}

std::string NormalMapGlRenderer::setIrradianceGrid(const rad::IrradianceVectorGrid& grid, std::string& note) {
    note.clear();
    if (!program_) return shaderProblem_;
    const std::string problem = grid_.upload(grid, caps_, kGridFirstUnit, note);  // units 0 .. kGridFirstUnit - 1 in use
    checkGl("irradiance grid upload");
    return problem;
}

std::string NormalMapGlRenderer::draw(NormalMapShading mode, const NormalMapLighting& lighting,
                                      const rad::ToneMapping& toneMapping, const Eigen::Vector3d& eyeObject) {
    if (!program_) return shaderProblem_;
    if (!cornerCount_) return "no mesh";
    if (mode != NormalMapShading::VertexNormals && !normalTexture_) return "no normal map";
    if (mode == NormalMapShading::Lean) {
        if (tangentSpace_) return "LEAN mapping needs an object-space normal map; this one is in tangent space";
        if (!momentTexture_) return "no LEAN moments";
    }
    if (lighting.indirect != IndirectLight::None && !grid_.ready()) return "no irradiance vector grid";

    GLint previousProgram = 0, previousArray = 0, previousActiveTexture = 0, previousTextures[3] = {0, 0, 0};
    GLint previousGridTextures[IrradianceGridTextures::kTextures] = {};
    glGetIntegerv(GL_CURRENT_PROGRAM, &previousProgram);
    glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &previousArray);
    glGetIntegerv(GL_ACTIVE_TEXTURE, &previousActiveTexture);
    for (int unit = 0; unit < 3; ++unit) {
        glActiveTexture(GL_TEXTURE0 + unit);
        glGetIntegerv(GL_TEXTURE_BINDING_2D, &previousTextures[unit]);
    }
    const bool gridBound = grid_.ready();
    if (gridBound)
        for (int t = 0; t < IrradianceGridTextures::kTextures; ++t) {
            glActiveTexture(GL_TEXTURE0 + kGridFirstUnit + t);
            glGetIntegerv(GL_TEXTURE_BINDING_3D, &previousGridTextures[t]);
        }
    glPushAttrib(GL_ENABLE_BIT | GL_DEPTH_BUFFER_BIT | GL_POLYGON_BIT | GL_LIGHTING_BIT | GL_CURRENT_BIT);
    glPushClientAttrib(GL_CLIENT_VERTEX_ARRAY_BIT);

    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(-1.0f, -1.0f);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glDisable(GL_LIGHTING);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);

    glUseProgram(program_);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, normalTexture_);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, momentTexture_);
    glActiveTexture(GL_TEXTURE0 + kDiffuseUnit);
    glBindTexture(GL_TEXTURE_2D, diffuseTexture_);
    if (gridBound)
        for (int t = 0; t < IrradianceGridTextures::kTextures; ++t) {
            glActiveTexture(GL_TEXTURE0 + kGridFirstUnit + t);
            glBindTexture(GL_TEXTURE_3D, grid_.texture(t / 2, t % 2));
        }
    glUniform1i(u_.normalMap, 0);
    glUniform1i(u_.moments, 1);
    // The 3D samplers always name their own units: two samplers of different types on one unit make
    // the draw fail, even when the shader never reads them.
    for (int t = 0; t < IrradianceGridTextures::kTextures; ++t) glUniform1i(u_.gridSamplers[t], kGridFirstUnit + t);
    glUniform1i(u_.indirect, static_cast<int>(lighting.indirect));
    glUniform1i(u_.gridAbsoluteWeights, lighting.gridAbsoluteWeights ? 1 : 0);
    glUniform1i(u_.vertexAlbedo, colorBuffer_ ? 1 : 0);
    glUniform1i(u_.diffuseMap, kDiffuseUnit);
    glUniform1i(u_.useDiffuseMap, diffuseTexture_ ? 1 : 0);
    glUniform3f(u_.gridOrigin, grid_.origin()[0], grid_.origin()[1], grid_.origin()[2]);
    glUniform3f(u_.gridCellSize, grid_.cellSize()[0], grid_.cellSize()[1], grid_.cellSize()[2]);
    glUniform3f(u_.gridVertexCounts, static_cast<float>(grid_.vertexCounts()[0]), static_cast<float>(grid_.vertexCounts()[1]),
                static_cast<float>(grid_.vertexCounts()[2]));
    glUniform1i(u_.mode, static_cast<int>(mode));
    glUniform1i(u_.tangentSpace, tangentSpace_ ? 1 : 0);
    glUniform1i(u_.mikkTSpace, mikkTSpace_ ? 1 : 0);
    glUniform2f(u_.textureSize, static_cast<float>(mapWidth_), static_cast<float>(mapHeight_));
    glUniform3f(u_.eye, static_cast<float>(eyeObject.x()), static_cast<float>(eyeObject.y()), static_cast<float>(eyeObject.z()));
    const Eigen::Vector3d l = lighting.lightDirection.norm() > 0 ? lighting.lightDirection.normalized() : Eigen::Vector3d(0, 0, 1);
    auto set3 = [](int location, const Eigen::Vector3d& v) {
        glUniform3f(location, static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z()));
    };
    set3(u_.lightDirection, l);
    set3(u_.lightColor, lighting.lightColor);
    set3(u_.albedo, lighting.albedo);
    set3(u_.specular, lighting.specular);
    set3(u_.ambient, lighting.ambient);
    glUniform1f(u_.shininess, static_cast<float>(std::max(lighting.shininess, 1e-6)));
    glUniform1f(u_.exposureScale, static_cast<float>(std::exp2(toneMapping.exposureStops)));
    glUniform1i(u_.toneCurve, toneMapping.curve == rad::ToneCurve::Reinhard ? 1 : 0);
    glUniform1i(u_.popLevel, popLevel_);
    glUniform1i(u_.popCorrection, popCorrect_ ? 1 : 0);
    glUniform3f(u_.boxMin, boxMin_.x(), boxMin_.y(), boxMin_.z());
    glUniform3f(u_.boxExtent, boxExtent_.x(), boxExtent_.y(), boxExtent_.z());

    const GLsizei stride = floatsPerCorner_ * sizeof(float);
    glBindBuffer(GL_ARRAY_BUFFER, vertexBuffer_);
    glEnableClientState(GL_VERTEX_ARRAY);
    glVertexPointer(3, GL_FLOAT, stride, nullptr);
    glEnableClientState(GL_NORMAL_ARRAY);
    glNormalPointer(GL_FLOAT, stride, reinterpret_cast<const void*>(3 * sizeof(float)));
    glClientActiveTexture(GL_TEXTURE0);
    glEnableClientState(GL_TEXTURE_COORD_ARRAY);
    glTexCoordPointer(2, GL_FLOAT, stride, reinterpret_cast<const void*>(6 * sizeof(float)));
    if (floatsPerCorner_ == kPopCornerFloats) {  // POP buffer: cell and derivatives as texture coordinates 1..3
        for (int unit = 1; unit <= 3; ++unit) {
            glClientActiveTexture(GL_TEXTURE0 + unit);
            glEnableClientState(GL_TEXTURE_COORD_ARRAY);
            glTexCoordPointer(3, GL_FLOAT, stride, reinterpret_cast<const void*>((8 + 3 * (unit - 1)) * sizeof(float)));
        }
    }
    // The corner's MikkTSpace tangent and sign as texture coordinate 4 (after the POP buffer's).
    glClientActiveTexture(GL_TEXTURE4);
    glEnableClientState(GL_TEXTURE_COORD_ARRAY);
    glTexCoordPointer(4, GL_FLOAT, stride, reinterpret_cast<const void*>(tangentOffset(floatsPerCorner_) * sizeof(float)));
    glClientActiveTexture(GL_TEXTURE0);
    if (colorBuffer_) {
        glBindBuffer(GL_ARRAY_BUFFER, colorBuffer_);
        glEnableClientState(GL_COLOR_ARRAY);
        glColorPointer(3, GL_FLOAT, 0, nullptr);
        glBindBuffer(GL_ARRAY_BUFFER, vertexBuffer_);
    } else {
        glDisableClientState(GL_COLOR_ARRAY);
    }

    // A level is a prefix of the buffer: no per-frame work besides the uniforms.
    glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(3 * drawnFaceCount()));

    if (gridBound)
        for (int t = IrradianceGridTextures::kTextures - 1; t >= 0; --t) {
            glActiveTexture(GL_TEXTURE0 + kGridFirstUnit + t);
            glBindTexture(GL_TEXTURE_3D, static_cast<GLuint>(previousGridTextures[t]));
        }
    for (int unit = 2; unit >= 0; --unit) {
        glActiveTexture(GL_TEXTURE0 + unit);
        glBindTexture(GL_TEXTURE_2D, static_cast<GLuint>(previousTextures[unit]));
    }
    glUseProgram(static_cast<GLuint>(previousProgram));
    glActiveTexture(static_cast<GLenum>(previousActiveTexture));
    glBindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(previousArray));
    glPopClientAttrib();
    glPopAttrib();
    checkGl("normal-map draw");
    return {};
}

}  // namespace radgl
