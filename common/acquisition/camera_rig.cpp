#include "acquisition/camera_rig.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace rad {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Uniform double in [-1, 1) from the raw 64-bit output: the std distributions are not specified
// bit-exactly across standard libraries, mt19937_64's sequence is.
double uniformSigned(std::mt19937_64& rng) { return 2.0 * (static_cast<double>(rng() >> 11) * 0x1.0p-53) - 1.0; }

[[noreturn]] void refuse(const std::string& what) { throw std::invalid_argument("camera rig: " + what); }

}  // namespace

double framingDistance(double radius, double focalPixels, int width, int height, double fillFraction) {
    const double t = fillFraction * std::min(width, height) / (2.0 * focalPixels);
    return radius * std::sqrt(1.0 + 1.0 / (t * t));
}

std::vector<PinholeCamera> makeCameraRig(const Eigen::Vector3d& centre, double radius, const CameraRigOptions& o) {
    if (!centre.allFinite()) refuse("the centre is not finite");
    if (!(radius > 0.0) || !std::isfinite(radius)) refuse("the bounding radius must be positive");
    if (o.count < 1) refuse("the number of cameras must be at least 1");
    if (o.width < 1 || o.height < 1) refuse("the image size must be positive");
    if (!(o.horizontalFovDegrees > 0.0 && o.horizontalFovDegrees < 180.0)) refuse("the field of view must lie in (0, 180) degrees");
    if (!(o.fillFraction > 0.0 && o.fillFraction <= 1.0)) refuse("the fill fraction must lie in (0, 1]");
    if (!(o.minElevationDegrees >= -90.0 && o.maxElevationDegrees <= 90.0 && o.minElevationDegrees < o.maxElevationDegrees))
        refuse("the elevation band must satisfy -90 <= min < max <= 90 degrees");
    if (!(o.jitter >= 0.0 && o.jitter <= 1.0)) refuse("the jitter must lie in [0, 1]");
    if (!o.up.allFinite() || o.up.norm() == 0.0) refuse("the up vector must be non-zero and finite");

    const Eigen::Vector3d up = o.up.normalized();
    // Two horizontal axes completing `up` to a right-handed frame.
    const Eigen::Vector3d helper = std::fabs(up.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    const Eigen::Vector3d east = (helper - helper.dot(up) * up).normalized();
    const Eigen::Vector3d north = up.cross(east);

    const double sMin = std::sin(o.minElevationDegrees * kPi / 180.0);
    const double sMax = std::sin(o.maxElevationDegrees * kPi / 180.0);
    const double golden = kPi * (3.0 - std::sqrt(5.0));
    // Band area 2 pi (sMax - sMin) on the unit sphere; spacing ~ sqrt(area / N), capped at 0.5
    // (~29 degrees) so that a rig of very few cameras is jittered, not randomised.
    const double spacing = std::min(0.5, std::sqrt(2.0 * kPi * (sMax - sMin) / o.count));

    const PinholeCamera model = PinholeCamera::lookAt(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(),
                                                      Eigen::Vector3d::UnitY(), o.horizontalFovDegrees, o.width, o.height);
    const double distance = framingDistance(radius, model.fx, o.width, o.height, o.fillFraction);

    std::mt19937_64 rng(o.seed);
    std::vector<PinholeCamera> cameras;
    cameras.reserve(o.count);
    for (int i = 0; i < o.count; ++i) {
        const double s = sMin + (sMax - sMin) * (i + 0.5) / o.count;
        const double azimuth = i * golden;
        const double c = std::sqrt(std::max(0.0, 1.0 - s * s));
        Eigen::Vector3d d = c * (std::cos(azimuth) * east + std::sin(azimuth) * north) + s * up;
        // Jitter in the tangent plane of the sphere at d, then back onto the sphere and the band.
        const double ja = uniformSigned(rng), jb = uniformSigned(rng);
        if (o.jitter > 0.0) {
            const Eigen::Vector3d h = std::fabs(d.dot(up)) < 0.99 ? up : east;
            const Eigen::Vector3d t1 = d.cross(h).normalized(), t2 = d.cross(t1);
            d = (d + o.jitter * spacing * (ja * t1 + jb * t2)).normalized();
            const double sd = std::clamp(d.dot(up), sMin, sMax);
            const Eigen::Vector3d horizontal = d - d.dot(up) * up;
            const double hn = horizontal.norm();
            if (hn > 1e-12) d = std::sqrt(std::max(0.0, 1.0 - sd * sd)) * horizontal / hn + sd * up;
        }
        cameras.push_back(PinholeCamera::lookAt(centre + distance * d, centre, up, o.horizontalFovDegrees, o.width, o.height));
    }
    return cameras;
}

}  // namespace rad
