// bake/toksvig_roughness.h: r' = (r0^4 + E[x^2] + E[y^2])^(1/4), worked out by hand here.
#include "bake/toksvig_roughness.h"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>

namespace {

TEST(ToksvigRoughness, FlatNormalsKeepTheBaseRoughness) {
    EXPECT_FLOAT_EQ(rad::toksvigRoughness(0.5f, 0.0f, 0.0f), 0.5f);
    EXPECT_FLOAT_EQ(rad::toksvigRoughness(0.0f, 0.0f, 0.0f), 0.0f);
}

TEST(ToksvigRoughness, SpreadOfNormalsAddsToAlphaSquared) {
    // r0 = 0.5: alpha0^2 = 0.0625; moments 0.05 + 0.05: alpha'^2 = 0.1625, r' = 0.1625^(1/4).
    EXPECT_NEAR(rad::toksvigRoughness(0.5f, 0.05f, 0.05f), 0.634912, 1e-5);
    // r0 = 0: r' = (0.0016 + 0.0009)^(1/4) = 0.0025^(1/4) = 0.05^(1/2).
    EXPECT_NEAR(rad::toksvigRoughness(0.0f, 0.0016f, 0.0009f), 0.2236068, 1e-6);
    // Only the trace counts: xx and yy swapped give the same.
    EXPECT_FLOAT_EQ(rad::toksvigRoughness(0.3f, 0.01f, 0.04f), rad::toksvigRoughness(0.3f, 0.04f, 0.01f));
}

TEST(ToksvigRoughness, ClampedToOneAndBadMomentsIgnored) {
    EXPECT_FLOAT_EQ(rad::toksvigRoughness(0.9f, 5.0f, 5.0f), 1.0f);
    EXPECT_FLOAT_EQ(rad::toksvigRoughness(0.5f, -1.0f, std::numeric_limits<float>::quiet_NaN()), 0.5f);
}

TEST(ToksvigRoughness, TextureHasRoughnessInGreenAndMetallicInBlue) {
    rad::MipImage moments;
    moments.width = 2;
    moments.height = 1;
    moments.data = {0, 0, 0, /* second texel */ 0.05f, 0.05f, 0.01f};
    const rad::Image8 image = rad::metallicRoughnessFromLean(moments, 0.5f, 0.2f);
    ASSERT_EQ(image.width, 2);
    ASSERT_EQ(image.height, 1);
    EXPECT_EQ(image.rgb[0], 255);
    EXPECT_EQ(image.rgb[1], 128);  // round(0.5 * 255) = 127.5 -> 128
    EXPECT_EQ(image.rgb[2], 51);   // 0.2 * 255
    EXPECT_EQ(image.rgb[4], 162);  // round(0.634912 * 255) = round(161.9)
    EXPECT_EQ(image.rgb[5], 51);
    EXPECT_THROW(rad::metallicRoughnessFromLean(moments, 1.5f, 0.0f), std::invalid_argument);
    moments.channels = 1;
    EXPECT_THROW(rad::metallicRoughnessFromLean(moments, 0.5f, 0.0f), std::invalid_argument);
}

}  // namespace
