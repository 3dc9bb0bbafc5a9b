// Tests of radiance_projection.h: weighted regularised least-squares fit and L2 projection.
#include "radiance/radiance_projection.h"

#include "radiance/basis.h"
#include "radiance/radiance_evaluation.h"
#include "radiance/radiance_frame.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace {

using Eigen::Vector3d;
using rad::BasisKind;
using rad::BasisSpec;

constexpr double kPi = 3.14159265358979323846;

using radtest::randomUnit;

Vector3d randomUpper(std::mt19937& rng, const Vector3d& n) {
    Vector3d w = randomUnit(rng);
    return w.dot(n) < 0 ? Vector3d(rad::reflect(n, -w)) : w;
}

std::vector<double> randomCoefficients(const BasisSpec& basis, std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<double> c(3 * basis.coefficientCount());
    for (double& x : c) x = u(rng);
    return c;
}

using radtest::bruteHemisphere;

// A Phong-like RF: diffuse + specular lobe around the mirror direction of a light.
Vector3d phong(const Vector3d& n, const Vector3d& w, double shininess) {
    const Vector3d light = Vector3d(0.3, 0.2, 1).normalized();
    const Vector3d mirror = 2 * n.dot(light) * n - light;
    const double s = std::pow(std::max(0.0, mirror.dot(w)), shininess);
    return Vector3d(0.3, 0.2, 0.1) + s * Vector3d(0.8, 0.8, 0.9);
}

// ---- (b) projection ---------------------------------------------------------------------------

TEST(RadianceProjection, PolynomialSpanIsReproducedExactly) {
    std::mt19937 rng(1);
    for (int degree = 1; degree <= 6; ++degree) {
        const BasisSpec basis{BasisKind::HemisphericalPolynomial, degree};
        SCOPED_TRACE(basis.name());
        const rad::FunctionProjector projector(basis);
        EXPECT_GE(projector.precision(), 2 * degree);
        for (int trial = 0; trial < 3; ++trial) {
            const rad::Frame frame = rad::frameFromNormalAndTangent(randomUnit(rng), randomUnit(rng));
            const std::vector<double> c = randomCoefficients(basis, rng);
            std::vector<double> out(c.size());
            projector.project(frame, [&](const Vector3d& w) { return radtest::polynomialValue(basis, c, frame, w); },
                              out.data());
            for (std::size_t k = 0; k < c.size(); ++k) EXPECT_NEAR(out[k], c[k], 1e-9) << k;
        }
    }
}

TEST(RadianceProjection, HarmonicSpanIsReproducedExactly) {
    std::mt19937 rng(2);
    for (int degree = 0; degree <= 8; ++degree) {
        const BasisSpec basis{BasisKind::SphericalHarmonics, degree};
        SCOPED_TRACE(basis.name());
        rad::ProjectionOptions options;
        options.borderExtension = false;  // the whole-sphere function itself (see next test)
        const rad::FunctionProjector projector(basis, options);
        for (int trial = 0; trial < 3; ++trial) {
            const rad::Frame frame = rad::frameFromNormal(randomUnit(rng));
            const std::vector<double> c = randomCoefficients(basis, rng);
            std::vector<double> out(c.size());
            projector.project(frame, [&](const Vector3d& w) { return radtest::harmonicValue(basis, c, w); }, out.data());
            for (std::size_t k = 0; k < c.size(); ++k) EXPECT_NEAR(out[k], c[k], 1e-9) << k;
        }
    }
}

TEST(RadianceProjection, HarmonicBorderExtensionProjectsTheExtendedFunction) {
    // With the border extension, the projected function is f(border(w)) below the horizon: compare
    // with projecting that function, extended here by hand, without the extension.
    std::mt19937 rng(3);
    const BasisSpec basis{BasisKind::SphericalHarmonics, 6};
    const rad::FunctionProjector withExtension(basis);
    rad::ProjectionOptions raw;
    raw.borderExtension = false;
    const rad::FunctionProjector withoutExtension(basis, raw);
    const rad::Frame frame = rad::frameFromNormal(randomUnit(rng));
    const auto f = [&](const Vector3d& w) { return phong(frame.n, w, 20); };
    const auto fExtended = [&](const Vector3d& w) {
        const double h = w.dot(frame.n);
        return h >= 0 ? f(w) : f((w - h * frame.n).normalized());
    };
    std::vector<double> a(3 * basis.coefficientCount()), b(a.size());
    withExtension.project(frame, f, a.data());
    withoutExtension.project(frame, fExtended, b.data());
    for (std::size_t k = 0; k < a.size(); ++k) EXPECT_NEAR(a[k], b[k], 1e-12);
    // A constant stays exactly constant.
    withExtension.project(frame, [](const Vector3d&) { return Vector3d(0.25, 0.5, 1.0); }, a.data());
    const int K = basis.coefficientCount();
    for (int ch = 0; ch < 3; ++ch)
        for (int k = 0; k < K; ++k)
            EXPECT_NEAR(a[ch * K + k], k == 0 ? Vector3d(0.25, 0.5, 1.0)[ch] / 0.2820947917738781 : 0.0, 1e-12);
}

