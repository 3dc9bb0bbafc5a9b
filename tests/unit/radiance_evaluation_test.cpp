// Tests of radiance_evaluation.h: evaluation of vertex RF, reflected storage (Vanhoey et al. 2015 sec. 3.1) and
// the border extension (sec. 7 "Exceeding hemispheres").
#include "radiance/radiance_evaluation.h"

#include "radiance/basis.h"
#include "radiance/radiance_frame.h"

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

using radtest::randomUnit;

// A field of `count` vertices with random frames (random tangents) and random coefficients.
RadianceField randomField(BasisSpec basis, std::size_t count, unsigned seed, bool reflected = false) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    RadianceField field(basis, count, reflected);
    for (float& c : field.coefficients) c = u(rng);
    for (std::size_t v = 0; v < count; ++v)
        rad::storeFrame(rad::frameFromNormalAndTangent(randomUnit(rng), randomUnit(rng)), field.frame(v));
    return field;
}

// Independent PB evaluation: sum c_ij u^i v^j with (u, v) the local coordinates, by std::pow.
Vector3d manualPolynomial(const RadianceField& f, std::size_t v, double u, double w) {
    const int K = f.coefficientsPerChannel();
    Vector3d out = Vector3d::Zero();
    for (int c = 0; c < 3; ++c) {
        int index = 0;
        for (int total = 0; total <= f.basis.degree; ++total)
            for (int j = 0; j <= total; ++j, ++index)
                out[c] += f.channelCoefficients(v, c)[index] * std::pow(u, total - j) * std::pow(w, j);
        EXPECT_EQ(index, K);
    }
    return out;
}

// Independent SH evaluation for degree <= 1 from the closed forms of spherical_harmonics.h.
Vector3d manualSh1(const RadianceField& f, std::size_t v, const Vector3d& d) {
    const double y00 = 0.2820947917738781, y1 = 0.4886025119029199;
    Vector3d out;
    for (int c = 0; c < 3; ++c) {
        const float* k = f.channelCoefficients(v, c);
        out[c] = k[0] * y00 + k[1] * y1 * d.y() + k[2] * y1 * d.z() + k[3] * y1 * d.x();
    }
    return out;
}

// The border direction of sec. 7 computed from scratch.
Vector3d manualBorder(const rad::Frame& f, const Vector3d& w) {
    if (w.dot(f.n) >= 0) return w;
    return (w - w.dot(f.n) * f.n).normalized();
}

const std::vector<BasisSpec>& allTestBases() {
    static const std::vector<BasisSpec> bases = {
        {BasisKind::HemisphericalPolynomial, 0}, {BasisKind::HemisphericalPolynomial, 1},
        {BasisKind::HemisphericalPolynomial, 4}, {BasisKind::HemisphericalPolynomial, 8},
        {BasisKind::SphericalHarmonics, 0},      {BasisKind::SphericalHarmonics, 1},
        {BasisKind::SphericalHarmonics, 3},      {BasisKind::SphericalHarmonics, 6},
        {BasisKind::SphericalHarmonics, 10},
    };
    return bases;
}

TEST(RadianceEvaluation, PolynomialMatchesManualEvaluationInLocalFrame) {
    const RadianceField f = randomField({BasisKind::HemisphericalPolynomial, 5}, 10, 1);
    std::mt19937 rng(2);
    for (std::size_t v = 0; v < f.vertexCount(); ++v) {
        const rad::Frame frame = rad::frameFromStored(f.frame(v));
        for (int i = 0; i < 20; ++i) {
            Vector3d w = randomUnit(rng);
            if (w.dot(frame.n) < 0) w = rad::reflect(frame.n, -w);  // upper hemisphere
            const Vector3d expected = manualPolynomial(f, v, frame.t.dot(w), frame.n.cross(frame.t).dot(w));
            EXPECT_LT((rad::evaluateRadiance(f, v, w) - expected).norm(), 1e-12);
        }
    }
}

