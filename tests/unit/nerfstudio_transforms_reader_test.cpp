// nerfstudio transforms.json written here by hand: OpenGL camera axes (camera-to-world, looking
// along -z), global and per-frame intrinsics, OpenCV distortion; refusals.
#include "cameras/camera_file.h"
#include "test_temporary_directory.h"
#include "cameras/nerfstudio_transforms_reader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

namespace {

std::string writeFile(const std::string& name, const std::string& text) {
    const std::string path = std::string(RADIANCE_TEST_TMPDIR) + "/" + name;
    std::ofstream(path) << text;
    return path;
}

// Frame 0: camera at (1, 2, 3), axes = world axes in OpenGL's sense (looks along world -z, image
// up = world +y). Frame 1: its own focal length and image size.
const char* kTransforms = R"({
  "camera_model": "OPENCV", "fl_x": 500, "fl_y": 490, "cx": 320.5, "cy": 240.25, "w": 640, "h": 480,
  "k1": -0.1, "k2": 0.02, "p1": 0.001, "p2": -0.002,
  "frames": [
    {"file_path": "./images/frame_00001.png",
     "transform_matrix": [[1, 0, 0, 1], [0, 1, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]]},
    {"file_path": "images/frame_00002.png", "fl_x": 250, "fl_y": 250, "w": 320, "h": 240, "cx": 160, "cy": 120,
     "k1": 0, "k2": 0, "p1": 0, "p2": 0,
     "transform_matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}
  ]
})";

TEST(NerfstudioTransformsReader, OpenGlAxesAndOpenCvDistortion) {
    const rad::CameraImport model = rad::readCameraFile(writeFile("transforms.json", kTransforms));
    EXPECT_EQ(model.format, "nerfstudio transforms.json");
    ASSERT_EQ(model.cameras.size(), 2u);
    const rad::ImportedCamera& c = model.cameras[0];
    EXPECT_EQ(c.imageName, "images/frame_00001.png");
    // World point (1.2, 2.3, 1): 2 units in front (-z), 0.2 right (+x), 0.3 UP (+y): in OpenCV's
    // axes x = 0.2, y = -0.3 (down is +y), z = 2.
    const double x = 0.2 / 2, y = -0.3 / 2, r2 = x * x + y * y;
    const double radial = 1 - 0.1 * r2 + 0.02 * r2 * r2;
    const double xd = x * radial + 2 * 0.001 * x * y - 0.002 * (r2 + 2 * x * x);
    const double yd = y * radial + 0.001 * (r2 + 2 * y * y) + 2 * -0.002 * x * y;
    double u = 0, v = 0;
    ASSERT_TRUE(c.project({1.2, 2.3, 1.0}, u, v));
    EXPECT_NEAR(u, 500 * xd + 320.5, 1e-9);
    EXPECT_NEAR(v, 490 * yd + 240.25, 1e-9);
    // A point behind (world +z of the camera) is not in front.
    EXPECT_FALSE(c.project({1.0, 2.0, 4.0}, u, v));
    const rad::ImportedCamera& d = model.cameras[1];
    EXPECT_EQ(d.width, 320);
    EXPECT_DOUBLE_EQ(d.lens.fx, 250.0);
    EXPECT_FALSE(d.lens.distorts());
}

// The original NeRF's Blender scenes (Mildenhall et al. 2020) give only the horizontal field of view;
// the photograph's size completes the camera. "lego" has camera_angle_x 0.6911112070083618 and
// 800 x 800 photographs, whose focal length its users quote as 1111.11 pixels.
TEST(NerfstudioTransformsReader, FieldOfViewOnlyIsCompletedByThePhotographsSize) {
    const rad::CameraImport model = rad::readCameraFile(writeFile("nerf_transforms.json", R"({
      "camera_angle_x": 0.6911112070083618,
      "frames": [{"file_path": "./train/r_0", "transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,4],[0,0,0,1]]}]
    })"));
    ASSERT_EQ(model.cameras.size(), 1u);
    rad::ImportedCamera camera = model.cameras[0];
    EXPECT_EQ(camera.imageName, "train/r_0");
    EXPECT_TRUE(camera.sizedByPhotograph());
    camera.takeSizeFromPhotograph(800, 800);
    EXPECT_FALSE(camera.sizedByPhotograph());
    EXPECT_EQ(camera.width, 800);
    EXPECT_NEAR(camera.lens.fx, 1111.111, 1e-3);
    EXPECT_NEAR(camera.lens.fy, 1111.111, 1e-3);
    EXPECT_DOUBLE_EQ(camera.lens.cx, 400.0);
    EXPECT_EQ(camera.validate(), "");
    // A point 4 units in front of the camera (world -z from the centre (0, 0, 4)) and 1 unit to the
    // right lands 1111.11 / 4 pixels right of the centre.
    double u = 0, v = 0;
    ASSERT_TRUE(camera.project({1.0, 0.0, 0.0}, u, v));
    EXPECT_NEAR(u, 400.0 + 1111.111 / 4, 1e-3);
    EXPECT_NEAR(v, 400.0, 1e-9);
    // With w and h in the file the size is the file's, and camera_angle_y gives fy.
    const rad::CameraImport sized = rad::readCameraFile(writeFile("nerf_sized.json", R"({
      "camera_angle_x": 1.0, "camera_angle_y": 0.8, "w": 640, "h": 480,
      "frames": [{"file_path": "a.png", "transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}]
    })"));
    EXPECT_FALSE(sized.cameras[0].sizedByPhotograph());
    EXPECT_NEAR(sized.cameras[0].lens.fx, 320.0 / std::tan(0.5), 1e-9);
    EXPECT_NEAR(sized.cameras[0].lens.fy, 240.0 / std::tan(0.4), 1e-9);
}

std::string refusal(const std::string& text) {
    try {
        rad::readCameraFile(writeFile("bad_transforms.json", text));
    } catch (const rad::CameraFileError& e) {
        return e.what();
    }
    return "";
}

TEST(NerfstudioTransformsReader, RefusesBadFiles) {
    std::string scaled = kTransforms;
    scaled.replace(scaled.find("[[1, 0, 0, 1]"), 13, "[[3, 0, 0, 1]");
    EXPECT_NE(refusal(scaled).find("not a rotation"), std::string::npos) << refusal(scaled);
    std::string nan = kTransforms;
    nan.replace(nan.find("\"fl_x\": 500"), 11, "\"fl_x\": NaN");
    EXPECT_NE(refusal(nan).find("not a finite number"), std::string::npos) << refusal(nan);
    EXPECT_NE(refusal("{\"frames\": [{\"file_path\": \"./r_0\", \"transform_matrix\": "
                      "[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}]}")
                  .find("no 'fl_x'"),
              std::string::npos);
    EXPECT_NE(refusal("{\"camera_angle_x\": -0.5, \"frames\": [{\"file_path\": \"./r_0\", \"transform_matrix\": "
                      "[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}]}")
                  .find("'camera_angle_x' must be a positive angle"),
              std::string::npos);
    std::string equirect = kTransforms;
    equirect.replace(equirect.find("\"OPENCV\""), 8, "\"EQUIRECTANGULAR\"");
    EXPECT_NE(refusal(equirect).find("EQUIRECTANGULAR"), std::string::npos);
    EXPECT_NE(refusal("{\"a\": 1}").find("not a nerfstudio"), std::string::npos);
    EXPECT_NE(refusal("{\"frames\": [1, }").find("not valid JSON"), std::string::npos);
}

}  // namespace
