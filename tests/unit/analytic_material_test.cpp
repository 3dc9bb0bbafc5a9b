// Tests of radiance/analytic_material.h against closed forms (Lambert under one light, inverse
// square falloff, ambient), geometric facts (the Blinn-Phong highlight peaks at the mirror
// direction, BRDF reciprocity), the stripes of Vanhoey et al. 2015 Fig. 8, the horizon clamp, and the
// energy of the lobe by white-furnace integration on a midpoint (theta, phi) grid.
#include "radiance/analytic_material.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

constexpr double kPi = 3.14159265358979323846;
using Eigen::Vector3d;
using rad::Rgb;

Vector3d fromAngles(double theta, double phi) {
    return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

void expectRgbNear(const Rgb& a, const Rgb& b, double tol) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], tol) << "channel " << c;
}

rad::AnalyticMaterial lambertOnly(const Rgb& albedo) {
    rad::AnalyticMaterial m;
    m.albedo = albedo;
    m.specular = Rgb::Zero();
    return m;
}

TEST(AnalyticMaterial, LambertUnderOneDirectionalLight) {
    const rad::AnalyticMaterial m = lambertOnly(Rgb(0.2, 0.5, 0.8));
    const Vector3d n(0, 0, 1);
    const double theta = 40.0 * kPi / 180.0;
    rad::AnalyticLighting lights;
    lights.directional.push_back({fromAngles(theta, 0.7) * 3.0 /* not unit on purpose */, Rgb(1, 2, 3)});
    const Rgb expected = Rgb(0.2 * 1, 0.5 * 2, 0.8 * 3) / kPi * std::cos(theta);
    // Independent of w_o and of p.
    for (const Vector3d& wo : {Vector3d(0, 0, 1), fromAngles(1.2, 2.0), fromAngles(0.4, -1.0)})
        expectRgbNear(rad::outgoingRadiance(m, lights, Vector3d(3, -1, 2), n, wo), expected, 1e-12);
    // Tilted normal: the same with the angle measured from it.
    const Vector3d tilted = Vector3d(1, 1, 1).normalized();
    lights.directional[0].direction = tilted;
    expectRgbNear(rad::outgoingRadiance(m, lights, Vector3d::Zero(), tilted, tilted), Rgb(0.2, 1.0, 2.4) / kPi, 1e-12);
}

TEST(AnalyticMaterial, LightsBelowTheHorizonContributeNothing) {
    rad::AnalyticMaterial m;
    rad::AnalyticLighting lights;
    lights.directional.push_back({Vector3d(0.3, 0, -1), Rgb::Ones()});
    lights.points.push_back({Vector3d(0, 1, -0.5), Rgb::Ones() * 10});
    const Rgb L = rad::outgoingRadiance(m, lights, Vector3d::Zero(), Vector3d(0, 0, 1), Vector3d(0, 0, 1));
    expectRgbNear(L, Rgb::Zero(), 0.0);
}

TEST(AnalyticMaterial, AmbientIsAlbedoTimesAmbientForEveryDirection) {
    rad::AnalyticMaterial m;
    m.albedo = Rgb(0.1, 0.4, 0.9);
    rad::AnalyticLighting lights;
    lights.ambient = Rgb(2, 1, 0.5);
    for (double theta : {0.0, 0.5, 1.5})
        expectRgbNear(rad::outgoingRadiance(m, lights, Vector3d::Zero(), Vector3d(0, 0, 1), fromAngles(theta, 1.0)),
                      Rgb(0.2, 0.4, 0.45), 1e-12);
}

TEST(AnalyticMaterial, HighlightPeaksAtTheMirrorDirection) {
    rad::AnalyticMaterial m;
    m.albedo = Rgb(0.3, 0.3, 0.3);
    m.specular = Rgb(0.5, 0.5, 0.5);
    m.exponent = 200.0;
    const Vector3d n = Vector3d(0.2, -0.1, 1).normalized();
    const Vector3d l = Vector3d(1, 0.5, 1.2).normalized();
    const Vector3d mirror = 2.0 * n.dot(l) * n - l;
    rad::AnalyticLighting lights;
    lights.directional.push_back({l, Rgb::Ones()});

    // Dense search over the sphere of directions (those below the horizon are clamped, never peaks).
    const int N = 400;
    double best = -1.0;
    Vector3d bestDir = Vector3d::Zero();
    for (int i = 0; i < N; ++i)
        for (int j = 0; j < 2 * N; ++j) {
            const Vector3d wo = fromAngles((i + 0.5) * kPi / N, (j + 0.5) * kPi / N);
            const double L = rad::outgoingRadiance(m, lights, Vector3d::Zero(), n, wo)[0];
            if (L > best) {
                best = L;
                bestDir = wo;
            }
        }
    EXPECT_LT(std::acos(std::min(1.0, bestDir.dot(mirror))), 1.0 * kPi / 180.0);
    // And exactly at the mirror direction: diffuse + the full lobe (n.h = 1).
    const double peak = rad::outgoingRadiance(m, lights, Vector3d::Zero(), n, mirror)[0];
    EXPECT_NEAR(peak, (0.3 / kPi + 0.5 * (200.0 + 8.0) / (8.0 * kPi)) * n.dot(l), 1e-9);
    EXPECT_GE(peak, best - 1e-12);
    // 26 degrees away from the mirror direction (13 degrees for the half vector) the lobe is gone.
    const Vector3d off = (mirror + 0.5 * n.cross(mirror).normalized()).normalized();
    EXPECT_LT(rad::outgoingRadiance(m, lights, Vector3d::Zero(), n, off)[0], 0.5 * peak);
}