TEST(RadianceEvaluation, HarmonicsMatchClosedFormInGlobalFrame) {
    const RadianceField f = randomField({BasisKind::SphericalHarmonics, 1}, 10, 3);
    std::mt19937 rng(4);
    for (std::size_t v = 0; v < f.vertexCount(); ++v) {
        const rad::Frame frame = rad::frameFromStored(f.frame(v));
        for (int i = 0; i < 20; ++i) {
            Vector3d w = randomUnit(rng);
            if (w.dot(frame.n) < 0) w = rad::reflect(frame.n, -w);
            EXPECT_LT((rad::evaluateRadiance(f, v, w) - manualSh1(f, v, w)).norm(), 1e-12);
        }
    }
}

TEST(RadianceEvaluation, ReflectedRadianceIsRadianceAtReflectedDirection) {
    // L~(w) = L(R_n w), sec. 3.1, for both storages.
    for (const BasisSpec& basis : allTestBases())
        for (bool reflected : {false, true}) {
            SCOPED_TRACE(basis.name() + (reflected ? " reflected" : " plain"));
            const RadianceField f = randomField(basis, 5, 7, reflected);
            std::mt19937 rng(8);
            for (std::size_t v = 0; v < f.vertexCount(); ++v) {
                const rad::Frame frame = rad::frameFromStored(f.frame(v));
                for (int i = 0; i < 20; ++i) {
                    const Vector3d w = randomUnit(rng);
                    const Vector3d lt = rad::evaluateReflectedRadiance(f, v, w);
                    const Vector3d l = rad::evaluateRadiance(f, v, rad::reflect(frame.n, w));
                    EXPECT_LT((lt - l).norm(), 1e-9 * (1 + l.norm()));
                }
            }
        }
}

TEST(RadianceEvaluation, ReflectedStorageRoundTripAndSameRadiance) {
    for (const BasisSpec& basis : allTestBases()) {
        SCOPED_TRACE(basis.name());
        const RadianceField plain = randomField(basis, 40, 9);
        RadianceField converted = plain;
        rad::setReflectedStorage(converted, true);
        EXPECT_TRUE(converted.reflected);
        EXPECT_EQ(converted.validate(), "");
        // L(w) from reflected storage = L(w) from plain storage, at random directions of both
        // hemispheres (below the horizon through the border extension).
        std::mt19937 rng(10);
        for (std::size_t v = 0; v < plain.vertexCount(); ++v)
            for (int i = 0; i < 10; ++i) {
                const Vector3d w = randomUnit(rng);
                const Vector3d a = rad::evaluateRadiance(plain, v, w);
                const Vector3d b = rad::evaluateRadiance(converted, v, w);
                EXPECT_LT((a - b).norm(), 2e-5 * (1 + a.norm())) << "v " << v << " w " << w.transpose();
            }
        // The reflected coefficients themselves are not the plain ones (unless the RF is symmetric).
        if (basis.degree > 0) {
            EXPECT_NE(converted.coefficients, plain.coefficients);
        }
        // No-op when already in the requested storage.
        RadianceField again = converted;
        rad::setReflectedStorage(again, true);
        EXPECT_EQ(again.coefficients, converted.coefficients);
        // Round trip.
        rad::setReflectedStorage(converted, false);
        EXPECT_FALSE(converted.reflected);
        for (std::size_t k = 0; k < plain.coefficients.size(); ++k) {
            if (basis.usesLocalFrame()) {
                EXPECT_EQ(converted.coefficients[k], plain.coefficients[k]);  // sign flips are exact
            } else {
                EXPECT_NEAR(converted.coefficients[k], plain.coefficients[k], 2e-5);
            }
        }
    }
}

TEST(RadianceEvaluation, PolynomialReflectionIsSignFlipByTotalDegree) {
    const BasisSpec basis{BasisKind::HemisphericalPolynomial, 4};
    const rad::Frame frame = rad::frameFromNormal(Vector3d(0.3, -0.2, 0.9));
    std::vector<double> in(3 * basis.coefficientCount()), out(in.size());
    for (std::size_t k = 0; k < in.size(); ++k) in[k] = 1.0 + k;
    rad::reflectCoefficients(basis, frame, in.data(), out.data());
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i <= 4; ++i)
            for (int j = 0; i + j <= 4; ++j) {
                const int k = c * basis.coefficientCount() + rad::polynomialIndex(i, j);
                EXPECT_EQ(out[k], ((i + j) % 2 ? -1.0 : 1.0) * in[k]);
            }
}

