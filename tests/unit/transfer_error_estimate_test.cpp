// Tests of prt/transfer_error_estimate.h (Křivánek et al. 2004 sec. 3.3): eq. 2, 3 and 4 on hand-computed
// values, the t1 + t2 = 0 and n1 + n2 + n3 = 0 conventions, eq. 4's angle taken at n1, all channels
// used, and a small angle computed accurately.
#include "prt/transfer_error_estimate.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using rad::TransferErrorMeasure;

const float kUp[3] = {0.0f, 0.0f, 1.0f};

double contrast(const float* t1, const float* t2, const float* t3, int width) {
    return rad::triangleTransferError(TransferErrorMeasure::Contrast, 0.0, t1, t2, t3, width, kUp, kUp, kUp);
}
double difference(const float* t1, const float* t2, const float* t3, int width) {
    return rad::triangleTransferError(TransferErrorMeasure::Difference, 0.0, t1, t2, t3, width, kUp, kUp, kUp);
}
double divergence(double alpha, const float* t1, const float* t2, const float* t3, int width, const float* n1,
                  const float* n2, const float* n3) {
    return rad::triangleTransferError(TransferErrorMeasure::NormalDivergence, alpha, t1, t2, t3, width, n1, n2, n3);
}

TEST(TransferErrorEstimate, ProbedEdgeErrorIsTheMidpointDeviationOverItsScale) {
    // Ends 0 and 2 (interpolated midpoint 1), the probe says 3: deviation 2, probe magnitude 3.
    const float a[1] = {0.0f}, b[1] = {2.0f}, m[1] = {3.0f};
    EXPECT_DOUBLE_EQ(rad::probedEdgeError(TransferErrorMeasure::ProbedRelative, a, b, m, 1, 0.5), 2.0 / 3.0);
    EXPECT_DOUBLE_EQ(rad::probedEdgeError(TransferErrorMeasure::ProbedRelative, a, b, m, 1, 10.0), 0.2);  // floor
    EXPECT_DOUBLE_EQ(rad::probedEdgeError(TransferErrorMeasure::ProbedAbsolute, a, b, m, 1, 4.0), 0.5);
    // Two channels: Euclidean over both; a midpoint on the segment deviates by nothing.
    const float a2[2] = {1.0f, 0.0f}, b2[2] = {3.0f, 4.0f}, m2[2] = {5.0f, 6.0f}, on[2] = {2.0f, 2.0f};
    EXPECT_DOUBLE_EQ(rad::probedEdgeError(TransferErrorMeasure::ProbedAbsolute, a2, b2, m2, 2, 1.0), 5.0);
    EXPECT_DOUBLE_EQ(rad::probedEdgeError(TransferErrorMeasure::ProbedRelative, a2, b2, on, 2, 0.0), 0.0);
}

TEST(TransferErrorEstimate, ContrastIsTheSumOfEdgeContrasts) {
    const float t1[2] = {1, 0}, t2[2] = {0, 1}, t3[2] = {1, 1};
    // |t1 - t2| / |t1 + t2| = sqrt2 / sqrt2; |t2 - t3| / |t2 + t3| = 1 / sqrt5; |t3 - t1| / |t3 + t1| = 1 / sqrt5.
    EXPECT_NEAR(contrast(t1, t2, t3, 2), 1.0 + 2.0 / std::sqrt(5.0), 1e-12);
}

TEST(TransferErrorEstimate, ContrastEdgeWithZeroSumContributesNothing) {
    const float t1[2] = {1, -2}, t2[2] = {-1, 2}, t3[2] = {0, 0};
    // Edge 1-2: t1 + t2 = 0 -> 0. Edges 2-3 and 3-1: |t| / |t| = 1 each.
    EXPECT_NEAR(contrast(t1, t2, t3, 2), 2.0, 1e-12);
    const float zero[2] = {0, 0};
    EXPECT_EQ(contrast(zero, zero, zero, 2), 0.0);
}

TEST(TransferErrorEstimate, DifferenceIsTheSumOfEdgeDistances) {
    const float t1[3] = {0, 0, 0}, t2[3] = {3, 4, 0}, t3[3] = {3, 4, 12};
    EXPECT_NEAR(difference(t1, t2, t3, 3), 5.0 + 12.0 + 13.0, 1e-12);
}

