// The lens model against each COLMAP camera model's formula, written out here as COLMAP's
// documentation and models.h state them (not through LensModel), and the scaling of a lens to a
// resized photograph.
#include "cameras/colmap_model_reader.h"
#include "cameras/lens_model.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

const double kX = 0.31, kY = -0.22;  // an ideal (undistorted) normalised point
const double kR2 = kX * kX + kY * kY;

TEST(LensModel, OpenCvIsRadialThenTangentialThenPixels) {
    const rad::LensModel lens = rad::colmapLens("OPENCV", {800, 780, 320.5, 240.25, -0.12, 0.03, 0.001, -0.002});
    const double radial = 1 + -0.12 * kR2 + 0.03 * kR2 * kR2;
    const double xd = kX * radial + 2 * 0.001 * kX * kY + -0.002 * (kR2 + 2 * kX * kX);
    const double yd = kY * radial + 0.001 * (kR2 + 2 * kY * kY) + 2 * -0.002 * kX * kY;
    const Eigen::Vector2d p = lens.pixelOf({kX, kY});
    EXPECT_NEAR(p.x(), 800 * xd + 320.5, 1e-9);
    EXPECT_NEAR(p.y(), 780 * yd + 240.25, 1e-9);
    EXPECT_TRUE(lens.distorts());
}

TEST(LensModel, PinholeModelsDoNotDistort) {
    const rad::LensModel simple = rad::colmapLens("SIMPLE_PINHOLE", {500, 100, 80});
    EXPECT_FALSE(simple.distorts());
    EXPECT_NEAR(simple.pixelOf({kX, kY}).x(), 500 * kX + 100, 1e-12);
    EXPECT_NEAR(simple.pixelOf({kX, kY}).y(), 500 * kY + 80, 1e-12);
    const rad::LensModel pinhole = rad::colmapLens("PINHOLE", {500, 510, 100, 80});
    EXPECT_NEAR(pinhole.pixelOf({kX, kY}).y(), 510 * kY + 80, 1e-12);
}

TEST(LensModel, RadialModels) {
    const rad::LensModel simple = rad::colmapLens("SIMPLE_RADIAL", {600, 300, 200, 0.05});
    EXPECT_NEAR(simple.pixelOf({kX, kY}).x(), 600 * kX * (1 + 0.05 * kR2) + 300, 1e-9);
    const rad::LensModel radial = rad::colmapLens("RADIAL", {600, 300, 200, 0.05, -0.01});
    EXPECT_NEAR(radial.pixelOf({kX, kY}).y(), 600 * kY * (1 + 0.05 * kR2 - 0.01 * kR2 * kR2) + 200, 1e-9);
}

TEST(LensModel, FullOpenCvHasARationalRadialTerm) {
    const rad::LensModel lens =
        rad::colmapLens("FULL_OPENCV", {700, 690, 310, 250, 0.1, -0.02, 0.0005, 0.0007, 0.003, 0.04, -0.01, 0.002});
    const double radial = (1 + 0.1 * kR2 - 0.02 * kR2 * kR2 + 0.003 * kR2 * kR2 * kR2) /
                          (1 + 0.04 * kR2 - 0.01 * kR2 * kR2 + 0.002 * kR2 * kR2 * kR2);
    const double xd = kX * radial + 2 * 0.0005 * kX * kY + 0.0007 * (kR2 + 2 * kX * kX);
    EXPECT_NEAR(lens.pixelOf({kX, kY}).x(), 700 * xd + 310, 1e-9);
}

TEST(LensModel, OpenCvFisheyeIsEquidistantWithAPolynomialInTheta) {
    const rad::LensModel lens = rad::colmapLens("OPENCV_FISHEYE", {400, 400, 320, 240, 0.02, -0.01, 0.003, -0.001});
    const double r = std::sqrt(kR2), theta = std::atan(r), t2 = theta * theta;
    const double thetaD = theta * (1 + 0.02 * t2 - 0.01 * t2 * t2 + 0.003 * t2 * t2 * t2 - 0.001 * t2 * t2 * t2 * t2);
    EXPECT_NEAR(lens.pixelOf({kX, kY}).x(), 400 * kX * thetaD / r + 320, 1e-9);
    EXPECT_NEAR(lens.pixelOf({kX, kY}).y(), 400 * kY * thetaD / r + 240, 1e-9);
    // Plain equidistant fisheye: the image radius is f times the angle from the axis.
    const rad::LensModel plain = rad::colmapLens("SIMPLE_FISHEYE", {400, 320, 240});
    const Eigen::Vector2d p = plain.pixelOf({1.0, 0.0});  // 45 degrees off axis
    EXPECT_NEAR(p.x(), 400 * 3.14159265358979 / 4 + 320, 1e-9);
}