TEST(RadianceEvaluation, HarmonicReflectionMatchesEvaluationAtReflectedDirection) {
    // Coefficient-level check on the whole sphere (no border extension): the reflected coefficients
    // evaluated at w equal the original ones at R_n w.
    const BasisSpec basis{BasisKind::SphericalHarmonics, 8};
    std::mt19937 rng(12);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<double> in(3 * basis.coefficientCount()), out(in.size());
    double scratch[rad::kMaxCoefficientsPerChannel];
    for (int trial = 0; trial < 5; ++trial) {
        for (double& c : in) c = u(rng);
        const rad::Frame frame = rad::frameFromNormal(randomUnit(rng));
        rad::reflectCoefficients(basis, frame, in.data(), out.data());
        for (int i = 0; i < 30; ++i) {
            const Vector3d w = randomUnit(rng);
            const Vector3d a = rad::evaluateCoefficients(basis, out.data(), w, scratch);
            const Vector3d b = rad::evaluateCoefficients(basis, in.data(), rad::reflect(frame.n, w), scratch);
            EXPECT_LT((a - b).norm(), 1e-11);
        }
    }
}

TEST(RadianceEvaluation, BelowHorizonEqualsBorderValue) {
    for (const BasisSpec& basis : allTestBases())
        for (bool reflected : {false, true}) {
            SCOPED_TRACE(basis.name() + (reflected ? " reflected" : " plain"));
            const RadianceField f = randomField(basis, 5, 13, reflected);
            std::mt19937 rng(14);
            for (std::size_t v = 0; v < f.vertexCount(); ++v) {
                const rad::Frame frame = rad::frameFromStored(f.frame(v));
                for (int i = 0; i < 20; ++i) {
                    Vector3d w = randomUnit(rng);
                    if (w.dot(frame.n) > 0) w = rad::reflect(frame.n, -w);  // lower hemisphere
                    const Vector3d border = manualBorder(frame, w);
                    EXPECT_NEAR(border.dot(frame.n), 0.0, 1e-14);
                    EXPECT_LT((rad::borderExtendedDirection(frame, w) - border).norm(), 1e-14);
                    const Vector3d below = rad::evaluateRadiance(f, v, w);
                    const Vector3d atBorder = rad::evaluateRadiance(f, v, border);
                    EXPECT_LT((below - atBorder).norm(), 1e-9 * (1 + below.norm()));
                    // Same for the reflected RF (extension commutes with R_n).
                    const Vector3d belowT = rad::evaluateReflectedRadiance(f, v, w);
                    const Vector3d atBorderT = rad::evaluateReflectedRadiance(f, v, border);
                    EXPECT_LT((belowT - atBorderT).norm(), 1e-9 * (1 + belowT.norm()));
                }
            }
        }
}

TEST(RadianceEvaluation, ContinuousAcrossTheHorizon) {
    for (const BasisSpec& basis : allTestBases()) {
        SCOPED_TRACE(basis.name());
        const RadianceField f = randomField(basis, 3, 15);
        std::mt19937 rng(16);
        for (std::size_t v = 0; v < f.vertexCount(); ++v) {
            const rad::Frame frame = rad::frameFromStored(f.frame(v));
            for (int i = 0; i < 10; ++i) {
                const Vector3d h = manualBorder(frame, -frame.n + 0.5 * randomUnit(rng));  // on the horizon
                const Vector3d atHorizon = rad::evaluateRadiance(f, v, h);
                double previous = 1e300;
                for (double eps : {1e-2, 1e-4, 1e-6}) {
                    const Vector3d up = (h + eps * frame.n).normalized(), down = (h - eps * frame.n).normalized();
                    const double jump = (rad::evaluateRadiance(f, v, up) - rad::evaluateRadiance(f, v, down)).norm();
                    EXPECT_LE(jump, previous + 1e-12);
                    previous = jump;
                    // Below: exactly the horizon value; above: within O(eps) (derivatives < ~1e3).
                    EXPECT_LT((rad::evaluateRadiance(f, v, down) - atHorizon).norm(), 1e-9 * (1 + atHorizon.norm()));
                }
                EXPECT_LT(previous, 1e-2);
            }
        }
    }
}

