// Tests of render/image_metrics.h: identical images (RMSE 0, PSNR +inf), known constant offsets
// against the closed-form PSNR, masks, the mixed linear/8-bit comparison, refusals.
#include "render/image_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace {

rad::ImageF constantF(int w, int h, float v) {
    rad::ImageF img(w, h);
    for (float& x : img.rgb) x = v;
    return img;
}

rad::Image8 constant8(int w, int h, std::uint8_t v) {
    rad::Image8 img(w, h);
    for (auto& x : img.rgb) x = v;
    return img;
}

TEST(ImageMetrics, IdenticalImagesHaveZeroErrorAndInfinitePsnr) {
    rad::ImageF a(7, 5);
    for (std::size_t i = 0; i < a.rgb.size(); ++i) a.rgb[i] = 0.01f * static_cast<float>(i % 97);
    const rad::ImageErrors e = rad::compareImages(a, a);
    EXPECT_EQ(e.pixelCount, 35u);
    EXPECT_EQ(e.rmseLinear, 0.0);
    EXPECT_EQ(e.rmseSrgb8, 0.0);
    EXPECT_EQ(e.psnrLinear, std::numeric_limits<double>::infinity());
    EXPECT_EQ(e.psnrSrgb8, std::numeric_limits<double>::infinity());
    const rad::Image8 b = constant8(4, 4, 77);
    EXPECT_EQ(rad::compareImages(b, b).psnrSrgb8, std::numeric_limits<double>::infinity());
}

TEST(ImageMetrics, ConstantOffsetMatchesTheFormula) {
    // 8-bit: every value differs by 10 codes -> RMSE 10, PSNR = 20 log10(255 / 10) = 28.1308 dB.
    const rad::ImageErrors e8 = rad::compareImages(constant8(6, 4, 100), constant8(6, 4, 110));
    EXPECT_DOUBLE_EQ(e8.rmseSrgb8, 10.0);
    EXPECT_NEAR(e8.psnrSrgb8, 28.130803608679, 1e-9);
    // Linear figures of 8-bit images use the decoded values.
    const double d = rad::srgbToLinear(110) - rad::srgbToLinear(100);
    EXPECT_NEAR(e8.rmseLinear, d, 1e-7);
    EXPECT_NEAR(e8.psnrLinear, 20.0 * std::log10(1.0 / d), 1e-5);

    // Linear: offset 0.05 -> RMSE 0.05, PSNR = 20 log10(1 / 0.05) = 26.0206 dB; no clamping above 1.
    const rad::ImageErrors ef = rad::compareImages(constantF(5, 3, 1.2f), constantF(5, 3, 1.25f));
    EXPECT_NEAR(ef.rmseLinear, 0.05, 1e-6);
    EXPECT_NEAR(ef.psnrLinear, 26.0206, 1e-3);
    EXPECT_EQ(ef.rmseSrgb8, 0.0);  // both encode to 255

    // Offsets on one channel only: RMSE over the three channels = sqrt(d^2 / 3).
    rad::ImageF a = constantF(2, 2, 0.5f), b = a;
    for (int p = 0; p < 4; ++p) b.rgb[3 * p + 1] += 0.3f;
    EXPECT_NEAR(rad::compareImages(a, b).rmseLinear, 0.3 / std::sqrt(3.0), 1e-6);
    EXPECT_NEAR(rad::psnrFromRmse(0.1, 1.0), 20.0, 1e-12);
}

TEST(ImageMetrics, MaskSelectsThePixels) {
    rad::Image8 a = constant8(3, 2, 50), b = a;
    b.pixel(2, 1)[0] = 90;  // one wrong pixel, masked out
    b.pixel(0, 0)[2] = 56;  // one wrong value in a masked pixel
    const std::vector<std::uint8_t> mask = {1, 0, 1, 0, 1, 0};  // pixels (0,0), (2,0), (1,1)
    const rad::ImageErrors e = rad::compareImages(a, b, mask);
    EXPECT_EQ(e.pixelCount, 3u);
    EXPECT_NEAR(e.rmseSrgb8, std::sqrt(36.0 / 9.0), 1e-12);
    const rad::ImageErrors all = rad::compareImages(a, b);
    EXPECT_NEAR(all.rmseSrgb8, std::sqrt((36.0 + 1600.0) / 18.0), 1e-12);
    // Nothing selected: NaN.
    const rad::ImageErrors none = rad::compareImages(a, b, std::vector<std::uint8_t>(6, 0));
    EXPECT_EQ(none.pixelCount, 0u);
    EXPECT_TRUE(std::isnan(none.rmseSrgb8));
    EXPECT_TRUE(std::isnan(none.psnrLinear));
}

TEST(ImageMetrics, RenderingAgainstPhotograph) {
    // A rendering whose values are exactly the decoded codes of the photo: 8-bit error 0, linear 0.
    rad::Image8 photo(4, 3);
    for (std::size_t i = 0; i < photo.rgb.size(); ++i) photo.rgb[i] = static_cast<std::uint8_t>(20 * i);
    rad::ImageF render(4, 3);
    for (std::size_t i = 0; i < render.rgb.size(); ++i) render.rgb[i] = rad::srgbToLinear(photo.rgb[i]);
    const rad::ImageErrors e = rad::compareImages(render, photo);
    EXPECT_EQ(e.rmseSrgb8, 0.0);
    EXPECT_NEAR(e.rmseLinear, 0.0, 1e-12);
    // Same as comparing with the rendering's own 8-bit encoding.
    render.rgb[5] += 0.1f;
    const rad::ImageErrors mixed = rad::compareImages(render, photo);
    const rad::ImageErrors both8 = rad::compareImages(rad::encodeToSrgb8(render), photo);
    EXPECT_DOUBLE_EQ(mixed.rmseSrgb8, both8.rmseSrgb8);
    EXPECT_NEAR(mixed.rmseLinear, 0.1 / std::sqrt(36.0), 1e-6);
}

TEST(ImageMetrics, RefusesMismatchedSizes) {
    EXPECT_THROW(rad::compareImages(constantF(2, 2, 0), constantF(2, 3, 0)), std::invalid_argument);
    EXPECT_THROW(rad::compareImages(constant8(2, 2, 0), constant8(2, 2, 0), std::vector<std::uint8_t>(3, 1)),
                 std::invalid_argument);
}

}  // namespace
