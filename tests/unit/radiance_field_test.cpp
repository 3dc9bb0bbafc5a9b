#include "radiance/radiance_field.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace {

rad::RadianceField unitFrames(rad::BasisSpec basis, std::size_t n) {
    rad::RadianceField field(basis, n);
    for (std::size_t v = 0; v < n; ++v) {
        float* f = field.frame(v);
        f[0] = 1; f[1] = 0; f[2] = 0;  // tangent x
        f[3] = 0; f[4] = 0; f[5] = 1;  // normal z
    }
    return field;
}

TEST(RadianceField, SizesAndLayout) {
    const rad::BasisSpec pb4{rad::BasisKind::HemisphericalPolynomial, 4};
    rad::RadianceField field = unitFrames(pb4, 7);
    EXPECT_EQ(field.vertexCount(), 7u);
    EXPECT_EQ(field.coefficientsPerChannel(), 15);
    EXPECT_EQ(field.coefficientsPerVertex(), 45);
    EXPECT_EQ(field.coefficients.size(), 7u * 45u);
    EXPECT_EQ(field.frames.size(), 7u * 6u);
    // coefficients[(v * 3 + c) * K + k]
    field.channelCoefficients(5, 2)[3] = 42.0f;
    EXPECT_EQ(field.coefficients[(5 * 3 + 2) * 15 + 3], 42.0f);
    EXPECT_EQ(field.vertexCoefficients(5) + 2 * 15 + 3, &field.coefficients[(5 * 3 + 2) * 15 + 3]);
    EXPECT_EQ(field.frame(3), field.frames.data() + 18);
    EXPECT_TRUE(field.validate().empty()) << field.validate();
}

TEST(RadianceField, ValidateReportsEachProblem) {
    const rad::BasisSpec sh3{rad::BasisKind::SphericalHarmonics, 3};
    {
        rad::RadianceField field = unitFrames(sh3, 4);
        field.coefficients.pop_back();
        EXPECT_NE(field.validate().find("expected"), std::string::npos);
    }
    {
        rad::RadianceField field = unitFrames(sh3, 4);
        field.channelCoefficients(2, 1)[0] = std::numeric_limits<float>::quiet_NaN();
        EXPECT_NE(field.validate().find("vertex 2"), std::string::npos) << field.validate();
    }
    {
        rad::RadianceField field = unitFrames(sh3, 4);
        field.frame(3)[5] = 2.0f;
        EXPECT_NE(field.validate().find("not unit length"), std::string::npos);
    }
    {
        rad::RadianceField field = unitFrames(sh3, 4);
        field.frame(1)[0] = std::numeric_limits<float>::infinity();
        EXPECT_NE(field.validate().find("not finite"), std::string::npos);
    }
    {
        rad::RadianceField field = unitFrames(sh3, 4);
        field.basis.degree = 99;
        EXPECT_NE(field.validate().find("unsupported"), std::string::npos);
    }
    {
        rad::RadianceField field = unitFrames(sh3, 4);
        field.frames.push_back(0.0f);
        EXPECT_NE(field.validate().find("whole number"), std::string::npos);
    }
}

TEST(RadianceField, EmptyFieldIsValid) {
    rad::RadianceField field(rad::BasisSpec{rad::BasisKind::SphericalHarmonics, 2}, 0);
    EXPECT_EQ(field.vertexCount(), 0u);
    EXPECT_TRUE(field.validate().empty());
}

}  // namespace
