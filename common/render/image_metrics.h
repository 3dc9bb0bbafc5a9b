// Image-space error between two pictures of the same view (a rendering and a photograph, or two
// renderings), over the pixels of a mask: what the fitting and simplification benchmarks report.
//
// Definitions, for the set M of masked pixels (all pixels without a mask) and the three channels:
//   RMSE = sqrt( (1 / (3 |M|)) sum_{p in M} sum_{c in R,G,B} (a_pc - b_pc)^2 )
//   PSNR = 20 log10(peak / RMSE)   in dB; +infinity when RMSE = 0
// in two unit systems:
//   - 8-bit sRGB: each value is the 0..255 code a PNG stores (linear images are encoded with
//     encodeSrgb8, i.e. clamped to [0, 1], sRGB curve, rounded), peak = 255. This is the figure
//     usually quoted for photographs and matches comparing the PNG files.
//   - linear: the linear radiance values themselves (8-bit images are decoded with the sRGB
//     curve), peak = 1 (the linear value that encodes to white). Values above 1 are NOT clamped.
// With an empty mask selection (|M| = 0) RMSE and PSNR are NaN and pixelCount is 0.
#pragma once

#include "image/rgb_image.h"

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace rad {

struct ImageErrors {
    std::size_t pixelCount = 0;  // |M|
    double rmseLinear = 0.0, psnrLinear = 0.0;  // peak 1
    double rmseSrgb8 = 0.0, psnrSrgb8 = 0.0;    // peak 255
};

// PSNR in dB of an RMSE for a peak value: 20 log10(peak / rmse); +inf for rmse = 0.
double psnrFromRmse(double rmse, double peak);

// The figures from the mean squared differences over `pixelCount` pixels (linear and 8-bit sRGB
// units): RMSE = sqrt(mean square), PSNR with peaks 1 and 255; NaN when pixelCount is 0.
ImageErrors imageErrorsFromMeanSquares(double meanSquareLinear, double meanSquareSrgb8, std::size_t pixelCount);

// A mask selects pixel i (row-major, rows top to bottom) when mask[i] != 0; an empty vector
// selects every pixel. Throws std::invalid_argument when the sizes differ.
ImageErrors compareImages(const ImageF& a, const ImageF& b, const std::vector<std::uint8_t>& mask = {});
ImageErrors compareImages(const Image8& a, const Image8& b, const std::vector<std::uint8_t>& mask = {});
// A linear rendering against an 8-bit photograph (the photograph decoded for the linear figures,
// the rendering encoded for the 8-bit ones).
ImageErrors compareImages(const ImageF& rendering, const Image8& photograph, const std::vector<std::uint8_t>& mask = {});

}  // namespace rad
