// Tests of acquisition/camera_rig.h: every camera looks at the centre, the object fills the asked
// fraction of the frame, directions stay in the elevation band and are spread, the rig is
// deterministic per seed, the image is upright, bad options are refused.
#include "acquisition/camera_rig.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace {

using Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;

TEST(CameraRig, EveryCameraSeesTheCentreAtThePrincipalPointFromTheFramingDistance) {
    rad::CameraRigOptions o;
    o.count = 40;
    o.width = 640;
    o.height = 480;
    const Vector3d centre(1.0, -2.0, 0.5);
    const double radius = 3.0;
    const std::vector<rad::PinholeCamera> cams = rad::makeCameraRig(centre, radius, o);
    ASSERT_EQ(cams.size(), 40u);
    // f = (W / 2) / tan(fov / 2); t = fill * min(W, H) / (2 f); d = r sqrt(1 + 1 / t^2).
    const double f = 320.0 / std::tan(0.5 * o.horizontalFovDegrees * kPi / 180.0);
    const double t = o.fillFraction * 480.0 / (2.0 * f);
    const double d = radius * std::sqrt(1.0 + 1.0 / (t * t));
    for (const rad::PinholeCamera& cam : cams) {
        EXPECT_TRUE(cam.validate().empty()) << cam.validate();
        double u = 0, v = 0;
        ASSERT_TRUE(cam.project(centre, u, v));
        EXPECT_NEAR(u, 320.0, 1e-9);
        EXPECT_NEAR(v, 240.0, 1e-9);
        EXPECT_NEAR(cam.cx, 320.0, 0.0);
        EXPECT_NEAR(cam.cy, 240.0, 0.0);
        EXPECT_NEAR((cam.center - centre).norm(), d, 1e-9 * d);
    }
}

// The bounding sphere's silhouette reaches fillFraction * min(W, H) / 2 pixels from the centre.
TEST(CameraRig, BoundingSphereFillsTheAskedFractionOfTheFrame) {
    rad::CameraRigOptions o;
    o.count = 5;
    o.width = 800;
    o.height = 600;
    o.fillFraction = 0.7;
    const Vector3d centre(0.0, 0.0, 0.0);
    const double radius = 2.0;
    for (const rad::PinholeCamera& cam : rad::makeCameraRig(centre, radius, o)) {
        // Dense sampling of the sphere: the largest image distance from the principal point.
        double farthest = 0.0;
        const int n = 400;
        for (int i = 0; i < n; ++i) {
            const double z = 1.0 - 2.0 * (i + 0.5) / n, s = std::sqrt(1.0 - z * z);
            for (int j = 0; j < n; ++j) {
                const double phi = 2.0 * kPi * j / n;
                const Vector3d p = centre + radius * Vector3d(s * std::cos(phi), s * std::sin(phi), z);
                double u, v;
                if (cam.project(p, u, v)) farthest = std::max(farthest, std::hypot(u - cam.cx, v - cam.cy));
            }
        }
        EXPECT_NEAR(farthest, 0.7 * 600 / 2, 1.0);  // sampled: slightly below the exact silhouette
        EXPECT_LE(farthest, 0.7 * 600 / 2 + 1e-6);
    }
}

