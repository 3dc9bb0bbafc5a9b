#include "render/image_metrics.h"

#include "radiance/view_colors.h"

#include <cmath>
#include <limits>
#include <string>

namespace rad {

namespace {

void checkSizes(int wa, int ha, int wb, int hb, const std::vector<std::uint8_t>& mask) {
    if (wa != wb || ha != hb)
        throw std::invalid_argument("cannot compare images of different sizes (" + std::to_string(wa) + "x" +
                                    std::to_string(ha) + " and " + std::to_string(wb) + "x" + std::to_string(hb) + ")");
    if (!mask.empty() && mask.size() != static_cast<std::size_t>(wa) * ha)
        throw std::invalid_argument("the mask has " + std::to_string(mask.size()) + " entries for " +
                                    std::to_string(static_cast<std::size_t>(wa) * ha) + " pixels");
}

// Sums of squared differences in both unit systems, given per-channel accessors for each image:
// linear(i) and code(i) of value i = 3 * pixel + channel.
template <typename LinearA, typename CodeA, typename LinearB, typename CodeB>
ImageErrors accumulate(std::size_t pixels, const std::vector<std::uint8_t>& mask, LinearA linA, CodeA codeA,
                       LinearB linB, CodeB codeB) {
    double sumLinear = 0.0, sumCode = 0.0;
    std::size_t count = 0;
    for (std::size_t p = 0; p < pixels; ++p) {
        if (!mask.empty() && mask[p] == 0) continue;
        ++count;
        for (std::size_t i = 3 * p; i < 3 * p + 3; ++i) {
            const double dl = linA(i) - linB(i);
            const double dc = double(codeA(i)) - double(codeB(i));
            sumLinear += dl * dl;
            sumCode += dc * dc;
        }
    }
    if (count == 0) return imageErrorsFromMeanSquares(0.0, 0.0, 0);
    return imageErrorsFromMeanSquares(sumLinear / (3.0 * count), sumCode / (3.0 * count), count);
}

}  // namespace

ImageErrors imageErrorsFromMeanSquares(double meanSquareLinear, double meanSquareSrgb8, std::size_t pixelCount) {
    ImageErrors e;
    e.pixelCount = pixelCount;
    if (pixelCount == 0) {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        e.rmseLinear = e.psnrLinear = e.rmseSrgb8 = e.psnrSrgb8 = nan;
        return e;
    }
    e.rmseLinear = std::sqrt(meanSquareLinear);
    e.rmseSrgb8 = std::sqrt(meanSquareSrgb8);
    e.psnrLinear = psnrFromRmse(e.rmseLinear, 1.0);
    e.psnrSrgb8 = psnrFromRmse(e.rmseSrgb8, 255.0);
    return e;
}

double psnrFromRmse(double rmse, double peak) {
    if (rmse == 0.0) return std::numeric_limits<double>::infinity();
    return 20.0 * std::log10(peak / rmse);
}

ImageErrors compareImages(const ImageF& a, const ImageF& b, const std::vector<std::uint8_t>& mask) {
    checkSizes(a.width, a.height, b.width, b.height, mask);
    const float* A = a.rgb.data();
    const float* B = b.rgb.data();
    return accumulate(
        static_cast<std::size_t>(a.width) * a.height, mask, [A](std::size_t i) { return double(A[i]); },
        [A](std::size_t i) { return encodeSrgb8(A[i]); }, [B](std::size_t i) { return double(B[i]); },
        [B](std::size_t i) { return encodeSrgb8(B[i]); });
}

ImageErrors compareImages(const Image8& a, const Image8& b, const std::vector<std::uint8_t>& mask) {
    checkSizes(a.width, a.height, b.width, b.height, mask);
    const std::uint8_t* A = a.rgb.data();
    const std::uint8_t* B = b.rgb.data();
    const float* lut = srgbToLinearTable();
    return accumulate(
        static_cast<std::size_t>(a.width) * a.height, mask, [A, lut](std::size_t i) { return double(lut[A[i]]); },
        [A](std::size_t i) { return A[i]; }, [B, lut](std::size_t i) { return double(lut[B[i]]); },
        [B](std::size_t i) { return B[i]; });
}

ImageErrors compareImages(const ImageF& rendering, const Image8& photograph, const std::vector<std::uint8_t>& mask) {
    checkSizes(rendering.width, rendering.height, photograph.width, photograph.height, mask);
    const float* A = rendering.rgb.data();
    const std::uint8_t* B = photograph.rgb.data();
    const float* lut = srgbToLinearTable();
    return accumulate(
        static_cast<std::size_t>(rendering.width) * rendering.height, mask, [A](std::size_t i) { return double(A[i]); },
        [A](std::size_t i) { return encodeSrgb8(A[i]); }, [B, lut](std::size_t i) { return double(lut[B[i]]); },
        [B](std::size_t i) { return B[i]; });
}

}  // namespace rad
