// Tests of prt/prt_lighting.h (the lightings l of L(x, l) = <t_x | l>, Křivánek et al. 2004 sec. 3.3;
// Sloan, Kautz, Snyder 2002).
// Expected values do not come from the code under test: the Hanning window and the SH constants
// are written out again here, the transfer of an unoccluded plane is integrated by brute-force
// quadrature, its relit value is checked against the Legendre series of the clamped cosine in
// closed form (R. Ramamoorthi, P. Hanrahan, "An efficient representation for irradiance
// environment maps", SIGGRAPH 2001, eq. 9 and after), and a map turned by a quarter turn is built
// by shifting its columns.
#include "prt/prt_lighting.h"

#include "lighting/environment_map.h"
#include "radiance/sh_rotation.h"
#include "radiance/spherical_harmonics.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kY00 = 0.28209479177387814;  // 1 / (2 sqrt(pi))

int bandOf(int k) { return static_cast<int>(std::floor(std::sqrt(double(k)) + 1e-9)); }

// The window of prt_lighting.h, written out again.
double hanning(int l, int degree) { return 0.5 * (1.0 + std::cos(kPi * l / (degree + 1))); }

// Legendre polynomial P_l(x) by Bonnet's recurrence.
double legendre(int l, double x) {
    double previous = 1.0, current = x;
    if (l == 0) return previous;
    for (int n = 1; n < l; ++n) {
        const double next = ((2 * n + 1) * x * current - n * previous) / (n + 1);
        previous = current;
        current = next;
    }
    return current;
}

double factorial(int n) { return n <= 1 ? 1.0 : n * factorial(n - 1); }

// a_l = integral over [0, 1] of mu P_l(mu) d mu, the Legendre moments of max(0, mu)
// (Ramamoorthi-Hanrahan 2001: 1/2, 1/3, 0 for odd l > 1, and the closed form below for even l).
double clampedCosineMoment(int l) {
    if (l == 0) return 0.5;
    if (l == 1) return 1.0 / 3.0;
    if (l % 2 == 1) return 0.0;
    const double sign = (l / 2) % 2 == 1 ? 1.0 : -1.0;  // (-1)^(l/2 - 1)
    return sign / ((l + 2.0) * (l - 1.0)) * factorial(l) / (std::pow(2.0, l) * factorial(l / 2) * factorial(l / 2));
}

// The windowed, truncated clamped cosine at angle theta from the normal: a zonal convolution, so by
// the addition theorem (sum_m Y_lm(n) Y_lm(d) = (2l+1)/(4 pi) P_l(n.d)) the relit value of the
// transfer (1/pi) max(0, n.w) under E h_l Y_lm(d) is (E/pi) sum_l h_l (2l+1)/2 a_l P_l(cos theta).
double windowedCosineConvolution(int degree, double cosTheta) {
    double sum = 0.0;
    for (int l = 0; l <= degree; ++l) sum += hanning(l, degree) * (2 * l + 1) / 2.0 * clampedCosineMoment(l) * legendre(l, cosTheta);
    return sum / kPi;
}

// f(w) = sum_k c[ch * K + k] Y_k(w) for one channel.
double shValue(int degree, const std::vector<double>& c, int channel, const Eigen::Vector3d& w) {
    const int K = (degree + 1) * (degree + 1);
    std::vector<double> y(K);
    rad::evaluateSphericalHarmonics(degree, w.x(), w.y(), w.z(), y.data());
    double sum = 0.0;
    for (int k = 0; k < K; ++k) sum += c[static_cast<std::size_t>(channel) * K + k] * y[k];
    return sum;
}

Eigen::Matrix3d quarterTurnAboutZ() {
    Eigen::Matrix3d r;
    r << 0, -1, 0, 1, 0, 0, 0, 0, 1;  // x -> y, y -> -x
    return r;
}

