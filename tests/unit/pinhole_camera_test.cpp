// Tests of camera/pinhole_camera.h. Expected pixel coordinates are worked out by hand from the
// stated conventions (camera x right, y down, z forward; u = fx x/z + cx, v = fy y/z + cy; origin at
// the image's top-left corner); lookAt is checked through what it must mean in an image (target at
// the principal point, world up pointing up in the image, the horizontal field of view reaching
// the image borders).
#include "camera/pinhole_camera.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <random>

namespace {

constexpr double kPi = 3.14159265358979323846;

rad::PinholeCamera axisCamera() {
    // At the origin, looking along +z, x right, y down (identity rotation).
    rad::PinholeCamera cam;
    cam.fx = 100.0;
    cam.fy = 120.0;
    cam.cx = 50.0;
    cam.cy = 40.0;
    cam.width = 100;
    cam.height = 80;
    return cam;
}

TEST(PinholeCamera, ProjectsHandPlacedPoints) {
    const rad::PinholeCamera cam = axisCamera();
    double u = 0, v = 0;
    // (1, 2, 10): u = 100 * 1/10 + 50 = 60, v = 120 * 2/10 + 40 = 64.
    ASSERT_TRUE(cam.project(Eigen::Vector3d(1, 2, 10), u, v));
    EXPECT_DOUBLE_EQ(u, 60.0);
    EXPECT_DOUBLE_EQ(v, 64.0);
    // On the axis: the principal point, whatever the depth.
    ASSERT_TRUE(cam.project(Eigen::Vector3d(0, 0, 0.01), u, v));
    EXPECT_DOUBLE_EQ(u, 50.0);
    EXPECT_DOUBLE_EQ(v, 40.0);
    // (-2, -1, 4): u = 100 * -0.5 + 50 = 0 (left border), v = 120 * -0.25 + 40 = 10.
    ASSERT_TRUE(cam.project(Eigen::Vector3d(-2, -1, 4), u, v));
    EXPECT_DOUBLE_EQ(u, 0.0);
    EXPECT_DOUBLE_EQ(v, 10.0);

    // Behind the camera or in its plane: refused, outputs untouched.
    u = v = -7.0;
    EXPECT_FALSE(cam.project(Eigen::Vector3d(1, 2, -10), u, v));
    EXPECT_FALSE(cam.project(Eigen::Vector3d(1, 2, 0), u, v));
    EXPECT_FALSE(cam.project(Eigen::Vector3d(1, 2, std::nan("")), u, v));
    EXPECT_EQ(u, -7.0);
    EXPECT_EQ(v, -7.0);
}

TEST(PinholeCamera, ProjectsThroughAMovedAndTurnedCamera) {
    // Centre (1, 2, 3); rotation rows (right, down, forward) = (-X, -Z, -Y) in world coordinates
    // (a proper rotation: (-X) x (-Z) = -Y). World point (0, -8, 1) is at X - C = (-1, -10, -2):
    // camera x = 1, y = 2, z = 10, so u = fx/10 + cx, v = 2 fy/10 + cy.
    rad::PinholeCamera cam = axisCamera();
    cam.center = Eigen::Vector3d(1, 2, 3);
    cam.rotation << -1, 0, 0, 0, 0, -1, 0, -1, 0;
    ASSERT_EQ(cam.validate(), "");
    double u = 0, v = 0;
    ASSERT_TRUE(cam.project(Eigen::Vector3d(0, -8, 1), u, v));
    EXPECT_DOUBLE_EQ(u, 60.0);
    EXPECT_DOUBLE_EQ(v, 64.0);
    EXPECT_LT((cam.forward() - Eigen::Vector3d(0, -1, 0)).norm(), 1e-15);
    EXPECT_LT((cam.toCamera(Eigen::Vector3d(0, -8, 1)) - Eigen::Vector3d(1, 2, 10)).norm(), 1e-12);
}

TEST(PinholeCamera, RayDirectionInvertsProject) {
    std::mt19937 rng(3);
    const rad::PinholeCamera cam = rad::PinholeCamera::lookAt(Eigen::Vector3d(0.3, -2, 1.5), Eigen::Vector3d(0.1, 0.2, 0),
                                                              Eigen::Vector3d(0, 0, 1), 55.0, 640, 480);
    std::uniform_real_distribution<double> spread(-1.0, 1.0);
    int checked = 0;
    for (int i = 0; i < 200; ++i) {
        const Eigen::Vector3d X(spread(rng), spread(rng), spread(rng));
        double u, v;
        if (!cam.project(X, u, v)) continue;
        const Eigen::Vector3d d = cam.rayDirection(u, v);
        EXPECT_NEAR(d.norm(), 1.0, 1e-12);
        EXPECT_LT((d - (X - cam.center).normalized()).norm(), 1e-12);
        // ...and the other way round: a point along the ray projects back to (u, v).
        double u2, v2;
        ASSERT_TRUE(cam.project(cam.center + 3.7 * d, u2, v2));
        EXPECT_NEAR(u2, u, 1e-9);
        EXPECT_NEAR(v2, v, 1e-9);
        ++checked;
    }
    EXPECT_GT(checked, 150);
    // The principal point's ray is the viewing direction.
    EXPECT_LT((cam.rayDirection(cam.cx, cam.cy) - cam.forward()).norm(), 1e-12);
}

TEST(PinholeCamera, LookAtCentresTheTargetKeepsUpUpAndIsRightHanded) {
    // Eye on +Z looking at the origin with +Y up: by hand, right = +X, down = -Y, forward = -Z, and
    // with a 90 degree horizontal field of view on 200 pixels, fx = 100 / tan(45 deg) = 100.
    rad::PinholeCamera cam =
        rad::PinholeCamera::lookAt(Eigen::Vector3d(0, 0, 5), Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 1, 0), 90.0, 200, 100);
    ASSERT_EQ(cam.validate(), "");
    Eigen::Matrix3d expected;
    expected << 1, 0, 0, 0, -1, 0, 0, 0, -1;
    EXPECT_LT((cam.rotation - expected).norm(), 1e-12);
    EXPECT_NEAR(cam.fx, 100.0, 1e-12);
    EXPECT_NEAR(cam.fy, 100.0, 1e-12);
    EXPECT_DOUBLE_EQ(cam.cx, 100.0);
    EXPECT_DOUBLE_EQ(cam.cy, 50.0);
    double u, v;
    ASSERT_TRUE(cam.project(Eigen::Vector3d(1, 0, 0), u, v));  // camera (1, 0, 5): u = 100/5 + 100
    EXPECT_NEAR(u, 120.0, 1e-12);
    EXPECT_NEAR(v, 50.0, 1e-12);