TEST(TransferErrorEstimate, EveryChannelCounts) {
    // Width 4; the vertices differ only in the last channel.
    const float t1[4] = {1, 2, 3, 0}, t2[4] = {1, 2, 3, 2}, t3[4] = {1, 2, 3, 2};
    EXPECT_NEAR(difference(t1, t2, t3, 4), 4.0, 1e-12);
    // Contrast of the same: |(0,0,0,2)| / |(2,4,6,2)| twice.
    EXPECT_NEAR(contrast(t1, t2, t3, 4), 2.0 * 2.0 / std::sqrt(4.0 + 16.0 + 36.0 + 4.0), 1e-12);
}

TEST(TransferErrorEstimate, NormalDivergenceWithParallelNormalsIsTheDifference) {
    const float t1[3] = {0, 0, 0}, t2[3] = {3, 4, 0}, t3[3] = {3, 4, 12};
    for (const double alpha : {0.0, 1.0, 7.5})
        EXPECT_NEAR(divergence(alpha, t1, t2, t3, 3, kUp, kUp, kUp), 30.0, 1e-12);
}

TEST(TransferErrorEstimate, NormalDivergenceDividesByOnePlusAlphaTimesTheAngleAtTheFirstNormal) {
    const float t1[1] = {0}, t2[1] = {1}, t3[1] = {3};  // numerator 1 + 2 + 3 = 6
    const float x[3] = {1, 0, 0}, y[3] = {0, 1, 0}, z[3] = {0, 0, 1};
    // Mean of the three axes: (1, 1, 1) / sqrt3, at acos(1 / sqrt3) from every axis.
    const double axesAngle = std::acos(1.0 / std::sqrt(3.0));
    EXPECT_NEAR(divergence(2.0, t1, t2, t3, 1, z, x, y), 6.0 / (1.0 + 2.0 * axesAngle), 1e-12);
    // n1 = z, n2 = n3 = x: mean (2, 0, 1) / sqrt5, at acos(1 / sqrt5) from z but acos(2 / sqrt5) from x.
    EXPECT_NEAR(divergence(3.0, t1, t2, t3, 1, z, x, x), 6.0 / (1.0 + 3.0 * std::acos(1.0 / std::sqrt(5.0))), 1e-12);
    EXPECT_NEAR(divergence(3.0, t1, t2, t3, 1, x, z, x), 6.0 / (1.0 + 3.0 * std::acos(2.0 / std::sqrt(5.0))), 1e-12);
    // alpha = 0: plain eq. 3 whatever the normals.
    EXPECT_NEAR(divergence(0.0, t1, t2, t3, 1, z, x, y), 6.0, 1e-12);
}

TEST(TransferErrorEstimate, NormalsSummingToZeroCountAsAQuarterTurn) {
    // Three unit normals 120 degrees apart whose float sum is exactly zero.
    const float y = std::sqrt(0.75f);
    const float n1[3] = {1, 0, 0}, n2[3] = {-0.5f, y, 0}, n3[3] = {-0.5f, -y, 0};
    const float t1[1] = {0}, t2[1] = {1}, t3[1] = {1};  // numerator 2
    const double pi = 3.14159265358979323846;
    EXPECT_NEAR(divergence(1.5, t1, t2, t3, 1, n1, n2, n3), 2.0 / (1.0 + 1.5 * pi / 2.0), 1e-12);
}

TEST(TransferErrorEstimate, SmallAnglesAreAccurate) {
    // n2 tilted by 1e-4 rad: the mean normal is at atan(sin e / (2 + cos e)) ~ 3.3e-5 rad from n1.
    // With alpha = 3e4 the denominator is about 2, so a relative error of 1e-6 in the angle shows.
    const float e = 1e-4f;
    const float n2[3] = {std::sin(e), 0.0f, std::cos(e)};
    const double angle = std::atan2(double(n2[0]), 2.0 + double(n2[2]));
    const float t1[1] = {0}, t2[1] = {1}, t3[1] = {0};  // numerator 2
    const double alpha = 3e4;
    EXPECT_NEAR(divergence(alpha, t1, t2, t3, 1, kUp, n2, kUp), 2.0 / (1.0 + alpha * angle), 1e-9);
}

TEST(TransferErrorEstimate, DefaultAlphaIsPositiveAndFinite) {
    EXPECT_GT(rad::kDefaultNormalDivergenceAlpha, 0.0);
    EXPECT_TRUE(std::isfinite(rad::kDefaultNormalDivergenceAlpha));
}

}  // namespace
