// Tests of io/meshlab_project.h: PinholeCamera <-> VCGCamera conversion (exact round trip, and a
// projection computed by hand with MeshLab's formula), project write/read round trip (float32
// values bit for bit, relative paths), a project as MeshLab writes it, binary cameras, and the
// refusal of malformed files with a message.
#include "io/meshlab_project.h"
#include "test_temporary_directory.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

namespace {

using Eigen::Vector3d;

rad::PinholeCamera randomCamera(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    rad::PinholeCamera cam;
    const Eigen::Quaterniond q = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized();
    cam.rotation = q.toRotationMatrix();
    cam.center = Vector3d(u(rng), u(rng), u(rng)) * 10.0;
    cam.width = 640 + static_cast<int>(100 * (u(rng) + 1));
    cam.height = 480 + static_cast<int>(50 * (u(rng) + 1));
    cam.fx = 700.0 + 100 * u(rng);
    cam.fy = cam.fx * (1.0 + 0.05 * u(rng));  // non-square pixels
    cam.cx = 0.5 * cam.width + 20 * u(rng);    // off-centre principal point
    cam.cy = 0.5 * cam.height + 20 * u(rng);
    return cam;
}

std::string tmpDir() { return std::string(RADIANCE_TEST_TMPDIR) + "/meshlab_project_test"; }

TEST(MeshLabProject, ConversionRoundTripIsExact) {
    std::mt19937 rng(5);
    for (int i = 0; i < 50; ++i) {
        const rad::PinholeCamera cam = randomCamera(rng);
        const rad::VcgCamera v = rad::toVcgCamera(cam);
        EXPECT_EQ(v.pixelSizeMm.x(), 0.01);
        EXPECT_EQ(v.viewportWidth, cam.width);
        EXPECT_EQ(v.viewportHeight, cam.height);
        const rad::PinholeCamera back = rad::fromVcgCamera(v);
        EXPECT_EQ(back.rotation, cam.rotation);  // sign flips are exact
        EXPECT_EQ(back.center, cam.center);
        EXPECT_NEAR(back.fx, cam.fx, 1e-12 * cam.fx);
        EXPECT_NEAR(back.fy, cam.fy, 1e-12 * cam.fy);
        EXPECT_EQ(back.cx, cam.cx);
        EXPECT_NEAR(back.cy, cam.cy, 1e-12 * cam.height);
        EXPECT_EQ(back.width, cam.width);
        EXPECT_EQ(back.height, cam.height);
        // MeshLab's projection of a random point equals ours with y counted from the bottom.
        for (int k = 0; k < 10; ++k) {
            const Vector3d X = cam.center + cam.rotation.transpose() * Vector3d(rng() % 7 - 3.0, rng() % 5 - 2.0, 5.0 + k);
            double u, vv, px, py;
            ASSERT_TRUE(cam.project(X, u, vv));
            ASSERT_TRUE(v.project(X, px, py));
            EXPECT_NEAR(px, u, 1e-9);
            EXPECT_NEAR(py, cam.height - vv, 1e-9);
        }
    }
}

// Values chosen so the doc's formula can be done on paper:
//   cp = R (X - C), cp.z = -cp.z, px = cp.x FocalMm / cp.z / PixelSizeMm.x + CenterPx.x (y likewise,
//   from the bottom).
TEST(MeshLabProject, HandComputedProjection) {
    {
        rad::VcgCamera v;  // rows right = x, up = y, backwards = z: looks along -z
        v.rotation.setIdentity();
        v.translation = Vector3d(-1, -2, -10);  // C = (1, 2, 10)
        v.focalMm = 35.0;
        v.pixelSizeMm = Eigen::Vector2d(0.01, 0.02);
        v.centerPx = Eigen::Vector2d(320.5, 200.25);
        v.viewportWidth = 640;
        v.viewportHeight = 480;
        // X = (1.5, 2.5, 0): X - C = (0.5, 0.5, -10), cp = (0.5, 0.5, 10 after the flip)
        //   px = 0.5 * 35 / 10 / 0.01 + 320.5 = 175 + 320.5 = 495.5
        //   py = 0.5 * 35 / 10 / 0.02 + 200.25 = 87.5 + 200.25 = 287.75  -> v = 480 - 287.75 = 192.25
        double px, py;
        ASSERT_TRUE(v.project(Vector3d(1.5, 2.5, 0.0), px, py));
        EXPECT_NEAR(px, 495.5, 1e-12);
        EXPECT_NEAR(py, 287.75, 1e-12);
        const rad::PinholeCamera cam = rad::fromVcgCamera(v);
        double u, vv;
        ASSERT_TRUE(cam.project(Vector3d(1.5, 2.5, 0.0), u, vv));
        EXPECT_NEAR(u, 495.5, 1e-12);
        EXPECT_NEAR(vv, 192.25, 1e-12);
        EXPECT_NEAR(cam.fx, 3500.0, 1e-9);
        EXPECT_NEAR(cam.fy, 1750.0, 1e-9);
        EXPECT_FALSE(v.project(Vector3d(1.5, 2.5, 20.0), px, py));  // behind the camera
    }
    {
        rad::VcgCamera v;  // right = +y, up = +z, backwards = +x (right x up = backwards): looks along -x
        v.rotation << 0, 1, 0, 0, 0, 1, 1, 0, 0;
        v.translation = Vector3d(-5, 0, 0);  // C = (5, 0, 0)
        v.focalMm = 3.5;
        v.pixelSizeMm = Eigen::Vector2d(0.01, 0.01);
        v.centerPx = Eigen::Vector2d(320, 240);
        v.viewportWidth = 640;
        v.viewportHeight = 480;
        // X = (0, 1, -0.5): X - C = (-5, 1, -0.5), cp = (1, -0.5, -5) -> cp.z = 5
        //   px = 1 * 3.5 / 5 / 0.01 + 320 = 390,  py = -0.5 * 3.5 / 5 / 0.01 + 240 = 205 -> v = 275
        double px, py, u, vv;
        ASSERT_TRUE(v.project(Vector3d(0, 1, -0.5), px, py));
        EXPECT_NEAR(px, 390.0, 1e-12);
        EXPECT_NEAR(py, 205.0, 1e-12);
        const rad::PinholeCamera cam = rad::fromVcgCamera(v);
        ASSERT_TRUE(cam.project(Vector3d(0, 1, -0.5), u, vv));
        EXPECT_NEAR(u, 390.0, 1e-12);
        EXPECT_NEAR(vv, 275.0, 1e-12);
        EXPECT_TRUE(cam.validate().empty());
        // Our camera's axes: right = +y, down = -z, forward = -x.
        EXPECT_EQ(cam.forward(), Vector3d(-1, 0, 0));
    }
}

TEST(MeshLabProject, WriteReadRoundTripIsBitExactInFloat32) {
    std::filesystem::create_directories(tmpDir());
    const std::string path = tmpDir() + "/roundtrip.mlp";
    std::mt19937 rng(11);
    rad::MeshLabProject project;
    std::vector<rad::PinholeCamera> cams;
    for (int i = 0; i < 5; ++i) {
        cams.push_back(randomCamera(rng));
        rad::ProjectRaster r;
        r.label = "view_" + std::to_string(i) + ".png";
        r.imageFile = "images/view_" + std::to_string(i) + ".png";
        r.camera = rad::toVcgCamera(cams.back());
        project.rasters.push_back(r);
    }
    rad::ProjectMesh mesh;
    mesh.label = "scan & \"friends\"";  // escaped in the attribute
    mesh.fileName = "mesh.ply";
    mesh.transform(0, 3) = 1.25;
    project.meshes.push_back(mesh);
    rad::writeMeshLabProject(path, project);

    const rad::MeshLabProject back = rad::readMeshLabProject(path);
    ASSERT_EQ(back.rasters.size(), 5u);
    ASSERT_EQ(back.meshes.size(), 1u);
    EXPECT_EQ(back.meshes[0].label, mesh.label);
    EXPECT_EQ(back.meshes[0].fileName, "mesh.ply");
    EXPECT_EQ(back.meshes[0].path, (std::filesystem::path(tmpDir()) / "mesh.ply").string());
    EXPECT_EQ(back.meshes[0].transform, mesh.transform);
    for (int i = 0; i < 5; ++i) {
        const rad::ProjectRaster& r = back.rasters[i];
        EXPECT_EQ(r.label, project.rasters[i].label);
        EXPECT_EQ(r.imageFile, project.rasters[i].imageFile);
        EXPECT_EQ(r.imagePath, (std::filesystem::path(tmpDir()) / "images" / r.label).string());
        const rad::VcgCamera want = rad::roundedToFloat(project.rasters[i].camera);
        EXPECT_EQ(0, std::memcmp(r.camera.rotation.data(), want.rotation.data(), 9 * sizeof(double)));  // bit for bit
        EXPECT_EQ(0, std::memcmp(r.camera.translation.data(), want.translation.data(), 3 * sizeof(double)));
        EXPECT_EQ(r.camera.focalMm, want.focalMm);
        EXPECT_EQ(r.camera.pixelSizeMm, want.pixelSizeMm);
        EXPECT_EQ(r.camera.centerPx, want.centerPx);
        EXPECT_EQ(r.camera.viewportWidth, want.viewportWidth);
        EXPECT_EQ(r.camera.viewportHeight, want.viewportHeight);
        EXPECT_EQ(r.camera.lensDistortion, want.lensDistortion);
        // The camera a tool reads is exactly storedCamera() of the one written.
        const rad::PinholeCamera read = rad::fromVcgCamera(r.camera);
        const rad::PinholeCamera stored = rad::storedCamera(cams[i]);
        EXPECT_EQ(read.rotation, stored.rotation);
        EXPECT_EQ(read.center, stored.center);
        EXPECT_EQ(read.fx, stored.fx);
        EXPECT_EQ(read.fy, stored.fy);
        EXPECT_EQ(read.cx, stored.cx);
        EXPECT_EQ(read.cy, stored.cy);
        // ... and within float precision of the original.
        EXPECT_NEAR((stored.center - cams[i].center).norm(), 0.0, 1e-5);
        EXPECT_NEAR(stored.fx, cams[i].fx, 1e-3);
    }
    std::filesystem::remove(path);
}

TEST(MeshLabProject, WrittenTextHasTheShapeMeshLabNeeds) {
    rad::MeshLabProject project;
    rad::ProjectRaster r;
    r.label = "a.png";
    r.imageFile = "images/a.png";
    r.camera = rad::toVcgCamera(rad::PinholeCamera::lookAt(Vector3d(0, 0, 5), Vector3d::Zero(), Vector3d::UnitY(), 40, 320, 240));
    project.rasters.push_back(r);
    const std::string text = rad::formatMeshLabProject(project);
    EXPECT_NE(text.find("<!DOCTYPE MeshLabDocument>"), std::string::npos);
    EXPECT_NE(text.find("<MeshGroup/>"), std::string::npos);  // empty: mesh comes with -i
    const std::size_t raster = text.find("<MLRaster label=\"a.png\">");
    ASSERT_NE(raster, std::string::npos);
    // The raster's first element is the camera, then the plane with the relative path.
    EXPECT_EQ(text.find('<', raster + 1), text.find("<VCGCamera", raster));
    EXPECT_NE(text.find("<Plane semantic=\"1\" fileName=\"images/a.png\"/>"), std::string::npos);
    EXPECT_NE(text.find("BinaryData=\"0\""), std::string::npos);
    EXPECT_NE(text.find("ViewportPx=\"320 240\""), std::string::npos);
    EXPECT_NE(text.find("CenterPx=\"160 120\""), std::string::npos);
    // Camera at (0, 0, 5) looking at the origin with up +y: rows right (1 0 0), up (0 1 0),
    // backwards (0 0 1); TranslationVector = -C.
    EXPECT_NE(text.find("RotationMatrix=\"1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 \""), std::string::npos) << text;
    EXPECT_NE(text.find("TranslationVector=\"0 0 -5 1\""), std::string::npos) << text;
}

// A project in the shape MeshLab 2020.09 itself saves (mesh with matrix and rendering options).
TEST(MeshLabProject, ReadsAProjectAsMeshLabWritesIt) {
    const std::string text = R"(<!DOCTYPE MeshLabDocument>
<MeshLabProject>
 <MeshGroup>
  <MLMesh visible="1" label="bunny.ply" filename="../meshes/bunny.ply">
   <MLMatrix44>
1 0 0 0 
0 1 0 0 
0 0 1 0 
0 0 0 1 
</MLMatrix44>
   <RenderingOption boxColor="234 234 234 255" pointSize="3" wireWidth="1">100001000000000000000000000001010100000010100000000100111011110000001001</RenderingOption>
  </MLMesh>
 </MeshGroup>
 <RasterGroup>
  <MLRaster label="IMG_0001.JPG">
   <VCGCamera TranslationVector="-0.5 0.25 -3 1" LensDistortion="0 0" ViewportPx="4000 3000" PixelSizeMm="0.0015 0.0015" CenterPx="2000 1500" FocalMm="4.5" RotationMatrix="1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 " CameraType="0" BinaryData="0"/>
   <Plane semantic="1" fileName="IMG_0001.JPG"/>
  </MLRaster>
 </RasterGroup>
</MeshLabProject>
)";
    const rad::MeshLabProject p = rad::parseMeshLabProject(text, "base/dir", "test.mlp");
    ASSERT_EQ(p.meshes.size(), 1u);
    EXPECT_EQ(p.meshes[0].path, "base/meshes/bunny.ply");
    EXPECT_EQ(p.meshes[0].transform, Eigen::Matrix4d::Identity());
    ASSERT_EQ(p.rasters.size(), 1u);
    EXPECT_EQ(p.rasters[0].imagePath, "base/dir/IMG_0001.JPG");
    const rad::PinholeCamera cam = rad::fromVcgCamera(p.rasters[0].camera);
    EXPECT_EQ(cam.center, Vector3d(0.5, -0.25, 3.0));
    EXPECT_NEAR(cam.fx, 3000.0, 1e-3);  // 4.5 / 0.0015 in float32
    EXPECT_EQ(cam.width, 4000);
    EXPECT_EQ(cam.cy, 1500.0);
    EXPECT_EQ(cam.forward(), Vector3d(0, 0, -1));
}

