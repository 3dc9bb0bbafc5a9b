// HDR environment maps in the equirectangular (latitude-longitude) parameterisation: distant
// lighting for the synthetic photographs of the virtual acquisition now, and for PRT relighting
// (projection on spherical harmonics) later.
//
// Files: OpenEXR (.exr, every compression OpenEXR 3 reads, DWAA/DWAB included; scanline or tiled;
// channels R, G, B as 32-bit floats, or luminance/chroma through Imf::RgbaInputFile; alpha ignored)
// and Radiance RGBE (.hdr, through stb_image). The format is recognised by the file's magic
// number, not by its extension. Values are linear radiance in the file's own units (Blender's maps
// are scene-linear Rec. 709).
//
// Direction convention (the one of Blender's "Environment Texture" node with its default
// equirectangular projection, so the Blender maps of data-cache/hdr light our scenes as they light
// Blender's; cf. Cycles' direction_to_equirectangular):
//   +Z is up. A texel (column c, row r counted from the TOP) covers the normalised image coordinates
//   s in [c/W, (c+1)/W], t in [r/H, (r+1)/H], with
//       theta = pi * t                  (polar angle from +Z: row 0 touches +Z, the last row -Z)
//       phi   = pi - 2 pi s             (longitude from +X toward +Y)
//       w     = (sin theta cos phi, sin theta sin phi, cos theta).
//   Hence the image centre (s = 1/2, t = 1/2) looks along +X, s = 1/4 along +Y, the left and right
//   borders along -X, and going right in the image turns clockwise seen from above (a panorama is
//   seen from inside the sphere).
//   Texel (c, r) covers the solid angle (2 pi / W) (cos(pi r / H) - cos(pi (r + 1) / H)) exactly
//   (the sin theta weighting of the latitude-longitude parameterisation); the H W texels tile the
//   sphere, total 4 pi.
//
// Rotation: the map carries a rotation R (world from map, default identity). Every world-frame
// query (radiance, texelDirection, the SH projection, median_cut_lights.h) sees the map ROTATED BY
// R: what the file shows in map direction d is seen in world direction R d, i.e.
//   L_world(w) = L_map(R^T w),
// the convention of radiance/sh_rotation.h, so that
//   projectOntoSphericalHarmonics(map with R) = ShRotation(degree, R) applied to the projection of
//   the map with the identity.
// rotationAboutZ(a) turns the map by a about the up axis (Blender: the Z rotation of a Mapping node
// in front of the Environment Texture).
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
// layout of radiance/radiance_field.h.
// The map is taken as constant over each texel (the box reconstruction whose integral is the sum
// of texel * solid angle) and each texel's integral of Y_lm is computed exactly up to rounding:
// the longitude factor cos(m phi) / sin(m phi) analytically, the latitude factor
// P_l^m(cos theta) sin theta (a trigonometric polynomial of degree <= degree + 1 in theta) by 8-point
// Gauss-Legendre in theta over pieces of the texel row short enough for that to be exact to
// rounding. So a constant map C gives C sqrt(4 pi) in Y_00 and zero elsewhere to rounding. The
// map-frame coefficients are then rotated by ShRotation(R) (exact: rotations map each band onto
// itself). Cost: O(W H (degree + 1)), about 5 ms for a 1024 x 512 map at degree 10.
// Note: radiance() interpolates bilinearly, the projection integrates the box reconstruction;
// the two differ by O(texel size^2) on smooth maps.
std::vector<double> projectOntoSphericalHarmonics(const EnvironmentMap& map, int degree);

}  // namespace rad
