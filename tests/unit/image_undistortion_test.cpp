// The undistortion map against the lens formula written out here, the resampling on a photograph
// of uniform blocks, the zoom that keeps barrel lenses inside the photograph, size checks and the
// cache's file names.
#include "cameras/colmap_model_reader.h"
#include "cameras/image_undistortion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace {

// A camera at the origin looking along +z (world = camera axes), 200 x 150 pixels, OPENCV lens.
rad::ImportedCamera openCvCamera(double k1) {
    rad::ImportedCamera camera;
    camera.imageName = "photos/IMG_1.JPG";
    camera.width = 200;
    camera.height = 150;
    camera.lens = rad::colmapLens("OPENCV", {180, 175, 101.5, 73.25, k1, 0.01, 0.002, -0.001});
    return camera;
}

// OPENCV's formula, written out.
Eigen::Vector2d openCvPixel(double k1, double x, double y) {
    const double r2 = x * x + y * y, radial = 1 + k1 * r2 + 0.01 * r2 * r2;
    const double xd = x * radial + 2 * 0.002 * x * y - 0.001 * (r2 + 2 * x * x);
    const double yd = y * radial + 0.002 * (r2 + 2 * y * y) + 2 * -0.001 * x * y;
    return {180 * xd + 101.5, 175 * yd + 73.25};
}

TEST(ImageUndistortion, PinholePixelShowsWhereTheLensImagesTheSamePoint) {
    for (double k1 : {-0.2, 0.15}) {
        const rad::ImportedCamera camera = openCvCamera(k1);
        const rad::UndistortionPlan plan = rad::planUndistortion(camera, 200, 150);
        ASSERT_TRUE(plan.resample);
        std::mt19937 rng(3);
        std::uniform_real_distribution<double> u(-0.4, 0.4);
        for (int i = 0; i < 100; ++i) {
            const Eigen::Vector3d X(u(rng), u(rng), 1.0 + u(rng));
            double pu = 0, pv = 0;
            ASSERT_TRUE(plan.target.project(X, pu, pv));
            const Eigen::Vector2d expected = openCvPixel(k1, X.x() / X.z(), X.y() / X.z());
            const Eigen::Vector2d source = plan.sourcePixel(pu, pv);
            EXPECT_NEAR(source.x(), expected.x(), 1e-6);
            EXPECT_NEAR(source.y(), expected.y(), 1e-6);
        }
    }
}

TEST(ImageUndistortion, PincushionLensIsZoomedToStayInsideThePhotograph) {
    // k1 > 0 images the pinhole image's corners beyond the photograph's: the focal length grows.
    const rad::UndistortionPlan pincushion = rad::planUndistortion(openCvCamera(0.3), 200, 150);
    EXPECT_GT(pincushion.zoom, 1.0);
    for (int c = 0; c < 200; ++c)
        for (int r : {0, 149}) {
            const Eigen::Vector2d s = pincushion.sourcePixel(c + 0.5, r + 0.5);
            EXPECT_TRUE(s.x() >= 0 && s.x() <= 200 && s.y() >= 0 && s.y() <= 150) << c << " " << r;
        }
    // One zoom step less lets a corner fall outside (the zoom is the smallest that works).
    rad::UndistortionPlan less = pincushion;
    less.target.fx /= 1.01;
    less.target.fy /= 1.01;
    bool outside = false;
    for (double u : {0.5, 199.5})
        for (double v : {0.5, 149.5}) {
            const Eigen::Vector2d s = less.sourcePixel(u, v);
            outside = outside || s.x() < 0 || s.x() > 200 || s.y() < 0 || s.y() > 150;
        }
    EXPECT_TRUE(outside);
    // A mild barrel lens images the whole pinhole image inside the photograph: no zoom.
    EXPECT_EQ(rad::planUndistortion(openCvCamera(-0.2), 200, 150).zoom, 1.0);
    // A strong barrel polynomial folds over (r (1 + k1 r^2 + k2 r^4) decreases beyond
    // r = 0.53 for k1 = -1.2, k2 = 0.01) before the corners (r = 0.70): zoomed to the valid part.
    const rad::UndistortionPlan folded = rad::planUndistortion(openCvCamera(-1.2), 200, 150);
    EXPECT_GT(folded.zoom, 0.70 / 0.53 * 0.9);
}

