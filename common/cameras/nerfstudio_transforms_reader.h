// nerfstudio's transforms.json (the format most NeRF and Gaussian-splatting tools exchange), as
// nerfstudio's data conventions describe it:
//  - intrinsics fl_x, fl_y, cx, cy, w, h and distortion k1..k4, p1, p2 at the top level, or per
//    frame (a frame's own values win); or, as the original NeRF's files (Mildenhall et al. 2020)
//    and instant-ngp's give them, only the horizontal field of view camera_angle_x (radians; and
//    camera_angle_y), the principal point at the image centre, the size the photograph's own;
//    camera_model "OPENCV" (radial k1..k4 and tangential p1, p2 in OpenCV's order),
//    "OPENCV_FISHEYE" (equidistant, k1..k4), "PINHOLE" / "SIMPLE_PINHOLE";
//    pixel coordinates from the top-left corner, pixel centres at +0.5 (as COLMAP's, which
//    nerfstudio's COLMAP conversion copies);
//  - per frame: file_path (relative to the image folder; nerfstudio's is the file's folder) and a
//    4 x 4 camera-to-world transform_matrix with OpenGL's camera axes (x right, y UP, z BACKWARD):
//    the camera looks along -z. The world frame is the file's (including any transform nerfstudio
//    applied to COLMAP's poses): the mesh must be in the same frame.
#pragma once

#include "cameras/imported_camera.h"

#include <string>

namespace rad {

// Throws CameraFileError naming the file, the frame and what to do.
CameraImport readNerfstudioTransforms(const std::string& path);

}  // namespace rad