TEST(RadianceProjection, ReflectedStorageGivesSameRadiance) {
    std::mt19937 rng(4);
    for (const BasisSpec& basis : {BasisSpec{BasisKind::HemisphericalPolynomial, 4},
                                   BasisSpec{BasisKind::SphericalHarmonics, 6}}) {
        SCOPED_TRACE(basis.name());
        rad::ProjectionOptions plainOptions, reflectedOptions;
        reflectedOptions.storeReflected = true;
        const rad::Frame frame = rad::frameFromNormalAndTangent(randomUnit(rng), randomUnit(rng));
        const auto f = [&](const Vector3d& w) { return phong(frame.n, w, 10); };
        std::vector<double> plain(3 * basis.coefficientCount()), reflected(plain.size()), expected(plain.size());
        rad::projectFunction(basis, frame, f, plainOptions, plain.data());
        rad::projectFunction(basis, frame, f, reflectedOptions, reflected.data());
        rad::reflectCoefficients(basis, frame, plain.data(), expected.data());
        for (std::size_t k = 0; k < plain.size(); ++k) EXPECT_NEAR(reflected[k], expected[k], 1e-12);
        rad::VertexRadianceD a{basis, plain.data(), frame, false}, b{basis, reflected.data(), frame, true};
        double scratch[rad::kMaxCoefficientsPerChannel];
        for (int i = 0; i < 50; ++i) {
            const Vector3d w = randomUnit(rng);
            EXPECT_LT((rad::evaluateRadiance(a, w, scratch) - rad::evaluateRadiance(b, w, scratch)).norm(), 1e-11);
        }
    }
}

TEST(RadianceProjection, ProjectIntoFieldUsesFieldFrameAndStorage) {
    const BasisSpec basis{BasisKind::HemisphericalPolynomial, 3};
    rad::RadianceField field(basis, 2, true);
    rad::storeFrame(rad::frameFromNormal(Vector3d(0, 0, 1)), field.frame(0));
    rad::storeFrame(rad::frameFromNormal(Vector3d(1, 1, 0)), field.frame(1));
    const rad::FunctionProjector projector(basis);
    const auto f = [](const Vector3d& w) { return Vector3d(1 + w.x(), 2 - w.y() * w.x(), 0.5 + w.z() * 0); };
    for (std::size_t v = 0; v < 2; ++v) projector.projectIntoField(field, v, f);
    EXPECT_EQ(field.validate(), "");
    // Vertex 0 has the canonical frame (t, b, n) = (x, y, z), where f is a PB2 polynomial in (u, v):
    // reproduced up to float storage. Vertex 1 (another frame): its own projection, finite.
    std::mt19937 rng(5);
    for (int i = 0; i < 20; ++i) {
        const Vector3d w = randomUpper(rng, Vector3d(0, 0, 1));
        EXPECT_LT((rad::evaluateRadiance(field, 0, w) - f(w)).norm(), 1e-5);
        EXPECT_TRUE(rad::evaluateRadiance(field, 1, w).allFinite());
    }
    // Reflected storage: the u coefficient of channel 0 (+1 in L) is stored as -1 (odd degree).
    EXPECT_NEAR(field.channelCoefficients(0, 0)[rad::polynomialIndex(1, 0)], -1.0, 1e-6);
    EXPECT_NEAR(field.channelCoefficients(0, 1)[rad::polynomialIndex(1, 1)], -1.0, 1e-6);  // even: kept
    // A projector of another basis refuses the field.
    const rad::FunctionProjector other(BasisSpec{BasisKind::SphericalHarmonics, 2});
    EXPECT_THROW(other.projectIntoField(field, 0, f), std::invalid_argument);
}

double hemisphereError(const BasisSpec& basis, const std::vector<double>& c, const rad::Frame& frame,
                       const rad::RadianceFunction& f) {
    const rad::VertexRadianceD rf{basis, c.data(), frame, false};
    double scratch[rad::kMaxCoefficientsPerChannel];
    return std::sqrt(bruteHemisphere(frame.n, 200, 400, [&](const Vector3d& w) {
        return (rad::evaluateRadiance(rf, w, scratch) - f(w)).squaredNorm();
    }));
}

