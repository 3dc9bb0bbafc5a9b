// Metashape camera XML written here by hand: a world point projects where Metashape's frame camera
// model (user manual, appendix "Camera models"), written out in the test, puts it, through the
// chunk transform (rotation, translation, scale) and the camera-to-chunk transform; several
// sensors; disabled and unaligned cameras skipped and counted; refusals.
#include "cameras/camera_file.h"
#include "test_temporary_directory.h"
#include "cameras/metashape_xml_reader.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace {

std::string writeFile(const std::string& name, const std::string& text) {
    const std::string path = std::string(RADIANCE_TEST_TMPDIR) + "/" + name;
    std::ofstream(path) << text;
    return path;
}

const char* kSensors = R"(
    <sensors next_id="2">
      <sensor id="0" label="body A" type="frame">
        <resolution width="640" height="480"/>
        <calibration type="frame" class="initial"><resolution width="640" height="480"/><f>900</f></calibration>
        <calibration type="frame" class="adjusted">
          <resolution width="640" height="480"/>
          <f>1000</f><cx>12.5</cx><cy>-7.25</cy><b1>3</b1><b2>-1.5</b2>
          <k1>-0.05</k1><k2>0.01</k2><p1>0.0004</p1><p2>-0.0003</p2>
        </calibration>
      </sensor>
      <sensor id="1" label="body B" type="frame">
        <resolution width="320" height="240"/>
        <calibration type="frame" class="adjusted"><resolution width="320" height="240"/><f>400</f></calibration>
      </sensor>
    </sensors>)";

// Camera-to-chunk: rotation diag(1, -1, -1) (the camera looks along the chunk's -z), centre (0, 0, 5).
// Chunk to world: 90 degrees about z, translation (10, 20, 30), scale 2.
std::string document(const std::string& chunkRotation, const std::string& focal = "1000") {
    std::string sensors = kSensors;
    sensors.replace(sensors.find("<f>1000</f>"), 11, "<f>" + focal + "</f>");
    return std::string(R"(<?xml version="1.0" encoding="UTF-8"?>
<document version="1.5.0">
  <chunk label="Chunk 1" enabled="true">)") + sensors + R"(
    <cameras next_id="4" next_group_id="1">
      <group id="0" label="folder" type="folder">
        <camera id="0" sensor_id="0" label="IMG_0001">
          <transform>1 0 0 0 0 -1 0 0 0 0 -1 5 0 0 0 1</transform>
        </camera>
      </group>
      <camera id="1" sensor_id="1" label="IMG_0002"><transform>1 0 0 1 0 1 0 0 0 0 1 -5 0 0 0 1</transform></camera>
      <camera id="2" sensor_id="0" label="IMG_0003" enabled="false"><transform>1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1</transform></camera>
      <camera id="3" sensor_id="0" label="IMG_0004"/>
    </cameras>
    <transform>
      <rotation locked="false">)" + chunkRotation + R"(</rotation>
      <translation locked="false">10 20 30</translation>
      <scale locked="false">2</scale>
    </transform>
  </chunk>
</document>
)";
}
const char* kRotationZ90 = "0 -1 0 1 0 0 0 0 1";

TEST(MetashapeXmlReader, ProjectsThroughChunkAndCameraTransformsWithMetashapesLensModel) {
    const rad::CameraImport model = rad::readCameraFile(writeFile("metashape.xml", document(kRotationZ90)));
    EXPECT_EQ(model.format, "Metashape camera XML");
    ASSERT_EQ(model.cameras.size(), 2u);
    ASSERT_EQ(model.skipped.size(), 2u);  // one disabled, one not aligned
    EXPECT_NE(model.skipped[0].find("IMG_0003' is disabled"), std::string::npos);
    EXPECT_NE(model.skipped[1].find("IMG_0004' is not aligned"), std::string::npos);
    const rad::ImportedCamera& c = model.cameras[0];
    EXPECT_EQ(c.imageName, "IMG_0001");
    EXPECT_EQ(c.width, 640);
    // The chunk point (0.3, -0.2, 0.5) is, in world coordinates, 2 Rz90 (0.3, -0.2, 0.5) + (10, 20, 30)
    // = (10.4, 20.6, 31), and in the camera's frame diag(1, -1, -1) ((0.3, -0.2, 0.5) - (0, 0, 5)) =
    // (0.3, 0.2, 4.5).
    const double x = 0.3 / 4.5, y = 0.2 / 4.5, r2 = x * x + y * y;
    const double radial = 1 - 0.05 * r2 + 0.01 * r2 * r2;
    const double P1 = 0.0004, P2 = -0.0003;
    const double xd = x * radial + P1 * (r2 + 2 * x * x) + 2 * P2 * x * y;
    const double yd = y * radial + P2 * (r2 + 2 * y * y) + 2 * P1 * x * y;
    const double u = 640 * 0.5 + 12.5 + xd * (1000 + 3) + yd * -1.5;
    const double v = 480 * 0.5 - 7.25 + yd * 1000;
    double pu = 0, pv = 0;
    ASSERT_TRUE(c.project({10.4, 20.6, 31.0}, pu, pv));
    EXPECT_NEAR(pu, u, 1e-9);
    EXPECT_NEAR(pv, v, 1e-9);
    // The centre: 2 Rz90 (0, 0, 5) + (10, 20, 30).
    EXPECT_NEAR((c.center - Eigen::Vector3d(10, 20, 40)).norm(), 0.0, 1e-12);
    // The second sensor (no distortion, principal point at the centre of 320 x 240).
    const rad::ImportedCamera& d = model.cameras[1];
    EXPECT_EQ(d.width, 320);
    EXPECT_FALSE(d.lens.distorts());
    EXPECT_DOUBLE_EQ(d.lens.cx, 160.0);
}

