// COLMAP models written here by hand, binary and text, as COLMAP's documentation ("Output format")
// describes them: a camera whose pose and lens are known projects a point where the formula
// written out in the test puts it; conventions (world-to-camera quaternion qw qx qy qz, pixel
// origin at the top-left corner) and refusals.
#include "cameras/camera_file.h"
#include "test_temporary_directory.h"
#include "cameras/colmap_model_reader.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

std::string freshFolder(const std::string& name) {
    const fs::path dir = fs::path(RADIANCE_TEST_TMPDIR) / ("colmap_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir.string();
}

void writeText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

struct Bytes {
    std::string data;
    template <typename T>
    Bytes& put(T v) {
        data.append(reinterpret_cast<const char*>(&v), sizeof v);
        return *this;
    }
    Bytes& name(const std::string& s) {
        data.append(s);
        data.push_back('\0');
        return *this;
    }
    void save(const std::string& path) const { std::ofstream(path, std::ios::binary) << data; }
};

// A rotation of 90 degrees about the camera's z axis: q = (cos 45, 0, 0, sin 45) maps world x to
// camera y and world y to camera -x (R = [[0,-1,0],[1,0,0],[0,0,1]]); t = (0.1, -0.2, 3).
const double kQ[4] = {std::sqrt(0.5), 0.0, 0.0, std::sqrt(0.5)};
const double kT[3] = {0.1, -0.2, 3.0};

// Where that camera, an OPENCV lens (fx 800, fy 790, cx 320.5, cy 240.5, k1 -0.1, k2 0.02, p1 0.001,
// p2 -0.0005), puts world point (0.3, 0.4, 0.5), computed step by step from COLMAP's formulas.
void expectedPixel(double& u, double& v) {
    const double X = 0.3, Y = 0.4, Z = 0.5;
    const double xc = -Y + kT[0], yc = X + kT[1], zc = Z + kT[2];  // R X + t
    const double x = xc / zc, y = yc / zc, r2 = x * x + y * y;
    const double radial = 1 - 0.1 * r2 + 0.02 * r2 * r2;
    const double xd = x * radial + 2 * 0.001 * x * y - 0.0005 * (r2 + 2 * x * x);
    const double yd = y * radial + 0.001 * (r2 + 2 * y * y) + 2 * -0.0005 * x * y;
    u = 800 * xd + 320.5;
    v = 790 * yd + 240.5;
}

void expectKnownCamera(const rad::CameraImport& model) {
    ASSERT_EQ(model.cameras.size(), 2u);
    const rad::ImportedCamera& c = model.cameras[0];
    EXPECT_EQ(c.imageName, "sub/a.jpg");
    EXPECT_EQ(c.width, 640);
    EXPECT_EQ(c.height, 480);
    double u = 0, v = 0, eu = 0, ev = 0;
    ASSERT_TRUE(c.project({0.3, 0.4, 0.5}, u, v));
    expectedPixel(eu, ev);
    EXPECT_NEAR(u, eu, 1e-9);
    EXPECT_NEAR(v, ev, 1e-9);
    // Camera centre -R^T t, written out: R^T t = (t_y, -t_x, t_z).
    EXPECT_NEAR((c.center - Eigen::Vector3d(-kT[1], kT[0], -kT[2])).norm(), 0.0, 1e-12);
    EXPECT_EQ(model.cameras[1].imageName, "b.png");
    EXPECT_FALSE(model.cameras[1].lens.distorts());
}

TEST(ColmapModelReader, TextModel) {
    const std::string dir = freshFolder("text");
    writeText(dir + "/cameras.txt",
              "# Camera list with one line of data per camera:\n#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
              "1 OPENCV 640 480 800 790 320.5 240.5 -0.1 0.02 0.001 -0.0005\n2 PINHOLE 640 480 700 700 320 240\n");
    char line[256];
    std::snprintf(line, sizeof line, "7 %.17g %.17g %.17g %.17g %.17g %.17g %.17g 1 sub/a.jpg\n", kQ[0], kQ[1], kQ[2],
                  kQ[3], kT[0], kT[1], kT[2]);
    // The first image's observation line is empty, the second's holds points: both are skipped.
    writeText(dir + "/images.txt",
              std::string("# Image list with two lines of data per image:\n") + line + "\n" +
                  "9 1 0 0 0 0 0 1 2 b.png\n100.5 20.5 -1 30 40 5\n");
    const rad::CameraImport model = rad::readCameraFile(dir);
    EXPECT_EQ(model.format, "COLMAP text model");
    expectKnownCamera(model);
    // One of the model's files names the model too.
    EXPECT_EQ(rad::readCameraFile(dir + "/images.txt").cameras.size(), 2u);
}

void writeBinaryCameras(const std::string& dir, int firstModelId, const std::vector<double>& firstParams) {
    Bytes cams;
    cams.put<std::uint64_t>(2);
    cams.put<std::uint32_t>(1).put<std::int32_t>(firstModelId).put<std::uint64_t>(640).put<std::uint64_t>(480);
    for (double p : firstParams) cams.put<double>(p);
    cams.put<std::uint32_t>(2).put<std::int32_t>(1).put<std::uint64_t>(640).put<std::uint64_t>(480);
    for (double p : {700.0, 700.0, 320.0, 240.0}) cams.put<double>(p);
    cams.save(dir + "/cameras.bin");
}

void writeBinaryImages(const std::string& dir, const double q[4]) {
    Bytes images;
    images.put<std::uint64_t>(2);
    images.put<std::uint32_t>(7);
    for (int i = 0; i < 4; ++i) images.put<double>(q[i]);
    for (double t : kT) images.put<double>(t);
    images.put<std::uint32_t>(1).name("sub/a.jpg").put<std::uint64_t>(1);
    images.put<double>(10.0).put<double>(20.0).put<std::int64_t>(-1);
    images.put<std::uint32_t>(9);
    for (double v : {1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0}) images.put<double>(v);
    images.put<std::uint32_t>(2).name("b.png").put<std::uint64_t>(0);
    images.save(dir + "/images.bin");
}

const std::vector<double> kOpenCvParams = {800, 790, 320.5, 240.5, -0.1, 0.02, 0.001, -0.0005};

TEST(ColmapModelReader, BinaryModel) {
    const std::string dir = freshFolder("binary");
    writeBinaryCameras(dir, 4, kOpenCvParams);
    writeBinaryImages(dir, kQ);
    const rad::CameraImport model = rad::readCameraFile(dir + "/cameras.bin");
    EXPECT_EQ(model.format, "COLMAP binary model");
    expectKnownCamera(model);
}

std::string refusal(const std::string& path) {
    return radtest::refusalMessage<rad::CameraFileError>([&] { rad::readCameraFile(path); });
}

TEST(ColmapModelReader, RefusesUnsupportedAndUnknownModelsByName) {
    const std::string dir = freshFolder("unsupported");
    writeBinaryCameras(dir, 11, std::vector<double>(16, 0.5));
    writeBinaryImages(dir, kQ);
    EXPECT_NE(refusal(dir).find("RAD_TAN_THIN_PRISM_FISHEYE"), std::string::npos) << refusal(dir);
    writeBinaryCameras(dir, 42, {});
    EXPECT_NE(refusal(dir).find("model id 42"), std::string::npos) << refusal(dir);
    const std::string text = freshFolder("unsupported_text");
    writeText(text + "/cameras.txt", "1 EUCM 640 480 500 500 320 240 0.5 1.0\n");
    writeText(text + "/images.txt", "1 1 0 0 0 0 0 1 1 a.jpg\n\n");
    EXPECT_NE(refusal(text).find("EUCM"), std::string::npos) << refusal(text);
}

TEST(ColmapModelReader, RefusesDamagedModels) {
    const std::string dir = freshFolder("damaged");
    // A NaN focal length.
    std::vector<double> nanFocal = kOpenCvParams;
    nanFocal[0] = std::nan("");
    writeBinaryCameras(dir, 4, nanFocal);
    writeBinaryImages(dir, kQ);
    EXPECT_NE(refusal(dir).find("not a finite number"), std::string::npos) << refusal(dir);
    // A quaternion that is not a rotation.
    writeBinaryCameras(dir, 4, kOpenCvParams);
    const double scaled[4] = {2 * kQ[0], 0, 0, 2 * kQ[3]};
    writeBinaryImages(dir, scaled);
    EXPECT_NE(refusal(dir).find("not a rotation"), std::string::npos) << refusal(dir);
    // A truncated images.bin.
    writeBinaryImages(dir, kQ);
    fs::resize_file(dir + "/images.bin", 40);
    EXPECT_NE(refusal(dir).find("truncated"), std::string::npos) << refusal(dir);
    // An image using a camera the cameras file lacks.
    const std::string text = freshFolder("missing_camera");
    writeText(text + "/cameras.txt", "1 PINHOLE 640 480 500 500 320 240\n");
    writeText(text + "/images.txt", "1 1 0 0 0 0 0 1 5 a.jpg\n\n");
    EXPECT_NE(refusal(text).find("camera 5"), std::string::npos) << refusal(text);
    // A folder without a model, and a file of another format.
    const std::string empty = freshFolder("empty");
    EXPECT_NE(refusal(empty).find("no COLMAP model"), std::string::npos) << refusal(empty);
    writeText(empty + "/scan.ply", "ply\nformat ascii 1.0\n");
    EXPECT_NE(refusal(empty + "/scan.ply").find("not a camera file"), std::string::npos) << refusal(empty + "/scan.ply");
    EXPECT_NE(refusal(empty + "/none.bin").find("does not exist"), std::string::npos);
}

}  // namespace
