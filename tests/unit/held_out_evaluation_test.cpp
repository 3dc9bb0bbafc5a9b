// Tests of fit/held_out_evaluation.h: per-view RMS errors of the three predictions of a held-out
// photograph, on a flat grid seen by uniform photographs whose 8-bit codes are chosen here, so that
// every expected error is a hand formula in sRGB levels.
#include "fit/held_out_evaluation.h"

#include "image/rgb_image.h"
#include "radiance/radiance_frame.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace {

using Eigen::Vector3d;

double decodeSrgb(int code) {
    const double c = code / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

rad::Image8 uniformImage(int w, int h, const int code[3]) {
    rad::Image8 image(w, h);
    for (int i = 0; i < w * h; ++i)
        for (int c = 0; c < 3; ++c) image.rgb[3 * i + c] = static_cast<std::uint8_t>(code[c]);
    return image;
}

TEST(HeldOutEvaluation, ErrorsAreTheRmsOfEachPredictionInSrgbLevels) {
    rad::TriangleMesh mesh;
    radtest::addGrid(mesh, 6);  // 36 vertices on [-1, 1]^2, z = 0, normals +z
    const int a1[3] = {100, 120, 140}, a2[3] = {120, 140, 160}, b[3] = {130, 100, 90}, meanCode[3] = {110, 110, 110};
    const rad::Image8 imageA1 = uniformImage(64, 48, a1), imageA2 = uniformImage(64, 48, a2),
                      imageB = uniformImage(64, 48, b);
    auto camera = [](const Vector3d& eye) {
        return rad::PinholeCamera::lookAt(eye, Vector3d::Zero(), Vector3d(0, 1, 0), 70, 64, 48);
    };
    const std::vector<rad::CalibratedView> training{{camera(Vector3d(0.5, 0.2, 5)), imageA1.view()},
                                                    {camera(Vector3d(-0.6, 0.1, 5)), imageA2.view()}};
    // Held-out: one view that sees the grid, one from below that sees nothing.
    const std::vector<rad::CalibratedView> heldOut{{camera(Vector3d(0.1, -0.7, 5)), imageB.view()},
                                                   {camera(Vector3d(0.1, 0.3, -5)), imageB.view()}};
    // The "fitted" field is the constant that the held-out photograph shows: its error is 0.
    rad::RadianceField field(rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, 1}, mesh.vertexCount(), false);
    std::vector<float> mean(3 * mesh.vertexCount());
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
        rad::storeFrame(rad::frameFromNormal(Vector3d(0, 0, 1)), field.frame(v));
        for (int c = 0; c < 3; ++c) {
            field.vertexCoefficients(v)[c * 3] = static_cast<float>(decodeSrgb(b[c]));
            mean[3 * v + c] = static_cast<float>(decodeSrgb(meanCode[c]));
        }
    }
    const rad::HeldOutEvaluation e = rad::evaluateHeldOutViews(mesh, field, mean, training, heldOut);
    ASSERT_EQ(e.views.size(), 2u);
    EXPECT_EQ(e.views[0].vertices, mesh.vertexCount());
    EXPECT_EQ(e.views[1].vertices, 0u);
    EXPECT_EQ(e.viewsCompared, 1u);
    EXPECT_NEAR(e.views[0].fitted, 0.0, 1e-3);
    EXPECT_NEAR(e.views[0].constant, std::sqrt((20.0 * 20 + 10 * 10 + 20 * 20) / 3), 1e-3);
    // Projection: the average of the training codes, (110, 130, 150).
    EXPECT_NEAR(e.views[0].projection, std::sqrt((20.0 * 20 + 30 * 30 + 60 * 60) / 3), 1e-3);
    EXPECT_EQ(e.fittedNotWorseThanConstant, 1u);
    EXPECT_NEAR(e.meanRatioToProjection, 0.0, 1e-4);

    // A vertex that no training view sees is not compared: move the training cameras so that they
    // see only the half x > 0 of the grid (a narrow field of view aimed there).
    auto narrow = [](const Vector3d& eye, const Vector3d& target) {
        return rad::PinholeCamera::lookAt(eye, target, Vector3d(0, 1, 0), 12, 64, 48);
    };
    const std::vector<rad::CalibratedView> half{{narrow(Vector3d(0.6, 0, 5), Vector3d(0.6, 0, 0)), imageA1.view()}};
    const rad::HeldOutEvaluation h = rad::evaluateHeldOutViews(mesh, field, mean, half, heldOut);
    std::size_t expected = 0;
    const rad::PinholeCamera c = half[0].camera;
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
        double u, w;
        const Vector3d X(mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]);
        expected += c.project(X, u, w) && c.isInside(u, w, 2.0);
    }
    ASSERT_GT(expected, 0u);
    ASSERT_LT(expected, mesh.vertexCount());
    EXPECT_EQ(h.views[0].vertices, expected);
    EXPECT_NEAR(h.views[0].projection, std::sqrt((30.0 * 30 + 20 * 20 + 50 * 50) / 3), 1e-3);
}

TEST(HeldOutEvaluation, MismatchedSizesAreRefused) {
    rad::TriangleMesh mesh;
    radtest::addGrid(mesh, 3);
    rad::RadianceField field(rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, 1}, 4, false);
    EXPECT_THROW(rad::evaluateHeldOutViews(mesh, field, std::vector<float>(27), {}, {}), std::invalid_argument);
}

TEST(HeldOutEvaluation, SrgbLevelIsTheContinuousTransferFunction) {
    EXPECT_DOUBLE_EQ(rad::srgbLevel(0.0), 0.0);
    EXPECT_DOUBLE_EQ(rad::srgbLevel(1.0), 255.0);
    EXPECT_DOUBLE_EQ(rad::srgbLevel(2.0), 255.0);
    for (int code : {1, 10, 50, 128, 200, 254}) EXPECT_NEAR(rad::srgbLevel(decodeSrgb(code)), code, 1e-9);
}

}  // namespace
