// COLMAP sparse models (Schoenberger and Frahm 2016), binary (cameras.bin, images.bin) or text
// (cameras.txt, images.txt), as COLMAP's documentation "Output format" describes them:
//  - an image's pose is world-to-camera, x_cam = R(q) X + t, with the unit quaternion stored
//    (qw, qx, qy, qz) and OpenCV's camera axes (x right, y down, z forward);
//  - pixel coordinates start at the image's top-left corner, the first pixel's centre at (0.5, 0.5):
//    our convention, so the principal point is taken as written.
// Camera models read exactly (COLMAP's src/colmap/sensor/models.h): SIMPLE_PINHOLE, PINHOLE,
// SIMPLE_RADIAL, RADIAL, OPENCV, OPENCV_FISHEYE, FULL_OPENCV, FOV, SIMPLE_RADIAL_FISHEYE,
// RADIAL_FISHEYE, THIN_PRISM_FISHEYE, SIMPLE_FISHEYE, FISHEYE. Others (RAD_TAN_THIN_PRISM_FISHEYE,
// the division models, EUCM, EQUIRECTANGULAR, ids a newer COLMAP may add) are refused by name.
#pragma once

#include "cameras/imported_camera.h"

#include <string>
#include <vector>

namespace rad {

// `folder` holds cameras.bin + images.bin or cameras.txt + images.txt (binary preferred when both).
// Throws CameraFileError naming the file, the camera or image, and what to do.
CameraImport readColmapModel(const std::string& folder);

// The lens of COLMAP camera model `modelName` with its parameters in COLMAP's order; throws
// CameraFileError naming the model when it is not supported or has the wrong parameter count.
LensModel colmapLens(const std::string& modelName, const std::vector<double>& params);
// COLMAP's numeric model id -> its name ("" for an id COLMAP does not define as of 4.x).
std::string colmapModelName(int modelId);

}  // namespace rad