TEST(RadianceEvaluation, OppositePoleUsesTangent) {
    for (const BasisSpec& basis : allTestBases())
        for (bool reflected : {false, true}) {
            SCOPED_TRACE(basis.name());
            const RadianceField f = randomField(basis, 3, 17, reflected);
            for (std::size_t v = 0; v < f.vertexCount(); ++v) {
                const rad::Frame frame = rad::frameFromStored(f.frame(v));
                const Vector3d atPole = rad::evaluateRadiance(f, v, -frame.n);
                EXPECT_TRUE(atPole.allFinite());
                EXPECT_LT((atPole - rad::evaluateRadiance(f, v, frame.t)).norm(), 1e-9 * (1 + atPole.norm()));
                EXPECT_LT((rad::borderExtendedDirection(frame, -frame.n) - frame.t).norm(), 1e-15);
                // Near (not at) the pole the azimuth still decides: the bitangent side.
                const Vector3d nearPole = (-frame.n + 1e-6 * frame.b).normalized();
                EXPECT_LT((rad::borderExtendedDirection(frame, nearPole) - frame.b).norm(), 1e-9);
            }
        }
}

TEST(RadianceEvaluation, VertexCoefficientsInEitherStorage) {
    const BasisSpec basis{BasisKind::SphericalHarmonics, 4};
    const RadianceField plain = randomField(basis, 4, 19);
    RadianceField reflected = plain;
    rad::setReflectedStorage(reflected, true);
    const int count = plain.coefficientsPerVertex();
    std::vector<double> a(count), b(count);
    for (std::size_t v = 0; v < plain.vertexCount(); ++v) {
        rad::vertexCoefficients(plain, v, true, a.data());
        rad::vertexCoefficients(reflected, v, true, b.data());
        for (int k = 0; k < count; ++k) EXPECT_NEAR(a[k], b[k], 1e-6);
        rad::vertexCoefficients(reflected, v, false, a.data());
        for (int k = 0; k < count; ++k) EXPECT_NEAR(a[k], plain.vertexCoefficients(v)[k], 2e-6);
    }
}

TEST(RadianceEvaluation, DoubleViewMatchesFloatField) {
    const RadianceField f = randomField({BasisKind::SphericalHarmonics, 5}, 2, 23, true);
    std::vector<double> coefficients(f.coefficients.begin(), f.coefficients.end());
    std::mt19937 rng(24);
    double scratch[rad::kMaxCoefficientsPerChannel];
    for (std::size_t v = 0; v < f.vertexCount(); ++v) {
        rad::VertexRadianceD view;
        view.basis = f.basis;
        view.coefficients = coefficients.data() + v * f.coefficientsPerVertex();
        view.frame = rad::frameFromStored(f.frame(v));
        view.reflected = true;
        for (int i = 0; i < 10; ++i) {
            const Vector3d w = randomUnit(rng);
            EXPECT_LT((rad::evaluateRadiance(view, w, scratch) - rad::evaluateRadiance(f, v, w)).norm(), 1e-12);
        }
    }
}

TEST(RadianceEvaluation, ParallelConversionMatchesPerVertex) {
    const BasisSpec basis{BasisKind::SphericalHarmonics, 6};
    const RadianceField plain = randomField(basis, 500, 25);
    RadianceField converted = plain;
    rad::setReflectedStorage(converted, true);
    const int count = plain.coefficientsPerVertex();
    std::vector<float> expected(count);
    for (std::size_t v = 0; v < plain.vertexCount(); v += 7) {
        rad::reflectCoefficients(basis, rad::frameFromStored(plain.frame(v)), plain.vertexCoefficients(v),
                                 expected.data());
        for (int k = 0; k < count; ++k) EXPECT_NEAR(converted.vertexCoefficients(v)[k], expected[k], 1e-6);
    }
}

}  // namespace