TEST(LensModel, FovModel) {
    const double omega = 0.9;
    const rad::LensModel lens = rad::colmapLens("FOV", {500, 500, 300, 200, omega});
    const double r = std::sqrt(kR2), factor = std::atan(2 * r * std::tan(omega / 2)) / (omega * r);
    EXPECT_NEAR(lens.pixelOf({kX, kY}).x(), 500 * kX * factor + 300, 1e-9);
}

TEST(LensModel, ThinPrismFisheye) {
    const rad::LensModel lens =
        rad::colmapLens("THIN_PRISM_FISHEYE", {450, 440, 300, 200, 0.01, -0.002, 0.0003, 0.0004, 0.0001, 0.00002, 0.0005, -0.0006});
    const double r = std::sqrt(kR2), theta = std::atan(r);
    const double u = kX * theta / r, v = kY * theta / r;
    const double r2 = u * u + v * v;
    const double radial = 0.01 * r2 - 0.002 * r2 * r2 + 0.0001 * r2 * r2 * r2 + 0.00002 * r2 * r2 * r2 * r2;
    const double du = u * radial + 2 * 0.0003 * u * v + 0.0004 * (r2 + 2 * u * u) + 0.0005 * r2;
    const double dv = v * radial + 2 * 0.0004 * u * v + 0.0003 * (r2 + 2 * v * v) - 0.0006 * r2;
    EXPECT_NEAR(lens.pixelOf({kX, kY}).x(), 450 * (u + du) + 300, 1e-9);
    EXPECT_NEAR(lens.pixelOf({kX, kY}).y(), 440 * (v + dv) + 200, 1e-9);
}

TEST(LensModel, UnsupportedModelsAreRefusedByName) {
    for (const char* name : {"RAD_TAN_THIN_PRISM_FISHEYE", "SIMPLE_DIVISION", "EUCM", "EQUIRECTANGULAR"}) {
        const int count = std::string(name) == "EQUIRECTANGULAR" ? 2 : std::string(name) == "EUCM" ? 6
                          : std::string(name) == "SIMPLE_DIVISION" ? 4 : 16;
        try {
            rad::colmapLens(name, std::vector<double>(count, 1.0));
            ADD_FAILURE() << name << " accepted";
        } catch (const rad::CameraFileError& e) {
            EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("image_undistorter"), std::string::npos) << e.what();
        }
    }
    EXPECT_THROW(rad::colmapLens("OPENCV", {1, 2, 3}), rad::CameraFileError);  // wrong parameter count
}

TEST(LensModel, ScaledLensImagesTheSamePointOnTheResizedPhotograph) {
    const rad::LensModel lens = rad::colmapLens("OPENCV", {800, 780, 320.5, 240.25, -0.12, 0.03, 0.001, -0.002});
    const rad::LensModel half = lens.scaled(0.5, 0.5);
    const Eigen::Vector2d full = lens.pixelOf({kX, kY}), small = half.pixelOf({kX, kY});
    // Pixel edges coincide (origin at the corner): coordinates simply halve.
    EXPECT_NEAR(small.x(), full.x() / 2, 1e-9);
    EXPECT_NEAR(small.y(), full.y() / 2, 1e-9);
}

TEST(LensModel, ValidationRefusesNaNAndNonPositiveFocals) {
    rad::LensModel lens = rad::colmapLens("PINHOLE", {500, 500, 100, 80});
    EXPECT_EQ(lens.validate(), "");
    lens.fx = std::nan("");
    EXPECT_NE(lens.validate().find("finite"), std::string::npos);
    lens.fx = -3;
    EXPECT_NE(lens.validate().find("focal"), std::string::npos);
}

}  // namespace
