#include "radiance/basis.h"
#include "radiance/spherical_harmonics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <vector>

namespace {

TEST(Basis, CoefficientCountsMatchEnumeration) {
    for (int d = 0; d <= rad::kMaxPolynomialDegree; ++d) {
        int monomials = 0;
        for (int i = 0; i <= d; ++i)
            for (int j = 0; j + i <= d; ++j) ++monomials;
        EXPECT_EQ((rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, d}.coefficientCount()), monomials);
    }
    for (int d = 0; d <= rad::kMaxHarmonicDegree; ++d) {
        int harmonics = 0;
        for (int l = 0; l <= d; ++l) harmonics += 2 * l + 1;
        EXPECT_EQ((rad::BasisSpec{rad::BasisKind::SphericalHarmonics, d}.coefficientCount()), harmonics);
    }
    // The paper's figures: PB(4) has 15 coefficients per channel, SH(2,3,6,8) 9, 16, 49, 81.
    EXPECT_EQ((rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, 4}.coefficientCount()), 15);
    EXPECT_EQ((rad::BasisSpec{rad::BasisKind::SphericalHarmonics, 8}.coefficientCount()), 81);
}

TEST(Basis, ParseAndNameRoundTrip) {
    for (int d = 0; d <= rad::kMaxPolynomialDegree; ++d) {
        const rad::BasisSpec spec{rad::BasisKind::HemisphericalPolynomial, d};
        const auto parsed = rad::BasisSpec::parse(spec.name());
        ASSERT_TRUE(parsed.has_value()) << spec.name();
        EXPECT_EQ(*parsed, spec);
    }
    const auto sh = rad::BasisSpec::parse("sh10");
    ASSERT_TRUE(sh.has_value());
    EXPECT_EQ(sh->kind, rad::BasisKind::SphericalHarmonics);
    EXPECT_EQ(sh->degree, 10);
    for (const char* bad : {"", "PB", "PB9", "SH11", "XX3", "PB-1", "PB4x", "SH 4", "PB100"})
        EXPECT_FALSE(rad::BasisSpec::parse(bad).has_value()) << bad;
}

TEST(Basis, ValidityRanges) {
    EXPECT_TRUE((rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, 6}.isValid()));
    EXPECT_FALSE((rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, rad::kMaxPolynomialDegree + 1}.isValid()));
    EXPECT_TRUE((rad::BasisSpec{rad::BasisKind::SphericalHarmonics, 8}.isValid()));
    EXPECT_FALSE((rad::BasisSpec{rad::BasisKind::SphericalHarmonics, -1}.isValid()));
    EXPECT_FALSE((rad::BasisSpec{static_cast<rad::BasisKind>(7), 2}.isValid()));
}

TEST(Basis, PolynomialIndexIsABijection) {
    for (int d = 0; d <= rad::kMaxPolynomialDegree; ++d) {
        std::set<int> seen;
        for (int i = 0; i <= d; ++i)
            for (int j = 0; i + j <= d; ++j) seen.insert(rad::polynomialIndex(i, j));
        const int k = rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, d}.coefficientCount();
        ASSERT_EQ(static_cast<int>(seen.size()), k);
        EXPECT_EQ(*seen.begin(), 0);
        EXPECT_EQ(*seen.rbegin(), k - 1);
    }
}

TEST(Basis, PolynomialValuesAreMonomialsOfTheTangentCoordinates) {
    std::mt19937 rng(3);
    std::normal_distribution<double> g;
    for (int trial = 0; trial < 50; ++trial) {
        double x = g(rng), y = g(rng), z = g(rng);
        const double len = std::sqrt(x * x + y * y + z * z);
        x /= len, y /= len, z /= len;
        for (int d = 0; d <= rad::kMaxPolynomialDegree; ++d) {
            const rad::BasisSpec spec{rad::BasisKind::HemisphericalPolynomial, d};
            std::vector<double> values(spec.coefficientCount());
            std::vector<float> valuesF(spec.coefficientCount());
            rad::evaluateBasis(spec, x, y, z, values.data());
            rad::evaluateBasis(spec, float(x), float(y), float(z), valuesF.data());
            for (int i = 0; i <= d; ++i)
                for (int j = 0; i + j <= d; ++j) {
                    const int k = rad::polynomialIndex(i, j);
                    EXPECT_NEAR(values[k], std::pow(x, i) * std::pow(y, j), 1e-13);
                    EXPECT_NEAR(valuesF[k], values[k], 1e-5);
                }
            // The PB value does not depend on the normal component (hence the border extension).
            std::vector<double> mirrored(spec.coefficientCount());
            rad::evaluateBasis(spec, x, y, -z, mirrored.data());
            for (int k = 0; k < spec.coefficientCount(); ++k) EXPECT_EQ(mirrored[k], values[k]);
        }
    }
}

TEST(Basis, HarmonicsDispatchToSphericalHarmonics) {
    const rad::BasisSpec spec{rad::BasisKind::SphericalHarmonics, 6};
    std::vector<double> viaBasis(spec.coefficientCount()), direct(spec.coefficientCount());
    const double x = 0.36, y = -0.48, z = 0.8;
    rad::evaluateBasis(spec, x, y, z, viaBasis.data());
    rad::evaluateSphericalHarmonics(6, x, y, z, direct.data());
    EXPECT_EQ(viaBasis, direct);
    // Y_0^0 = 1 / (2 sqrt(pi)).
    EXPECT_NEAR(viaBasis[0], 0.5 / std::sqrt(M_PI), 1e-15);
}

}  // namespace
