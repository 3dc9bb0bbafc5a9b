// Tests of radiance/lebedev_quadrature.h against closed-form integrals: the sphere monomial integral
//   int_S2 x^a y^b z^c = 2 G((a+1)/2) G((b+1)/2) G((c+1)/2) / G((a+b+c+3)/2)   (a, b, c all even)
//                      = 0                                                     (otherwise)
// (G = Gamma; e.g. G. B. Folland, "How to integrate a polynomial over a sphere", Amer. Math.
// Monthly 108(5), 2001), and SH orthonormality (checked independently in spherical_harmonics_test).
#include "radiance/lebedev_quadrature.h"
#include "radiance/spherical_harmonics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace {

constexpr double kPi = 3.14159265358979323846;

double sphereMonomialIntegral(int a, int b, int c) {
    if (a % 2 || b % 2 || c % 2) return 0.0;
    return 2.0 * std::tgamma((a + 1) / 2.0) * std::tgamma((b + 1) / 2.0) * std::tgamma((c + 1) / 2.0) /
           std::tgamma((a + b + c + 3) / 2.0);
}

struct MonomialError {
    double worst = 0.0;  // max over monomials of |Q - I| / scale
    int a = 0, b = 0, c = 0;
};

// Applies the rule (points x, y, z, weights w) to every monomial of total degree exactly `degree`
// (or all degrees <= degree when `upTo`), relative to scale = sum |w_i f(p_i)| (the size of the
// rounding error of the sum), and reports the worst. `exact` gives the true integral.
template <typename Rule, typename Exact>
MonomialError monomialErrors(const Rule& rule, int degree, bool upTo, bool zEvenOnly, Exact exact) {
    const std::size_t n = rule.size();
    std::vector<double> px((degree + 1) * n), py((degree + 1) * n), pz((degree + 1) * n);
    for (std::size_t i = 0; i < n; ++i) {
        px[i] = py[i] = pz[i] = 1.0;
        for (int k = 1; k <= degree; ++k) {
            px[k * n + i] = px[(k - 1) * n + i] * rule.x[i];
            py[k * n + i] = py[(k - 1) * n + i] * rule.y[i];
            pz[k * n + i] = pz[(k - 1) * n + i] * rule.z[i];
        }
    }
    MonomialError result;
    for (int total = upTo ? 0 : degree; total <= degree; ++total)
        for (int a = 0; a <= total; ++a)
            for (int b = 0; a + b <= total; ++b) {
                const int c = total - a - b;
                if (zEvenOnly && c % 2) continue;
                double sum = 0.0, scale = 0.0;
                for (std::size_t i = 0; i < n; ++i) {
                    const double f = rule.w[i] * px[a * n + i] * py[b * n + i] * pz[c * n + i];
                    sum += f;
                    scale += std::fabs(f);
                }
                // scale == 0 (every point on a zero of the monomial): any nonzero error counts as huge.
                const double err = std::fabs(sum - exact(a, b, c)) / std::max(scale, 1e-300);
                if (err > result.worst) result = {err, a, b, c};
            }
    return result;
}

TEST(LebedevQuadrature, AvailableRulesAreTheListedOnes) {
    const std::vector<int> expected{6,   14,  26,  38,  50,  74,  86,  110, 146, 170,
                                    194, 230, 266, 302, 350, 434, 590, 770, 974, 1202};
    EXPECT_EQ(rad::availableLebedevRules(), expected);
    const std::vector<int> precisions{3,  5,  7,  9,  11, 13, 15, 17, 19, 21,
                                      23, 25, 27, 29, 31, 35, 41, 47, 53, 59};
    for (std::size_t i = 0; i < expected.size(); ++i) {
        EXPECT_EQ(rad::lebedevPrecision(expected[i]), precisions[i]);
        EXPECT_EQ(rad::lebedevRule(expected[i]).precision, precisions[i]);
    }
}

