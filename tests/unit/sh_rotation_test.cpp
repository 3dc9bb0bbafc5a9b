// Tests of radiance/sh_rotation.h. The reference is always the definition of the operator,
// g(w) = f(R^T w), checked by evaluating both sides with evaluateSphericalHarmonics at random
// directions, plus closed forms (rotations about z) and an independent construction of the
// blocks by exact Lebedev projection.
#include "radiance/lebedev_quadrature.h"
#include "radiance/sh_rotation.h"
#include "radiance/spherical_harmonics.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace {

constexpr int kMax = rad::kMaxHarmonicDegree;
constexpr int kCount = (kMax + 1) * (kMax + 1);

Eigen::Matrix3d randomRotation(std::mt19937& rng) {
    std::normal_distribution<double> g(0.0, 1.0);
    // A normalised Gaussian quaternion is uniform on SO(3).
    return Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
}

Eigen::Vector3d randomDirection(std::mt19937& rng) {
    std::normal_distribution<double> g(0.0, 1.0);
    Eigen::Vector3d v;
    do v = Eigen::Vector3d(g(rng), g(rng), g(rng));
    while (v.norm() < 1e-3);
    return v.normalized();
}

std::vector<double> randomCoefficients(std::mt19937& rng, int degree) {
    std::normal_distribution<double> g(0.0, 1.0);
    std::vector<double> c((degree + 1) * (degree + 1));
    for (double& v : c) v = g(rng);
    return c;
}

double evaluate(int degree, const std::vector<double>& c, const Eigen::Vector3d& w) {
    double y[kCount];
    rad::evaluateSphericalHarmonics(degree, w.x(), w.y(), w.z(), y);
    double sum = 0.0;
    for (int i = 0; i < (degree + 1) * (degree + 1); ++i) sum += c[i] * y[i];
    return sum;
}

std::vector<double> applied(const rad::ShRotation& rotation, const std::vector<double>& c) {
    std::vector<double> out(c.size());
    rotation.apply(c.data(), out.data());
    return out;
}

TEST(ShRotation, RotatedExpansionEqualsOriginalAtRotatedBackDirection) {
    std::mt19937 rng(11);
    for (int degree = 0; degree <= kMax; ++degree)
        for (int trial = 0; trial < 5; ++trial) {
            const Eigen::Matrix3d R = randomRotation(rng);
            const std::vector<double> c = randomCoefficients(rng, degree);
            const std::vector<double> rotated = applied(rad::ShRotation(degree, R), c);
            for (int k = 0; k < 30; ++k) {
                const Eigen::Vector3d w = randomDirection(rng);
                EXPECT_NEAR(evaluate(degree, rotated, w), evaluate(degree, c, R.transpose() * w), 1e-9)
                    << "degree " << degree << " trial " << trial;
            }
        }
}

TEST(ShRotation, ConventionIsNotTheTransposeOne) {
    // Guards the documented convention: g(w) = f(R^T w), NOT f(R w) (which would pass the test
    // above only for R symmetric).
    std::mt19937 rng(12);
    const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    const std::vector<double> c = randomCoefficients(rng, 4);
    const std::vector<double> rotated = applied(rad::ShRotation(4, R), c);
    double worst = 0.0;
    for (int k = 0; k < 20; ++k) {
        const Eigen::Vector3d w = randomDirection(rng);
        worst = std::max(worst, std::fabs(evaluate(4, rotated, w) - evaluate(4, c, R * w)));
    }
    EXPECT_GT(worst, 1e-3);
}

TEST(ShRotation, RotationAboutZMatchesClosedForm) {
    // Rotating by a about z shifts phi: cos(m phi) -> cos(m (phi - a)), so the (m, -m) pair turns by
    // m a: D_{m,m} = D_{-m,-m} = cos(m a), D_{-m,m} = sin(m a), D_{m,-m} = -sin(m a), all else 0.
    const double a = 0.37;
    const rad::ShRotation rotation(kMax, Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix());
    for (int l = 0; l <= kMax; ++l)
        for (int m = -l; m <= l; ++m)
            for (int mp = -l; mp <= l; ++mp) {
                double expected = 0.0;
                const int am = std::abs(m);
                if (m == mp) expected = std::cos(am * a);
                else if (m == -mp && m < 0) expected = std::sin(am * a);
                else if (m == -mp && m > 0) expected = -std::sin(am * a);
                EXPECT_NEAR(rotation.element(l, m, mp), expected, 1e-13) << "l=" << l << " m=" << m << " m'=" << mp;
            }
}