// Minimal base64 encoder for the binary-camera test.
std::string base64(const void* data, std::size_t n) {
    static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const auto* b = static_cast<const unsigned char*>(data);
    std::string out;
    for (std::size_t i = 0; i < n; i += 3) {
        const unsigned v = (b[i] << 16) | ((i + 1 < n ? b[i + 1] : 0) << 8) | (i + 2 < n ? b[i + 2] : 0);
        out += t[(v >> 18) & 63];
        out += t[(v >> 12) & 63];
        out += i + 1 < n ? t[(v >> 6) & 63] : '=';
        out += i + 2 < n ? t[v & 63] : '=';
    }
    return out;
}

TEST(MeshLabProject, ReadsBinaryCameras) {
    const float rot[16] = {0, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0, 0, 0, 1};
    const float tra[3] = {-5, 0, 0};
    const float focal = 3.5f, pixel[2] = {0.01f, 0.01f}, center[2] = {320, 240}, lens[2] = {0, 0};
    const int viewport[2] = {640, 480};
    const std::string text = "<!DOCTYPE MeshLabDocument><MeshLabProject><MeshGroup/><RasterGroup><MLRaster label=\"b\">"
                             "<VCGCamera BinaryData=\"1\" CameraType=\"0\" TranslationVector=\"" + base64(tra, 12) +
                             "\" RotationMatrix=\"" + base64(rot, 64) + "\" FocalMm=\"" + base64(&focal, 4) +
                             "\" PixelSizeMm=\"" + base64(pixel, 8) + "\" CenterPx=\"" + base64(center, 8) +
                             "\" LensDistortion=\"" + base64(lens, 8) + "\" ViewportPx=\"" + base64(viewport, 8) +
                             "\"/><Plane semantic=\"1\" fileName=\"b.png\"/></MLRaster></RasterGroup></MeshLabProject>";
    const rad::MeshLabProject p = rad::parseMeshLabProject(text, "", "binary.mlp");
    ASSERT_EQ(p.rasters.size(), 1u);
    const rad::PinholeCamera cam = rad::fromVcgCamera(p.rasters[0].camera);
    double u, v;
    ASSERT_TRUE(cam.project(Vector3d(0, 1, -0.5), u, v));  // the second hand-computed case above
    EXPECT_NEAR(u, 390.0, 1e-4);
    EXPECT_NEAR(v, 275.0, 1e-4);
}

