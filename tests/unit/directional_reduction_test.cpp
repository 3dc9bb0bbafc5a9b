// Tests of simplify/directional_reduction.h: SH truncation keeps the low bands bit for bit and its L2
// error over the sphere is the norm of the dropped bands (Parseval; the integral computed here with
// a Gauss-Legendre x uniform-azimuth product rule, exact for these polynomials and independent of
// the project's Lebedev rules); a PB4 field that is a PB2 polynomial reduces to it; the PB
// projection's residual is orthogonal to PB(d') over the hemisphere (the least-squares condition,
// same independent rule); reflected storage commutes with the reduction; identity at the same
// degree; equal-memory degrees against hand arithmetic; refusals.
#include "simplify/directional_reduction.h"

#include "radiance/radiance_evaluation.h"
#include "radiance/radiance_frame.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace {

using Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;

// Gauss-Legendre nodes and weights on [-1, 1] (Newton on the Legendre recurrence).
void gaussLegendre(int n, std::vector<double>& x, std::vector<double>& w) {
    x.assign(n, 0.0);
    w.assign(n, 0.0);
    for (int i = 0; i < n; ++i) {
        double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0.0;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1.0, p1 = z;
            for (int k = 2; k <= n; ++k) {
                const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = n * (z * p1 - p0) / (z * z - 1.0);
            const double dz = p1 / dp;
            z -= dz;
            if (std::fabs(dz) < 1e-15) break;
        }
        x[i] = z;
        w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
}

// Integral of g over the part z in [z0, z1] of the unit sphere around the frame (t, b, n):
// Gauss-Legendre in z = n.w, uniform in the azimuth. Exact for polynomials in (t.w, b.w, n.w) of
// degree < 2 * zNodes (in z) and < phiSteps (in the azimuth): every integrand below.
template <typename G>
double sphereZoneIntegral(const rad::Frame& f, double z0, double z1, int zNodes, int phiSteps, G g) {
    std::vector<double> x, w;
    gaussLegendre(zNodes, x, w);
    double sum = 0.0;
    for (int i = 0; i < zNodes; ++i) {
        const double z = 0.5 * (z0 + z1) + 0.5 * (z1 - z0) * x[i], r = std::sqrt(std::max(0.0, 1.0 - z * z));
        double ring = 0.0;
        for (int j = 0; j < phiSteps; ++j) {
            const double p = 2.0 * kPi * (j + 0.5) / phiSteps;
            ring += g(Vector3d(r * std::cos(p) * f.t + r * std::sin(p) * f.b + z * f.n));
        }
        sum += 0.5 * (z1 - z0) * w[i] * ring * 2.0 * kPi / phiSteps;
    }
    return sum;
}

// A field of `count` vertices with random frames and random coefficients in [-1, 1].
rad::RadianceField randomField(rad::BasisSpec basis, std::size_t count, bool reflected, std::mt19937& rng) {
    rad::RadianceField field(basis, count, reflected);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (std::size_t v = 0; v < count; ++v) {
        rad::storeFrame(rad::frameFromNormalAndTangent(radtest::randomUnit(rng), radtest::randomUnit(rng)), field.frame(v));
        for (int k = 0; k < field.coefficientsPerVertex(); ++k) field.vertexCoefficients(v)[k] = static_cast<float>(u(rng));
    }
    return field;
}

std::vector<double> channelBlock(const rad::RadianceField& f, std::size_t v) {
    const float* c = f.vertexCoefficients(v);
    return std::vector<double>(c, c + f.coefficientsPerVertex());
}

TEST(DirectionalReduction, ShTruncationIsParseval) {
    std::mt19937 rng(7);
    const rad::BasisSpec high{rad::BasisKind::SphericalHarmonics, 6}, low{rad::BasisKind::SphericalHarmonics, 3};
    for (bool reflected : {false, true}) {
        const rad::RadianceField field = randomField(high, 5, reflected, rng);
        const rad::RadianceField reduced = rad::reduceDirectionalDegree(field, low);
        ASSERT_EQ(reduced.basis, low);
        EXPECT_EQ(reduced.reflected, reflected);
        EXPECT_EQ(reduced.frames, field.frames);
        ASSERT_TRUE(reduced.validate().empty());
        for (std::size_t v = 0; v < 5; ++v) {
            for (int c = 0; c < 3; ++c)
                for (int k = 0; k < 16; ++k)
                    ASSERT_EQ(reduced.channelCoefficients(v, c)[k], field.channelCoefficients(v, c)[k]);
            const std::vector<double> a = channelBlock(field, v), b = channelBlock(reduced, v);
            const rad::Frame canonical;
            for (int c = 0; c < 3; ++c) {
                double dropped = 0.0;
                for (int k = 16; k < 49; ++k) dropped += a[c * 49 + k] * a[c * 49 + k];
                // Degree 12 integrand: 8 nodes in z and 16 azimuths are exact; use more anyway.
                const double l2 = sphereZoneIntegral(canonical, -1.0, 1.0, 12, 32, [&](const Vector3d& w) {
                    const double d = radtest::harmonicValue(high, a, w)[c] - radtest::harmonicValue(low, b, w)[c];
                    return d * d;
                });
                EXPECT_NEAR(l2, dropped, 1e-10 * dropped) << "vertex " << v << " channel " << c;
                EXPECT_GT(dropped, 0.1);
            }
        }
    }
}

TEST(DirectionalReduction, Pb4FieldThatIsPb2ReducesExactly) {
    std::mt19937 rng(11);
    const rad::BasisSpec high{rad::BasisKind::HemisphericalPolynomial, 4}, low{rad::BasisKind::HemisphericalPolynomial, 2};
    for (bool reflected : {false, true}) {
        rad::RadianceField field = randomField(high, 20, reflected, rng);
        for (std::size_t v = 0; v < 20; ++v)
            for (int c = 0; c < 3; ++c)
                for (int k = 6; k < 15; ++k) field.channelCoefficients(v, c)[k] = 0.0f;  // degree 3 and 4 terms
        const rad::RadianceField reduced = rad::reduceDirectionalDegree(field, low);
        ASSERT_EQ(reduced.basis, low);
        EXPECT_EQ(reduced.reflected, reflected);
        EXPECT_EQ(reduced.frames, field.frames);
        for (std::size_t v = 0; v < 20; ++v) {
            for (int c = 0; c < 3; ++c)
                for (int k = 0; k < 6; ++k)  // same monomial order in both bases up to degree 2
                    EXPECT_NEAR(reduced.channelCoefficients(v, c)[k], field.channelCoefficients(v, c)[k], 1e-5);
            for (int i = 0; i < 10; ++i) {
                const Vector3d w = radtest::randomUnit(rng);
                EXPECT_LT((rad::evaluateRadiance(reduced, v, w) - rad::evaluateRadiance(field, v, w)).norm(), 1e-5);
            }
        }
    }
}

// Least squares over the hemisphere: <f - Pf, u^i v^j> = 0 for every monomial of PB(d'), and Pf is
// no farther from f than the plain truncation (which is another element of PB(d')).
TEST(DirectionalReduction, PbProjectionResidualIsOrthogonalOverTheHemisphere) {
    std::mt19937 rng(3);
    const rad::BasisSpec high{rad::BasisKind::HemisphericalPolynomial, 5}, low{rad::BasisKind::HemisphericalPolynomial, 2};
    const rad::RadianceField field = randomField(high, 4, false, rng);
    const rad::RadianceField reduced = rad::reduceDirectionalDegree(field, low);
    for (std::size_t v = 0; v < 4; ++v) {
        const rad::Frame f = rad::frameFromStored(field.frame(v));
        const std::vector<double> a = channelBlock(field, v), b = channelBlock(reduced, v);
        std::vector<double> truncated(3 * 6);
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 6; ++k) truncated[c * 6 + k] = a[c * 21 + k];
        for (int c = 0; c < 3; ++c) {
            auto residual = [&](const Vector3d& w) {
                return radtest::polynomialValue(high, a, f, w)[c] - radtest::polynomialValue(low, b, f, w)[c];
            };
            double norm2 = 0.0;
            for (int i = 0; i <= 2; ++i)
                for (int j = 0; i + j <= 2; ++j) {
                    const double dot = sphereZoneIntegral(f, 0.0, 1.0, 12, 32, [&](const Vector3d& w) {
                        return residual(w) * std::pow(f.t.dot(w), i) * std::pow(f.b.dot(w), j);
                    });
                    EXPECT_NEAR(dot, 0.0, 1e-5) << "vertex " << v << " channel " << c << " u^" << i << " v^" << j;
                }
            norm2 = sphereZoneIntegral(f, 0.0, 1.0, 12, 32, [&](const Vector3d& w) { return residual(w) * residual(w); });
            const double truncation2 = sphereZoneIntegral(f, 0.0, 1.0, 12, 32, [&](const Vector3d& w) {
                const double d = radtest::polynomialValue(high, a, f, w)[c] - radtest::polynomialValue(low, truncated, f, w)[c];
                return d * d;
            });
            EXPECT_LT(norm2, truncation2);
        }
    }
}