// Components (Metashape 1.6 and later): a camera's transform is relative to its component, whose
// own similarity leads into the chunk. One component without a partition applies to every camera;
// with partitions, each camera takes its own component's.
std::string withComponents(const std::string& components) {
    std::string text = document(kRotationZ90);
    text.insert(text.find("    <transform>\n      <rotation"), components);
    return text;
}

TEST(MetashapeXmlReader, ComponentTransformsLeadFromTheCamerasIntoTheChunk) {
    // Component: scale 3, translation (1, 0, 0), no rotation. IMG_0001's centre (0, 0, 5) in the
    // component is (1, 0, 15) in the chunk, and 2 Rz90 (1, 0, 15) + (10, 20, 30) = (10, 22, 60) in the world.
    const rad::CameraImport single = rad::readCameraFile(writeFile("component.xml", withComponents(R"(
    <components next_id="1" active_id="0">
      <component id="0" label="Component 1">
        <transform><rotation>1 0 0 0 1 0 0 0 1</rotation><translation>1 0 0</translation><scale>3</scale></transform>
      </component>
    </components>
)")));
    ASSERT_EQ(single.cameras.size(), 2u);
    EXPECT_NEAR((single.cameras[0].center - Eigen::Vector3d(10, 22, 60)).norm(), 0.0, 1e-12);
    // The camera's viewing direction (component -z, rotation diag(1, -1, -1)) turned by Rz90: world -z.
    EXPECT_NEAR((single.cameras[0].rotation.row(2).transpose() - Eigen::Vector3d(0, 0, -1)).norm(), 0.0, 1e-12);

    // Two components with partitions: camera 0 in the first (as above), camera 1 in the second, turned
    // 90 degrees about x. IMG_0002's centre (1, 0, -5) becomes Rx90 (1, 0, -5) = (1, 5, 0) in the chunk,
    // then 2 Rz90 (1, 5, 0) + (10, 20, 30) = (0, 22, 30).
    const rad::CameraImport parts = rad::readCameraFile(writeFile("components.xml", withComponents(R"(
    <components next_id="2" active_id="0">
      <component id="0" label="Component 1">
        <transform><rotation>1 0 0 0 1 0 0 0 1</rotation><translation>1 0 0</translation><scale>3</scale></transform>
        <partition><camera_ids>0 2 3</camera_ids></partition>
      </component>
      <component id="1" label="Component 2">
        <transform><rotation>1 0 0 0 0 -1 0 1 0</rotation><translation>0 0 0</translation><scale>1</scale></transform>
        <partition><camera_ids>1</camera_ids></partition>
      </component>
    </components>
)")));
    ASSERT_EQ(parts.cameras.size(), 2u);
    EXPECT_NEAR((parts.cameras[0].center - Eigen::Vector3d(10, 22, 60)).norm(), 0.0, 1e-12);
    EXPECT_NEAR((parts.cameras[1].center - Eigen::Vector3d(0, 22, 30)).norm(), 0.0, 1e-12);
}

std::string refusal(const std::string& path) {
    return radtest::refusalMessage<rad::CameraFileError>([&] { rad::readCameraFile(path); });
}

TEST(MetashapeXmlReader, RefusesBadFiles) {
    EXPECT_NE(refusal(writeFile("scaled.xml", document("2 0 0 0 1 0 0 0 1"))).find("not a rotation"), std::string::npos);
    EXPECT_NE(refusal(writeFile("nan.xml", document(kRotationZ90, "nan"))).find("not a finite number"), std::string::npos);
    std::string spherical = document(kRotationZ90);
    spherical.replace(spherical.find("type=\"frame\">"), 13, "type=\"spherical\">");
    EXPECT_NE(refusal(writeFile("spherical.xml", spherical)).find("type 'spherical'"), std::string::npos);
    EXPECT_NE(refusal(writeFile("svg.xml", "<svg><rect/></svg>")).find("not a Metashape camera file"), std::string::npos);
    EXPECT_NE(refusal(writeFile("broken.xml", "<document><chunk></document>")).find("not well-formed"), std::string::npos);
}

}  // namespace
