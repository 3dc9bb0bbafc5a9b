// Tests of radiance/spherical_harmonics.h against computations that share no code with it:
// closed-form polynomials for l <= 3, the C++17 special functions std::sph_legendre and
// std::assoc_legendre for every l <= kMaxHarmonicDegree, and brute-force (theta, phi) integration
// for orthonormality.
#include "radiance/basis.h"
#include "radiance/spherical_harmonics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kCount = (rad::kMaxHarmonicDegree + 1) * (rad::kMaxHarmonicDegree + 1);

struct Dir {
    double x, y, z;
};

std::vector<Dir> randomDirections(int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> g(0.0, 1.0);
    std::vector<Dir> dirs;
    while (static_cast<int>(dirs.size()) < n) {
        const double x = g(rng), y = g(rng), z = g(rng);
        const double r = std::sqrt(x * x + y * y + z * z);
        if (r < 1e-3) continue;
        dirs.push_back({x / r, y / r, z / r});
    }
    // Special directions: poles, equator, axes, where sin t = 0 or z = 0.
    dirs.push_back({0, 0, 1});
    dirs.push_back({0, 0, -1});
    dirs.push_back({1, 0, 0});
    dirs.push_back({0, 1, 0});
    dirs.push_back({-1, 0, 0});
    dirs.push_back({0, -1, 0});
    dirs.push_back({std::sqrt(0.5), -std::sqrt(0.5), 0});
    return dirs;
}

// The real SH table written out by hand (no Condon-Shortley phase, see spherical_harmonics.h).
std::vector<double> closedFormUpTo3(double x, double y, double z) {
    const double pi = kPi;
    return {
        0.5 * std::sqrt(1 / pi),
        std::sqrt(3 / (4 * pi)) * y,
        std::sqrt(3 / (4 * pi)) * z,
        std::sqrt(3 / (4 * pi)) * x,
        0.5 * std::sqrt(15 / pi) * x * y,
        0.5 * std::sqrt(15 / pi) * y * z,
        0.25 * std::sqrt(5 / pi) * (3 * z * z - 1),
        0.5 * std::sqrt(15 / pi) * x * z,
        0.25 * std::sqrt(15 / pi) * (x * x - y * y),
        0.25 * std::sqrt(35 / (2 * pi)) * y * (3 * x * x - y * y),
        0.5 * std::sqrt(105 / pi) * x * y * z,
        0.25 * std::sqrt(21 / (2 * pi)) * y * (5 * z * z - 1),
        0.25 * std::sqrt(7 / pi) * (5 * z * z * z - 3 * z),
        0.25 * std::sqrt(21 / (2 * pi)) * x * (5 * z * z - 1),
        0.25 * std::sqrt(105 / pi) * z * (x * x - y * y),
        0.25 * std::sqrt(35 / (2 * pi)) * x * (x * x - 3 * y * y),
    };
}

// Y_l^m via std::sph_legendre, which includes the Condon-Shortley phase (-1)^m: we remove it.
double viaSphLegendre(int l, int m, const Dir& d) {
    const int am = std::abs(m);
    const double theta = std::acos(std::max(-1.0, std::min(1.0, d.z)));
    const double phi = std::atan2(d.y, d.x);
    const double v = std::sph_legendre(l, am, theta) * ((am % 2) ? -1.0 : 1.0);
    if (m == 0) return v;
    return std::sqrt(2.0) * v * (m > 0 ? std::cos(am * phi) : std::sin(am * phi));
}

// Y_l^m via std::assoc_legendre (no Condon-Shortley phase in the C++ standard's definition) and
// the normalisation written with Gamma functions.
double viaAssocLegendre(int l, int m, const Dir& d) {
    const int am = std::abs(m);
    const double k = std::sqrt((2 * l + 1) / (4 * kPi) * std::tgamma(l - am + 1.0) / std::tgamma(l + am + 1.0));
    const double p = std::assoc_legendre(l, am, d.z);
    const double phi = std::atan2(d.y, d.x);
    if (m == 0) return k * p;
    return std::sqrt(2.0) * k * p * (m > 0 ? std::cos(am * phi) : std::sin(am * phi));
}

TEST(SphericalHarmonics, MatchesClosedFormUpToDegree3) {
    double out[16];
    for (const Dir& d : randomDirections(200, 1)) {
        rad::evaluateSphericalHarmonics(3, d.x, d.y, d.z, out);
        const std::vector<double> expected = closedFormUpTo3(d.x, d.y, d.z);
        for (int i = 0; i < 16; ++i) EXPECT_NEAR(out[i], expected[i], 1e-14) << "index " << i;
    }
}

TEST(SphericalHarmonics, BandOneIsPositiveMultipleOfYZX) {
    // The documented sign convention: Y_1^-1, Y_1^0, Y_1^1 = c (y, z, x), c > 0.
    double out[4];
    rad::evaluateSphericalHarmonics(1, 1.0, 0.0, 0.0, out);
    EXPECT_GT(out[rad::harmonicIndex(1, 1)], 0.48);
    rad::evaluateSphericalHarmonics(1, 0.0, 1.0, 0.0, out);
    EXPECT_GT(out[rad::harmonicIndex(1, -1)], 0.48);
    rad::evaluateSphericalHarmonics(1, 0.0, 0.0, 1.0, out);
    EXPECT_GT(out[rad::harmonicIndex(1, 0)], 0.48);
}