// Reducing the reflected storage gives the reflected storage of the reduced plain field.
TEST(DirectionalReduction, CommutesWithReflectedStorage) {
    std::mt19937 rng(5);
    for (const auto& pair : {std::make_pair(rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, 4},
                                            rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, 1}),
                             std::make_pair(rad::BasisSpec{rad::BasisKind::SphericalHarmonics, 5},
                                            rad::BasisSpec{rad::BasisKind::SphericalHarmonics, 2})}) {
        const rad::RadianceField plain = randomField(pair.first, 10, false, rng);
        rad::RadianceField reflected = plain;
        rad::setReflectedStorage(reflected, true);
        rad::RadianceField a = rad::reduceDirectionalDegree(reflected, pair.second);
        rad::RadianceField b = rad::reduceDirectionalDegree(plain, pair.second);
        rad::setReflectedStorage(b, true);
        ASSERT_EQ(a.coefficients.size(), b.coefficients.size());
        for (std::size_t i = 0; i < a.coefficients.size(); ++i)
            EXPECT_NEAR(a.coefficients[i], b.coefficients[i], 1e-4) << pair.first.name() << " " << i;
    }
}

TEST(DirectionalReduction, SameDegreeIsIdentity) {
    std::mt19937 rng(1);
    for (const rad::BasisSpec basis : {rad::BasisSpec{rad::BasisKind::HemisphericalPolynomial, 3},
                                       rad::BasisSpec{rad::BasisKind::SphericalHarmonics, 4}}) {
        const rad::RadianceField field = randomField(basis, 6, true, rng);
        const rad::RadianceField same = rad::reduceDirectionalDegree(field, basis);
        EXPECT_EQ(same.basis, basis);
        EXPECT_EQ(same.reflected, true);
        EXPECT_EQ(same.coefficients, field.coefficients);
        EXPECT_EQ(same.frames, field.frames);
    }
}