TEST(RadianceProjection, PhongLobeErrorDecreasesWithDegree) {
    const rad::Frame frame = rad::frameFromNormal(Vector3d(0.2, -0.3, 0.93));
    const auto f = [&](const Vector3d& w) { return phong(frame.n, w, 8); };
    {
        std::vector<double> errors;
        for (int degree = 1; degree <= 6; ++degree) {
            const BasisSpec basis{BasisKind::HemisphericalPolynomial, degree};
            std::vector<double> c(3 * basis.coefficientCount());
            rad::projectFunction(basis, frame, f, {}, c.data());
            errors.push_back(hemisphereError(basis, c, frame, f));
        }
        for (std::size_t i = 1; i < errors.size(); ++i) EXPECT_LE(errors[i], errors[i - 1] * (1 + 1e-6)) << "PB" << i + 1;
        EXPECT_LT(errors.back(), 0.3 * errors.front());
    }
    {
        std::vector<double> errors;
        for (int degree : {1, 2, 4, 6, 8}) {
            const BasisSpec basis{BasisKind::SphericalHarmonics, degree};
            std::vector<double> c(3 * basis.coefficientCount());
            rad::projectFunction(basis, frame, f, {}, c.data());
            errors.push_back(hemisphereError(basis, c, frame, f));
        }
        for (std::size_t i = 1; i < errors.size(); ++i) EXPECT_LT(errors[i], errors[i - 1]) << i;
        EXPECT_LT(errors.back(), 0.3 * errors.front());
    }
}

TEST(RadianceProjection, PolynomialProjectionIsHemisphereL2Optimal) {
    // The projection minimises the hemisphere L2 error: perturbing any coefficient increases it.
    const BasisSpec basis{BasisKind::HemisphericalPolynomial, 3};
    const rad::Frame frame = rad::frameFromNormal(Vector3d(0, 0.6, 0.8));
    const auto f = [&](const Vector3d& w) { return phong(frame.n, w, 5); };
    std::vector<double> c(3 * basis.coefficientCount());
    rad::projectFunction(basis, frame, f, {}, c.data());
    const double best = hemisphereError(basis, c, frame, f);
    for (std::size_t k = 0; k < c.size(); k += 4)
        for (double delta : {-0.02, 0.02}) {
            std::vector<double> d = c;
            d[k] += delta;
            EXPECT_GT(hemisphereError(basis, d, frame, f), best);
        }
}

// ---- (a) least squares ------------------------------------------------------------------------

TEST(RadianceFit, ExactDataIsReproduced) {
    std::mt19937 rng(6);
    for (const BasisSpec& basis : {BasisSpec{BasisKind::HemisphericalPolynomial, 4},
                                   BasisSpec{BasisKind::SphericalHarmonics, 3}}) {
        SCOPED_TRACE(basis.name());
        const rad::Frame frame = rad::frameFromNormalAndTangent(randomUnit(rng), randomUnit(rng));
        const std::vector<double> c = randomCoefficients(basis, rng);
        std::vector<rad::RadianceSample> samples;
        std::uniform_real_distribution<double> weight(0.5, 2.0);
        for (int i = 0; i < 200; ++i) {
            // Upper hemisphere (samples below are moved to the border); that determines SH3 as well.
            const Vector3d w = randomUpper(rng, frame.n);
            const Vector3d value = basis.usesLocalFrame() ? radtest::polynomialValue(basis, c, frame, w) : radtest::harmonicValue(basis, c, w);
            samples.push_back({w, value, weight(rng)});
        }
        std::vector<double> out(c.size());
        ASSERT_TRUE(rad::fitRadiance(basis, frame, samples, {}, out.data()));
        for (std::size_t k = 0; k < c.size(); ++k) EXPECT_NEAR(out[k], c[k], 1e-8);
        // Reflected storage: same L.
        rad::FitOptions reflectedOptions;
        reflectedOptions.storeReflected = true;
        std::vector<double> outR(c.size());
        ASSERT_TRUE(rad::fitRadiance(basis, frame, samples, reflectedOptions, outR.data()));
        const rad::VertexRadianceD rf{basis, outR.data(), frame, true};
        double scratch[rad::kMaxCoefficientsPerChannel];
        for (const rad::RadianceSample& s : samples)
            EXPECT_LT((rad::evaluateRadiance(rf, s.direction, scratch) - s.value).norm(), 1e-8);
    }
}

