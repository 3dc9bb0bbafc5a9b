// The vcg::Shot -> PinholeCamera conversion of plugins_shared/shot_conversion.h, checked against
// vcg's own projection (vcg::Shot::Project): the reference is vcglib, not our code.
#include "shot_conversion.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <random>

namespace {

// A random proper rotation (rows orthonormal, det +1) as a vcg matrix.
vcg::Matrix44f randomRotation(std::mt19937& rng) {
    std::normal_distribution<double> g;
    Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
    q.normalize();
    const Eigen::Matrix3d r = q.toRotationMatrix();
    vcg::Matrix44f m;
    m.SetIdentity();
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) m[i][j] = float(r(i, j));
    return m;
}

vcg::Shotf randomShot(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    vcg::Shotf shot;
    shot.Intrinsics.cameraType = vcg::Camera<float>::PERSPECTIVE;
    shot.Intrinsics.FocalMm = float(20.0 + 15.0 * u(rng));
    shot.Intrinsics.PixelSizeMm = vcg::Point2f(float(0.01 * (1.0 + 0.2 * u(rng))), float(0.01 * (1.0 + 0.2 * u(rng))));
    shot.Intrinsics.ViewportPx = vcg::Point2i(640 + int(300 * u(rng)), 480 + int(200 * u(rng)));
    // Off-centre principal point: the case MeshLab's own GL path gets wrong.
    shot.Intrinsics.CenterPx = vcg::Point2f(float(shot.Intrinsics.ViewportPx[0] * (0.5 + 0.1 * u(rng))),
                                            float(shot.Intrinsics.ViewportPx[1] * (0.5 + 0.1 * u(rng))));
    shot.Extrinsics.SetRot(randomRotation(rng));
    shot.Extrinsics.SetTra(vcg::Point3f(float(3 * u(rng)), float(3 * u(rng)), float(3 * u(rng))));
    return shot;
}

TEST(ShotConversion, ProjectsLikeVcgShotProject) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int checked = 0;
    for (int trial = 0; trial < 50; ++trial) {
        const vcg::Shotf shot = randomShot(rng);
        rad::PinholeCamera camera;
        ASSERT_EQ(radml::pinholeFromShot(shot, camera), "");
        EXPECT_EQ(camera.width, shot.Intrinsics.ViewportPx[0]);
        EXPECT_EQ(camera.height, shot.Intrinsics.ViewportPx[1]);
        for (int k = 0; k < 40; ++k) {
            const vcg::Point3f X(float(5 * u(rng)), float(5 * u(rng)), float(5 * u(rng)));
            const float depth = shot.Depth(X);  // vcg: > 0 in front of the camera
            const Eigen::Vector3d x(X[0], X[1], X[2]);
            double pu = 0.0, pv = 0.0;
            const bool inFront = camera.project(x, pu, pv);
            if (std::abs(depth) < 0.05f) continue;  // too close to the camera plane for a float comparison
            ASSERT_EQ(inFront, depth > 0.0f) << "trial " << trial;
            if (!inFront) continue;
            const vcg::Point2f p = shot.Project(X);
            // vcg: px from the left, py from the bottom; ours: v from the top.
            const double tolerance = 1e-4 * (1.0 + std::abs(p[0]) + std::abs(p[1]));
            EXPECT_NEAR(pu, p[0], tolerance);
            EXPECT_NEAR(pv, shot.Intrinsics.ViewportPx[1] - p[1], tolerance);
            EXPECT_NEAR(camera.toCamera(x).z(), depth, 1e-4 * (1.0 + std::abs(depth)));
            ++checked;
        }
    }
    EXPECT_GT(checked, 500);
}

