// Tests of radiance_distance.h: the L2 distance of Vanhoey et al. 2015 eq. (5)-(6) between (reflected) RF.
#include "radiance/radiance_distance.h"

#include "radiance/radiance_evaluation.h"
#include "radiance/radiance_frame.h"
#include "radiance/radiance_interpolation.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <vector>

namespace {

using Eigen::Vector3d;
using rad::BasisKind;
using rad::BasisSpec;
using rad::RadianceField;

constexpr double kPi = 3.14159265358979323846;

using radtest::randomUnit;

using radtest::bruteHemisphere;

// Two vertices, random coefficients, normals tilted by `tiltDegrees` from n0 about random axes.
RadianceField pairField(BasisSpec basis, const Vector3d& n0, double tiltDegrees, std::mt19937& rng,
                        bool reflected = false) {
    std::uniform_real_distribution<float> u(-1, 1);
    RadianceField f(basis, 2, reflected);
    for (float& c : f.coefficients) c = u(rng);
    for (std::size_t v = 0; v < 2; ++v) {
        const Vector3d axis = n0.cross(randomUnit(rng)).normalized();
        const Vector3d n = Eigen::AngleAxisd(tiltDegrees * kPi / 180, axis) * n0;
        rad::storeFrame(rad::frameFromNormalAndTangent(n, randomUnit(rng)), f.frame(v));
    }
    return f;
}

double bruteDistance2(const RadianceField& f, const Vector3d& n0, int steps) {
    const rad::VertexRadiance a = rad::vertexRadiance(f, 0), b = rad::vertexRadiance(f, 1);
    double scratch[rad::kMaxCoefficientsPerChannel];
    return bruteHemisphere(n0, steps, 2 * steps, [&](const Vector3d& w) {
        return (rad::evaluateReflectedRadiance(a, w, scratch) - rad::evaluateReflectedRadiance(b, w, scratch))
            .squaredNorm();
    });
}

TEST(RadianceDistance, GaussLegendreIsExactForPolynomials) {
    std::vector<double> x, w;
    for (int n = 1; n <= 20; ++n) {
        rad::gaussLegendre(n, 0.0, 1.0, x, w);
        for (int p = 0; p <= 2 * n - 1; ++p) {
            double sum = 0;
            for (int i = 0; i < n; ++i) sum += w[i] * std::pow(x[i], p);
            EXPECT_NEAR(sum, 1.0 / (p + 1), 1e-14) << "n " << n << " p " << p;
        }
    }
}

TEST(RadianceDistance, DefaultRuleIntegratesHemispherePolynomialsExactly) {
    // (1/2pi) int_{z>=0} of 1, z, z^3, x^2, x^2 z, x^4 y^2 z^5 (degree 11), z^23 (the limit).
    const rad::HemisphereIntegrator& rule = rad::defaultHemisphereIntegrator();
    double total = 0;
    for (double w : rule.weights()) total += w;
    EXPECT_NEAR(total, 1.0, 1e-14);
    const Vector3d n0(0, 0, 1);
    const auto integral = [&](auto g) { return rule.integrate(n0, g); };
    // Reference values by brute force (the odd powers of z are what the Lebedev hemisphere misses).
    const std::vector<std::function<double(const Vector3d&)>> fs = {
        [](const Vector3d&) { return 1.0; },
        [](const Vector3d& w) { return w.z(); },
        [](const Vector3d& w) { return std::pow(w.z(), 3); },
        [](const Vector3d& w) { return w.x() * w.x(); },
        [](const Vector3d& w) { return w.x() * w.x() * w.z(); },
        [](const Vector3d& w) { return std::pow(w.x(), 4) * w.y() * w.y() * std::pow(w.z(), 5); },
        [](const Vector3d& w) { return std::pow(w.z(), 23); },
    };
    const std::vector<double> exact = {1.0, 0.5, 0.25, 1.0 / 3.0, 0.125, -1, 1.0 / 24.0};
    for (std::size_t i = 0; i < fs.size(); ++i) {
        const double expected = exact[i] >= 0 ? exact[i] : bruteHemisphere(n0, 2000, 200, fs[i]);
        EXPECT_NEAR(integral(fs[i]), expected, exact[i] >= 0 ? 1e-14 : 1e-8) << i;
    }
    // Rotated: same values about any normal.
    std::mt19937 rng(1);
    const Vector3d n = randomUnit(rng);
    EXPECT_NEAR(rule.integrate(n, [&](const Vector3d& w) { return std::pow(w.dot(n), 3); }), 0.25, 1e-14);
    std::vector<Vector3d> dirs;
    rule.directions(n, dirs);
    for (const Vector3d& d : dirs) EXPECT_GE(d.dot(n), -1e-15);
}

TEST(RadianceDistance, MatchesBruteForceWithEqualNormals) {
    // All normals = n0: the integrand is a polynomial, the default rule is exact.
    std::mt19937 rng(2);
    for (const BasisSpec& basis : {BasisSpec{BasisKind::HemisphericalPolynomial, 4},
                                   BasisSpec{BasisKind::SphericalHarmonics, 6}}) {
        SCOPED_TRACE(basis.name());
        for (int trial = 0; trial < 2; ++trial) {
            const Vector3d n0 = randomUnit(rng);
            const RadianceField f = pairField(basis, n0, 0.0, rng, trial == 1);
            const double reference = bruteDistance2(f, n0, 1000);
            const double d2 = rad::squaredRadianceDistance(f, 0, f, 1, n0);
            EXPECT_NEAR(d2, reference, 1e-6 * reference);
            EXPECT_NEAR(rad::radianceDistance(f, 0, f, 1, n0), std::sqrt(reference), 1e-6 * std::sqrt(reference));
        }
    }
}

TEST(RadianceDistance, MatchesBruteForceWithTiltedNormals) {
    // Normals tilted from n0: border extension inside Omega (kinks); accuracy documented in the header.
    std::mt19937 rng(3);
    for (const BasisSpec& basis : {BasisSpec{BasisKind::HemisphericalPolynomial, 4},
                                   BasisSpec{BasisKind::SphericalHarmonics, 6}}) {
        SCOPED_TRACE(basis.name());
        for (double tilt : {10.0, 30.0}) {
            const Vector3d n0 = randomUnit(rng);
            const RadianceField f = pairField(basis, n0, tilt, rng);
            const double reference = bruteDistance2(f, n0, 1000);
            const double d2 = rad::squaredRadianceDistance(f, 0, f, 1, n0);
            const double tolerance = basis.usesLocalFrame() ? 1e-4 : 2e-3;
            EXPECT_NEAR(d2, reference, tolerance * reference) << "tilt " << tilt;
            // The Lebedev hemisphere variant also converges to it, less accurately.
            const double lebedev = rad::squaredRadianceDistance(rad::vertexRadiance(f, 0), rad::vertexRadiance(f, 1), n0,
                                                                rad::HemisphereIntegrator::lebedev(1202));
            EXPECT_NEAR(lebedev, reference, 5e-3 * reference) << "tilt " << tilt;
        }
    }
}

TEST(RadianceDistance, SymmetricZeroForEqualAndTriangleInequality) {
    std::mt19937 rng(4);
    const BasisSpec basis{BasisKind::SphericalHarmonics, 4};
    const Vector3d n0 = randomUnit(rng);
    RadianceField f(basis, 3);
    std::uniform_real_distribution<float> u(-1, 1);
    for (float& c : f.coefficients) c = u(rng);
    for (std::size_t v = 0; v < 3; ++v) rad::storeFrame(rad::frameFromNormal((n0 + 0.3 * randomUnit(rng)).normalized()), f.frame(v));
    for (std::size_t a = 0; a < 3; ++a) {
        EXPECT_NEAR(rad::squaredRadianceDistance(f, a, f, a, n0), 0.0, 1e-30);
        for (std::size_t b = 0; b < 3; ++b) {
            EXPECT_DOUBLE_EQ(rad::squaredRadianceDistance(f, a, f, b, n0), rad::squaredRadianceDistance(f, b, f, a, n0));
            for (std::size_t c = 0; c < 3; ++c)
                EXPECT_LE(rad::radianceDistance(f, a, f, c, n0),
                          rad::radianceDistance(f, a, f, b, n0) + rad::radianceDistance(f, b, f, c, n0) + 1e-12);
        }
    }
    // The same RF in the other storage is at distance ~0 (float rounding of the conversion).
    RadianceField g = f;
    rad::setReflectedStorage(g, true);
    for (std::size_t v = 0; v < 3; ++v) EXPECT_LT(rad::squaredRadianceDistance(f, v, g, v, n0), 1e-10);
}

TEST(RadianceDistance, ConstantFunctionsGiveColourDistance) {
    // Vanhoey et al. 2015 sec. 3.5, second bullet: between diffuse RF the distance is the RGB 2-norm of the
    // colour difference, whatever the normals (the border extension of a constant is that constant).
    std::mt19937 rng(5);
    for (const BasisSpec& basis : {BasisSpec{BasisKind::HemisphericalPolynomial, 0},
                                   BasisSpec{BasisKind::HemisphericalPolynomial, 3},
                                   BasisSpec{BasisKind::SphericalHarmonics, 0},
                                   BasisSpec{BasisKind::SphericalHarmonics, 5}}) {
        SCOPED_TRACE(basis.name());
        const Vector3d c1(0.2, 0.5, 0.9), c2(0.6, 0.1, 0.3);
        const double constant = basis.usesLocalFrame() ? 1.0 : 0.2820947917738781;  // value of basis fn 0
        RadianceField f(basis, 2, true);
        for (int ch = 0; ch < 3; ++ch) {
            f.channelCoefficients(0, ch)[0] = static_cast<float>(c1[ch] / constant);
            f.channelCoefficients(1, ch)[0] = static_cast<float>(c2[ch] / constant);
        }
        rad::storeFrame(rad::frameFromNormal(randomUnit(rng)), f.frame(0));
        rad::storeFrame(rad::frameFromNormal(randomUnit(rng)), f.frame(1));
        const Vector3d n0 = randomUnit(rng);
        EXPECT_NEAR(rad::radianceDistance(f, 0, f, 1, n0), (c1 - c2).norm(), 1e-6);
        // Callable version.
        const auto a = [&](const Vector3d&) { return c1; };
        const auto b = [&](const Vector3d&) { return c2; };
        EXPECT_NEAR(rad::radianceDistance(a, b, n0), (c1 - c2).norm(), 1e-14);
        EXPECT_NEAR(rad::squaredRadianceNorm(a, n0), c1.squaredNorm(), 1e-14);
    }
}

TEST(RadianceDistance, CallableVersionMatchesFieldVersion) {
    std::mt19937 rng(6);
    const Vector3d n0 = randomUnit(rng);
    const RadianceField f = pairField({BasisKind::HemisphericalPolynomial, 3}, n0, 20.0, rng);
    const auto a = [&](const Vector3d& w) { return rad::evaluateReflectedRadiance(f, 0, w); };
    const auto b = [&](const Vector3d& w) { return rad::evaluateReflectedRadiance(f, 1, w); };
    EXPECT_NEAR(rad::squaredRadianceDistance(a, b, n0), rad::squaredRadianceDistance(f, 0, f, 1, n0), 1e-13);
}

TEST(RadianceDistance, NormOfReflectedEqualsNormOnOwnHemisphere) {
    // Sec. 3.5 third bullet: ||L||_Omega = ||L~||_Omega on the RF's own hemisphere (R_n maps it onto
    // itself and preserves the measure).
    std::mt19937 rng(7);
    for (const BasisSpec& basis : {BasisSpec{BasisKind::HemisphericalPolynomial, 5},
                                   BasisSpec{BasisKind::SphericalHarmonics, 7}}) {
        RadianceField f(basis, 1);
        std::uniform_real_distribution<float> u(-1, 1);
        for (float& c : f.coefficients) c = u(rng);
        rad::storeFrame(rad::frameFromNormalAndTangent(randomUnit(rng), randomUnit(rng)), f.frame(0));
        const Vector3d n = rad::frameFromStored(f.frame(0)).n;
        const double plain = rad::squaredRadianceNorm([&](const Vector3d& w) { return rad::evaluateRadiance(f, 0, w); }, n);
        const double refl =
            rad::squaredRadianceNorm([&](const Vector3d& w) { return rad::evaluateReflectedRadiance(f, 0, w); }, n);
        EXPECT_NEAR(plain, refl, 1e-10 * plain) << basis.name();
    }
}

TEST(RadianceDistance, AverageMinimisesSumOfSquaredDistances) {
    // Sec. 3.5 first bullet: the average of two r-RF minimises the sum of squared distances to them.
    std::mt19937 rng(8);
    const Vector3d n0 = randomUnit(rng);
    const RadianceField f = pairField({BasisKind::SphericalHarmonics, 3}, n0, 15.0, rng);
    const auto a = [&](const Vector3d& w) { return rad::evaluateReflectedRadiance(f, 0, w); };
    const auto b = [&](const Vector3d& w) { return rad::evaluateReflectedRadiance(f, 1, w); };
    const auto cost = [&](double t) {
        const auto m = [&](const Vector3d& w) -> Vector3d { return (1 - t) * a(w) + t * b(w); };
        return rad::squaredRadianceDistance(m, a, n0) + rad::squaredRadianceDistance(m, b, n0);
    };
    EXPECT_LT(cost(0.5), cost(0.45));
    EXPECT_LT(cost(0.5), cost(0.55));
    EXPECT_NEAR(cost(0.5), 0.5 * rad::squaredRadianceDistance(a, b, n0), 1e-12);
}

TEST(RadianceDistance, CombinationMatchesExtrapolationDistance) {
    // Eq. (7) for one triangle: d^2 between L~(p0) and the eq. (4) extrapolation of the triangle's
    // r-RF at p0, three ways: the combination with extrapolation weights, callables through
    // extrapolateReflectedRadiance, and brute force.
    std::mt19937 rng(9);
    for (const BasisSpec& basis : {BasisSpec{BasisKind::HemisphericalPolynomial, 4},
                                   BasisSpec{BasisKind::SphericalHarmonics, 4}}) {
        SCOPED_TRACE(basis.name());
        RadianceField f(basis, 4);
        std::uniform_real_distribution<float> u(-1, 1);
        for (float& c : f.coefficients) c = u(rng);
        const Vector3d mean = randomUnit(rng);
        for (std::size_t v = 0; v < 4; ++v)
            rad::storeFrame(rad::frameFromNormalAndTangent((mean + 0.3 * randomUnit(rng)).normalized(), randomUnit(rng)),
                            f.frame(v));
        const rad::Frame mf = rad::frameFromNormal(mean);
        const Vector3d p1 = mf.toWorld(Vector3d(0, 0, 0)), p2 = mf.toWorld(Vector3d(1, 0, 0.1)),
                       p3 = mf.toWorld(Vector3d(0.2, 0.9, -0.1)), p0 = mf.toWorld(Vector3d(0.5, 0.6, 0.3));
        const rad::TriangleRadiance tri = rad::triangleRadiance(f, 1, 2, 3, p1, p2, p3);
        const auto op = rad::TriangleGradient::create(p1, p2, p3);
        ASSERT_TRUE(op.has_value());
        const Vector3d beta = op->extrapolationWeights(p0);
        const rad::VertexRadiance target = rad::vertexRadiance(f, 0);
        const Vector3d n0 = target.frame.n;
        const double combination = rad::squaredDistanceToCombination(target, tri.vertices.data(), beta.data(), 3, n0);
        const auto original = [&](const Vector3d& w) { return rad::evaluateReflectedRadiance(f, 0, w); };
        const auto extrapolated = [&](const Vector3d& w) { return *rad::extrapolateReflectedRadiance(tri, p0, w); };
        EXPECT_NEAR(combination, rad::squaredRadianceDistance(original, extrapolated, n0), 1e-12 * (1 + combination));
        const double brute = bruteHemisphere(n0, 600, 1200, [&](const Vector3d& w) {
            return (original(w) - extrapolated(w)).squaredNorm();
        });
        EXPECT_NEAR(combination, brute, 2e-3 * brute);
    }
}

}  // namespace
