#include "radiance/view_colors.h"

#include "radiance/basis.h"
#include "radiance/radiance_frame.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace {

TEST(ViewColors, SrgbEncodingKnownValues) {
    EXPECT_EQ(rad::encodeSrgb8(0.0f), 0);
    EXPECT_EQ(rad::encodeSrgb8(1.0f), 255);
    EXPECT_EQ(rad::encodeSrgb8(0.5f), 188);        // 1.055 * 0.5^(1/2.4) - 0.055 = 0.7354
    EXPECT_EQ(rad::encodeSrgb8(0.002f), 7);        // linear segment: 12.92 * 0.002 * 255 = 6.59
    EXPECT_EQ(rad::encodeSrgb8(0.21586f), 128);    // ((128/255 + 0.055) / 1.055)^2.4 = 0.21586
    EXPECT_EQ(rad::encodeSrgb8(-3.0f), 0);
    EXPECT_EQ(rad::encodeSrgb8(7.0f), 255);
    EXPECT_EQ(rad::encodeSrgb8(std::numeric_limits<float>::quiet_NaN()), 0);
    for (int i = 1; i < 1000; ++i) EXPECT_LE(rad::encodeSrgb8((i - 1) / 999.0f), rad::encodeSrgb8(i / 999.0f));
}

TEST(ViewColors, TowardViewpointEvaluatesTheFunctionWithBorderExtension) {
    // PB(1), red = u (the tangent coordinate), green = 0.25, at the origin with normal z, tangent x.
    rad::RadianceField field(rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, 1}, 1);
    rad::storeFrame(rad::Frame{}, field.frame(0));  // tangent x, normal z
    field.channelCoefficients(0, 0)[rad::polynomialIndex(1, 0)] = 1.0f;
    field.channelCoefficients(0, 1)[rad::polynomialIndex(0, 0)] = 0.25f;
    const float position[3] = {0, 0, 0};
    float rgb[3];

    const double above[3] = {10.0, 0.0, 10.0};  // direction (1, 0, 1)/sqrt(2): u = 0.7071
    rad::radianceTowardViewpoint(field, position, above, 2.0f, rgb);
    EXPECT_NEAR(rgb[0], 2.0 * std::sqrt(0.5), 1e-5);
    EXPECT_NEAR(rgb[1], 0.5, 1e-6);
    EXPECT_NEAR(rgb[2], 0.0, 1e-7);

    const double below[3] = {3.0, 0.0, -3.0};  // below the horizon: border direction (1, 0, 0), u = 1
    rad::radianceTowardViewpoint(field, position, below, 1.0f, rgb);
    EXPECT_NEAR(rgb[0], 1.0, 1e-5);

    const double atVertex[3] = {0.0, 0.0, 0.0};  // eye at the vertex: the normal direction, u = 0
    rad::radianceTowardViewpoint(field, position, atVertex, 1.0f, rgb);
    EXPECT_NEAR(rgb[0], 0.0, 1e-6);
    EXPECT_NEAR(rgb[1], 0.25, 1e-6);
}

TEST(ViewColors, TowardViewpointRefusesANonFiniteEyeAndABadExposure) {
    rad::RadianceField field(rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, 1}, 1);
    rad::storeFrame(rad::Frame{}, field.frame(0));
    const float position[3] = {0, 0, 0};
    float rgb[3] = {7, 7, 7};
    const double eye[3] = {0, 0, 5};
    const double nanEye[3] = {0, std::nan(""), 5};
    for (float exposure : {-1.0f, std::numeric_limits<float>::infinity(), std::nanf("")})
        EXPECT_THROW(rad::radianceTowardViewpoint(field, position, eye, exposure, rgb), std::invalid_argument);
    EXPECT_THROW(rad::radianceTowardViewpoint(field, position, nanEye, 1.0f, rgb), std::invalid_argument);
    EXPECT_EQ(rgb[0], 7.0f);  // nothing written
    EXPECT_NO_THROW(rad::radianceTowardViewpoint(field, position, eye, 0.0f, rgb));  // black is allowed
}

}  // namespace
