// Tests of render/tone_mapping.h. Expected values are worked out by hand or from the published sRGB
// definition (IEC 61966-2-1: 12.92 d below 0.0031308, 1.055 d^(1/2.4) - 0.055 above; known points
// 0.5 -> 0.735357, 0.18 -> 0.461356), and from x / (1 + x) for Reinhard.
#include "render/tone_mapping.h"

#include "image/rgb_image.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace {

using rad::ToneCurve;
using rad::ToneMapping;

TEST(ToneMapping, SrgbCurveAtKnownPoints) {
    EXPECT_DOUBLE_EQ(rad::srgbEncode(0.0), 0.0);
    EXPECT_NEAR(rad::srgbEncode(1.0), 1.0, 1e-12);
    EXPECT_NEAR(rad::srgbEncode(0.5), 0.735357, 1e-6);
    EXPECT_NEAR(rad::srgbEncode(0.18), 0.461356, 1e-6);
    // Linear segment below the boundary: 12.92 d.
    EXPECT_NEAR(rad::srgbEncode(0.001), 0.01292, 1e-12);
    // At the boundary both pieces give 0.0404499...: the curve is continuous there (to 1e-7, the
    // precision of the standard's constants).
    const double b = 0.0031308;
    EXPECT_NEAR(rad::srgbEncode(b), 12.92 * b, 1e-12);
    EXPECT_NEAR(rad::srgbEncode(b + 1e-12), 12.92 * b, 1e-7);
    EXPECT_NEAR(rad::srgbEncode(b), 0.04045, 1e-5);
}

TEST(ToneMapping, EightBitCodes) {
    EXPECT_EQ(rad::toSrgb8(0.0), 0);
    EXPECT_EQ(rad::toSrgb8(1.0), 255);
    EXPECT_EQ(rad::toSrgb8(0.5), 188);   // 255 * 0.735357 = 187.52
    EXPECT_EQ(rad::toSrgb8(0.18), 118);  // 255 * 0.461356 = 117.65
    EXPECT_EQ(rad::toSrgb8(0.001), 3);   // 255 * 0.01292 = 3.29
    // Clamped to [0, 1] first, NaN -> 0.
    EXPECT_EQ(rad::toSrgb8(2.0), 255);
    EXPECT_EQ(rad::toSrgb8(-0.5), 0);
    EXPECT_EQ(rad::toSrgb8(std::numeric_limits<double>::quiet_NaN()), 0);
    EXPECT_EQ(rad::toSrgb8(std::numeric_limits<double>::infinity()), 255);
}

TEST(ToneMapping, EncodingInvertsTheDecoderOfPhotographs) {
    // image/rgb_image.h decodes photographs with the inverse curve: every code must come back.
    for (int code = 0; code < 256; ++code)
        EXPECT_EQ(rad::toSrgb8(rad::srgbToLinear(static_cast<std::uint8_t>(code))), code) << "code " << code;
}

TEST(ToneMapping, ClampCurve) {
    const ToneMapping m;  // 0 stops, clamp
    const Eigen::Vector3d d = rad::toneMap(m, Eigen::Vector3d(0.25, 1.5, -0.2));
    EXPECT_DOUBLE_EQ(d[0], 0.25);
    EXPECT_DOUBLE_EQ(d[1], 1.0);
    EXPECT_DOUBLE_EQ(d[2], 0.0);
}

TEST(ToneMapping, ReinhardCurve) {
    ToneMapping m;
    m.curve = ToneCurve::Reinhard;
    const Eigen::Vector3d d = rad::toneMap(m, Eigen::Vector3d(1.0, 3.0, 0.0));
    EXPECT_DOUBLE_EQ(d[0], 0.5);
    EXPECT_DOUBLE_EQ(d[1], 0.75);
    EXPECT_DOUBLE_EQ(d[2], 0.0);
    // Never reaches 1 for finite input; infinity maps to 1, not NaN.
    EXPECT_LT(rad::toneMap(m, Eigen::Vector3d::Constant(1e6))[0], 1.0);
    EXPECT_DOUBLE_EQ(rad::toneMap(m, Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()))[0], 1.0);
}

TEST(ToneMapping, ExposureScalesBeforeTheCurve) {
    ToneMapping m;
    m.exposureStops = 1.0;  // x 2
    EXPECT_DOUBLE_EQ(rad::toneMap(m, Eigen::Vector3d::Constant(0.3))[0], 0.6);
    EXPECT_DOUBLE_EQ(rad::toneMap(m, Eigen::Vector3d::Constant(0.7))[0], 1.0);  // 1.4, then clamped
    m.curve = ToneCurve::Reinhard;
    EXPECT_DOUBLE_EQ(rad::toneMap(m, Eigen::Vector3d::Constant(1.0))[0], 2.0 / 3.0);  // 2 / (1 + 2)
    m.exposureStops = -2.0;  // x 1/4
    EXPECT_DOUBLE_EQ(rad::toneMap(m, Eigen::Vector3d::Constant(1.0))[0], 0.25 / 1.25);
}

TEST(ToneMapping, NegativesAndNanBecomeBlack) {
    for (ToneCurve curve : {ToneCurve::Clamp, ToneCurve::Reinhard}) {
        ToneMapping m;
        m.curve = curve;
        m.exposureStops = 3.0;
        const Eigen::Vector3d d = rad::toneMap(
            m, Eigen::Vector3d(-1.0, std::numeric_limits<double>::quiet_NaN(), -std::numeric_limits<double>::infinity()));
        EXPECT_EQ(d, Eigen::Vector3d::Zero());
    }
}

TEST(ToneMapping, WholeImage) {
    rad::ImageF linear(2, 1);
    const float values[6] = {0.5f, 1.0f, 0.0f, 3.0f, -1.0f, 0.125f};
    for (int i = 0; i < 6; ++i) linear.rgb[i] = values[i];
    ToneMapping m;
    m.curve = ToneCurve::Reinhard;
    m.exposureStops = 1.0;
    // Scaled: 1, 2, 0 | 6, -2, 0.25; Reinhard: 1/2, 2/3, 0 | 6/7, 0, 1/5.
    const rad::Image8 out = rad::toneMapToSrgb8(linear, m);
    ASSERT_EQ(out.width, 2);
    ASSERT_EQ(out.height, 1);
    const double expected[6] = {0.5, 2.0 / 3.0, 0.0, 6.0 / 7.0, 0.0, 0.2};
    for (int i = 0; i < 6; ++i) {
        const double code = expected[i] <= 0.0031308 ? 12.92 * expected[i] : 1.055 * std::pow(expected[i], 1 / 2.4) - 0.055;
        EXPECT_EQ(out.rgb[i], static_cast<int>(std::lround(255 * code))) << "value " << i;
    }
    EXPECT_EQ(out.rgb[0], 188);
}

}  // namespace