TEST(ShRotation, BlocksMatchExactLebedevProjection) {
    // Independent construction: D^l_{m,m'} = int Y_l^m(w) Y_l^m'(R^T w) dw, exact with a rule of
    // precision >= 2 kMax = 20 (170 points, precision 21).
    std::mt19937 rng(13);
    const Eigen::Matrix3d R = randomRotation(rng);
    const rad::ShRotation rotation(kMax, R);
    const rad::SphereQuadrature& rule = rad::lebedevRule(rad::lebedevPointCountForPrecision(2 * kMax));
    std::vector<double> projected(kCount * kCount, 0.0);
    double y[kCount], yr[kCount];
    for (std::size_t p = 0; p < rule.size(); ++p) {
        const Eigen::Vector3d w(rule.x[p], rule.y[p], rule.z[p]);
        const Eigen::Vector3d u = R.transpose() * w;
        rad::evaluateSphericalHarmonics(kMax, w.x(), w.y(), w.z(), y);
        rad::evaluateSphericalHarmonics(kMax, u.x(), u.y(), u.z(), yr);
        for (int i = 0; i < kCount; ++i)
            for (int j = 0; j < kCount; ++j) projected[i * kCount + j] += rule.w[p] * y[i] * yr[j];
    }
    for (int l = 0; l <= kMax; ++l)
        for (int m = -l; m <= l; ++m)
            for (int mp = -l; mp <= l; ++mp)
                EXPECT_NEAR(rotation.element(l, m, mp),
                            projected[rad::harmonicIndex(l, m) * kCount + rad::harmonicIndex(l, mp)], 1e-12)
                    << "l=" << l << " m=" << m << " m'=" << mp;
    // And nothing leaks between bands.
    for (int i = 0; i < kCount; ++i)
        for (int j = 0; j < kCount; ++j) {
            const int li = static_cast<int>(std::sqrt(double(i))), lj = static_cast<int>(std::sqrt(double(j)));
            if (li != lj) {
                EXPECT_NEAR(projected[i * kCount + j], 0.0, 1e-12);
            }
        }
}

TEST(ShRotation, CompositionAndInverse) {
    std::mt19937 rng(14);
    for (int trial = 0; trial < 10; ++trial) {
        const Eigen::Matrix3d R1 = randomRotation(rng), R2 = randomRotation(rng);
        const std::vector<double> c = randomCoefficients(rng, kMax);
        // Rotate by R2, then by R1 == rotate by R1 R2.
        const std::vector<double> twoSteps = applied(rad::ShRotation(kMax, R1), applied(rad::ShRotation(kMax, R2), c));
        const std::vector<double> oneStep = applied(rad::ShRotation(kMax, R1 * R2), c);
        for (int i = 0; i < kCount; ++i) EXPECT_NEAR(twoSteps[i], oneStep[i], 1e-11) << "index " << i;
        // R^T undoes R.
        const std::vector<double> back = applied(rad::ShRotation(kMax, R1.transpose()), applied(rad::ShRotation(kMax, R1), c));
        for (int i = 0; i < kCount; ++i) EXPECT_NEAR(back[i], c[i], 1e-11) << "index " << i;
    }
}

TEST(ShRotation, BlocksAreOrthogonal) {
    std::mt19937 rng(15);
    const rad::ShRotation rotation(kMax, randomRotation(rng));
    for (int l = 0; l <= kMax; ++l) {
        const int n = 2 * l + 1;
        const double* b = rotation.block(l);
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                double dot = 0.0;
                for (int k = 0; k < n; ++k) dot += b[i * n + k] * b[j * n + k];
                EXPECT_NEAR(dot, i == j ? 1.0 : 0.0, 1e-12) << "l=" << l;
            }
    }
}

TEST(ShRotation, IdentityAndDegreeRange) {
    const std::vector<double> c = [] {
        std::mt19937 rng(16);
        return randomCoefficients(rng, kMax);
    }();
    const std::vector<double> same = applied(rad::ShRotation(kMax, Eigen::Matrix3d::Identity()), c);
    for (int i = 0; i < kCount; ++i) EXPECT_NEAR(same[i], c[i], 1e-15);
    const std::vector<double> same2 = applied(rad::ShRotation(kMax), c);
    for (int i = 0; i < kCount; ++i) EXPECT_EQ(same2[i], c[i]);
    EXPECT_EQ(rad::ShRotation(3).coefficientCount(), 16);
    EXPECT_THROW(rad::ShRotation(-1, Eigen::Matrix3d::Identity()), std::out_of_range);
    EXPECT_THROW(rad::ShRotation(kMax + 1, Eigen::Matrix3d::Identity()), std::out_of_range);
}

