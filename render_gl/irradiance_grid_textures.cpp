#include "irradiance_grid_textures.h"

#include "gl_helpers.h"

#include <GL/glew.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <vector>

namespace radgl {

namespace {
constexpr float kHalfMax = 65504.0f;  // the largest finite half float
}

std::string irradianceGridTextureProblem(const GlCapabilities& caps, const std::array<int, 3>& vertexCounts,
                                         int otherUnits) {
    if (!caps.supportsShaders()) return caps.missingForShaders();
    const int largest = std::max({vertexCounts[0], vertexCounts[1], vertexCounts[2]});
    if (largest > caps.max3dTextureSize)
        return "the grid has " + std::to_string(largest) + " vertices along an axis, more than this OpenGL's 3D texture size (" +
               std::to_string(caps.max3dTextureSize) + "); compute the grid with at most " +
               std::to_string(caps.max3dTextureSize - 1) + " cells per axis";
    const int needed = IrradianceGridTextures::kTextures + otherUnits;
    if (needed > caps.maxFragmentTextureUnits)
        return "the grid needs " + std::to_string(needed) + " fragment texture units, this OpenGL has " +
               std::to_string(caps.maxFragmentTextureUnits);
    return {};
}

IrradianceGridTextures::~IrradianceGridTextures() { release(); }

void IrradianceGridTextures::release() {
    for (unsigned& t : textures_) deleteGlTexture(t);
    bytes_ = 0;
}

std::string IrradianceGridTextures::upload(const rad::IrradianceVectorGrid& grid, const GlCapabilities& caps,
                                           int otherUnits, std::string& note) {
    note.clear();
    try {
        grid.validate();
    } catch (const std::exception& e) {
        return e.what();
    }
    const std::array<int, 3> counts = grid.vertexCounts();
    const std::string problem = irradianceGridTextureProblem(caps, counts, otherUnits);
    if (!problem.empty()) return problem;
    release();

    const std::vector<float> compressed = rad::gpuCompressed(grid);  // 6 directions x (colour, direction) per vertex
    const std::size_t vertices = grid.vertexCount();
    std::vector<float> texels(vertices * 3);
    std::size_t clamped = 0;

    GLint previousTexture = 0, previousUnpackBuffer = 0;
    glGetIntegerv(GL_TEXTURE_BINDING_3D, &previousTexture);
    glGetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &previousUnpackBuffer);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    glPushClientAttrib(GL_CLIENT_PIXEL_STORE_BIT);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    glPixelStorei(GL_UNPACK_IMAGE_HEIGHT, 0);
    glPixelStorei(GL_UNPACK_SKIP_ROWS, 0);
    glPixelStorei(GL_UNPACK_SKIP_PIXELS, 0);
    glPixelStorei(GL_UNPACK_SKIP_IMAGES, 0);
    glGenTextures(kTextures, textures_.data());
    for (int d = 0; d < rad::IrradianceVectorGrid::kDirections; ++d)
        for (int kind = 0; kind < 2; ++kind) {
            // Vertex order i fastest, then j, then k: GL's order of a 3D image (x, then y, then z).
            for (std::size_t v = 0; v < vertices; ++v) {
                const float* slot = compressed.data() + (v * rad::IrradianceVectorGrid::kDirections + d) * 6 + 3 * kind;
                for (int c = 0; c < 3; ++c) {
                    float value = slot[c];
                    if (kind == 0 && value > kHalfMax) {
                        value = kHalfMax;
                        ++clamped;
                    }
                    texels[3 * v + c] = value;
                }
            }
            glBindTexture(GL_TEXTURE_3D, textures_[2 * d + kind]);
            glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_BASE_LEVEL, 0);
            glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAX_LEVEL, 0);
            glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
            glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
            glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
            glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
            glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
            glTexImage3D(GL_TEXTURE_3D, 0, GL_RGB16F, counts[0], counts[1], counts[2], 0, GL_RGB, GL_FLOAT, texels.data());
        }
    glPopClientAttrib();
    glBindTexture(GL_TEXTURE_3D, static_cast<GLuint>(previousTexture));
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, static_cast<GLuint>(previousUnpackBuffer));
    std::string errors;
    appendGlErrors(errors, "irradiance grid upload");
    if (!errors.empty()) {
        release();
        return errors;
    }
    origin_ = grid.origin;
    cellSize_ = grid.cellSize;
    vertexCounts_ = counts;
    bytes_ = vertices * kTextures * 3 * 2;
    if (clamped)
        note = std::to_string(clamped) + " irradiance magnitudes above the half-float range (65504) were clamped; "
               "scale the light down";
    return {};
}

}  // namespace radgl
