// Tests of camera/gl_view_camera.h. The GL side is rebuilt here from the OpenGL definitions, not
// from the unit's derivation: gluLookAt and glFrustum / glOrtho matrices as their manual pages give
// them (column-major storage), the fixed-function pipeline clip = P MV X, ndc = clip / w,
// x_win = X0 + (ndc.x + 1) W / 2, y_win = Y0 + (ndc.y + 1) H / 2 (from the bottom), and the top-left
// image rows u = x_win - X0, v = H - (y_win - Y0). PinholeCamera::project must agree to 1e-6 px.
#include "camera/gl_view_camera.h"
#include "test_temporary_directory.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <fstream>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

namespace {

using Mat4 = Eigen::Matrix4d;

std::array<double, 16> columnMajor(const Mat4& m) {
    std::array<double, 16> out{};
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) out[4 * j + i] = m(i, j);
    return out;
}

// gluLookAt: rows s, u, -f of the rotation, then a translation by -eye.
Mat4 lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& center, const Eigen::Vector3d& up) {
    const Eigen::Vector3d f = (center - eye).normalized();
    const Eigen::Vector3d s = f.cross(up).normalized();
    const Eigen::Vector3d u = s.cross(f);
    Mat4 M = Mat4::Identity();
    M.block<1, 3>(0, 0) = s.transpose();
    M.block<1, 3>(1, 0) = u.transpose();
    M.block<1, 3>(2, 0) = -f.transpose();
    Mat4 T = Mat4::Identity();
    T.block<3, 1>(0, 3) = -eye;
    return M * T;
}

Mat4 scaling(double k) {
    Mat4 S = Mat4::Identity();
    S(0, 0) = S(1, 1) = S(2, 2) = k;
    return S;
}

Mat4 translation(const Eigen::Vector3d& t) {
    Mat4 T = Mat4::Identity();
    T.block<3, 1>(0, 3) = t;
    return T;
}

// glFrustum(l, r, b, t, n, f).
Mat4 frustum(double l, double r, double b, double t, double n, double f) {
    Mat4 P = Mat4::Zero();
    P(0, 0) = 2 * n / (r - l);
    P(0, 2) = (r + l) / (r - l);
    P(1, 1) = 2 * n / (t - b);
    P(1, 2) = (t + b) / (t - b);
    P(2, 2) = -(f + n) / (f - n);
    P(2, 3) = -2 * f * n / (f - n);
    P(3, 2) = -1;
    return P;
}

// glOrtho(l, r, b, t, n, f).
Mat4 ortho(double l, double r, double b, double t, double n, double f) {
    Mat4 P = Mat4::Identity();
    P(0, 0) = 2 / (r - l);
    P(0, 3) = -(r + l) / (r - l);
    P(1, 1) = 2 / (t - b);
    P(1, 3) = -(t + b) / (t - b);
    P(2, 2) = -2 / (f - n);
    P(2, 3) = -(f + n) / (f - n);
    return P;
}

rad::GlView makeView(const Mat4& MV, const Mat4& P, std::array<double, 4> viewport) {
    rad::GlView v;
    v.viewport = viewport;
    v.modelview = columnMajor(MV);
    v.projection = columnMajor(P);
    return v;
}

// The GL pipeline: top-left image coordinates of object point X inside the viewport.
Eigen::Vector2d glProject(const rad::GlView& v, const Mat4& MV, const Mat4& P, const Eigen::Vector3d& X) {
    const Eigen::Vector4d clip = P * MV * X.homogeneous();
    const Eigen::Vector3d ndc = clip.head<3>() / clip.w();
    const double X0 = v.viewport[0], Y0 = v.viewport[1], W = v.viewport[2], H = v.viewport[3];
    const double xWin = X0 + (ndc.x() + 1) * W / 2, yWin = Y0 + (ndc.y() + 1) * H / 2;
    return {xWin - X0, H - (yWin - Y0)};
}

// A MeshLab-like modelview: look-at, then the trackball's uniform scale and re-centring.
Mat4 meshlabLikeModelview(double scale) {
    return lookAt({0.3, -0.4, 3.0}, {0.05, 0.1, 0.0}, {0.1, 1.0, 0.2}) * scaling(scale) *
           translation({-12.0, 4.0, -7.5});
}