TEST(AnalyticMaterial, BrdfIsReciprocal) {
    rad::AnalyticMaterial m;
    m.exponent = 30.0;
    const Vector3d n(0, 0, 1);
    for (int k = 0; k < 20; ++k) {
        const Vector3d a = fromAngles(0.07 * k, 0.3 * k), b = fromAngles(1.4 - 0.05 * k, -0.2 * k);
        expectRgbNear(rad::evaluateBrdf(m, Vector3d::Zero(), n, a, b), rad::evaluateBrdf(m, Vector3d::Zero(), n, b, a),
                      1e-12);
    }
}

TEST(AnalyticMaterial, StripesAlternateDiffuseAndSpecularBands) {
    rad::AnalyticMaterial m;
    m.albedo = Rgb(0.4, 0.4, 0.4);
    m.specular = Rgb(0.5, 0.5, 0.5);
    m.exponent = 40.0;
    m.stripes = rad::StripePattern::covering(Vector3d::UnitZ(), -1.0, 1.0, 8);  // bands of 0.25
    EXPECT_DOUBLE_EQ(m.stripes.bandWidth, 0.25);
    rad::AnalyticLighting lights;
    const Vector3d n(1, 0, 0);  // a vertical wall facing +x, points spread along z
    lights.directional.push_back({Vector3d(1, 0, 1).normalized(), Rgb::Ones()});
    const Vector3d mirror = Vector3d(1, 0, -1).normalized();
    const double diffuse = 0.4 / kPi * std::sqrt(0.5);

    for (int band = 0; band < 8; ++band) {
        const Vector3d p(0.0, 0.3, -1.0 + 0.25 * (band + 0.5));
        EXPECT_EQ(m.stripes.band(p), band);
        EXPECT_EQ(m.stripes.isSpecular(p), band % 2 == 1);
        const double L = rad::outgoingRadiance(m, lights, p, n, mirror)[1];
        if (band % 2 == 1)
            EXPECT_GT(L, 5.0 * diffuse) << "band " << band;
        else
            EXPECT_NEAR(L, diffuse, 1e-12) << "band " << band;
    }
    // Beyond the covered range the pattern continues (negative bands too), and the parity flips.
    EXPECT_EQ(m.stripes.band(Vector3d(0, 0, -1.1)), -1);
    EXPECT_TRUE(m.stripes.isSpecular(Vector3d(0, 0, -1.1)));
    m.stripes.specularOnOdd = false;
    EXPECT_TRUE(m.stripes.isSpecular(Vector3d(0, 0, -0.9)));
    EXPECT_FALSE(m.stripes.isSpecular(Vector3d(0, 0, -0.7)));
    // An oblique, non-unit axis is normalised.
    m.stripes.axis = Vector3d(0, 2, 2);
    EXPECT_EQ(m.stripes.band(Vector3d(0, 1, 1) * (0.3 / std::sqrt(2.0))), 5);
    m.stripes.enabled = false;
    EXPECT_TRUE(m.stripes.isSpecular(Vector3d(0, 0, -0.7)));
}

TEST(AnalyticMaterial, PointLightFallsOffWithTheSquareOfTheDistance) {
    const rad::AnalyticMaterial m = lambertOnly(Rgb(0.6, 0.6, 0.6));
    const Vector3d p(0.5, -0.5, 0.0), n(0, 0, 1), wo(0, 0, 1);
    const Vector3d dir = Vector3d(0.3, 0.4, 1).normalized();
    double first = 0.0;
    for (double d : {0.5, 1.0, 2.0, 8.0}) {
        rad::AnalyticLighting lights;
        lights.points.push_back({p + d * dir, Rgb(5, 5, 5)});
        const double L = rad::outgoingRadiance(m, lights, p, n, wo)[0];
        EXPECT_NEAR(L, 0.6 / kPi * 5.0 * dir.z() / (d * d), 1e-12) << "d = " << d;
        if (d == 0.5) first = L;
        EXPECT_NEAR(L * d * d, first * 0.25, 1e-12);
    }
    // A light at the point itself contributes nothing (no division by zero).
    rad::AnalyticLighting at;
    at.points.push_back({p, Rgb::Ones()});
    expectRgbNear(rad::outgoingRadiance(m, at, p, n, wo), Rgb::Zero(), 0.0);
}

