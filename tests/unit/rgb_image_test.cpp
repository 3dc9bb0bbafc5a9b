// Tests of image/rgb_image.h. References: the IEC 61966-2-1 decoding formula written out here, the
// decoded values of hand-filled pixels (bilinear weights worked out by hand), and a BGRA buffer laid
// out as Qt's QImage::Format_RGB32 is in memory on little-endian machines (bytes B, G, R, 0xFF,
// rows padded to a stride), which must sample exactly like the packed RGB image it copies.
#include "image/rgb_image.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace {

// IEC 61966-2-1 (sRGB) decoding of code c / 255.
double iecDecode(int code) {
    const double c = code / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

rad::Image8 randomImage(int w, int h, unsigned seed) {
    rad::Image8 image(w, h);
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> code(0, 255);
    for (auto& b : image.rgb) b = static_cast<std::uint8_t>(code(rng));
    return image;
}

float decoded(const rad::Image8& image, int column, int row, int channel) {
    return rad::srgbToLinear(image.rgb[(std::size_t(row) * image.width + column) * 3 + channel]);
}

TEST(RgbImage, SrgbDecodingFollowsTheIecFormula) {
    // 0 and 255 are exact; 10 is on the linear segment (10/255 = 0.0392 <= 0.04045), 11 just past
    // it on the power segment; the rest spread over the curve.
    for (int code : {0, 1, 10, 11, 12, 50, 128, 187, 254, 255})
        EXPECT_NEAR(rad::srgbToLinear(std::uint8_t(code)), iecDecode(code), 1e-7) << code;
    EXPECT_EQ(rad::srgbToLinear(0), 0.0f);
    EXPECT_EQ(rad::srgbToLinear(255), 1.0f);
    EXPECT_NEAR(rad::srgbToLinear(10), 10.0 / 255.0 / 12.92, 1e-9);
    EXPECT_NEAR(rad::srgbToLinear(128), 0.2158605, 1e-6);  // a commonly quoted value of the curve
    const float* table = rad::srgbToLinearTable();
    for (int code = 0; code < 256; ++code) {
        EXPECT_EQ(table[code], rad::srgbToLinear(std::uint8_t(code)));
        if (code > 0) EXPECT_GT(table[code], table[code - 1]) << code;  // strictly increasing
    }
}

TEST(RgbImage, EncodingInvertsDecodingAtEveryCode) {
    rad::ImageF linear(256, 1);
    for (int code = 0; code < 256; ++code)
        for (int k = 0; k < 3; ++k) linear.pixel(code, 0)[k] = rad::srgbToLinear(std::uint8_t(code));
    const rad::Image8 encoded = rad::encodeToSrgb8(linear);
    ASSERT_EQ(encoded.width, 256);
    for (int code = 0; code < 256; ++code) EXPECT_EQ(int(encoded.rgb[3 * code]), code);
    // Exposure scales before encoding (IEC encoding of 2 x, rounded); the result saturates at 255.
    const rad::Image8 doubled = rad::encodeToSrgb8(linear, 2.0f);
    for (int code : {0, 5, 60, 128, 187, 188, 255}) {
        const double x = std::min(1.0, 2.0 * iecDecode(code));
        const double e = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
        EXPECT_EQ(int(doubled.rgb[3 * code]), std::lround(255.0 * e)) << code;
    }
    EXPECT_EQ(int(doubled.rgb[3 * 255]), 255);
}

TEST(RgbImage, BilinearAtPixelCentreIsThePixelAndHalfwayIsTheMeanOfDecodedValues) {
    const rad::Image8 image = randomImage(5, 4, 1);
    const rad::ImageView8 view = image.view();
    float out[3];
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 5; ++c) {
            ASSERT_TRUE(rad::sampleBilinearLinear(view, c + 0.5, r + 0.5, out));
            for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(out[k], decoded(image, c, r, k));
        }
    // Halfway between (1, 2) and (2, 2): mean of the DECODED values (not the decoded mean code).
    ASSERT_TRUE(rad::sampleBilinearLinear(view, 2.0, 2.5, out));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(out[k], 0.5f * (decoded(image, 1, 2, k) + decoded(image, 2, 2, k)), 1e-6);
    // Halfway vertically, and the centre of four pixels.
    ASSERT_TRUE(rad::sampleBilinearLinear(view, 3.5, 2.0, out));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(out[k], 0.5f * (decoded(image, 3, 1, k) + decoded(image, 3, 2, k)), 1e-6);
    ASSERT_TRUE(rad::sampleBilinearLinear(view, 1.0, 3.0, out));
    for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(out[k],
                    0.25f * (decoded(image, 0, 2, k) + decoded(image, 1, 2, k) + decoded(image, 0, 3, k) + decoded(image, 1, 3, k)),
                    1e-6);
    // A quarter of the way from (0, 0) to (1, 0): weights 3/4 and 1/4.
    ASSERT_TRUE(rad::sampleBilinearLinear(view, 0.75, 0.5, out));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(out[k], 0.75f * decoded(image, 0, 0, k) + 0.25f * decoded(image, 1, 0, k), 1e-6);

    // Decoding before interpolating matters: black and white give 0.5 linear, not decode(127.5).
    rad::Image8 bw(2, 1);
    for (int k = 0; k < 3; ++k) bw.rgb[3 + k] = 255;
    ASSERT_TRUE(rad::sampleBilinearLinear(bw.view(), 1.0, 0.5, out));
    EXPECT_FLOAT_EQ(out[0], 0.5f);
}

