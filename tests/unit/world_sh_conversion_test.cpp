// World-frame SH conversion of radiance functions (radiance/world_sh_conversion.h): the PB -> SH
// projection against PB and SH functions evaluated independently (test_support.h), the way back,
// and the hemisphere Gram matrix against integrals done by hand.
#include "radiance/world_sh_conversion.h"

#include "radiance/basis.h"
#include "radiance/radiance_frame.h"
#include "test_support.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <vector>

namespace {

// One PB(4) vertex with random coefficients in a tilted frame.
rad::RadianceField tiltedPbVertex(std::mt19937& random) {
    const rad::BasisSpec pb{rad::BasisKind::HemisphericalPolynomial, 4};
    rad::RadianceField field(pb, 1);
    std::uniform_real_distribution<float> value(-1.0f, 1.0f);
    for (float& c : field.coefficients) c = value(random);
    const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
    rad::Frame frame;
    frame.n = n;
    frame.t = n.unitOrthogonal();
    frame.b = n.cross(frame.t);
    rad::storeFrame(frame, field.frame(0));
    return field;
}

}  // namespace

TEST(HemisphereGramMatrix, MatchesHandComputedIntegrals) {
    // PB1: 1, u, v with (u, v) = (x, y) of the local frame. (1/2pi) int over the hemisphere of
    // 1 = 1, of x^2 = y^2 = 1/3, of x = y = xy = 0.
    const std::vector<double> g = rad::hemisphereGramMatrix({rad::BasisKind::HemisphericalPolynomial, 1});
    ASSERT_EQ(g.size(), 9u);
    EXPECT_NEAR(g[0], 1.0, 1e-12);
    EXPECT_NEAR(g[4], 1.0 / 3.0, 1e-12);
    EXPECT_NEAR(g[8], 1.0 / 3.0, 1e-12);
    EXPECT_NEAR(g[1], 0.0, 1e-12);
    EXPECT_NEAR(g[5], 0.0, 1e-12);
    // PB2 adds x^2: (1/2pi) int x^4 = 1/5, and x^2 y^2 = 1/15.
    const std::vector<double> g2 = rad::hemisphereGramMatrix({rad::BasisKind::HemisphericalPolynomial, 2});
    const int k = 6;
    const int xx = rad::polynomialIndex(2, 0), yy = rad::polynomialIndex(0, 2);
    EXPECT_NEAR(g2[xx * k + xx], 1.0 / 5.0, 1e-12);
    EXPECT_NEAR(g2[xx * k + yy], 1.0 / 15.0, 1e-12);
    EXPECT_NEAR(g2[0 * k + xx], 1.0 / 3.0, 1e-12);
}

TEST(WorldShConversion, PbInATiltedFrameIsTheSameFunctionAsWorldSh) {
    std::mt19937 random(7);
    const rad::RadianceField field = tiltedPbVertex(random);
    const rad::WorldShConversion conversion(field.basis);
    ASSERT_TRUE(conversion.convertsFrames());
    ASSERT_EQ(conversion.worldPerChannel(), 25);
    std::vector<double> world(conversion.worldPerVertex());
    conversion.toWorld(field.vertexCoefficients(0), field.frame(0), world.data());
    const rad::Frame frame = rad::frameFromStored(field.frame(0));
    const Eigen::Vector3d n = frame.n;
    const std::vector<double> coefficients(field.coefficients.begin(), field.coefficients.end());
    std::normal_distribution<double> gauss;
    int checked = 0;
    while (checked < 50) {
        Eigen::Vector3d w(gauss(random), gauss(random), gauss(random));
        w.normalize();
        if (w.dot(n) < 0.05) continue;  // the hemisphere where the PB function is defined
        const Eigen::Vector3d expected = radtest::polynomialValue(field.basis, coefficients, frame, w);
        const Eigen::Vector3d actual = radtest::harmonicValue({rad::BasisKind::SphericalHarmonics, 4}, world, w);
        EXPECT_LT((actual - expected).norm(), 1e-4 * (1.0 + expected.norm())) << "direction " << w.transpose();
        ++checked;
    }
}

TEST(WorldShConversion, BackToPbRecoversTheCoefficients) {
    std::mt19937 random(11);
    const rad::RadianceField field = tiltedPbVertex(random);
    const rad::WorldShConversion conversion(field.basis);
    std::vector<double> world(conversion.worldPerVertex());
    conversion.toWorld(field.vertexCoefficients(0), field.frame(0), world.data());
    std::vector<float> back(field.coefficientsPerVertex());
    conversion.fromWorld(world.data(), field.frame(0), back.data(), 0.5);  // divisor 0.5: every coefficient doubled
    for (int i = 0; i < field.coefficientsPerVertex(); ++i)
        EXPECT_NEAR(back[i], 2.0f * field.coefficients[i], 2e-4) << "coefficient " << i;
}

TEST(WorldShConversion, ShFieldsPassThrough) {
    const rad::BasisSpec sh{rad::BasisKind::SphericalHarmonics, 2};
    const rad::WorldShConversion conversion(sh);
    EXPECT_FALSE(conversion.convertsFrames());
    EXPECT_EQ(conversion.worldPerVertex(), 27);
    std::vector<float> coefficients(27);
    for (int i = 0; i < 27; ++i) coefficients[i] = 0.25f * i - 3.0f;
    std::vector<double> world(27);
    conversion.toWorld(coefficients.data(), nullptr, world.data());
    for (int i = 0; i < 27; ++i) EXPECT_EQ(world[i], coefficients[i]);
    std::vector<float> back(27);
    conversion.fromWorld(world.data(), nullptr, back.data(), 2.0);
    for (int i = 0; i < 27; ++i) EXPECT_FLOAT_EQ(back[i], 0.5f * coefficients[i]);
}
