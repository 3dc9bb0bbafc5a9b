// The irradiance vector grid (Granier et al. 2007, common/lighting/irradiance_vector_grid.h) as
// OpenGL 3D textures, in the paper's compressed form: "these two vectors are encoded in two 16 bits
// 3D textures ... 12 3D textures". Per direction delta (+x, -x, +y, -y, +z, -z): a colour texture
// (|I_R|, |I_G|, |I_B|) and a direction texture (the unit direction of I_R + I_G + I_B), both RGB16F
// (half floats: about 3 significant decimal digits, magnitudes up to 65504), one texel per grid
// vertex, GL_LINEAR (hardware trilinear = the paper's spatial interpolation), clamp to edge, no
// mipmaps. The shader side is irradiance_grid_shaders.h. 72 bytes per grid vertex (96 if the
// driver pads RGB16F to RGBA16F).
//
// Limits (gl_capabilities.h): each axis's vertex count at most GL_MAX_3D_TEXTURE_SIZE (at least 256
// from GL 3.0 on) and the fragment shader needs 12 texture units besides the ones its renderer
// already uses (the normal-map renderer: 3, so 15 of the at least 16 of GL 3.2). When a limit is not
// met, upload() refuses with the reason (the decoration logs it and draws without indirect light).
#pragma once

#include "gl_capabilities.h"

#include "lighting/irradiance_vector_grid.h"

#include <array>
#include <cstddef>
#include <string>

namespace radgl {

// Why a grid of these vertex counts cannot be drawn with `caps` by a shader that already uses
// `otherUnits` texture units, or empty.
std::string irradianceGridTextureProblem(const GlCapabilities& caps, const std::array<int, 3>& vertexCounts,
                                         int otherUnits);

class IrradianceGridTextures {
public:
    static constexpr int kTextures = 12;  // colour then direction per direction: unit first + 2 d, + 2 d + 1

    IrradianceGridTextures() = default;
    ~IrradianceGridTextures();  // the context that uploaded must be current
    IrradianceGridTextures(const IrradianceGridTextures&) = delete;
    IrradianceGridTextures& operator=(const IrradianceGridTextures&) = delete;

    // Compresses (rad::gpuCompressed) and uploads; replaces a previous grid. Returns why it refused
    // (limits above, shaders unavailable), else empty; `note` gets what was changed on the way
    // (colour magnitudes above the half-float range clamped), else is cleared.
    std::string upload(const rad::IrradianceVectorGrid& grid, const GlCapabilities& caps, int otherUnits,
                       std::string& note);
    void release();
    bool ready() const { return textures_[0] != 0; }

    // The texture of direction d (0..5): colour (kind 0) or direction (kind 1).
    unsigned texture(int direction, int kind) const { return textures_[2 * direction + kind]; }
    const std::array<float, 3>& origin() const { return origin_; }
    const std::array<float, 3>& cellSize() const { return cellSize_; }
    const std::array<int, 3>& vertexCounts() const { return vertexCounts_; }
    std::size_t gpuBytes() const { return bytes_; }

private:
    std::array<unsigned, kTextures> textures_{};
    std::array<float, 3> origin_{{0, 0, 0}}, cellSize_{{1, 1, 1}};
    std::array<int, 3> vertexCounts_{{0, 0, 0}};
    std::size_t bytes_ = 0;
};

}  // namespace radgl