TEST(CameraRig, DirectionsStayInTheElevationBandAndAreSpread) {
    rad::CameraRigOptions o;
    o.count = 60;
    o.minElevationDegrees = 0.0;
    o.maxElevationDegrees = 75.0;
    o.up = Vector3d(0.0, 1.0, 0.0);
    o.jitter = 1.0;  // the largest jitter must still respect the band
    const std::vector<rad::PinholeCamera> cams = rad::makeCameraRig(Vector3d::Zero(), 1.0, o);
    std::vector<Vector3d> dirs;
    for (const rad::PinholeCamera& cam : cams) {
        const Vector3d d = cam.center.normalized();
        const double elevation = std::asin(std::clamp(d.y(), -1.0, 1.0)) * 180.0 / kPi;
        EXPECT_GE(elevation, -1e-9);
        EXPECT_LE(elevation, 75.0 + 1e-9);
        dirs.push_back(d);
    }
    // Spread: spacing ~ sqrt(band area / N); no two cameras much closer than a fraction of it.
    const double spacing = std::sqrt(2.0 * kPi * std::sin(75.0 * kPi / 180.0) / o.count);
    double closest = 10.0;
    for (std::size_t i = 0; i < dirs.size(); ++i)
        for (std::size_t j = i + 1; j < dirs.size(); ++j) closest = std::min(closest, (dirs[i] - dirs[j]).norm());
    EXPECT_GT(closest, 0.1 * spacing);
    // Both halves of the azimuth circle are used, and high and low elevations.
    int east = 0, high = 0;
    for (const Vector3d& d : dirs) {
        east += d.x() > 0.0;
        high += d.y() > std::sin(45.0 * kPi / 180.0);
    }
    EXPECT_GT(east, 15);
    EXPECT_LT(east, 45);
    EXPECT_GT(high, 5);
}

TEST(CameraRig, ImagesAreUpright) {
    rad::CameraRigOptions o;
    o.count = 20;
    o.minElevationDegrees = -60.0;
    o.maxElevationDegrees = 60.0;
    for (const rad::PinholeCamera& cam : rad::makeCameraRig(Vector3d::Zero(), 1.0, o)) {
        double u0, v0, u1, v1;
        ASSERT_TRUE(cam.project(Vector3d::Zero(), u0, v0));
        ASSERT_TRUE(cam.project(Vector3d(0, 0, 0.1), u1, v1));  // world up = +z by default
        EXPECT_LT(v1, v0);                                       // higher in the image (v counts down)
        EXPECT_NEAR(u1, u0, 1e-6);                               // no roll
    }
}

TEST(CameraRig, DeterministicPerSeed) {
    rad::CameraRigOptions o;
    o.count = 10;
    o.seed = 42;
    const auto a = rad::makeCameraRig(Vector3d::Zero(), 1.0, o);
    const auto b = rad::makeCameraRig(Vector3d::Zero(), 1.0, o);
    o.seed = 43;
    const auto c = rad::makeCameraRig(Vector3d::Zero(), 1.0, o);
    o.jitter = 0.0;
    const auto d = rad::makeCameraRig(Vector3d::Zero(), 1.0, o);
    o.seed = 7;
    const auto e = rad::makeCameraRig(Vector3d::Zero(), 1.0, o);
    for (int i = 0; i < 10; ++i) {
        EXPECT_EQ(a[i].center, b[i].center);
        EXPECT_EQ(a[i].rotation, b[i].rotation);
        EXPECT_GT((a[i].center - c[i].center).norm(), 1e-6);
        EXPECT_EQ(d[i].center, e[i].center);  // without jitter the seed does not matter
    }
}

TEST(CameraRig, RefusesBadOptions) {
    rad::CameraRigOptions o;
    EXPECT_THROW(rad::makeCameraRig(Vector3d::Zero(), 0.0, o), std::invalid_argument);
    o.count = 0;
    EXPECT_THROW(rad::makeCameraRig(Vector3d::Zero(), 1.0, o), std::invalid_argument);
    o = {};
    o.horizontalFovDegrees = 180.0;
    EXPECT_THROW(rad::makeCameraRig(Vector3d::Zero(), 1.0, o), std::invalid_argument);
    o = {};
    o.minElevationDegrees = 30.0;
    o.maxElevationDegrees = 10.0;
    EXPECT_THROW(rad::makeCameraRig(Vector3d::Zero(), 1.0, o), std::invalid_argument);
    o = {};
    o.fillFraction = 1.5;
    EXPECT_THROW(rad::makeCameraRig(Vector3d::Zero(), 1.0, o), std::invalid_argument);
    o = {};
    o.up = Vector3d::Zero();
    EXPECT_THROW(rad::makeCameraRig(Vector3d::Zero(), 1.0, o), std::invalid_argument);
}

}  // namespace