// Direction convention of environment_map.h written out again (texel centres).
Eigen::Vector3d mapDirection(double s, double t) {
    const double theta = kPi * t, phi = kPi - 2.0 * kPi * s;
    return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// A non-symmetric test map: a smooth part plus a per-texel pseudo-random part (the projection is
// exact for the box reconstruction, so roughness costs nothing).
rad::EnvironmentMap testMap(int width, int height, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> noise(0.0f, 0.5f);
    std::vector<float> rgb(std::size_t(width) * height * 3);
    for (int r = 0; r < height; ++r)
        for (int c = 0; c < width; ++c) {
            const Eigen::Vector3d w = mapDirection((c + 0.5) / width, (r + 0.5) / height);
            float* p = rgb.data() + (std::size_t(r) * width + c) * 3;
            p[0] = static_cast<float>(1.0 + w.x() + 0.5 * w.y() * w.z()) + noise(rng);
            p[1] = static_cast<float>(2.0 + w.y() * w.y() - w.z()) + noise(rng);
            p[2] = static_cast<float>(1.5 + w.x() * w.y() + 0.3 * w.x()) + noise(rng);
        }
    return rad::EnvironmentMap(width, height, std::move(rgb));
}

// Right-handed rotation by `angle` about world axis `axis` (0 = X, 1 = Y, 2 = Z), the elemental
// rotation matrices written out (no Eigen::AngleAxis, which the code under test uses).
Eigen::Matrix3d elementalRotation(int axis, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    Eigen::Matrix3d r;
    if (axis == 0) r << 1, 0, 0, 0, c, -s, 0, s, c;
    else if (axis == 1) r << c, 0, s, 0, 1, 0, -s, 0, c;
    else r << c, -s, 0, s, c, 0, 0, 0, 1;
    return r;
}

// The documented placement of the map frame in the world for each up axis (prt_lighting.h): the
// map's (x, y, z) becomes (z, x, y) for +X, (y, z, x) for +Y, itself for +Z.
Eigen::Vector3d mapToWorld(int axis, const Eigen::Vector3d& m) {
    if (axis == 0) return {m.z(), m.x(), m.y()};
    if (axis == 1) return {m.y(), m.z(), m.x()};
    return m;
}

// The Hanning-windowed SH projection of a directional light of irradiance E toward unit d,
// written out again: E h_l Y_k(d), the same vector on the three channels.
std::vector<double> expectedDirectional(int degree, const Eigen::Vector3d& d, double E, double width) {
    const int K = (degree + 1) * (degree + 1);
    std::vector<double> y(K);
    rad::evaluateSphericalHarmonics(degree, d.x(), d.y(), d.z(), y.data());
    std::vector<double> out(3 * K);
    for (int ch = 0; ch < 3; ++ch)
        for (int k = 0; k < K; ++k) {
            const int l = bandOf(k);
            const double h = l < width ? 0.5 * (1.0 + std::cos(kPi * l / width)) : 0.0;
            out[ch * K + k] = E * h * y[k];
        }
    return out;
}

rad::PrtLightingSettings directionalSettings(int degree, const Eigen::Vector3d& d, double intensity) {
    rad::PrtLightingSettings s;
    s.source = rad::PrtLightSource::Directional;
    s.degree = degree;
    s.direction = d;
    s.intensity = intensity;
    return s;
}

rad::PrtLightingSettings environmentSettings(int degree, rad::UpAxis up, double rotationDegrees, double intensity) {
    rad::PrtLightingSettings s;
    s.source = rad::PrtLightSource::EnvironmentMap;
    s.degree = degree;
    s.upAxis = up;
    s.rotationDegrees = rotationDegrees;
    s.intensity = intensity;
    return s;
}

}  // namespace

TEST(PrtLighting, DirectionalLightKeepsPowerInBandZero) {
    std::mt19937 rng(3);
    for (int degree : {0, 2, 5, 10})
        for (int trial = 0; trial < 5; ++trial) {
            const Eigen::Vector3d d = radtest::randomUnit(rng) * (0.5 + trial);  // need not be unit
            const Eigen::Vector3d E(1.5, 0.25, 3.0);
            const std::vector<double> c = rad::directionalLightSH(degree, d, E);
            const int K = (degree + 1) * (degree + 1);
            ASSERT_EQ(c.size(), 3u * K);
            for (int ch = 0; ch < 3; ++ch) {
                // h_0 = 1: band 0 is E Y_00, and the integral of the expansion over the sphere,
                // sqrt(4 pi) c_00, is the light's irradiance E.
                EXPECT_NEAR(c[ch * K], E[ch] * kY00, 1e-14);
                EXPECT_NEAR(c[ch * K] * std::sqrt(4 * kPi), E[ch], 1e-12);
            }
        }
}

TEST(PrtLighting, DirectionalLightIsTheHanningWindowedDelta) {
    std::mt19937 rng(4);
    const int degree = 6, K = 49;
    const Eigen::Vector3d d = radtest::randomUnit(rng);
    const std::vector<double> c = rad::directionalLightSH(degree, 3.0 * d, Eigen::Vector3d(1, 2, 0.5));
    std::vector<double> y(K);
    rad::evaluateSphericalHarmonics(degree, d.x(), d.y(), d.z(), y.data());
    for (int ch = 0; ch < 3; ++ch)
        for (int k = 0; k < K; ++k)
            EXPECT_NEAR(c[ch * K + k], (ch == 0 ? 1.0 : ch == 1 ? 2.0 : 0.5) * hanning(bandOf(k), degree) * y[k], 1e-13)
                << "k " << k;
}