TEST(LebedevQuadrature, SizesUnitPointsDistinctAndWeightsSumTo4Pi) {
    for (int count : rad::availableLebedevRules()) {
        const rad::SphereQuadrature& rule = rad::lebedevRule(count);
        ASSERT_EQ(static_cast<int>(rule.size()), count);
        ASSERT_EQ(rule.x.size(), rule.w.size());
        ASSERT_EQ(rule.y.size(), rule.w.size());
        ASSERT_EQ(rule.z.size(), rule.w.size());
        double sum = 0.0;
        for (std::size_t i = 0; i < rule.size(); ++i) {
            const double r2 = rule.x[i] * rule.x[i] + rule.y[i] * rule.y[i] + rule.z[i] * rule.z[i];
            EXPECT_NEAR(r2, 1.0, 1e-15) << count << " point " << i;
            sum += rule.w[i];
        }
        EXPECT_NEAR(sum, 4 * kPi, 1e-13) << count;
        // No point twice (a wrong orbit generator would duplicate points and still sum weights).
        double minDist2 = 4.0;
        for (std::size_t i = 0; i < rule.size(); ++i)
            for (std::size_t j = i + 1; j < rule.size(); ++j) {
                const double dx = rule.x[i] - rule.x[j], dy = rule.y[i] - rule.y[j], dz = rule.z[i] - rule.z[j];
                minDist2 = std::min(minDist2, dx * dx + dy * dy + dz * dz);
            }
        EXPECT_GT(minDist2, 1e-4) << count;
    }
}

TEST(LebedevQuadrature, EveryRuleIntegratesAllMonomialsUpToItsPrecision) {
    for (int count : rad::availableLebedevRules()) {
        const rad::SphereQuadrature& rule = rad::lebedevRule(count);
        const MonomialError e = monomialErrors(rule, rule.precision, true, false, sphereMonomialIntegral);
        EXPECT_LT(e.worst, 1e-13) << count << "-point rule, precision " << rule.precision << ": worst monomial x^"
                                  << e.a << " y^" << e.b << " z^" << e.c;
    }
}

TEST(LebedevQuadrature, EveryRuleFailsOnSomeMonomialJustAboveItsPrecision) {
    // Shows the previous test can detect a rule that is wrong: degree precision+1 (the first even
    // degree above; odd monomials integrate to 0 by the central symmetry of every rule).
    for (int count : rad::availableLebedevRules()) {
        const rad::SphereQuadrature& rule = rad::lebedevRule(count);
        const MonomialError e = monomialErrors(rule, rule.precision + 1, false, false, sphereMonomialIntegral);
        EXPECT_GT(e.worst, 1e-9) << count << "-point rule is unexpectedly exact at degree " << rule.precision + 1;
    }
}

TEST(LebedevQuadrature, SphericalHarmonicProductsGiveIdentityWith110Points) {
    // Products Y_i Y_j up to band 8 have degree 16 <= 17, the 110-point rule's precision.
    const int degree = 8, n = (degree + 1) * (degree + 1);
    const rad::SphereQuadrature& rule = rad::lebedevRule(110);
    std::vector<double> gram(n * n, 0.0), y(n);
    for (std::size_t p = 0; p < rule.size(); ++p) {
        rad::evaluateSphericalHarmonics(degree, rule.x[p], rule.y[p], rule.z[p], y.data());
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) gram[i * n + j] += rule.w[p] * y[i] * y[j];
    }
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            EXPECT_NEAR(gram[i * n + j], i == j ? 1.0 : 0.0, 1e-12) << "i=" << i << " j=" << j;
}

TEST(LebedevQuadrature, SphericalHarmonicProductsNotIdentityWithTooSmallRule) {
    // 86 points (precision 15) cannot integrate band-8 products of degree 16: detectable.
    const int degree = 8, n = (degree + 1) * (degree + 1);
    const rad::SphereQuadrature& rule = rad::lebedevRule(86);
    std::vector<double> gram(n * n, 0.0), y(n);
    for (std::size_t p = 0; p < rule.size(); ++p) {
        rad::evaluateSphericalHarmonics(degree, rule.x[p], rule.y[p], rule.z[p], y.data());
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) gram[i * n + j] += rule.w[p] * y[i] * y[j];
    }
    double worst = 0.0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) worst = std::max(worst, std::fabs(gram[i * n + j] - (i == j ? 1.0 : 0.0)));
    EXPECT_GT(worst, 1e-6);
}