TEST(ShotConversion, CameraCentreAndViewingDirectionMatchVcg) {
    std::mt19937 rng(11);
    const vcg::Shotf shot = randomShot(rng);
    rad::PinholeCamera camera;
    ASSERT_EQ(radml::pinholeFromShot(shot, camera), "");
    const vcg::Point3f c = shot.GetViewPoint();
    EXPECT_NEAR((camera.center - Eigen::Vector3d(c[0], c[1], c[2])).norm(), 0.0, 1e-6);
    // vcg looks along -Z of its camera frame (Axis(2) is backwards).
    const vcg::Point3f back = shot.Axis(2);
    EXPECT_NEAR((camera.forward() + Eigen::Vector3d(back[0], back[1], back[2])).norm(), 0.0, 1e-6);
    // A ray through a pixel goes through the point vcg projects there.
    const vcg::Point3f X = c - back * 4.0f + shot.Axis(0) * 0.3f;
    const vcg::Point2f p = shot.Project(X);
    const Eigen::Vector3d d = camera.rayDirection(p[0], shot.Intrinsics.ViewportPx[1] - p[1]);
    const Eigen::Vector3d expected = (Eigen::Vector3d(X[0], X[1], X[2]) - camera.center).normalized();
    EXPECT_NEAR((d - expected).norm(), 0.0, 1e-5);
}

TEST(ShotConversion, RefusesDistortionOrthographicAndDegenerateCameras) {
    std::mt19937 rng(3);
    rad::PinholeCamera camera;
    vcg::Shotf distorted = randomShot(rng);
    distorted.Intrinsics.k[0] = 0.1f;
    EXPECT_NE(radml::pinholeFromShot(distorted, camera).find("distortion"), std::string::npos);
    vcg::Shotf ortho = randomShot(rng);
    ortho.Intrinsics.cameraType = vcg::Camera<float>::ORTHO;
    EXPECT_NE(radml::pinholeFromShot(ortho, camera).find("perspective"), std::string::npos);
    vcg::Shotf noFocal = randomShot(rng);
    noFocal.Intrinsics.FocalMm = 0.0f;
    EXPECT_NE(radml::pinholeFromShot(noFocal, camera).find("focal"), std::string::npos);
    vcg::Shotf emptyViewport = randomShot(rng);
    emptyViewport.Intrinsics.ViewportPx = vcg::Point2i(0, 0);
    EXPECT_NE(radml::pinholeFromShot(emptyViewport, camera).find("viewport"), std::string::npos);
    vcg::Shotf notRotation = randomShot(rng);
    vcg::Matrix44f scaled = notRotation.Extrinsics.Rot();
    scaled[0][0] *= 2.0f;
    notRotation.Extrinsics.SetRot(scaled);
    EXPECT_NE(radml::pinholeFromShot(notRotation, camera).find("rotation"), std::string::npos);
    // A default vcg::Shot (as MeshLab creates for a raster without a camera) has no focal length.
    EXPECT_NE(radml::pinholeFromShot(vcg::Shotf(), camera), "");
}

// shotFromPinhole: the shot it makes projects, by vcg::Shot::Project itself, where the pinhole
// camera's own formula puts each point (fx != fy and an off-centre principal point included).
TEST(ShotConversion, ShotFromPinholeProjectsLikeThePinholeCamera) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    rad::PinholeCamera camera = rad::PinholeCamera::lookAt({2.0, 1.0, 3.0}, {0.1, -0.2, 0.0}, {0.0, 1.0, 0.0}, 50.0, 800, 600);
    camera.fx = 700.0;
    camera.fy = 690.0;
    camera.cx = 380.25;
    camera.cy = 317.75;
    const vcg::Shotf shot = radml::shotFromPinhole<float>(camera);
    int checked = 0;
    for (int k = 0; k < 200; ++k) {
        const Eigen::Vector3d x(u(rng), u(rng), u(rng));
        // The pinhole formula written out here: x_cam = R (X - C), u = fx x/z + cx, v = fy y/z + cy.
        const Eigen::Vector3d p = camera.rotation * (x - camera.center);
        ASSERT_GT(p.z(), 0.5);
        const double expectedU = camera.fx * p.x() / p.z() + camera.cx;
        const double expectedV = camera.fy * p.y() / p.z() + camera.cy;
        const vcg::Point2f q = shot.Project(vcg::Point3f(float(x.x()), float(x.y()), float(x.z())));
        EXPECT_NEAR(q[0], expectedU, 2e-3);
        EXPECT_NEAR(camera.height - q[1], expectedV, 2e-3);  // vcg's py counts from the bottom edge
        ++checked;
    }
    EXPECT_EQ(checked, 200);
    rad::PinholeCamera back;
    ASSERT_EQ(radml::pinholeFromShot(shot, back), "");
    EXPECT_NEAR(back.fy, camera.fy, 1e-2);
}

}  // namespace