void expectSameProjection(const Mat4& MV, const Mat4& P, const std::array<double, 4>& viewport, double tolerancePx) {
    const rad::GlView view = makeView(MV, P, viewport);
    const rad::PinholeCamera cam = rad::cameraFromGlView(view);
    EXPECT_EQ(cam.validate(), "");
    EXPECT_EQ(cam.width, static_cast<int>(viewport[2]));
    EXPECT_EQ(cam.height, static_cast<int>(viewport[3]));
    // Points spread through the visible frustum: random NDC in [-1.2, 1.2]^2, depth in (-1, 1),
    // taken back to object space with the inverse of P MV.
    const Mat4 inv = (P * MV).inverse();
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> xy(-1.2, 1.2), z(-0.95, 0.95);
    for (int i = 0; i < 200; ++i) {
        const Eigen::Vector4d h = inv * Eigen::Vector4d(xy(rng), xy(rng), z(rng), 1.0);
        const Eigen::Vector3d X = h.head<3>() / h.w();
        const Eigen::Vector2d expected = glProject(view, MV, P, X);
        double u = 0, v = 0;
        ASSERT_TRUE(cam.project(X, u, v)) << "point " << i << " is in front of the GL camera";
        EXPECT_NEAR(u, expected.x(), tolerancePx) << "point " << i;
        EXPECT_NEAR(v, expected.y(), tolerancePx) << "point " << i;
    }
    // The camera centre is the eye: the modelview takes it to the origin.
    EXPECT_LT((MV * cam.center.homogeneous()).head<3>().norm(), 1e-9 * (1 + cam.center.norm()));
}

TEST(GlViewCamera, SymmetricFrustumWithScaledModelview) {
    expectSameProjection(meshlabLikeModelview(0.137), frustum(-0.4, 0.4, -0.3, 0.3, 0.5, 20.0), {0, 0, 640, 480},
                         1e-6);
}

TEST(GlViewCamera, OffCentreFrustumAndOffsetViewport) {
    expectSameProjection(meshlabLikeModelview(2.5), frustum(-0.2, 0.5, -0.35, 0.1, 0.8, 50.0), {37, 15, 801, 333},
                         1e-6);
}

TEST(GlViewCamera, HandWorkedCamera) {
    // Identity modelview, 90 degree symmetric frustum (n = 1, l = -1, r = 1, b = -1, t = 1) on a
    // 200 x 100 viewport: fx = 100, fy = 50, principal point at the centre; GL looks along -z with
    // y up, so the point (0.5, 0.5, -1) is right of and ABOVE the centre: u = 150, v = 25.
    const rad::PinholeCamera cam =
        rad::cameraFromGlView(makeView(Mat4::Identity(), frustum(-1, 1, -1, 1, 1, 10), {5, 7, 200, 100}));
    EXPECT_DOUBLE_EQ(cam.fx, 100.0);
    EXPECT_DOUBLE_EQ(cam.fy, 50.0);
    EXPECT_DOUBLE_EQ(cam.cx, 100.0);
    EXPECT_DOUBLE_EQ(cam.cy, 50.0);
    double u = 0, v = 0;
    ASSERT_TRUE(cam.project(Eigen::Vector3d(0.5, 0.5, -1.0), u, v));
    EXPECT_DOUBLE_EQ(u, 150.0);
    EXPECT_DOUBLE_EQ(v, 25.0);
    EXPECT_FALSE(cam.project(Eigen::Vector3d(0, 0, 1.0), u, v));  // behind the GL eye
}

TEST(GlViewCamera, FloatMatricesAsMeshLabKeepsThem) {
    // GL state is float: the matrices read back are rounded to float. Still accepted (tolerance
    // 1e-4), the rotation made exactly orthonormal, the projection within a thousandth of a pixel.
    Mat4 MV = meshlabLikeModelview(0.0213), P = frustum(-0.41, 0.41, -0.3, 0.3, 0.2, 9.0);
    for (int i = 0; i < 16; ++i) {
        MV(i % 4, i / 4) = static_cast<float>(MV(i % 4, i / 4));
        P(i % 4, i / 4) = static_cast<float>(P(i % 4, i / 4));
    }
    expectSameProjection(MV, P, {0, 0, 1186, 771}, 1e-3);
}

TEST(GlViewCamera, HomogeneousScaleOfTheProjectionIsTheSameCamera) {
    const Mat4 MV = meshlabLikeModelview(1.0), P = frustum(-0.4, 0.3, -0.3, 0.35, 0.5, 20.0);
    const rad::PinholeCamera a = rad::cameraFromGlView(makeView(MV, P, {0, 0, 300, 200}));
    const rad::PinholeCamera b = rad::cameraFromGlView(makeView(MV, 2.0 * P, {0, 0, 300, 200}));
    EXPECT_NEAR(a.fx, b.fx, 1e-12);
    EXPECT_NEAR(a.cx, b.cx, 1e-12);
    EXPECT_NEAR(a.fy, b.fy, 1e-12);
    EXPECT_NEAR(a.cy, b.cy, 1e-12);
}

