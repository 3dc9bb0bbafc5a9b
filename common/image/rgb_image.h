// 8-bit RGB images as the fitting reads them, and linear float images as the renderers write them.
//
// Colour decision (stated in the README): photographs are 8-bit sRGB-encoded; every sample is
// decoded to linear radiance with the IEC 61966-2-1 sRGB curve BEFORE interpolation and fitting,
// so that radiance functions hold linear values (additive, as light is) and view_colors.h encodes
// them back with the same curve. Bilinear interpolation is done on the decoded linear values.
//
// ImageView8 is a zero-copy view: the MeshLab adapter points it at a QImage's 32-bit pixels
// (bytes B, G, R, A on little-endian machines), the tools at stb's packed RGB buffers.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rad {

struct ImageView8 {
    const std::uint8_t* data = nullptr;
    int width = 0, height = 0;
    std::ptrdiff_t rowStride = 0;   // bytes from one row to the next (rows top to bottom)
    int pixelStride = 3;            // bytes from one pixel to the next
    int channelOffset[3] = {0, 1, 2};  // byte offsets of R, G, B inside a pixel

    bool empty() const { return data == nullptr || width <= 0 || height <= 0; }
    const std::uint8_t* pixel(int column, int row) const { return data + row * rowStride + column * pixelStride; }
};

// A packed 8-bit RGB image (rows top to bottom).
struct Image8 {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;  // 3 * width * height

    Image8() = default;
    Image8(int w, int h) : width(w), height(h), rgb(static_cast<std::size_t>(w) * h * 3, 0) {}
    ImageView8 view() const { return {rgb.data(), width, height, std::ptrdiff_t(width) * 3, 3, {0, 1, 2}}; }
    std::uint8_t* pixel(int column, int row) { return rgb.data() + (std::size_t(row) * width + column) * 3; }
};

// A linear RGB float image (rows top to bottom), e.g. a rendering before tone mapping.
struct ImageF {
    int width = 0, height = 0;
    std::vector<float> rgb;  // 3 * width * height

    ImageF() = default;
    ImageF(int w, int h) : width(w), height(h), rgb(static_cast<std::size_t>(w) * h * 3, 0.0f) {}
    float* pixel(int column, int row) { return rgb.data() + (std::size_t(row) * width + column) * 3; }
    const float* pixel(int column, int row) const { return rgb.data() + (std::size_t(row) * width + column) * 3; }
};

// sRGB 8-bit code -> linear value in [0, 1] (table lookup).
float srgbToLinear(std::uint8_t code);
// The 256-entry table itself (for hot loops).
const float* srgbToLinearTable();

// Bilinear sample of the linear (decoded) colour at image coordinates (u, v): origin at the image's
// top-left corner, pixel (c, r) centred at (c + 0.5, r + 0.5) (camera/pinhole_camera.h). Points
// closer than half a pixel to the border are clamped to the border pixels' centres. Returns false
// (out untouched) when (u, v) is outside [0, width] x [0, height] or not finite.
bool sampleBilinearLinear(const ImageView8& image, double u, double v, float out[3]);

// 8-bit sRGB image of a linear image: out = encodeSrgb8(exposure * in) per channel.
Image8 encodeToSrgb8(const ImageF& linear, float exposure = 1.0f);

}  // namespace rad
