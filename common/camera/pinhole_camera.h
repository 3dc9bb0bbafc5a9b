// A plain pinhole camera, the common currency between MeshLab's vcg::Shotf (converted in the
// plugin adapter, plugins_shared/shot_conversion.h), the virtual acquisition that renders
// photographs, the fitting that samples them and the CPU renderers.
//
// Conventions (stated once, used everywhere):
//  - camera space: x right, y DOWN, z FORWARD (the camera looks along +z; OpenCV's convention);
//    `rotation` maps world to camera: x_cam = rotation * (X - center). Its rows are the camera's
//    right, down and forward axes in world coordinates.
//  - image coordinates (u, v) are continuous, in pixels, with the origin at the TOP-LEFT corner of
//    the image: pixel (column c, row r counted from the top) covers [c, c+1) x [r, r+1) and its
//    centre is (c + 0.5, r + 0.5).
//  - projection: u = fx * x / z + cx, v = fy * y / z + cy (no lens distortion: images must be
//    undistorted; the adapter refuses MeshLab cameras with a non-zero radial coefficient).
#pragma once
#include <Eigen/Core>
#include <string>

namespace rad {

struct PinholeCamera {
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // world -> camera, rows = right, down, forward
    Eigen::Vector3d center = Eigen::Vector3d::Zero();        // optical centre in world coordinates
    double fx = 1.0, fy = 1.0;                               // focal lengths in pixels
    double cx = 0.5, cy = 0.5;                               // principal point, image coordinates
    int width = 1, height = 1;                               // image size in pixels

    // Camera-space coordinates of world point X (z = depth along the viewing axis).
    Eigen::Vector3d toCamera(const Eigen::Vector3d& X) const { return rotation * (X - center); }
    // Image coordinates of world point X; false (uv untouched) when X is not strictly in front of
    // the camera (z <= 0). uv may lie outside the image: see isInside.
    bool project(const Eigen::Vector3d& X, double& u, double& v) const;
    // Whether (u, v) lies inside the image shrunk by `margin` pixels on every side.
    bool isInside(double u, double v, double margin = 0.0) const {
        return u >= margin && v >= margin && u <= width - margin && v <= height - margin;
    }
    // Unit world direction of the ray through image point (u, v).
    Eigen::Vector3d rayDirection(double u, double v) const;
    // Forward axis (viewing direction) in world coordinates.
    Eigen::Vector3d forward() const { return rotation.row(2).transpose(); }

    // A camera at `eye` looking at `target`, with `up` giving the image's upward direction,
    // a horizontal field of view in degrees, and the principal point at the image centre.
    static PinholeCamera lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, const Eigen::Vector3d& up,
                                double horizontalFovDegrees, int width, int height);

    // Empty when the camera is usable (finite values, orthonormal right-handed rotation to 1e-4,
    // positive focal lengths and image size); otherwise a sentence saying what is wrong.
    std::string validate() const;
};

}  // namespace rad