TEST(LebedevQuadrature, PointCountForPrecisionIsTheSmallestSufficientRule) {
    EXPECT_EQ(rad::lebedevPointCountForPrecision(-3), 6);
    EXPECT_EQ(rad::lebedevPointCountForPrecision(0), 6);
    EXPECT_EQ(rad::lebedevPointCountForPrecision(3), 6);
    EXPECT_EQ(rad::lebedevPointCountForPrecision(4), 14);
    EXPECT_EQ(rad::lebedevPointCountForPrecision(16), 110);
    EXPECT_EQ(rad::lebedevPointCountForPrecision(17), 110);
    EXPECT_EQ(rad::lebedevPointCountForPrecision(18), 146);
    EXPECT_EQ(rad::lebedevPointCountForPrecision(20), 170);
    EXPECT_EQ(rad::lebedevPointCountForPrecision(31), 350);
    EXPECT_EQ(rad::lebedevPointCountForPrecision(32), 434);
    EXPECT_EQ(rad::lebedevPointCountForPrecision(36), 590);
    EXPECT_EQ(rad::lebedevPointCountForPrecision(59), 1202);
    EXPECT_THROW(rad::lebedevPointCountForPrecision(60), std::out_of_range);
    for (int degree = 0; degree <= 59; ++degree) {
        const int count = rad::lebedevPointCountForPrecision(degree);
        EXPECT_GE(rad::lebedevPrecision(count), degree);
        for (int other : rad::availableLebedevRules())
            if (other < count) {
                EXPECT_LT(rad::lebedevPrecision(other), degree);
            }
    }
}

TEST(LebedevQuadrature, UnknownPointCountThrows) {
    EXPECT_THROW(rad::lebedevRule(7), std::invalid_argument);
    EXPECT_THROW(rad::lebedevPrecision(100), std::invalid_argument);
    EXPECT_THROW(rad::hemisphereRule(0), std::invalid_argument);
}

TEST(LebedevQuadrature, HemisphereRuleIntegratesZEvenPolynomialsAndHasWeight2Pi) {
    // Exact hemisphere integral of a z-even monomial: half the sphere integral.
    const auto hemisphereEven = [](int a, int b, int c) { return 0.5 * sphereMonomialIntegral(a, b, c); };
    for (int count : rad::availableLebedevRules()) {
        const rad::HemisphereQuadrature h = rad::hemisphereRule(count);
        EXPECT_EQ(h.precision, rad::lebedevPrecision(count));
        double sum = 0.0;
        for (std::size_t i = 0; i < h.size(); ++i) {
            EXPECT_GE(h.z[i], 0.0);
            sum += h.w[i];
        }
        EXPECT_NEAR(sum, 2 * kPi, 1e-13) << count;
        const MonomialError e = monomialErrors(h, h.precision, true, true, hemisphereEven);
        EXPECT_LT(e.worst, 1e-13) << count << ": worst x^" << e.a << " y^" << e.b << " z^" << e.c;
    }
}

TEST(LebedevQuadrature, HemisphereRuleHalvesEquatorWeights) {
    // The 38-point rule has 24 (a, b, 0)-type points, 8 of them on the z = 0 equator, plus the
    // 4 octahedron vertices (+-1, 0, 0), (0, +-1, 0); the hemisphere keeps 1 + 4 + 8 + 4 + 8 = 25.
    const rad::SphereQuadrature& s = rad::lebedevRule(38);
    const rad::HemisphereQuadrature h = rad::hemisphereRule(38);
    int equator = 0, upper = 0;
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (s.z[i] == 0.0) ++equator;
        if (s.z[i] > 0.0) ++upper;
    }
    EXPECT_EQ(equator, 4 + 8);
    EXPECT_EQ(upper, 1 + 4 + 8);
    EXPECT_EQ(static_cast<int>(h.size()), equator + upper);
    for (std::size_t i = 0; i < h.size(); ++i) {
        // Find the sphere point and compare weights.
        for (std::size_t j = 0; j < s.size(); ++j)
            if (s.x[j] == h.x[i] && s.y[j] == h.y[i] && s.z[j] == h.z[i]) {
                EXPECT_DOUBLE_EQ(h.w[i], h.z[i] == 0.0 ? 0.5 * s.w[j] : s.w[j]);
            }
    }
}

TEST(LebedevQuadrature, HemisphereRuleIsNotExactForZOdd) {
    // Documented limitation: int_{z>=0} z = pi, and the rule is not built for it.
    const rad::HemisphereQuadrature h = rad::hemisphereRule(110);
    double q = 0.0;
    for (std::size_t i = 0; i < h.size(); ++i) q += h.w[i] * h.z[i];
    EXPECT_GT(std::fabs(q - kPi), 1e-6);
    EXPECT_LT(std::fabs(q - kPi), 0.1);  // still a fair approximation
}

}  // namespace
