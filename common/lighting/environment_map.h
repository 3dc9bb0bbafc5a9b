// HDR environment maps in the equirectangular (latitude-longitude) parameterisation: distant lighting
// for the virtual acquisition, PRT relighting and the irradiance vector grid. Reads OpenEXR and
// Radiance RGBE (.hdr), recognised by content; values are linear radiance. Directions follow
// Blender's "Environment Texture" node, +Z up: texel column c, row r from the TOP covers
// s in [c/W, (c+1)/W], t in [r/H, (r+1)/H], with theta = pi t (polar angle from +Z) and
// phi = pi - 2 pi s, so the image centre looks along +X. The map carries a rotation R (world from
// map): L_world(w) = L_map(R^T w), the convention of radiance/sh_rotation.h.
// Details: docs/irradiance-vector-grid.md, "`common/lighting/environment_map.h`: how it works".
#pragma once

#include "errors/error_categories.h"

#include <Eigen/Core>

#include <stdexcept>
#include <string>
#include <vector>

namespace rad {

// Thrown for unreadable, empty, truncated or invalid environment maps; the message names the file
// (or says "environment map" for in-memory data) and the reason.
struct EnvironmentMapError : FileError {
    using FileError::FileError;
};

class EnvironmentMap {
public:
    EnvironmentMap() = default;
    // rgb: 3 * width * height linear values, rows top to bottom, R G B per texel.
    // Negative values are clamped to 0 (lossy compressions such as DWAB and resampling filters
    // leave small negative ringing near black; radiance cannot be negative) and counted, see
    // clampedNegativeCount(). Throws EnvironmentMapError when the size is empty or does not match,
    // a value is NaN or infinite, or the negative values sum to more than 1e-3 of the positive
    // ones (then the data is not radiance, and clamping would change it silently).
    EnvironmentMap(int width, int height, std::vector<float> rgb);

    int width() const { return width_; }
    int height() const { return height_; }
    bool empty() const { return width_ <= 0 || height_ <= 0; }
    // Number of negative input values that were set to 0.
    long long clampedNegativeCount() const { return clampedNegatives_; }

    // Texel (column, row) as stored (map frame; rows from the top).
    const float* texel(int column, int row) const {
        return rgb_.data() + (static_cast<std::size_t>(row) * width_ + column) * 3;
    }
    const std::vector<float>& pixels() const { return rgb_; }

    // World from map rotation. Throws std::invalid_argument unless R is a proper rotation
    // (orthonormal to 1e-6, determinant +1): a mirror would turn the map inside out.
    void setRotation(const Eigen::Matrix3d& worldFromMap);
    const Eigen::Matrix3d& rotation() const { return rotation_; }

    // Map-frame direction of normalised image coordinates (s, t), see the file comment.
    static Eigen::Vector3d mapDirection(double s, double t);
    // World direction of the centre of texel (column, row): R * mapDirection((c + .5)/W, (r + .5)/H).
    Eigen::Vector3d texelDirection(int column, int row) const;
    // Exact solid angle of every texel of that row (steradians).
    double texelSolidAngle(int row) const;

    // Radiance seen in world direction w (need not be unit): bilinear interpolation between the
    // four nearest texel centres, wrapping in longitude and clamped to the first/last row's centres
    // near the poles. A zero or non-finite w gives black.
    Eigen::Vector3d radiance(const Eigen::Vector3d& worldDirection) const;

    // Integral of the radiance over the sphere per channel, sum of texel * solid angle (W/m^2 when
    // the texels are in W/(m^2 sr)); rotation-invariant. It is also the summed irradiance of the
    // median-cut lights.
    Eigen::Vector3d sphereIntegral() const;

private:
    int width_ = 0, height_ = 0;
    std::vector<float> rgb_;
    Eigen::Matrix3d rotation_ = Eigen::Matrix3d::Identity();
    long long clampedNegatives_ = 0;
};

// Reads an OpenEXR or Radiance RGBE equirectangular map (rotation identity). Throws
// EnvironmentMapError naming the file when it is missing, empty, truncated, in another format,
// lacks colour channels, holds NaN or infinite values or more than ringing-sized negative ones.
EnvironmentMap readEnvironmentMap(const std::string& path);

// Rotation by `radians` about +Z (counter-clockwise seen from above): with setRotation, turns the
// map's content toward increasing longitude.
Eigen::Matrix3d rotationAboutZ(double radians);

// L2 projection of the world-frame radiance on the real spherical harmonics of
// radiance/spherical_harmonics.h (orthonormal, no Condon-Shortley phase, index l*l + l + m) up to
// `degree` (0..kMaxHarmonicDegree, std::out_of_range otherwise):
//     c_lm = integral over the sphere of L_world(w) Y_lm(w) dw.
// Returns kColorChannels * (degree+1)^2 doubles, channel-major (c[ch * K + k]) like the vertex
// layout of radiance/radiance_field.h. Exact to rounding for the map taken as constant over each
// texel (a constant map C gives C sqrt(4 pi) in Y_00 and zero elsewhere), which differs from
// radiance()'s bilinear interpolation by O(texel size^2); about 5 ms for 1024 x 512 at degree 10.
// How: docs/irradiance-vector-grid.md, "`common/lighting/environment_map.h`: how it works".
std::vector<double> projectOntoSphericalHarmonics(const EnvironmentMap& map, int degree);

}  // namespace rad
