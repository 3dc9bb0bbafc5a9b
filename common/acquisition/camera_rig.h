// A ring of virtual cameras around an object, as a photographer walking around it would take: N
// viewpoints on a Fibonacci (golden-angle) spiral within an elevation band, jittered deterministically
// (std::mt19937_64: the same rig on every platform), every camera looking at the centre, from the
// distance at which the object's bounding sphere (radius r) fills a chosen fraction of the frame:
//   d = r sqrt(1 + 1 / t^2),  t = fillFraction * min(W, H) / (2 f).
// Details: docs/fitting.md, "`common/acquisition/camera_rig.h`: how it works".
#pragma once

#include "camera/pinhole_camera.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace rad {

struct CameraRigOptions {
    int count = 50;
    int width = 1024, height = 768;
    double horizontalFovDegrees = 40.0;   // in (0, 180)
    double fillFraction = 0.9;            // bounding-sphere diameter / smaller image side, in (0, 1]
    double minElevationDegrees = -90.0;   // elevation band, -90 <= min < max <= 90
    double maxElevationDegrees = 90.0;
    Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  // world up (need not be unit)
    double jitter = 0.25;                 // fraction of the spiral spacing, in [0, 1]
    std::uint64_t seed = 1;
};

// Throws std::invalid_argument (with the offending value) when an option is out of range, the
// radius is not positive or a value is not finite.
std::vector<PinholeCamera> makeCameraRig(const Eigen::Vector3d& centre, double radius, const CameraRigOptions& options);

// The distance d of the file comment for a camera of the given intrinsics.
double framingDistance(double radius, double focalPixels, int width, int height, double fillFraction);

}  // namespace rad
