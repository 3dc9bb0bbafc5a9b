// From 3DGS conventions to ours: our SH with the converted coefficients, evaluated toward the viewer,
// equals the reference implementation's eval_sh (splat_test_support.h, transcribed from its code)
// evaluated from the camera to the splat; the sRGB decoding, the opacity and the covariance against
// values written out by hand.
#include "splats/splat_radiance_conventions.h"

#include "radiance/spherical_harmonics.h"

#include "splat_test_support.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <random>

namespace {

TEST(SplatRadianceConventions, ConvertedShTowardTheViewerEqualsTheReferenceFromTheCamera) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int degree = 0; degree <= 3; ++degree) {
        const int k = (degree + 1) * (degree + 1);
        for (int trial = 0; trial < 50; ++trial) {
            std::vector<float> splat(k);
            for (float& c : splat) c = u(rng);
            std::vector<double> ours(k), y(k);
            rad::toViewerShCoefficients(degree, splat.data(), ours.data());
            // A camera at c sees the splat at mu along d = mu - c; the viewer's direction is w = -d.
            const Eigen::Vector3d mu(0.3, -0.2, 0.5);
            const Eigen::Vector3d w = radtest::randomUnit(rng);
            const Eigen::Vector3d camera = mu + 4.0 * w;
            rad::evaluateSphericalHarmonics(degree, w.x(), w.y(), w.z(), y.data());
            double value = 0.0;
            for (int j = 0; j < k; ++j) value += ours[j] * y[j];
            EXPECT_NEAR(value, splattest::referenceEvalSh(degree, splat, (mu - camera).normalized()), 1e-6)
                << "degree " << degree;
            EXPECT_NEAR(std::max(0.0, value + 0.5), splattest::referenceSplatColor(degree, splat, mu, camera), 1e-6);
        }
    }
}

TEST(SplatRadianceConventions, SignsOfBandOneWrittenOut) {
    // Band 1 (index 1..3 = m -1, 0, 1): l + m = 0, 1, 2, so only the m = 0 (z) coefficient flips.
    EXPECT_EQ(rad::splatToViewerShSign(0), 1.0);
    EXPECT_EQ(rad::splatToViewerShSign(1), 1.0);
    EXPECT_EQ(rad::splatToViewerShSign(2), -1.0);
    EXPECT_EQ(rad::splatToViewerShSign(3), 1.0);
    // Band 3, m = 0 (index 12): l + m = 3.
    EXPECT_EQ(rad::splatToViewerShSign(12), -1.0);
    EXPECT_EQ(rad::splatToViewerShSign(9), 1.0);  // l = 3, m = -3
}

TEST(SplatRadianceConventions, DcConstantAndOffset) {
    // A splat of display colour 0.8 everywhere has f_dc = (0.8 - 0.5) / SH_C0.
    const float dc = static_cast<float>((0.8 - 0.5) / 0.28209479177387814);
    double ours = 0.0, y = 0.0;
    rad::toViewerShCoefficients(0, &dc, &ours);
    rad::evaluateSphericalHarmonics(0, 0.0, 0.0, 1.0, &y);
    EXPECT_NEAR(ours * y + rad::kSplatColorOffset, 0.8, 1e-7);
    EXPECT_DOUBLE_EQ(rad::kSplatShC0, 0.28209479177387814);
}

TEST(SplatRadianceConventions, DisplayToLinearIsTheSrgbDecodingClamped) {
    EXPECT_DOUBLE_EQ(rad::displayToLinear(0.0), 0.0);
    EXPECT_DOUBLE_EQ(rad::displayToLinear(1.0), 1.0);
    EXPECT_NEAR(rad::displayToLinear(0.5), 0.21404114048223255, 1e-12);   // ((0.5+0.055)/1.055)^2.4
    EXPECT_NEAR(rad::displayToLinear(0.04), 0.04 / 12.92, 1e-15);         // linear segment
    EXPECT_DOUBLE_EQ(rad::displayToLinear(-0.3), 0.0);
    EXPECT_DOUBLE_EQ(rad::displayToLinear(1.7), 1.0);
}

TEST(SplatRadianceConventions, OpacityIsTheSigmoid) {
    EXPECT_DOUBLE_EQ(rad::splatOpacity(0.0), 0.5);
    EXPECT_NEAR(rad::splatOpacity(std::log(3.0)), 0.75, 1e-15);
}

TEST(SplatRadianceConventions, CovarianceOfARotatedSplat) {
    // Scales (0.1, 0.2, 0.3) turned by 90 degrees about z: quaternion (cos 45, 0, 0, sin 45), given
    // unnormalised (times 2). The x axis goes to y: variances (0.04, 0.01, 0.09) on x, y, z.
    const float logScale[3] = {std::log(0.1f), std::log(0.2f), std::log(0.3f)};
    const float q[4] = {2.0f * std::sqrt(0.5f), 0.0f, 0.0f, 2.0f * std::sqrt(0.5f)};
    const Eigen::Matrix3d c = rad::splatCovariance(logScale, q);
    EXPECT_NEAR(c(0, 0), 0.04, 1e-7);
    EXPECT_NEAR(c(1, 1), 0.01, 1e-7);
    EXPECT_NEAR(c(2, 2), 0.09, 1e-7);
    EXPECT_NEAR(c(0, 1), 0.0, 1e-7);
    // A general rotation: the covariance is R diag(s^2) R^T with R's columns the turned axes.
    const float q2[4] = {0.9f, 0.3f, -0.2f, 0.4f};
    const Eigen::Matrix3d c2 = rad::splatCovariance(logScale, q2);
    const double n = std::sqrt(0.81 + 0.09 + 0.04 + 0.16), w = 0.9 / n, x = 0.3 / n, y = -0.2 / n, z = 0.4 / n;
    Eigen::Matrix3d r;
    r << 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
        2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
        2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y);
    const Eigen::Matrix3d expected = r * Eigen::Vector3d(0.01, 0.04, 0.09).asDiagonal() * r.transpose();
    EXPECT_LT((c2 - expected).cwiseAbs().maxCoeff(), 1e-7);
}

}  // namespace
