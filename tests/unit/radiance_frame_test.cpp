// Tests of radiance_frame.h: per-vertex frames and the reflection R_n of Vanhoey et al. 2015 sec. 3.1.
#include "radiance/radiance_frame.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace {

using rad::Frame;
using Eigen::Vector3d;

using radtest::randomUnit;

void expectOrthonormalRightHanded(const Frame& f, const Vector3d& expectedNormal, double tol = 1e-14) {
    EXPECT_NEAR(f.t.norm(), 1.0, tol);
    EXPECT_NEAR(f.b.norm(), 1.0, tol);
    EXPECT_NEAR(f.n.norm(), 1.0, tol);
    EXPECT_NEAR(f.t.dot(f.b), 0.0, tol);
    EXPECT_NEAR(f.t.dot(f.n), 0.0, tol);
    EXPECT_NEAR(f.b.dot(f.n), 0.0, tol);
    EXPECT_LT((f.t.cross(f.b) - f.n).norm(), 4 * tol);  // b = n x t  <=>  t x b = n
    EXPECT_LT((f.n.cross(f.t) - f.b).norm(), 4 * tol);
    EXPECT_LT((f.n - expectedNormal.normalized()).norm(), 4 * tol);
}

// Normals covering the troublesome places: poles, the equator z = 0 (where Duff et al.'s sign switch
// lies), the edge of the south cap, and random ones.
std::vector<Vector3d> testNormals() {
    std::vector<Vector3d> normals = {
        {0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {1, 1, 0}, {1, 0, 1e-300},
        {1, 0, -1e-300}, {1e-9, 0, -1}, {0, 1e-9, -1}, {1e-3, 2e-3, -1}, {3, -4, 12}, {0.2, 0.1, -0.97},
    };
    // Either side of the cap edge 1 + z = kFrameSouthCap.
    for (double dz : {-1e-9, 1e-9}) {
        const double z = -1.0 + rad::kFrameSouthCap + dz;
        const double r = std::sqrt(1 - z * z);
        normals.emplace_back(r * 0.6, r * 0.8, z);
    }
    std::mt19937 rng(11);
    for (int i = 0; i < 500; ++i) normals.push_back(randomUnit(rng));
    return normals;
}

TEST(RadianceFrame, OrthonormalRightHandedForAllNormals) {
    for (const Vector3d& n : testNormals()) {
        SCOPED_TRACE(testing::Message() << "n = " << n.transpose());
        expectOrthonormalRightHanded(rad::frameFromNormal(n), n);
    }
}

TEST(RadianceFrame, UnnormalisedNormalIsNormalised) {
    const Frame f = rad::frameFromNormal(Vector3d(0, 0, 5));
    expectOrthonormalRightHanded(f, Vector3d(0, 0, 1));
    const Frame g = rad::frameFromNormal(Vector3d(3, -4, 12) * 1e-7);
    expectOrthonormalRightHanded(g, Vector3d(3, -4, 12));
}

TEST(RadianceFrame, ZeroOrNonFiniteNormalGivesCanonicalFrame) {
    for (const Vector3d& n : {Vector3d(0, 0, 0), Vector3d(std::numeric_limits<double>::quiet_NaN(), 0, 1),
                              Vector3d(std::numeric_limits<double>::infinity(), 0, 0)}) {
        const Frame f = rad::frameFromNormal(n);
        EXPECT_EQ(f.t, Vector3d(1, 0, 0));
        EXPECT_EQ(f.b, Vector3d(0, 1, 0));
        EXPECT_EQ(f.n, Vector3d(0, 0, 1));
    }
}

TEST(RadianceFrame, ContinuousAcrossTheEquatorAndAwayFromTheSouthPole) {
    // A Lipschitz-like check: moving the normal by 1e-7 moves the tangent by O(1e-7), including across
    // z = 0 (where the sign-switching construction would flip the tangent) and down to the cap edge.
    std::mt19937 rng(5);
    std::vector<Vector3d> normals = {{1, 0, 0}, {0.6, 0.8, 0}, {-0.6, 0.8, 0}, {0, -1, 0}, {0.3, 0.1, -0.94}};
    for (int i = 0; i < 300; ++i) {
        const Vector3d n = randomUnit(rng);
        if (1 + n.z() > 1e-2) normals.push_back(n);  // continuity constant grows like 1/(1+z) near -z
    }
    const double delta = 1e-7;
    for (const Vector3d& n : normals) {
        for (int axis = 0; axis < 3; ++axis) {
            const Vector3d n2 = (n + delta * Vector3d::Unit(axis)).normalized();
            const Vector3d n1 = (n - delta * Vector3d::Unit(axis)).normalized();
            const Frame f1 = rad::frameFromNormal(n1), f2 = rad::frameFromNormal(n2);
            EXPECT_LT((f1.t - f2.t).norm(), 1e3 * delta) << n.transpose();
            EXPECT_LT((f1.b - f2.b).norm(), 1e3 * delta) << n.transpose();
        }
    }
    // Explicitly across the equator.
    const Frame above = rad::frameFromNormal(Vector3d(0.6, 0.8, 1e-9));
    const Frame below = rad::frameFromNormal(Vector3d(0.6, 0.8, -1e-9));
    EXPECT_LT((above.t - below.t).norm(), 1e-8);
}

TEST(RadianceFrame, LocalWorldRoundTrip) {
    std::mt19937 rng(3);
    for (int i = 0; i < 100; ++i) {
        const Frame f = rad::frameFromNormal(randomUnit(rng));
        const Vector3d w = randomUnit(rng);
        const Vector3d l = f.toLocal(w);
        EXPECT_LT((f.toWorld(l) - w).norm(), 1e-14);
        EXPECT_NEAR(l.norm(), 1.0, 1e-14);
        EXPECT_LT((f.toLocal(f.n) - Vector3d(0, 0, 1)).norm(), 1e-14);
        EXPECT_LT((f.toLocal(f.t) - Vector3d(1, 0, 0)).norm(), 1e-14);
        EXPECT_LT((f.rotation() * w - l).norm(), 1e-14);
        EXPECT_NEAR(f.rotation().determinant(), 1.0, 1e-13);
    }
}

TEST(RadianceFrame, TangentHintIsProjected) {
    const Vector3d n = Vector3d(1, 2, 3).normalized();
    const Vector3d hint(1, 0, 0);
    const Frame f = rad::frameFromNormalAndTangent(n, hint);
    expectOrthonormalRightHanded(f, n);
    const Vector3d expected = (hint - n.dot(hint) * n).normalized();
    EXPECT_LT((f.t - expected).norm(), 1e-14);
    // Parallel, zero or NaN hint: falls back to the normal-only frame.
    const Frame fromNormal = rad::frameFromNormal(n);
    for (const Vector3d& bad : {Vector3d(2 * n), Vector3d(0, 0, 0), Vector3d(std::nan(""), 0, 0)}) {
        const Frame g = rad::frameFromNormalAndTangent(n, bad);
        EXPECT_LT((g.t - fromNormal.t).norm(), 1e-15);
    }
}

TEST(RadianceFrame, StoredFrameRoundTrip) {
    std::mt19937 rng(8);
    for (int i = 0; i < 50; ++i) {
        const Frame f = rad::frameFromNormalAndTangent(randomUnit(rng), randomUnit(rng));
        float stored[6];
        rad::storeFrame(f, stored);
        const Frame g = rad::frameFromStored(stored);
        expectOrthonormalRightHanded(g, Vector3d(stored[3], stored[4], stored[5]));
        EXPECT_LT((g.t - f.t).norm(), 1e-6);
        EXPECT_LT((g.n - f.n).norm(), 1e-6);
    }
}

TEST(RadianceFrame, ReflectionAboutNormal) {
    std::mt19937 rng(21);
    for (int i = 0; i < 100; ++i) {
        const Frame f = rad::frameFromNormal(randomUnit(rng));
        const Vector3d w = randomUnit(rng);
        const Vector3d r = rad::reflect(f.n, w);
        // Rotation by pi about n: n fixed, tangent plane negated.
        EXPECT_LT((rad::reflect(f.n, f.n) - f.n).norm(), 1e-15);
        EXPECT_LT((rad::reflect(f.n, f.t) + f.t).norm(), 1e-15);
        EXPECT_LT((f.toLocal(r) - Vector3d(-f.toLocal(w).x(), -f.toLocal(w).y(), f.toLocal(w).z())).norm(), 1e-14);
        EXPECT_NEAR(r.norm(), 1.0, 1e-14);
        EXPECT_NEAR(r.dot(f.n), w.dot(f.n), 1e-15);              // same hemisphere
        EXPECT_LT((rad::reflect(f.n, r) - w).norm(), 1e-14);      // involution
        // Mirror direction: the classical mirror reflection d - 2 (d.n) n of the incoming d = -w.
        const Vector3d incoming = -w;
        EXPECT_LT((r - (incoming - 2 * incoming.dot(f.n) * f.n)).norm(), 1e-14);
    }
}

}  // namespace