TEST(ImageUndistortion, ResamplesEachPixelFromTheMappedPoint) {
    const rad::ImportedCamera camera = openCvCamera(-0.2);
    const rad::UndistortionPlan plan = rad::planUndistortion(camera, 200, 150);
    // A photograph of 10 x 10 blocks, each of its own colour.
    rad::Image8 photograph(200, 150);
    const auto blockColour = [](int bx, int by, int c) { return std::uint8_t((37 * bx + 91 * by + 53 * c) % 251); };
    for (int r = 0; r < 150; ++r)
        for (int c = 0; c < 200; ++c)
            for (int k = 0; k < 3; ++k) photograph.pixel(c, r)[k] = blockColour(c / 10, r / 10, k);
    const rad::Image8 out = rad::undistortImage(photograph.view(), plan);
    ASSERT_EQ(out.width, 200);
    ASSERT_EQ(out.height, 150);
    int checked = 0;
    for (int r = 0; r < 150; ++r)
        for (int c = 0; c < 200; ++c) {
            const Eigen::Vector2d s = plan.sourcePixel(c + 0.5, r + 0.5);
            // Cubic convolution reads the 4 x 4 pixels around the point (their weights sum to 1):
            // well inside a block (more than 2 pixels from its edges) the block's colour comes out
            // unchanged.
            const double fx = std::fmod(s.x(), 10.0), fy = std::fmod(s.y(), 10.0);
            if (fx < 2.01 || fx > 7.99 || fy < 2.01 || fy > 7.99) continue;
            for (int k = 0; k < 3; ++k)
                ASSERT_EQ(out.rgb[(std::size_t(r) * 200 + c) * 3 + k], blockColour(int(s.x()) / 10, int(s.y()) / 10, k))
                    << c << " " << r;
            ++checked;
        }
    EXPECT_GT(checked, 5000);
}

TEST(ImageUndistortion, PinholeLensNeedsNoResamplingAndResizedPhotographsScaleTheCamera) {
    rad::ImportedCamera camera = openCvCamera(0.0);
    camera.lens = rad::colmapLens("PINHOLE", {180, 175, 101.5, 73.25});
    camera.width = 6000;
    camera.height = 4000;
    const rad::UndistortionPlan plan = rad::planUndistortion(camera, 1500, 1000);
    EXPECT_FALSE(plan.resample);
    EXPECT_DOUBLE_EQ(plan.target.fx, 45.0);
    EXPECT_DOUBLE_EQ(plan.target.cx, 101.5 / 4);
    EXPECT_EQ(rad::imageSizeProblem(camera, 6000, 4000), "");
    EXPECT_EQ(rad::imageSizeProblem(camera, 857, 571), "");  // 6000 / 7 and 4000 / 7, rounded
    EXPECT_NE(rad::imageSizeProblem(camera, 4000, 6000), "");
    EXPECT_NE(rad::imageSizeProblem(camera, 1500, 1100).find("1500 x 1100"), std::string::npos);
}

TEST(ImageUndistortion, CacheNamesChangeWithTheCalibrationAndThePhotograph) {
    const rad::UndistortionPlan a = rad::planUndistortion(openCvCamera(-0.2), 200, 150);
    const rad::UndistortionPlan b = rad::planUndistortion(openCvCamera(-0.2001), 200, 150);
    const std::string name = rad::undistortedFileName("photos/IMG_1.JPG", a, "size 1 time 2");
    EXPECT_EQ(name.rfind("photos__IMG_1.", 0), 0u) << name;
    EXPECT_EQ(name.substr(name.size() - 4), ".png");
    EXPECT_EQ(name, rad::undistortedFileName("photos/IMG_1.JPG", a, "size 1 time 2"));
    EXPECT_NE(name, rad::undistortedFileName("photos/IMG_1.JPG", b, "size 1 time 2"));
    EXPECT_NE(name, rad::undistortedFileName("photos/IMG_1.JPG", a, "size 1 time 3"));
}

}  // namespace