TEST(PrtLighting, WindowedLightPeaksTowardTheLightAndRingsFarLess) {
    std::mt19937 rng(5);
    for (int degree : {3, 5, 8}) {
        const Eigen::Vector3d d = radtest::randomUnit(rng);
        const std::vector<double> windowed = rad::directionalLightSH(degree, d, Eigen::Vector3d::Ones());
        // The unwindowed truncation E Y_k(d), built here.
        const int K = (degree + 1) * (degree + 1);
        std::vector<double> raw(3 * K);
        rad::evaluateSphericalHarmonics(degree, d.x(), d.y(), d.z(), raw.data());
        for (int ch = 1; ch < 3; ++ch) std::copy(raw.begin(), raw.begin() + K, raw.begin() + ch * K);

        double windowedMax = -1e300, windowedMin = 1e300, rawMin = 1e300;
        Eigen::Vector3d argMax = Eigen::Vector3d::Zero();
        const int thetaSteps = 180, phiSteps = 360;
        for (int i = 0; i < thetaSteps; ++i)
            for (int j = 0; j < phiSteps; ++j) {
                const double t = (i + 0.5) * kPi / thetaSteps, p = (j + 0.5) * 2 * kPi / phiSteps;
                const Eigen::Vector3d w(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
                const double fw = shValue(degree, windowed, 0, w), fr = shValue(degree, raw, 0, w);
                if (fw > windowedMax) windowedMax = fw, argMax = w;
                windowedMin = std::min(windowedMin, fw);
                rawMin = std::min(rawMin, fr);
            }
        // Also at d itself: the peak value there is at least the grid's maximum.
        EXPECT_GE(shValue(degree, windowed, 0, d), windowedMax - 1e-12);
        EXPECT_LT(std::acos(std::clamp(argMax.dot(d), -1.0, 1.0)), 2.0 * kPi / 180.0) << "degree " << degree;
        ASSERT_LT(rawMin, 0.0);  // the truncated delta rings
        EXPECT_LT(std::fabs(std::min(windowedMin, 0.0)), 0.1 * std::fabs(rawMin)) << "degree " << degree;
        // And relative to its own peak the windowed light is nearly non-negative (a few per cent).
        EXPECT_LT(std::fabs(std::min(windowedMin, 0.0)), 0.05 * windowedMax) << "degree " << degree;
    }
}

TEST(PrtLighting, UnoccludedPlaneUnderDirectionalLightMatchesWindowedCosineConvolution) {
    const int degree = 5, K = 36;
    const Eigen::Vector3d n(0, 0, 1);
    // t_k = (1/pi) integral of max(0, n.w) Y_k(w) over the sphere = 2 * (1/(2 pi)) * hemisphere
    // integral: brute-force quadrature, independent of transfer_vectors.
    std::vector<float> transfer(K);
    for (int k = 0; k < K; ++k)
        transfer[k] = static_cast<float>(2.0 * radtest::bruteHemisphere(n, 800, 32, [&](const Eigen::Vector3d& w) {
                                             std::vector<double> y(K);
                                             rad::evaluateSphericalHarmonics(degree, w.x(), w.y(), w.z(), y.data());
                                             return n.dot(w) * y[k];
                                         }));
    // The quadrature itself against the closed form: zonal, t_l0 = 2 sqrt((2l+1)/(4 pi)) a_l.
    for (int l = 0; l <= degree; ++l)
        EXPECT_NEAR(transfer[l * l + l], 2.0 * std::sqrt((2 * l + 1) / (4 * kPi)) * clampedCosineMoment(l), 2e-5);

    const Eigen::Vector3d E(2.0, 1.0, 0.5);
    for (double thetaDegrees : {0.0, 30.0, 60.0, 89.0, 120.0, 180.0}) {
        const double theta = thetaDegrees * kPi / 180.0;
        const Eigen::Vector3d toLight(std::sin(theta) * std::cos(0.4), std::sin(theta) * std::sin(0.4), std::cos(theta));
        const std::vector<double> light = rad::directionalLightSH(degree, toLight, E);
        const std::vector<float> L = rad::relightVertices(transfer.data(), 1, degree, 1, light, degree);
        ASSERT_EQ(L.size(), 3u);
        for (int ch = 0; ch < 3; ++ch)
            EXPECT_NEAR(L[ch], E[ch] * windowedCosineConvolution(degree, std::cos(theta)), 2e-5 * E[ch])
                << "theta " << thetaDegrees << " channel " << ch;
    }
    // From straight above the windowed light gives about E/pi (the exact Lambertian value): the
    // window blurs the light over a cone, so a little less.
    const std::vector<float> above =
        rad::relightVertices(transfer.data(), 1, degree, 1, rad::directionalLightSH(degree, n, E), degree);
    EXPECT_GT(above[0], 0.85 * E[0] / kPi);
    EXPECT_LT(above[0], 1.0 * E[0] / kPi);
}

TEST(PrtLighting, RelightVerticesDotProductLayout) {
    std::mt19937 rng(7);
    std::normal_distribution<double> g;
    const int degree = 2, K = 9, lightingDegree = 4, lightingK = 25;
    const std::size_t vertices = 5;
    std::vector<double> lighting(3 * lightingK);
    for (double& v : lighting) v = g(rng);
    for (int channels : {1, 3}) {
        std::vector<float> transfer(vertices * channels * K);
        for (float& v : transfer) v = static_cast<float>(g(rng));
        const std::vector<float> out = rad::relightVertices(transfer.data(), vertices, degree, channels, lighting, lightingDegree);
        ASSERT_EQ(out.size(), vertices * 3);
        for (std::size_t v = 0; v < vertices; ++v)
            for (int ch = 0; ch < 3; ++ch) {
                // transfer_vectors.h layout: values[(v * channels + c) * K + k].
                const int c = channels == 1 ? 0 : ch;
                double expected = 0.0;
                for (int k = 0; k < K; ++k) expected += transfer[(v * channels + c) * K + k] * lighting[ch * lightingK + k];
                EXPECT_NEAR(out[v * 3 + ch], expected, 1e-5 * (1.0 + std::fabs(expected)));
            }
    }
}

TEST(PrtLighting, RelightVerticesRefusesMismatches) {
    const std::vector<float> transfer(9, 1.0f);
    const std::vector<double> lighting(3 * 9, 1.0);
    EXPECT_NO_THROW(rad::relightVertices(transfer.data(), 1, 2, 1, lighting, 2));
    EXPECT_THROW(rad::relightVertices(transfer.data(), 1, 2, 1, lighting, 1), std::invalid_argument);  // size
    EXPECT_THROW(rad::relightVertices(transfer.data(), 1, 3, 1, std::vector<double>(3 * 16), 2), std::invalid_argument);
    EXPECT_THROW(rad::relightVertices(transfer.data(), 1, 2, 2, lighting, 2), std::invalid_argument);  // channels
    EXPECT_THROW(rad::relightVertices(nullptr, 1, 2, 1, lighting, 2), std::invalid_argument);
    EXPECT_TRUE(rad::relightVertices(nullptr, 0, 2, 1, lighting, 2).empty());
    // Damaged transfer values (NaN, infinity) are refused with the count and the fix, not relit black.
    std::vector<float> damaged(18, 1.0f);
    damaged[4] = std::nanf("");
    damaged[13] = std::numeric_limits<float>::infinity();
    try {
        rad::relightVertices(damaged.data(), 2, 2, 1, lighting, 2);
        FAIL() << "NaN transfer accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("2 transfer values are NaN or infinite"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("Compute PRT Transfer"), std::string::npos) << e.what();
    }
}

TEST(PrtLighting, DirectionalLightRefusesBadArguments) {
    EXPECT_THROW(rad::directionalLightSH(3, Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()), std::invalid_argument);
    EXPECT_THROW(rad::directionalLightSH(-1, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Ones()), std::out_of_range);
    EXPECT_THROW(rad::directionalLightSH(rad::kMaxHarmonicDegree + 1, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Ones()),
                 std::out_of_range);
}

TEST(PrtLighting, ConstantEnvironmentIsBandZeroOnly) {
    const int width = 64, height = 32, degree = 5, K = 36;
    const float C[3] = {0.5f, 1.0f, 2.0f};
    std::vector<float> rgb(std::size_t(width) * height * 3);
    for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = C[i % 3];
    const rad::EnvironmentMap map(width, height, std::move(rgb));
    for (double angle : {0.0, 0.7, -2.0}) {
        const std::vector<double> c = rad::environmentLightSH(map, degree, angle);
        ASSERT_EQ(c.size(), 3u * K);
        for (int ch = 0; ch < 3; ++ch) {
            EXPECT_NEAR(c[ch * K], C[ch] * std::sqrt(4 * kPi), 1e-10);
            for (int k = 1; k < K; ++k) EXPECT_NEAR(c[ch * K + k], 0.0, 1e-10) << "k " << k;
        }
    }
}

TEST(PrtLighting, EnvironmentQuarterTurnEqualsShRotationOfCoefficients) {
    const rad::EnvironmentMap map = testMap(96, 48, 11);
    const int degree = 4, K = 25;
    const std::vector<double> unturned = rad::environmentLightSH(map, degree, 0.0);
    const std::vector<double> turned = rad::environmentLightSH(map, degree, kPi / 2);
    const rad::ShRotation rotation(degree, quarterTurnAboutZ());
    for (int ch = 0; ch < 3; ++ch) {
        std::vector<double> expected(K);
        rotation.apply(unturned.data() + ch * K, expected.data());
        for (int k = 0; k < K; ++k) EXPECT_NEAR(turned[ch * K + k], expected[k], 1e-10) << "channel " << ch << " k " << k;
    }
}

TEST(PrtLighting, EnvironmentQuarterTurnEqualsMapWithShiftedColumns) {
    // Turning the map by +pi/2 about +Z shows in world longitude phi what the file shows at
    // phi - pi/2; longitude decreases by 2 pi / W per column, so column c of the turned map is
    // column c + W/4 of the original. The projection integrates whole texels, so this is exact.
    const int width = 96, height = 48, degree = 5;
    const rad::EnvironmentMap map = testMap(width, height, 12);
    std::vector<float> shifted(map.pixels().size());
    for (int r = 0; r < height; ++r)
        for (int c = 0; c < width; ++c)
            for (int ch = 0; ch < 3; ++ch)
                shifted[(std::size_t(r) * width + c) * 3 + ch] = map.texel((c + width / 4) % width, r)[ch];
    const rad::EnvironmentMap shiftedMap(width, height, std::move(shifted));
    const std::vector<double> turned = rad::environmentLightSH(map, degree, kPi / 2);
    const std::vector<double> reference = rad::environmentLightSH(shiftedMap, degree, 0.0);
    ASSERT_EQ(turned.size(), reference.size());
    for (std::size_t i = 0; i < turned.size(); ++i) EXPECT_NEAR(turned[i], reference[i], 1e-9) << "i " << i;
    // The turn is not a no-op on this map.
    double change = 0.0;
    const std::vector<double> unturned = rad::environmentLightSH(map, degree, 0.0);
    for (std::size_t i = 0; i < turned.size(); ++i) change = std::max(change, std::fabs(turned[i] - unturned[i]));
    EXPECT_GT(change, 0.1);
}

TEST(PrtLighting, EnvironmentTurnComposesWithTheMapsOwnRotation) {
    rad::EnvironmentMap map = testMap(64, 32, 13);
    const std::vector<double> reference = rad::environmentLightSH(map, 4, 0.8);
    map.setRotation(rad::rotationAboutZ(0.3));
    const std::vector<double> composed = rad::environmentLightSH(map, 4, 0.5);
    for (std::size_t i = 0; i < reference.size(); ++i) EXPECT_NEAR(composed[i], reference[i], 1e-10);
    // The map passed const keeps its rotation.
    EXPECT_TRUE(map.rotation().isApprox(rad::rotationAboutZ(0.3), 1e-15));
}

// ---- prtLightingSH: the one lighting of the relighting filter and the decoration ----

TEST(PrtLightingSettings, UpAxisNamesAreInTheOneOrder) {
    ASSERT_EQ(rad::kUpAxisCount, 3);
    EXPECT_STREQ(rad::kUpAxisNames[static_cast<int>(rad::UpAxis::X)], "+X");
    EXPECT_STREQ(rad::kUpAxisNames[static_cast<int>(rad::UpAxis::Y)], "+Y");
    EXPECT_STREQ(rad::kUpAxisNames[static_cast<int>(rad::UpAxis::Z)], "+Z");
    for (int a = 0; a < 3; ++a) {
        EXPECT_EQ(rad::upAxisVector(static_cast<rad::UpAxis>(a)), Eigen::Vector3d::Unit(a));
        // zenithToAxis takes the map's zenith to the same axis.
        EXPECT_TRUE((rad::zenithToAxis(a) * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::Unit(a), 1e-15));
    }
}

TEST(PrtLightingSettings, UnturnedDirectionalIsTheWindowedDelta) {
    std::mt19937 rng(21);
    for (int degree : {0, 3, 5}) {
        const Eigen::Vector3d d = radtest::randomUnit(rng);
        for (int axis = 0; axis < 3; ++axis) {
            rad::PrtLightingSettings s = directionalSettings(degree, 2.5 * d, 1.75);  // need not be unit
            s.upAxis = static_cast<rad::UpAxis>(axis);  // no rotation: the up axis does not move it
            const std::vector<double> c = rad::prtLightingSH(s);
            const std::vector<double> expected = expectedDirectional(degree, d, 1.75, degree + 1.0);
            ASSERT_EQ(c.size(), expected.size());
            for (std::size_t i = 0; i < c.size(); ++i) EXPECT_NEAR(c[i], expected[i], 1e-13) << "i " << i;
        }
    }
}

TEST(PrtLightingSettings, QuarterTurnOfDirectionalEqualsLightAlongTurnedDirection) {
    // Right-handed quarter turns about each axis, written by hand.
    const auto turn = [](int axis, const Eigen::Vector3d& v) -> Eigen::Vector3d {
        if (axis == 0) return {v.x(), -v.z(), v.y()};  // y -> z
        if (axis == 1) return {v.z(), v.y(), -v.x()};  // z -> x
        return {-v.y(), v.x(), v.z()};                 // x -> y
    };
    std::mt19937 rng(22);
    const int degree = 5;
    for (int axis = 0; axis < 3; ++axis)
        for (int trial = 0; trial < 4; ++trial) {
            const Eigen::Vector3d d = radtest::randomUnit(rng);
            rad::PrtLightingSettings s = directionalSettings(degree, d, 2.0);
            s.upAxis = static_cast<rad::UpAxis>(axis);
            s.rotationDegrees = 90.0;
            const std::vector<double> turned = rad::prtLightingSH(s);
            const std::vector<double> expected = expectedDirectional(degree, turn(axis, d), 2.0, degree + 1.0);
            for (std::size_t i = 0; i < turned.size(); ++i)
                EXPECT_NEAR(turned[i], expected[i], 1e-12) << "axis " << axis << " i " << i;
            // A full turn (and -270 degrees) gives the same light.
            s.rotationDegrees = -270.0;
            const std::vector<double> again = rad::prtLightingSH(s);
            for (std::size_t i = 0; i < turned.size(); ++i) EXPECT_NEAR(again[i], expected[i], 1e-12);
        }
}

TEST(PrtLightingSettings, RotationTurnsBothSourcesAboutTheUpAxisInTheSameSense) {
    // f_a(R_up(a) w) = f_0(w): the lighting with rotation a, looked up along the turned direction,
    // is the unturned lighting, for the map and for the directional light alike.
    const rad::EnvironmentMap map = testMap(64, 32, 23);
    std::mt19937 rng(24);
    const int degree = 4;
    const Eigen::Vector3d d = radtest::randomUnit(rng);
    for (int axis = 0; axis < 3; ++axis)
        for (double degrees : {37.0, 90.0, 200.0}) {
            const Eigen::Matrix3d R = elementalRotation(axis, degrees * kPi / 180.0);
            for (int source = 0; source < 2; ++source) {
                rad::PrtLightingSettings s = source == 0
                                                 ? environmentSettings(degree, static_cast<rad::UpAxis>(axis), 0.0, 1.0)
                                                 : directionalSettings(degree, d, 1.0);
                s.upAxis = static_cast<rad::UpAxis>(axis);
                const std::vector<double> unturned = rad::prtLightingSH(s, &map);
                s.rotationDegrees = degrees;
                const std::vector<double> turned = rad::prtLightingSH(s, &map);
                for (int trial = 0; trial < 6; ++trial) {
                    const Eigen::Vector3d w = radtest::randomUnit(rng);
                    for (int ch = 0; ch < 3; ++ch)
                        EXPECT_NEAR(shValue(degree, turned, ch, R * w), shValue(degree, unturned, ch, w), 1e-9)
                            << "source " << source << " axis " << axis << " degrees " << degrees;
                }
            }
        }
}

TEST(PrtLightingSettings, EnvironmentUpAxisPlacesTheMapAsDocumented) {
    const rad::EnvironmentMap map = testMap(96, 48, 25);
    const int degree = 4;
    // +Z, no turn, intensity 1: the map's own projection (environment_map.h), untouched.
    const std::vector<double> own = rad::projectOntoSphericalHarmonics(map, degree);
    const std::vector<double> zUp = rad::prtLightingSH(environmentSettings(degree, rad::UpAxis::Z, 0.0, 1.0), &map);
    ASSERT_EQ(zUp.size(), own.size());
    for (std::size_t i = 0; i < own.size(); ++i) EXPECT_NEAR(zUp[i], own[i], 1e-12);
    // Other axes: the light the map shows in its direction m arrives from mapToWorld(axis, m).
    std::mt19937 rng(26);
    for (int axis = 0; axis < 3; ++axis) {
        const std::vector<double> placed =
            rad::prtLightingSH(environmentSettings(degree, static_cast<rad::UpAxis>(axis), 0.0, 1.0), &map);
        for (int trial = 0; trial < 8; ++trial) {
            const Eigen::Vector3d m = radtest::randomUnit(rng);
            for (int ch = 0; ch < 3; ++ch)
                EXPECT_NEAR(shValue(degree, placed, ch, mapToWorld(axis, m)), shValue(degree, own, ch, m), 1e-9)
                    << "axis " << axis;
        }
    }
}

TEST(PrtLightingSettings, EnvironmentSkyBrightestAtTheChosenUpAxis) {
    // A sky lit only near its zenith (texel values max(0, cos theta)^8): of the six axis directions,
    // the lighting is brightest toward the chosen up axis.
    const int width = 128, height = 64, degree = 4;
    std::vector<float> rgb(std::size_t(width) * height * 3);
    for (int r = 0; r < height; ++r)
        for (int c = 0; c < width; ++c) {
            const double z = mapDirection((c + 0.5) / width, (r + 0.5) / height).z();
            for (int ch = 0; ch < 3; ++ch) rgb[(std::size_t(r) * width + c) * 3 + ch] = float(std::pow(std::max(0.0, z), 8));
        }
    const rad::EnvironmentMap sky(width, height, std::move(rgb));
    for (int axis = 0; axis < 3; ++axis)
        for (double degrees : {0.0, 123.0}) {  // a turn about up leaves a zenith cap in place
            const std::vector<double> c =
                rad::prtLightingSH(environmentSettings(degree, static_cast<rad::UpAxis>(axis), degrees, 1.0), &sky);
            const double atUp = shValue(degree, c, 0, Eigen::Vector3d::Unit(axis));
            // (The truncated cap rings, so the nadir need not be darker than the horizon.)
            EXPECT_GT(atUp, shValue(degree, c, 0, -Eigen::Vector3d::Unit(axis)) + 0.1) << "axis " << axis;
            for (int other = 0; other < 3; ++other)
                if (other != axis) {
                    EXPECT_GT(atUp, shValue(degree, c, 0, Eigen::Vector3d::Unit(other)) + 0.1) << "axis " << axis;
                    EXPECT_GT(atUp, shValue(degree, c, 0, -Eigen::Vector3d::Unit(other)) + 0.1) << "axis " << axis;
                }
        }
}

TEST(PrtLightingSettings, IntensityScalesEveryCoefficientOfBothSources) {
    const rad::EnvironmentMap map = testMap(64, 32, 27);
    std::mt19937 rng(28);
    const int degree = 5;
    const Eigen::Vector3d d = radtest::randomUnit(rng);
    for (int source = 0; source < 2; ++source) {
        rad::PrtLightingSettings s =
            source == 0 ? environmentSettings(degree, rad::UpAxis::Y, 40.0, 1.5) : directionalSettings(degree, d, 1.5);
        s.upAxis = rad::UpAxis::Y;
        s.rotationDegrees = 40.0;
        const std::vector<double> once = rad::prtLightingSH(s, &map);
        s.intensity = 3.0;
        const std::vector<double> twice = rad::prtLightingSH(s, &map);
        ASSERT_EQ(once.size(), twice.size());
        double largest = 0.0;
        for (std::size_t i = 0; i < once.size(); ++i) {
            EXPECT_NEAR(twice[i], 2.0 * once[i], 1e-12 * (1.0 + std::fabs(once[i]))) << "source " << source << " i " << i;
            largest = std::max(largest, std::fabs(once[i]));
        }
        EXPECT_GT(largest, 0.1);  // not a trivially zero lighting
        s.intensity = 0.0;
        for (double c : rad::prtLightingSH(s, &map)) EXPECT_EQ(c, 0.0);
    }
}

TEST(PrtLightingSettings, WindowWidthDefaultsToDegreePlusOneAndCutsBandsBeyond) {
    std::mt19937 rng(29);
    const int degree = 6;
    const Eigen::Vector3d d = radtest::randomUnit(rng);
    // Default (0) = directionalLightSH's window.
    const std::vector<double> byDefault = rad::prtLightingSH(directionalSettings(degree, d, 1.0));
    const std::vector<double> legacy = rad::directionalLightSH(degree, d, Eigen::Vector3d::Ones());
    for (std::size_t i = 0; i < legacy.size(); ++i) EXPECT_NEAR(byDefault[i], legacy[i], 1e-15);
    for (double width : {2.5, 4.0, 20.0}) {
        rad::PrtLightingSettings s = directionalSettings(degree, d, 1.0);
        s.windowWidth = width;
        const std::vector<double> c = rad::prtLightingSH(s);
        const std::vector<double> expected = expectedDirectional(degree, d, 1.0, width);
        for (std::size_t i = 0; i < c.size(); ++i) EXPECT_NEAR(c[i], expected[i], 1e-13) << "width " << width;
        const int K = (degree + 1) * (degree + 1);
        for (int k = 0; k < K; ++k)
            if (bandOf(k) >= width) EXPECT_EQ(c[k], 0.0) << "width " << width << " k " << k;
    }
}

namespace {

// The call throws std::invalid_argument whose message names `parameter` and contains `range`.
template <typename F>
void expectRefusal(F call, const std::string& parameter, const std::string& range) {
    try {
        call();
        ADD_FAILURE() << "no exception for " << parameter;
    } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(parameter), std::string::npos) << what;
        EXPECT_NE(what.find(range), std::string::npos) << what;
    } catch (...) {
        ADD_FAILURE() << "another exception for " << parameter;
    }
}

}  // namespace