TEST(ShRotation, InPlaceAndFloatApply) {
    std::mt19937 rng(17);
    const rad::ShRotation rotation(kMax, randomRotation(rng));
    const std::vector<double> c = randomCoefficients(rng, kMax);
    const std::vector<double> expected = applied(rotation, c);
    std::vector<double> inPlace = c;
    rotation.apply(inPlace.data(), inPlace.data());
    for (int i = 0; i < kCount; ++i) EXPECT_NEAR(inPlace[i], expected[i], 1e-15);
    std::vector<float> f(c.begin(), c.end()), fOut(kCount);
    rotation.apply(f.data(), fOut.data());
    for (int i = 0; i < kCount; ++i) EXPECT_NEAR(fOut[i], expected[i], 1e-5 * (1.0 + std::fabs(expected[i])));
}

TEST(ShRotation, ReflectionAboutAxisFixesAxisAndNegatesTangents) {
    std::mt19937 rng(18);
    for (int trial = 0; trial < 10; ++trial) {
        const Eigen::Vector3d n = randomDirection(rng);
        const Eigen::Vector3d t = n.unitOrthogonal();
        const Eigen::Matrix3d Rn = rad::reflectionAbout(n);
        // The 3x3 map itself: n -> n, t -> -t, a rotation (det +1), an involution.
        EXPECT_LT((Rn * n - n).norm(), 1e-15);
        EXPECT_LT((Rn * t + t).norm(), 1e-15);
        EXPECT_NEAR(Rn.determinant(), 1.0, 1e-14);
        EXPECT_LT((Rn * Rn - Eigen::Matrix3d::Identity()).norm(), 1e-14);
        // Not normalised input is normalised.
        EXPECT_LT((rad::reflectionAbout(3.0 * n) - Rn).norm(), 1e-14);

        // The SH operator, on band 1, where the coefficients ARE the vector (times c, order y z x):
        // the linear function w -> a.w becomes w -> (R_n a).w, so n stays and t flips.
        const rad::ShRotation sh = rad::reflectionAboutAxisSH(n, kMax);
        const auto band1 = [](const Eigen::Vector3d& a) {
            std::vector<double> c(kCount, 0.0);
            c[1] = a.y();
            c[2] = a.z();
            c[3] = a.x();
            return c;
        };
        const std::vector<double> nOut = applied(sh, band1(n)), tOut = applied(sh, band1(t));
        const std::vector<double> nIn = band1(n), tIn = band1(t);
        for (int i = 0; i < kCount; ++i) {
            EXPECT_NEAR(nOut[i], nIn[i], 1e-14);
            EXPECT_NEAR(tOut[i], -tIn[i], 1e-14);
        }

        // On a full random expansion: g(n) = f(n), g(t) = f(-t), g(w) = f(2(n.w)n - w), and g's
        // reflection is f again.
        const std::vector<double> c = randomCoefficients(rng, kMax);
        const std::vector<double> g = applied(sh, c);
        EXPECT_NEAR(evaluate(kMax, g, n), evaluate(kMax, c, n), 1e-9);
        EXPECT_NEAR(evaluate(kMax, g, t), evaluate(kMax, c, -t), 1e-9);
        for (int k = 0; k < 10; ++k) {
            const Eigen::Vector3d w = randomDirection(rng);
            EXPECT_NEAR(evaluate(kMax, g, w), evaluate(kMax, c, 2.0 * n.dot(w) * n - w), 1e-9);
        }
        const std::vector<double> back = applied(sh, g);
        for (int i = 0; i < kCount; ++i) EXPECT_NEAR(back[i], c[i], 1e-11);
    }
}

TEST(ShRotation, ImproperMatrixMirrorReflection) {
    // A mirror (det -1): Q = I - 2 m m^T. Still g(w) = f(Q^T w).
    std::mt19937 rng(19);
    for (int trial = 0; trial < 5; ++trial) {
        const Eigen::Vector3d m = randomDirection(rng);
        const Eigen::Matrix3d Q = Eigen::Matrix3d::Identity() - 2.0 * m * m.transpose();
        const std::vector<double> c = randomCoefficients(rng, kMax);
        const std::vector<double> g = applied(rad::ShRotation(kMax, Q), c);
        for (int k = 0; k < 10; ++k) {
            const Eigen::Vector3d w = randomDirection(rng);
            EXPECT_NEAR(evaluate(kMax, g, w), evaluate(kMax, c, Q.transpose() * w), 1e-9);
        }
    }
}

}  // namespace