TEST(DirectionalReduction, Refusals) {
    std::mt19937 rng(2);
    const rad::RadianceField pb = randomField({rad::BasisKind::HemisphericalPolynomial, 3}, 2, false, rng);
    const rad::RadianceField sh = randomField({rad::BasisKind::SphericalHarmonics, 3}, 2, false, rng);
    EXPECT_THROW(rad::reduceDirectionalDegree(pb, {rad::BasisKind::SphericalHarmonics, 1}), std::invalid_argument);
    EXPECT_THROW(rad::reduceDirectionalDegree(sh, {rad::BasisKind::HemisphericalPolynomial, 1}), std::invalid_argument);
    EXPECT_THROW(rad::reduceDirectionalDegree(pb, {rad::BasisKind::HemisphericalPolynomial, 4}), std::invalid_argument);
    EXPECT_THROW(rad::reduceDirectionalDegree(sh, {rad::BasisKind::SphericalHarmonics, 5}), std::invalid_argument);
    EXPECT_THROW(rad::reduceDirectionalDegree(pb, {rad::BasisKind::HemisphericalPolynomial, -1}), std::invalid_argument);
    rad::RadianceField broken = pb;
    broken.coefficients.pop_back();
    EXPECT_THROW(rad::reduceDirectionalDegree(broken, {rad::BasisKind::HemisphericalPolynomial, 1}), std::invalid_argument);
    EXPECT_THROW(rad::equalMemoryDegree(pb, 0.0), std::invalid_argument);
    EXPECT_THROW(rad::equalMemoryDegree(pb, 1.5), std::invalid_argument);
    EXPECT_THROW(rad::equalMemoryDegree(pb, 0.5, -1.0), std::invalid_argument);
    EXPECT_THROW(rad::equalMemoryDegree(rad::BasisSpec{rad::BasisKind::SphericalHarmonics, 11}, 0.5), std::invalid_argument);
}

// Per original vertex, with F = 2V (24 B of faces per vertex):
//   PB4: 12 + 12*15 + 24 + 24 = 240. A reduction to PB(d) costs 60 + 12 K(d): 72, 96, 132, 180, 240.
//     r = 0.5 -> 120: PB2 (|132 - 120| = 12 < |96 - 120| = 24); r = 0.25 -> 60: PB0; r = 1 -> PB4.
//   SH6: 12 + 12*49 + 12 + 24 = 636. A reduction to SH(d) costs 48 + 12 (d+1)^2: 60, 96, 156, 240, 348...
//     r = 0.25 -> 159: SH2; r = 0.5 -> 318: SH4 (|348 - 318| = 30 < |240 - 318| = 78).
//   Without faces (facesPerVertex 0): PB4 216 per vertex, r = 0.5 -> 108 vs 36 + 12 K: 48, 72, 108 -> PB2 exactly.
TEST(DirectionalReduction, EqualMemoryDegreeByHand) {
    const rad::BasisSpec pb4{rad::BasisKind::HemisphericalPolynomial, 4}, sh6{rad::BasisKind::SphericalHarmonics, 6};
    EXPECT_EQ(rad::equalMemoryDegree(pb4, 0.5), 2);
    EXPECT_EQ(rad::equalMemoryDegree(pb4, 0.25), 0);
    EXPECT_EQ(rad::equalMemoryDegree(pb4, 1.0), 4);
    EXPECT_EQ(rad::equalMemoryDegree(sh6, 0.25), 2);
    EXPECT_EQ(rad::equalMemoryDegree(sh6, 0.5), 4);
    EXPECT_EQ(rad::equalMemoryDegree(pb4, 0.5, 0.0), 2);
    EXPECT_EQ(rad::equalMemoryDegree(rad::RadianceField(sh6, 1), 0.5), 4);  // the field overload
    EXPECT_EQ(rad::equalMemoryDegree(pb4, 1e-3), 0);                       // never below degree 0
}

}  // namespace