// Maximum and minimum of every channel of the fitted L over a grid of the upper hemisphere.
std::pair<double, double> fittedRange(const BasisSpec& basis, const rad::Frame& frame, const std::vector<double>& c) {
    const rad::VertexRadianceD rf{basis, c.data(), frame, false};
    double scratch[rad::kMaxCoefficientsPerChannel];
    double lo = 1e300, hi = -1e300;
    for (int i = 0; i <= 30; ++i)
        for (int j = 0; j < 60; ++j) {
            const double t = 0.5 * kPi * i / 30, p = 2 * kPi * j / 60;
            const Vector3d w = frame.toWorld(Vector3d(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)));
            const Vector3d v = rad::evaluateRadiance(rf, w, scratch);
            lo = std::min(lo, v.minCoeff());
            hi = std::max(hi, v.maxCoeff());
        }
    return {lo, hi};
}

TEST(RadianceFit, RegularisationPreventsOvershootOnClusteredSamples) {
    // Three samples within ~2 degrees of each other with different colours: the unregularised fit
    // interpolates them with a steep plane that overshoots far away; the regularised one stays bounded.
    const rad::Frame frame = rad::frameFromNormal(Vector3d(0, 0, 1));
    const std::vector<rad::RadianceSample> samples = {
        {Vector3d(0.02, 0.0, 1).normalized(), Vector3d(0.4, 0.4, 0.4), 1.0},
        {Vector3d(-0.01, 0.02, 1).normalized(), Vector3d(0.6, 0.6, 0.6), 1.0},
        {Vector3d(-0.01, -0.02, 1).normalized(), Vector3d(0.5, 0.5, 0.5), 1.0},
    };
    const double sampleMin = 0.4, sampleMax = 0.6, range = sampleMax - sampleMin;
    for (const BasisSpec& basis : {BasisSpec{BasisKind::HemisphericalPolynomial, 1},
                                   BasisSpec{BasisKind::SphericalHarmonics, 1}}) {
        SCOPED_TRACE(basis.name());
        std::vector<double> c(3 * basis.coefficientCount());
        if (basis.usesLocalFrame()) {  // PB1: 3 unknowns, determined; SH1 has 4 (singular without lambda)
            ASSERT_TRUE(rad::fitRadiance(basis, frame, samples, {}, c.data()));
            const auto [lo, hi] = fittedRange(basis, frame, c);
            EXPECT_TRUE(hi > sampleMax + 2 * range || lo < sampleMin - 2 * range) << lo << " " << hi;
        } else {
            EXPECT_FALSE(rad::fitRadiance(basis, frame, samples, {}, c.data()));
        }
        rad::FitOptions options;
        options.lambda = 0.1;
        ASSERT_TRUE(rad::fitRadiance(basis, frame, samples, options, c.data()));
        const auto [lo, hi] = fittedRange(basis, frame, c);
        EXPECT_GE(lo, sampleMin - 2 * range);
        EXPECT_LE(hi, sampleMax + 2 * range);
        // Still close to the data where the data is.
        const rad::VertexRadianceD rf{basis, c.data(), frame, false};
        double scratch[rad::kMaxCoefficientsPerChannel];
        for (const rad::RadianceSample& s : samples)
            EXPECT_LT(std::fabs(rad::evaluateRadiance(rf, s.direction, scratch)[0] - s.value[0]), range);
    }
}

TEST(RadianceFit, LargeLambdaGivesWeightedMeanColour) {
    const BasisSpec basis{BasisKind::HemisphericalPolynomial, 4};
    const rad::Frame frame = rad::frameFromNormal(Vector3d(1, 0, 0));
    std::mt19937 rng(7);
    std::vector<rad::RadianceSample> samples;
    Vector3d weightedSum = Vector3d::Zero();
    double totalWeight = 0;
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < 30; ++i) {
        const Vector3d value(u(rng), u(rng), u(rng));
        const double w = 0.1 + u(rng);
        samples.push_back({randomUpper(rng, frame.n), value, w});
        weightedSum += w * value;
        totalWeight += w;
    }
    rad::FitOptions options;
    options.lambda = 1e9;
    std::vector<double> c(3 * basis.coefficientCount());
    ASSERT_TRUE(rad::fitRadiance(basis, frame, samples, options, c.data()));
    const rad::VertexRadianceD rf{basis, c.data(), frame, false};
    double scratch[rad::kMaxCoefficientsPerChannel];
    for (int i = 0; i < 10; ++i)
        EXPECT_LT((rad::evaluateRadiance(rf, randomUpper(rng, frame.n), scratch) - weightedSum / totalWeight).norm(), 1e-6);
}