void expectRefused(const rad::GlView& view, const std::string& words) {
    try {
        rad::cameraFromGlView(view);
        ADD_FAILURE() << "accepted, expected a refusal mentioning '" << words << "'";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
}

TEST(GlViewCamera, Refusals) {
    const Mat4 MV = meshlabLikeModelview(0.5), P = frustum(-0.4, 0.4, -0.3, 0.3, 0.5, 20.0);
    const std::array<double, 4> vp{0, 0, 640, 480};

    Mat4 nonUniform = scaling(1.0);
    nonUniform(1, 1) = 1.01;
    expectRefused(makeView(MV * nonUniform, P, vp), "non-uniform scale or shear");
    Mat4 shear = Mat4::Identity();
    shear(0, 1) = 0.01;
    expectRefused(makeView(MV * shear, P, vp), "non-uniform scale or shear");
    expectRefused(makeView(MV * scaling(-1.0), P, vp), "mirror");
    Mat4 projective = MV;
    projective(3, 0) = 0.1;
    expectRefused(makeView(projective, P, vp), "last row");

    expectRefused(makeView(MV, ortho(-1, 1, -0.75, 0.75, 0.1, 10), vp), "orthographic");
    Mat4 skew = P;
    skew(0, 1) = 0.05;
    expectRefused(makeView(MV, skew, vp), "skewed");
    Mat4 mirrored = P;
    mirrored(1, 1) = -mirrored(1, 1);
    expectRefused(makeView(MV, mirrored, vp), "mirrors");

    expectRefused(makeView(MV, P, {0, 0, 0, 480}), "degenerate");
    expectRefused(makeView(MV, P, {0, 0, 640, -5}), "degenerate");
    expectRefused(makeView(MV, P, {0, 0, 640.5, 480}), "degenerate");
    expectRefused(makeView(MV, P, {0, std::nan(""), 640, 480}), "non-finite");
    Mat4 nan = MV;
    nan(0, 3) = std::numeric_limits<double>::infinity();
    expectRefused(makeView(nan, P, vp), "non-finite");
}

// ---- view file ----

std::string tmpPath(const std::string& name) { return std::string(RADIANCE_TEST_TMPDIR) + "/gl_view_" + name; }

const char* const kGoodFile =
    "radiance-decoration-view 1\n"
    "frame 42\n"
    "mode per-fragment\n"
    "viewport 0 0 1186 771   # device pixels\n"
    "widget_origin 10 57\n"
    "widget_size 1186 771\n"
    "device_pixel_ratio 1\n"
    "modelview 1 0 0 0 0 1 0 0 0 0 1 0 0 0 -3 1\n"
    "projection 2 0 0 0 0 3 0 0 0.1 -0.2 -1.01 -1 0 0 -0.2 0\n"
    "exposure -0.5\n"
    "tonemap reinhard\n";

std::string writeFile(const std::string& name, const std::string& text) {
    const std::string path = tmpPath(name);
    std::ofstream(path) << text;
    return path;
}

TEST(DecorationViewFile, ReadsEveryField) {
    const rad::DecorationViewFile f = rad::readDecorationViewFile(writeFile("good.txt", kGoodFile));
    EXPECT_EQ(f.version, 1);
    EXPECT_EQ(f.frame, 42);
    EXPECT_EQ(f.mode, "per-fragment");
    EXPECT_EQ(f.view.viewport, (std::array<double, 4>{0, 0, 1186, 771}));
    EXPECT_EQ(f.widgetOrigin, (std::array<double, 2>{10, 57}));
    EXPECT_EQ(f.widgetSize, (std::array<double, 2>{1186, 771}));
    EXPECT_EQ(f.devicePixelRatio, 1.0);
    EXPECT_EQ(f.view.modelview[14], -3.0);
    EXPECT_EQ(f.view.projection[8], 0.1);   // column 2, row 0: P02
    EXPECT_EQ(f.view.projection[11], -1.0);  // column 2, row 3: P32
    EXPECT_EQ(f.exposureStops, -0.5);
    EXPECT_EQ(f.toneMap, "reinhard");
    // And the camera it describes: fx = W/2 P00, cx = W/2 (1 - P02), fy = H/2 P11, cy = H/2 (1 + P12).
    const rad::PinholeCamera cam = rad::cameraFromGlView(f.view);
    EXPECT_DOUBLE_EQ(cam.fx, 1186.0);
    EXPECT_DOUBLE_EQ(cam.cx, 593.0 * 0.9);
    EXPECT_DOUBLE_EQ(cam.fy, 771.0 * 1.5);
    EXPECT_DOUBLE_EQ(cam.cy, 385.5 * 0.8);
    EXPECT_TRUE(cam.center.isApprox(Eigen::Vector3d(0, 0, 3)));
}

void expectMalformed(const std::string& name, const std::string& text, const std::string& words) {
    const std::string path = writeFile(name, text);
    try {
        rad::readDecorationViewFile(path);
        ADD_FAILURE() << name << ": accepted, expected '" << words << "'";
    } catch (const std::runtime_error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(path), std::string::npos) << what;
        EXPECT_NE(what.find(words), std::string::npos) << what;
    }
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    text.replace(text.find(from), from.size(), to);
    return text;
}