    std::mt19937 rng(8);
    for (int i = 0; i < 50; ++i) {
        const Eigen::Vector3d eye = 4.0 * radtest::randomUnit(rng), target = 0.5 * radtest::randomUnit(rng);
        Eigen::Vector3d up = radtest::randomUnit(rng);
        const Eigen::Vector3d f = (target - eye).normalized();
        if (std::fabs(up.dot(f)) > 0.95) continue;  // nearly parallel: see the next test
        const double fov = 30.0 + 100.0 * (i % 7) / 7.0;
        cam = rad::PinholeCamera::lookAt(eye, target, up, fov, 320, 240);
        ASSERT_EQ(cam.validate(), "");
        // Right-handed, orthonormal: right x down = forward, det +1.
        const Eigen::Vector3d right = cam.rotation.row(0), down = cam.rotation.row(1), forward = cam.rotation.row(2);
        EXPECT_LT((right.cross(down) - forward).norm(), 1e-12);
        EXPECT_NEAR(cam.rotation.determinant(), 1.0, 1e-12);
        EXPECT_LT((forward - f).norm(), 1e-12);
        // The target at the principal point.
        ASSERT_TRUE(cam.project(target, u, v));
        EXPECT_NEAR(u, 160.0, 1e-9);
        EXPECT_NEAR(v, 120.0, 1e-9);
        // World up points up in the image (smaller v), and straight up: the up vector's part
        // orthogonal to the viewing direction lands on the principal column.
        const Eigen::Vector3d upInPlane = (up - up.dot(f) * f).normalized();
        ASSERT_TRUE(cam.project(target + 0.1 * upInPlane, u, v));
        EXPECT_LT(v, 120.0);
        EXPECT_NEAR(u, 160.0, 1e-9);
        // The viewer's right, f x up (looking along f with up above; the hand example above: -Z x +Y
        // = +X), lands right of the centre, on the principal row.
        ASSERT_TRUE(cam.project(target + 0.1 * f.cross(upInPlane), u, v));
        EXPECT_GT(u, 160.0);
        EXPECT_NEAR(v, 120.0, 1e-9);
        // The horizontal field of view: a point at half the angle to the right is on the right border.
        const double half = 0.5 * fov * kPi / 180.0;
        const Eigen::Vector3d border = Eigen::AngleAxisd(-half, upInPlane) * f;  // turn right about up
        ASSERT_TRUE(cam.project(eye + 2.0 * border, u, v));
        EXPECT_NEAR(u, 320.0, 1e-9);
    }
}

