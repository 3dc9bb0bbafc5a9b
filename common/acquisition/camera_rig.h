// A ring of virtual cameras around an object, as a photographer walking around it would take:
// N viewpoints on a sphere around the object's bounding sphere, every camera looking at the
// centre, the object filling a chosen fraction of the frame.
//
// Directions: a Fibonacci (golden-angle) spiral, which spreads N points on a sphere with nearly
// equal areas per point (Gonzalez, "Measurement of areas on a sphere using Fibonacci and
// latitude-longitude lattices", Math. Geosciences 2010): point i has
//   sin(elevation_i) = s_min + (s_max - s_min) (i + 0.5) / N,   azimuth_i = i * golden angle,
// where the elevation is measured from the plane perpendicular to `up` and [s_min, s_max] are the
// sines of the elevation band (e.g. [0, 80] degrees: no view from below a ground plane). The
// spacing between neighbouring points is about sqrt(band area / N) (capped at 0.5, ~29 degrees, for
// rigs of very few cameras); each direction is then
// jittered deterministically by up to `jitter` times that spacing (uniform in a square of the
// tangent plane, from a std::mt19937_64 seeded with `seed`, whose output sequence the C++ standard
// fixes, so every platform makes the same rig), clamped back into the band.
//
// Distance: a sphere of radius r whose centre is on the optical axis at distance d images as a
// disc of radius f r / sqrt(d^2 - r^2) pixels; it is set to fillFraction * min(W, H) / 2, i.e.
//   d = r sqrt(1 + 1 / t^2),  t = fillFraction * min(W, H) / (2 f).
// Every camera is PinholeCamera::lookAt(eye, centre, up, fov, W, H): the centre projects to the
// principal point (W/2, H/2) and `up` points up in the image (when a camera looks along +-up,
// lookAt picks another up direction).
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