TEST(DecorationViewFile, RefusesMalformedInputNamingTheLine) {
    expectMalformed("header.txt", replaced(kGoodFile, "radiance-decoration-view 1", "hello 1"), ":1: not a decoration");
    expectMalformed("version.txt", replaced(kGoodFile, "radiance-decoration-view 1", "radiance-decoration-view 2"),
                    ":1: unsupported view file version");
    expectMalformed("number.txt", replaced(kGoodFile, "widget_origin 10 57", "widget_origin 10 5x7"),
                    ":5: 'widget_origin' needs finite numbers");
    expectMalformed("count.txt", replaced(kGoodFile, "modelview 1 0 0 0 ", "modelview 1 0 0 "),
                    ":8: 'modelview' needs 16 values, got 15");
    expectMalformed("frame.txt", replaced(kGoodFile, "frame 42", "frame 4.5"), ":2: 'frame' needs a non-negative integer");
    expectMalformed("mode.txt", replaced(kGoodFile, "per-fragment", "phong"), ":3: unknown mode 'phong'");
    expectMalformed("tone.txt", replaced(kGoodFile, "tonemap reinhard", "tonemap aces"), ":11: unknown tone curve");
    expectMalformed("unknown.txt", std::string(kGoodFile) + "gamma 2.2\n", ":12: unknown key 'gamma'");
    expectMalformed("repeat.txt", std::string(kGoodFile) + "frame 43\n", ":12: 'frame' repeated (first on line 2)");
    expectMalformed("missing.txt", replaced(kGoodFile, "exposure -0.5\n", ""), "'exposure' is missing");
    expectMalformed("nan.txt", replaced(kGoodFile, "exposure -0.5", "exposure nan"), ":10: 'exposure' needs finite");
    expectMalformed("dpr.txt", replaced(kGoodFile, "device_pixel_ratio 1", "device_pixel_ratio 0"), ":7:");
    expectMalformed("empty.txt", "", "empty file");
    EXPECT_THROW(rad::readDecorationViewFile(tmpPath("does_not_exist.txt")), std::runtime_error);
}

}  // namespace

namespace {

TEST(DecorationViewFile, ViewportInTheScreenCapture) {
    rad::DecorationViewFile f;
    f.widgetOrigin = {10, 57};
    f.widgetSize = {600, 400};
    f.devicePixelRatio = 1.0;
    f.view.viewport = {0, 0, 600, 400};  // the whole widget
    rad::ScreenRect r = rad::viewportInScreen(f);
    EXPECT_EQ(r.x, 10);
    EXPECT_EQ(r.y, 57);
    EXPECT_EQ(r.width, 600);
    EXPECT_EQ(r.height, 400);
    // A viewport in the widget's lower-left part: 30 px from the left, 20 px from the BOTTOM,
    // 100 x 50. Its top row is 400 - (20 + 50) = 330 px below the widget's top.
    f.view.viewport = {30, 20, 100, 50};
    r = rad::viewportInScreen(f);
    EXPECT_EQ(r.x, 40);
    EXPECT_EQ(r.y, 57 + 330);
    // Device pixel ratio 2: logical origin and size doubled, the viewport already in device px.
    f.devicePixelRatio = 2.0;
    r = rad::viewportInScreen(f);
    EXPECT_EQ(r.x, 20 + 30);
    EXPECT_EQ(r.y, 114 + 800 - 70);
    f.view.viewport = {0, 0, 100.5, 50};
    EXPECT_THROW(rad::viewportInScreen(f), std::invalid_argument);
}

}  // namespace