TEST(RgbImage, BorderIsClampedAndOutsideIsRefused) {
    const rad::Image8 image = randomImage(4, 3, 2);
    const rad::ImageView8 view = image.view();
    float out[3], ref[3];
    // Within half a pixel of the border: the border pixels' values (no fading to black).
    ASSERT_TRUE(rad::sampleBilinearLinear(view, 0.0, 0.0, out));
    for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(out[k], decoded(image, 0, 0, k));
    ASSERT_TRUE(rad::sampleBilinearLinear(view, 4.0, 3.0, out));
    for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(out[k], decoded(image, 3, 2, k));
    ASSERT_TRUE(rad::sampleBilinearLinear(view, 0.2, 1.5, out));
    ASSERT_TRUE(rad::sampleBilinearLinear(view, 0.5, 1.5, ref));
    for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(out[k], ref[k]);
    ASSERT_TRUE(rad::sampleBilinearLinear(view, 2.0, 2.9, out));  // interpolated along u, clamped along v
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(out[k], 0.5f * (decoded(image, 1, 2, k) + decoded(image, 2, 2, k)), 1e-6);

    // Outside [0, w] x [0, h], or not finite: false, output untouched.
    for (const auto& uv : {std::pair<double, double>{-0.01, 1.0}, {4.01, 1.0}, {1.0, -1e-9}, {1.0, 3.5},
                           {std::nan(""), 1.0}, {1.0, INFINITY}}) {
        out[0] = out[1] = out[2] = -3.0f;
        EXPECT_FALSE(rad::sampleBilinearLinear(view, uv.first, uv.second, out)) << uv.first << ", " << uv.second;
        EXPECT_EQ(out[0], -3.0f);
        EXPECT_EQ(out[2], -3.0f);
    }
    // An empty view samples nothing.
    EXPECT_FALSE(rad::sampleBilinearLinear(rad::ImageView8{}, 0.0, 0.0, out));
    // A single pixel is constant everywhere inside.
    const rad::Image8 one = randomImage(1, 1, 3);
    ASSERT_TRUE(rad::sampleBilinearLinear(one.view(), 0.9, 0.1, out));
    for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(out[k], decoded(one, 0, 0, k));
}

TEST(RgbImage, StridedBgraViewSamplesLikeThePackedRgbImage) {
    const int w = 7, h = 5;
    const rad::Image8 image = randomImage(w, h, 4);
    // QImage::Format_RGB32 on little-endian: 32-bit 0xffRRGGBB words, i.e. bytes B, G, R, 0xFF;
    // rows padded here to a stride larger than 4 w to exercise rowStride.
    const std::ptrdiff_t stride = 4 * w + 12;
    std::vector<std::uint8_t> bgra(std::size_t(stride) * h, 0xAB);
    for (int r = 0; r < h; ++r)
        for (int c = 0; c < w; ++c) {
            std::uint8_t* p = &bgra[std::size_t(r) * stride + 4 * c];
            const std::uint8_t* rgb = &image.rgb[(std::size_t(r) * w + c) * 3];
            p[0] = rgb[2];
            p[1] = rgb[1];
            p[2] = rgb[0];
            p[3] = 0xFF;
        }
    rad::ImageView8 view;
    view.data = bgra.data();
    view.width = w;
    view.height = h;
    view.rowStride = stride;
    view.pixelStride = 4;
    view.channelOffset[0] = 2;
    view.channelOffset[1] = 1;
    view.channelOffset[2] = 0;

    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0.0, w), v(0.0, h);
    for (int i = 0; i < 500; ++i) {
        const double su = u(rng), sv = v(rng);
        float a[3], b[3];
        ASSERT_TRUE(rad::sampleBilinearLinear(image.view(), su, sv, a));
        ASSERT_TRUE(rad::sampleBilinearLinear(view, su, sv, b));
        for (int k = 0; k < 3; ++k) EXPECT_EQ(a[k], b[k]) << su << ", " << sv;
    }
    // Pixel addressing itself.
    EXPECT_EQ(view.pixel(3, 2), bgra.data() + 2 * stride + 12);
    EXPECT_EQ(image.view().pixel(3, 2), image.rgb.data() + (2 * w + 3) * 3);
}

}  // namespace
