// MeshLab's camera (vcg::Shot) <-> our plain pinhole camera (common/camera/pinhole_camera.h). vcg's
// camera rows are image right, UP, BACKWARDS and its image y counts from the BOTTOM edge; ours are
// right, DOWN, FORWARD with v from the TOP, so rows 1-2 are negated and v = height - py, for every
// point in front of the camera (checked by tests/adapter against vcg::Shot::Project itself).
// Refused, with a sentence for the log: orthographic cameras, a non-zero radial distortion (vcg's k1
// model; undistort the photographs first), non-finite or degenerate values.
// Details: docs/camera-import.md, "`plugins_shared/shot_conversion.h`: how it works".
#pragma once

#include "camera/pinhole_camera.h"

#include <vcg/math/shot.h>

#include <cmath>
#include <string>

namespace radml {

// Empty string on success (out filled); otherwise why the shot cannot be used (out untouched).
template <typename S>
std::string pinholeFromShot(const vcg::Shot<S>& shot, rad::PinholeCamera& out) {
    const vcg::Camera<S>& intrinsics = shot.Intrinsics;
    if (intrinsics.cameraType != vcg::Camera<S>::PERSPECTIVE)
        return "the camera is not a perspective camera (orthographic and isometric cameras are not supported)";
    if (intrinsics.k[0] != S(0) || intrinsics.k[1] != S(0))
        return "the camera has radial lens distortion (k1 = " + std::to_string(double(intrinsics.k[0])) +
               "); undistort the photographs and set the distortion to 0";
    const double pixelX = intrinsics.PixelSizeMm[0], pixelY = intrinsics.PixelSizeMm[1];
    const double focal = intrinsics.FocalMm;
    if (!std::isfinite(pixelX) || !std::isfinite(pixelY) || !std::isfinite(focal) || !(pixelX > 0.0) ||
        !(pixelY > 0.0) || !(focal > 0.0))
        return "the camera's focal length or pixel size is not positive";
    if (intrinsics.ViewportPx[0] <= 0 || intrinsics.ViewportPx[1] <= 0)
        return "the camera's viewport (image size) is empty";

    vcg::Matrix44<S> rot = shot.Extrinsics.Rot();
    const vcg::Point3<S> centre = shot.Extrinsics.Tra();
    rad::PinholeCamera camera;
    for (int c = 0; c < 3; ++c) {
        camera.rotation(0, c) = rot[0][c];
        camera.rotation(1, c) = -double(rot[1][c]);
        camera.rotation(2, c) = -double(rot[2][c]);
        camera.center[c] = centre[c];
    }
    camera.fx = focal / pixelX;
    camera.fy = focal / pixelY;
    camera.width = intrinsics.ViewportPx[0];
    camera.height = intrinsics.ViewportPx[1];
    camera.cx = intrinsics.CenterPx[0];
    camera.cy = camera.height - double(intrinsics.CenterPx[1]);
    const std::string problem = camera.validate();
    if (!problem.empty()) return problem;
    out = camera;
    return {};
}

// The inverse: the vcg::Shot that projects like `camera` (the conventions above, read backwards).
// Only FocalMm / PixelSizeMm matters to vcg: PixelSizeMm.x is 0.01 mm, as MeshLab's importers
// write it, and PixelSizeMm.y carries fx / fy.
template <typename S>
vcg::Shot<S> shotFromPinhole(const rad::PinholeCamera& camera) {
    vcg::Shot<S> shot;
    shot.Intrinsics.cameraType = vcg::Camera<S>::PERSPECTIVE;
    const double pixelX = 0.01;
    shot.Intrinsics.FocalMm = S(camera.fx * pixelX);
    shot.Intrinsics.PixelSizeMm = vcg::Point2<S>(S(pixelX), S(pixelX * camera.fx / camera.fy));
    shot.Intrinsics.ViewportPx = vcg::Point2i(camera.width, camera.height);
    shot.Intrinsics.CenterPx = vcg::Point2<S>(S(camera.cx), S(camera.height - camera.cy));
    shot.Intrinsics.DistorCenterPx = shot.Intrinsics.CenterPx;
    shot.Intrinsics.k[0] = shot.Intrinsics.k[1] = S(0);
    vcg::Matrix44<S> rot;
    rot.SetIdentity();
    for (int c = 0; c < 3; ++c) {
        rot[0][c] = S(camera.rotation(0, c));
        rot[1][c] = S(-camera.rotation(1, c));
        rot[2][c] = S(-camera.rotation(2, c));
    }
    shot.Extrinsics.SetRot(rot);
    shot.Extrinsics.SetTra(vcg::Point3<S>(S(camera.center.x()), S(camera.center.y()), S(camera.center.z())));
    return shot;
}

}  // namespace radml