// parse() must throw a MeshLabProjectError whose message contains `needle`.
void expectRefused(const std::string& text, const std::string& needle) {
    try {
        rad::parseMeshLabProject(text, "", "bad.mlp");
        ADD_FAILURE() << "accepted: " << text;
    } catch (const rad::MeshLabProjectError& e) {
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("bad.mlp"), std::string::npos) << e.what();
    }
}

const char* kCamera =
    R"(<VCGCamera TranslationVector="0 0 -5 1" LensDistortion="0 0" ViewportPx="64 48" PixelSizeMm="0.01 0.01" CenterPx="32 24" FocalMm="0.5" RotationMatrix="1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 " CameraType="0" BinaryData="0"/>)";

std::string withRaster(const std::string& rasterContent) {
    return "<MeshLabProject><MeshGroup/><RasterGroup><MLRaster label=\"r\">" + rasterContent +
           "</MLRaster></RasterGroup></MeshLabProject>";
}

TEST(MeshLabProject, RefusesMalformedFiles) {
    const std::string plane = R"(<Plane semantic="1" fileName="r.png"/>)";
    // Sanity: the pieces make a valid project.
    EXPECT_NO_THROW(rad::parseMeshLabProject(withRaster(kCamera + plane), "", "ok.mlp"));

    expectRefused("", "no root element");
    expectRefused("<MeshLabProject><RasterGroup>", "not closed");
    expectRefused("<Project/>", "not a MeshLab project");
    expectRefused("<MeshLabProject><MeshGroup></RasterGroup></MeshLabProject>", "closes");
    expectRefused("<MeshLabProject a=1/>", "not quoted");
    expectRefused("<MeshLabProject a=\"&bogus;\"/>", "unknown entity");
    expectRefused(withRaster(plane + kCamera), "first child must be <VCGCamera>");
    expectRefused(withRaster("<!-- note -->" + std::string(kCamera) + plane), "first child must be <VCGCamera>");
    expectRefused(withRaster(kCamera), "no <Plane>");
    expectRefused(withRaster(kCamera + std::string("<Plane semantic=\"1\"/>")), "without a fileName");
    expectRefused("<MeshLabProject><MeshGroup><!-- c --></MeshGroup></MeshLabProject>", "comment inside <MeshGroup>");

    auto replaced = [&](const std::string& from, const std::string& to) {
        std::string cam = kCamera;
        cam.replace(cam.find(from), from.size(), to);
        return withRaster(cam + plane);
    };
    expectRefused(replaced("FocalMm=\"0.5\" ", ""), "missing attribute FocalMm");
    expectRefused(replaced("FocalMm=\"0.5\"", "FocalMm=\"abc\""), "not a finite float");
    expectRefused(replaced("FocalMm=\"0.5\"", "FocalMm=\"1e50\""), "not a finite float");  // overflows float32
    expectRefused(replaced("FocalMm=\"0.5\"", "FocalMm=\"-1\""), "FocalMm must be positive");
    expectRefused(replaced("CenterPx=\"32 24\"", "CenterPx=\"32\""), "needs 2 numbers");
    expectRefused(replaced("ViewportPx=\"64 48\"", "ViewportPx=\"64.5 48\""), "not an integer");
    expectRefused(replaced("RotationMatrix=\"1 0 0 0", "RotationMatrix=\"2 0 0 0"), "not a proper orthonormal");
    expectRefused(replaced("0 0 0 1 \"", "0 0 0 2 \""), "0 0 0 1");

    // Lens distortion and orthographic cameras are read, but not converted to a pinhole camera.
    const rad::MeshLabProject distorted =
        rad::parseMeshLabProject(replaced("LensDistortion=\"0 0\"", "LensDistortion=\"0.1 0\""), "", "d.mlp");
    EXPECT_THROW(rad::fromVcgCamera(distorted.rasters[0].camera), rad::MeshLabProjectError);
    const rad::MeshLabProject ortho =
        rad::parseMeshLabProject(replaced("CameraType=\"0\"", "CameraType=\"1\""), "", "o.mlp");
    EXPECT_THROW(rad::fromVcgCamera(ortho.rasters[0].camera), rad::MeshLabProjectError);

    EXPECT_THROW(rad::readMeshLabProject(tmpDir() + "/does_not_exist.mlp"), rad::MeshLabProjectError);
}

}  // namespace