TEST(AnalyticMaterial, ViewDirectionsBelowTheHorizonUseTheHorizon) {
    rad::AnalyticMaterial m;
    m.exponent = 10.0;
    rad::AnalyticLighting lights;
    lights.directional.push_back({Vector3d(-1, 0, 0.3), Rgb::Ones()});  // grazing, so the lobe reaches the horizon
    const Vector3d n(0, 0, 1);
    const Vector3d below = Vector3d(1, 0.2, -0.5);
    const Vector3d horizon = Vector3d(1, 0.2, 0).normalized();
    EXPECT_TRUE(rad::clampToHemisphere(n, below).isApprox(horizon, 1e-12));
    const Rgb atHorizon = rad::outgoingRadiance(m, lights, Vector3d::Zero(), n, horizon);
    expectRgbNear(rad::outgoingRadiance(m, lights, Vector3d::Zero(), n, below), atHorizon, 1e-12);
    EXPECT_GT(atHorizon[0], 0.5 / kPi * std::sin(std::atan2(0.3, 1.0)));  // the lobe is visible there
    // Continuity across the horizon.
    const Rgb justAbove = rad::outgoingRadiance(m, lights, Vector3d::Zero(), n, Vector3d(1, 0.2, 1e-7));
    expectRgbNear(justAbove, atHorizon, 1e-6);
    // w_o = -n: some horizon direction, finite.
    const Rgb antipodal = rad::outgoingRadiance(m, lights, Vector3d::Zero(), n, -n);
    for (int c = 0; c < 3; ++c) EXPECT_TRUE(std::isfinite(antipodal[c]));
    EXPECT_NEAR(rad::clampToHemisphere(n, -n).dot(n), 0.0, 1e-12);
    // Zero vectors give zero radiance, not NaN.
    expectRgbNear(rad::outgoingRadiance(m, lights, Vector3d::Zero(), Vector3d::Zero(), n), Rgb::Zero(), 0.0);
}

// White furnace: uniform incident radiance 1 from the whole upper hemisphere, made of one
// directional light per cell of a midpoint (theta, phi) grid with irradiance dOmega. The result is
// the directional albedo of the material towards w_o.
double whiteFurnace(const rad::AnalyticMaterial& m, const Vector3d& wo, int N = 200) {
    const Vector3d n(0, 0, 1);
    const double dTheta = 0.5 * kPi / N, dPhi = 2.0 * kPi / (2 * N);
    double sum = 0.0;
    for (int i = 0; i < N; ++i) {
        const double theta = (i + 0.5) * dTheta;
        const double dOmega = std::sin(theta) * dTheta * dPhi;
        for (int j = 0; j < 2 * N; ++j) {
            const rad::DirectionalLight light{fromAngles(theta, (j + 0.5) * dPhi), Rgb::Constant(dOmega)};
            sum += rad::lightContribution(m, light, Vector3d::Zero(), n, wo)[0];
        }
    }
    return sum;
}

TEST(AnalyticMaterial, WhiteFurnaceLambertReflectsItsAlbedo) {
    const rad::AnalyticMaterial m = lambertOnly(Rgb(0.7, 0.7, 0.7));
    EXPECT_NEAR(whiteFurnace(m, Vector3d(0, 0, 1)), 0.7, 0.7e-3);
    EXPECT_NEAR(whiteFurnace(m, fromAngles(1.2, 0.5)), 0.7, 0.7e-3);
}

TEST(AnalyticMaterial, WhiteFurnaceLobeNormalisationHoldsAtNormalIncidence) {
    // (e + 8) / (8 pi) approximates the exact normalisation of the Blinn-Phong lobe: the directional
    // albedo towards the normal is ks within 8 % for small e and 2 % for e >= 100.
    for (double e : {1.0, 10.0, 32.0, 100.0, 500.0}) {
        rad::AnalyticMaterial m;
        m.albedo = Rgb::Zero();
        m.specular = Rgb::Ones();
        m.exponent = e;
        const double albedo = whiteFurnace(m, Vector3d(0, 0, 1), e >= 100.0 ? 400 : 200);
        EXPECT_NEAR(albedo, 1.0, e >= 100.0 ? 0.02 : 0.08) << "e = " << e;
        // Away from the normal Blinn-Phong loses energy (part of the lobe falls below the horizon):
        // never more than at normal incidence.
        EXPECT_LE(whiteFurnace(m, fromAngles(1.0, 0.0)), albedo + 1e-9) << "e = " << e;
    }
    // A half-diffuse, half-glossy material conserves energy within a few percent.
    rad::AnalyticMaterial half;
    half.albedo = Rgb::Constant(0.5);
    half.specular = Rgb::Constant(0.5);
    half.exponent = 100.0;
    EXPECT_NEAR(whiteFurnace(half, Vector3d(0, 0, 1), 400), 1.0, 0.02);
}

}  // namespace