TEST(PrtLightingSettings, RefusesInvalidParameters) {
    const rad::EnvironmentMap map = testMap(32, 16, 30);
    const double nan = std::nan(""), inf = std::numeric_limits<double>::infinity();
    for (int source = 0; source < 2; ++source) {
        const rad::PrtLightingSettings good = source == 0 ? environmentSettings(3, rad::UpAxis::Y, 10.0, 1.0)
                                                          : directionalSettings(3, Eigen::Vector3d(0, 1, 1), 1.0);
        EXPECT_NO_THROW(rad::prtLightingSH(good, &map));
        auto with = [&](auto change) {
            rad::PrtLightingSettings s = good;
            change(s);
            return [s, &map] { rad::prtLightingSH(s, &map); };
        };
        for (double bad : {nan, -1.0, -1e-300, inf, -inf})
            expectRefusal(with([&](rad::PrtLightingSettings& s) { s.intensity = bad; }), "intensity", "[0, +inf)");
        for (double bad : {nan, inf, -inf})
            expectRefusal(with([&](rad::PrtLightingSettings& s) { s.rotationDegrees = bad; }), "rotation", "finite");
        for (int bad : {-1, 3})
            expectRefusal(with([&](rad::PrtLightingSettings& s) { s.upAxis = static_cast<rad::UpAxis>(bad); }), "upAxis",
                          "[0, 2]");
        for (int bad : {-1, rad::kMaxHarmonicDegree + 1})
            expectRefusal(with([&](rad::PrtLightingSettings& s) { s.degree = bad; }), "degree",
                          "[0, " + std::to_string(rad::kMaxHarmonicDegree) + "]");
        for (double bad : {nan, -0.5, inf})
            expectRefusal(with([&](rad::PrtLightingSettings& s) { s.windowWidth = bad; }), "window width", "[0, +inf)");
        expectRefusal(with([&](rad::PrtLightingSettings& s) { s.source = static_cast<rad::PrtLightSource>(2); }), "source",
                      "[0, 1]");
        // A rotation of any finite size is fine, and so is intensity 0.
        EXPECT_NO_THROW(with([&](rad::PrtLightingSettings& s) { s.rotationDegrees = -1234.5; })());
        EXPECT_NO_THROW(with([&](rad::PrtLightingSettings& s) { s.intensity = 0.0; })());
    }
    // The direction matters for the directional light only.
    for (const Eigen::Vector3d& bad : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(nan, 0, 1), Eigen::Vector3d(inf, 0, 1)}) {
        rad::PrtLightingSettings s = directionalSettings(3, bad, 1.0);
        expectRefusal([s] { rad::prtLightingSH(s); }, "direction", "non-zero");
        s.source = rad::PrtLightSource::EnvironmentMap;
        EXPECT_NO_THROW(rad::prtLightingSH(s, &map));
    }
    // The map source needs a map.
    expectRefusal([] { rad::prtLightingSH(environmentSettings(3, rad::UpAxis::Z, 0.0, 1.0), nullptr); }, "map", "none");
}