TEST(RadianceFit, LambdaIsInvariantToWeightScaleAndDuplication) {
    const BasisSpec basis{BasisKind::SphericalHarmonics, 2};
    const rad::Frame frame = rad::frameFromNormal(Vector3d(0, 1, 1));
    std::mt19937 rng(8);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<rad::RadianceSample> samples, scaled, duplicated;
    for (int i = 0; i < 12; ++i) {
        const rad::RadianceSample s{randomUpper(rng, frame.n), Vector3d(u(rng), u(rng), u(rng)), 0.5 + u(rng)};
        samples.push_back(s);
        scaled.push_back({s.direction, s.value, 7.0 * s.weight});
        duplicated.push_back(s);
        duplicated.push_back(s);
    }
    rad::FitOptions options;
    options.lambda = 0.05;
    std::vector<double> a(3 * basis.coefficientCount()), b(a.size()), c(a.size());
    ASSERT_TRUE(rad::fitRadiance(basis, frame, samples, options, a.data()));
    ASSERT_TRUE(rad::fitRadiance(basis, frame, scaled, options, b.data()));
    ASSERT_TRUE(rad::fitRadiance(basis, frame, duplicated, options, c.data()));
    for (std::size_t k = 0; k < a.size(); ++k) {
        EXPECT_NEAR(a[k], b[k], 1e-10);
        EXPECT_NEAR(a[k], c[k], 1e-10);
    }
}

TEST(RadianceFit, RejectsEmptyDegenerateAndInvalidInput) {
    const BasisSpec basis{BasisKind::HemisphericalPolynomial, 2};
    const rad::Frame frame;
    std::vector<double> c(3 * basis.coefficientCount(), 42.0);
    EXPECT_FALSE(rad::fitRadiance(basis, frame, std::vector<rad::RadianceSample>{}, {}, c.data()));
    const std::vector<rad::RadianceSample> zeroWeight = {{Vector3d(0, 0, 1), Vector3d(1, 1, 1), 0.0}};
    EXPECT_FALSE(rad::fitRadiance(basis, frame, zeroWeight, {}, c.data()));
    // Two samples, six unknowns, no regularisation: singular.
    const std::vector<rad::RadianceSample> two = {{Vector3d(0, 0, 1), Vector3d(1, 1, 1), 1.0},
                                                  {Vector3d(1, 0, 1).normalized(), Vector3d(0, 0, 0), 1.0}};
    EXPECT_FALSE(rad::fitRadiance(basis, frame, two, {}, c.data()));
    for (double x : c) EXPECT_EQ(x, 42.0);  // untouched on failure
    // ... but fine with regularisation.
    rad::FitOptions options;
    options.lambda = 0.01;
    EXPECT_TRUE(rad::fitRadiance(basis, frame, two, options, c.data()));
    for (double x : c) EXPECT_TRUE(std::isfinite(x));
    // Non-finite input, negative weight, negative lambda.
    std::vector<rad::RadianceSample> bad = two;
    bad[0].value.x() = std::nan("");
    EXPECT_FALSE(rad::fitRadiance(basis, frame, bad, options, c.data()));
    bad = two;
    bad[1].weight = -1;
    EXPECT_FALSE(rad::fitRadiance(basis, frame, bad, options, c.data()));
    options.lambda = -1;
    EXPECT_FALSE(rad::fitRadiance(basis, frame, two, options, c.data()));
}

TEST(RadianceFit, SamplesBelowHorizonCountAtTheirBorderDirection) {
    const BasisSpec basis{BasisKind::HemisphericalPolynomial, 2};
    const rad::Frame frame = rad::frameFromNormal(Vector3d(0, 0, 1));
    std::mt19937 rng(9);
    std::vector<rad::RadianceSample> below, atBorder;
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < 20; ++i) {
        const Vector3d w = randomUnit(rng);
        const Vector3d value(u(rng), u(rng), u(rng));
        below.push_back({w, value, 1.0});
        atBorder.push_back({rad::borderExtendedDirection(frame, w), value, 1.0});
    }
    std::vector<double> a(3 * basis.coefficientCount()), b(a.size());
    rad::FitOptions options;
    options.lambda = 1e-3;
    ASSERT_TRUE(rad::fitRadiance(basis, frame, below, options, a.data()));
    ASSERT_TRUE(rad::fitRadiance(basis, frame, atBorder, options, b.data()));
    for (std::size_t k = 0; k < a.size(); ++k) EXPECT_NEAR(a[k], b[k], 1e-10);
}

}  // namespace