TEST(SphericalHarmonics, MatchesStdSphLegendreAllDegrees) {
    double out[kCount];
    for (const Dir& d : randomDirections(300, 2)) {
        rad::evaluateSphericalHarmonics(rad::kMaxHarmonicDegree, d.x, d.y, d.z, out);
        for (int l = 0; l <= rad::kMaxHarmonicDegree; ++l)
            for (int m = -l; m <= l; ++m)
                EXPECT_NEAR(out[rad::harmonicIndex(l, m)], viaSphLegendre(l, m, d), 1e-12)
                    << "l=" << l << " m=" << m << " at (" << d.x << ", " << d.y << ", " << d.z << ")";
    }
}

TEST(SphericalHarmonics, MatchesStdAssocLegendreAllDegrees) {
    double out[kCount];
    for (const Dir& d : randomDirections(300, 3)) {
        rad::evaluateSphericalHarmonics(rad::kMaxHarmonicDegree, d.x, d.y, d.z, out);
        for (int l = 0; l <= rad::kMaxHarmonicDegree; ++l)
            for (int m = -l; m <= l; ++m)
                EXPECT_NEAR(out[rad::harmonicIndex(l, m)], viaAssocLegendre(l, m, d), 1e-12)
                    << "l=" << l << " m=" << m;
    }
}

TEST(SphericalHarmonics, PolesGiveZonalValuesOnly) {
    double out[kCount];
    for (double s : {1.0, -1.0}) {
        rad::evaluateSphericalHarmonics(rad::kMaxHarmonicDegree, 0.0, 0.0, s, out);
        for (int l = 0; l <= rad::kMaxHarmonicDegree; ++l)
            for (int m = -l; m <= l; ++m) {
                const double expected = m == 0 ? std::sqrt((2 * l + 1) / (4 * kPi)) * std::pow(s, l) : 0.0;
                EXPECT_NEAR(out[rad::harmonicIndex(l, m)], expected, 1e-13) << "l=" << l << " m=" << m;
            }
    }
}

TEST(SphericalHarmonics, WritesExactlyTheRequestedCountAndLowerDegreesArePrefixes) {
    const Dir d{0.36, -0.48, 0.8};
    double full[kCount];
    rad::evaluateSphericalHarmonics(rad::kMaxHarmonicDegree, d.x, d.y, d.z, full);
    for (int degree = 0; degree <= rad::kMaxHarmonicDegree; ++degree) {
        std::vector<double> out(kCount + 1, -12345.0);
        rad::evaluateSphericalHarmonics(degree, d.x, d.y, d.z, out.data());
        const int n = (degree + 1) * (degree + 1);
        for (int i = 0; i < n; ++i) EXPECT_EQ(out[i], full[i]) << "degree " << degree << " index " << i;
        for (int i = n; i <= kCount; ++i) EXPECT_EQ(out[i], -12345.0) << "degree " << degree << " wrote index " << i;
    }
}

TEST(SphericalHarmonics, FloatMatchesDouble) {
    double outD[kCount];
    float outF[kCount];
    for (const Dir& d : randomDirections(200, 4)) {
        rad::evaluateSphericalHarmonics(rad::kMaxHarmonicDegree, d.x, d.y, d.z, outD);
        rad::evaluateSphericalHarmonics(rad::kMaxHarmonicDegree, static_cast<float>(d.x), static_cast<float>(d.y),
                                        static_cast<float>(d.z), outF);
        for (int i = 0; i < kCount; ++i) EXPECT_NEAR(outF[i], outD[i], 2e-5) << "index " << i;
    }
}

TEST(SphericalHarmonics, RejectsDegreeOutOfRange) {
    double out[kCount + 64];
    EXPECT_THROW(rad::evaluateSphericalHarmonics(-1, 0.0, 0.0, 1.0, out), std::out_of_range);
    EXPECT_THROW(rad::evaluateSphericalHarmonics(rad::kMaxHarmonicDegree + 1, 0.0, 0.0, 1.0, out), std::out_of_range);
}

// Orthonormality by brute force on a (theta, phi) midpoint grid, independent of any quadrature
// rule in the library. In phi the midpoint rule is exact for trigonometric polynomials of degree
// < nPhi (products here have degree <= 20); in theta the error is O(h^2) ~ 1e-6 for nTheta = 2000.
TEST(SphericalHarmonics, OrthonormalByBruteForceIntegration) {
    const int degree = rad::kMaxHarmonicDegree;
    const int n = (degree + 1) * (degree + 1);
    const int nTheta = 2000, nPhi = 48;
    std::vector<double> gram(static_cast<std::size_t>(n) * n, 0.0);
    std::vector<double> y(n);
    for (int i = 0; i < nTheta; ++i) {
        const double theta = (i + 0.5) * kPi / nTheta;
        const double w = std::sin(theta) * (kPi / nTheta) * (2 * kPi / nPhi);
        for (int j = 0; j < nPhi; ++j) {
            const double phi = (j + 0.5) * 2 * kPi / nPhi;
            rad::evaluateSphericalHarmonics(degree, std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                                            std::cos(theta), y.data());
            for (int a = 0; a < n; ++a) {
                const double wa = w * y[a];
                for (int b = a; b < n; ++b) gram[a * n + b] += wa * y[b];
            }
        }
    }
    double worst = 0.0;
    for (int a = 0; a < n; ++a)
        for (int b = a; b < n; ++b) {
            const double err = std::fabs(gram[a * n + b] - (a == b ? 1.0 : 0.0));
            worst = std::max(worst, err);
            EXPECT_LT(err, 2e-5) << "<Y_" << a << ", Y_" << b << "> = " << gram[a * n + b];
        }
    RecordProperty("worst_gram_error", std::to_string(worst));
}

}  // namespace