TEST(PinholeCamera, LookAtWithUpAlongTheViewStillGivesAValidCamera) {
    const rad::PinholeCamera cam =
        rad::PinholeCamera::lookAt(Eigen::Vector3d(0, 0, 3), Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 1), 60.0, 64, 48);
    EXPECT_EQ(cam.validate(), "");
    double u, v;
    ASSERT_TRUE(cam.project(Eigen::Vector3d::Zero(), u, v));
    EXPECT_NEAR(u, 32.0, 1e-9);
    EXPECT_NEAR(v, 24.0, 1e-9);
}

TEST(PinholeCamera, DegenerateLookAtInputsAreRefused) {
    // A field of view outside (0, 179) degrees throws; other degenerate inputs give cameras that
    // validate() (the gate the callers use) refuses.
    const Eigen::Vector3d eye(1, 2, 3);
    EXPECT_NE(rad::PinholeCamera::lookAt(eye, eye, Eigen::Vector3d::UnitZ(), 60.0, 64, 48).validate(), "");
    EXPECT_THROW(rad::PinholeCamera::lookAt(eye, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.0, 64, 48),
                 std::invalid_argument);
    EXPECT_THROW(rad::PinholeCamera::lookAt(eye, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 180.0, 64, 48),
                 std::invalid_argument);
    EXPECT_NE(rad::PinholeCamera::lookAt(eye, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 60.0, 0, 48).validate(), "");
}

TEST(PinholeCamera, IsInsideUsesTheWholeImageShrunkByTheMargin) {
    const rad::PinholeCamera cam = axisCamera();  // 100 x 80
    EXPECT_TRUE(cam.isInside(0.0, 0.0));
    EXPECT_TRUE(cam.isInside(100.0, 80.0));
    EXPECT_FALSE(cam.isInside(-0.01, 10.0));
    EXPECT_FALSE(cam.isInside(50.0, 80.01));
    EXPECT_FALSE(cam.isInside(1.0, 40.0, 2.0));
    EXPECT_TRUE(cam.isInside(2.0, 78.0, 2.0));
}

TEST(PinholeCamera, ValidateSaysWhatIsWrong) {
    EXPECT_EQ(axisCamera().validate(), "");
    EXPECT_EQ(rad::PinholeCamera().validate(), "");  // the default 1 x 1 camera is usable

    rad::PinholeCamera cam = axisCamera();
    cam.center.x() = std::numeric_limits<double>::infinity();
    EXPECT_NE(cam.validate().find("non-finite"), std::string::npos) << cam.validate();
    cam = axisCamera();
    cam.cy = std::nan("");
    EXPECT_NE(cam.validate().find("non-finite"), std::string::npos) << cam.validate();

    cam = axisCamera();
    cam.fy = 0.0;
    EXPECT_NE(cam.validate().find("focal length"), std::string::npos) << cam.validate();
    cam.fy = -5.0;
    EXPECT_NE(cam.validate().find("focal length"), std::string::npos) << cam.validate();

    cam = axisCamera();
    cam.height = 0;
    EXPECT_NE(cam.validate().find("image size"), std::string::npos) << cam.validate();

    cam = axisCamera();
    cam.rotation *= 1.01;  // not orthonormal
    EXPECT_NE(cam.validate().find("rotation"), std::string::npos) << cam.validate();
    cam = axisCamera();
    cam.rotation(1, 1) = -1.0;  // a mirror (left-handed camera)
    EXPECT_NE(cam.validate().find("rotation"), std::string::npos) << cam.validate();
    cam = axisCamera();
    cam.rotation = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    cam.rotation(0, 0) += 5e-5;  // within the documented 1e-4 tolerance
    EXPECT_EQ(cam.validate(), "");
}

}  // namespace