TEST(SlerpNormal, RotatesAlongTheGreatCircle) {
    const Eigen::Vector3d n0 = Eigen::Vector3d::UnitZ(), n1 = Eigen::Vector3d::UnitX();
    EXPECT_LT((rad::slerpNormal(n0, n1, 0.0) - n0).norm(), 1e-12);
    EXPECT_LT((rad::slerpNormal(n0, n1, 1.0) - n1).norm(), 1e-12);
    EXPECT_LT((rad::slerpNormal(n0, n1, 0.5) - Eigen::Vector3d(1.0, 0.0, 1.0).normalized()).norm(), 1e-12);
    // A third of the way: 30 degrees from n0 in the plane of the two.
    const Eigen::Vector3d third = rad::slerpNormal(n0, n1, 1.0 / 3.0);
    EXPECT_NEAR(third.z(), std::cos(M_PI / 6.0), 1e-12);
    EXPECT_NEAR(third.x(), std::sin(M_PI / 6.0), 1e-12);
    EXPECT_NEAR(third.y(), 0.0, 1e-12);
    // Opposite normals: halfway is a unit vector orthogonal to both.
    const Eigen::Vector3d half = rad::slerpNormal(n0, -n0, 0.5);
    EXPECT_NEAR(half.norm(), 1.0, 1e-12);
    EXPECT_NEAR(half.dot(n0), 0.0, 1e-12);
}
