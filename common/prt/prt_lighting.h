// Distant lightings as spherical-harmonic coefficient vectors for PRT relighting, and the relit
// colour L = <t, l> (transfer_vectors.h).
//
// Layout: 3 * K doubles, channel-major (l[ch * K + k]), K = (degree + 1)^2, like
// lighting/environment_map.h's projectOntoSphericalHarmonics.
//
// Directional light: the SH projection of a delta of irradiance E in direction d is E Y_k(d); cut at a
// low degree it rings (negative lobes, so L < 0 appears in shadows). We multiply band l by the
// Hanning window h_l = (1 + cos(pi l / (degree + 1))) / 2 (P.-P. Sloan, "Stupid Spherical Harmonics
// Tricks", GDC 2008, sec. "windowing"), the "approximation of a point light source" of Křivánek et
// al. 2004, sec. 4, that is smooth and nearly non-negative. h_0 = 1, so the total power is kept.
// PRT relighting itself: Sloan, Kautz, Snyder 2002.
#pragma once

#include "lighting/environment_map.h"

#include <Eigen/Core>

#include <vector>

namespace rad {

// Windowed SH of a directional light of colour `rgb` toward the (unit or not) direction `toLight`:
// l[ch * K + k] = rgb[ch] h_l Y_k(toLight / |toLight|). Throws std::invalid_argument for a zero or
// non-finite direction, std::out_of_range for a degree outside [0, kMaxHarmonicDegree].
std::vector<double> directionalLightSH(int degree, const Eigen::Vector3d& toLight, const Eigen::Vector3d& rgb);

// SH of an environment map rotated by rotationAboutZ(radians) (environment_map.h conventions),
// truncated to `degree` (no window: the map's own projection). The turn composes with the map's
// own rotation R: the result is the projection of the map with rotation rotationAboutZ(radians) * R
// (the map itself is not modified; with R = identity, the map turned by `radians` about +Z).
// Throws std::out_of_range for a degree outside [0, kMaxHarmonicDegree].
std::vector<double> environmentLightSH(const EnvironmentMap& map, int degree, double rotationRadians);

// The rotation taking the lighting frame's zenith (+Z, as in environment_map.h) to the world axis
// `upAxis` (0 = X, 1 = Y, 2 = Z, the order of UpAxis below; Z gives the identity): X -> Y -> Z cyclic permutations, proper
// rotations. Throws std::invalid_argument for another axis.
Eigen::Matrix3d zenithToAxis(int upAxis);

// Rotates SH lighting coefficients (3 * (degree + 1)^2, channel-major) in place by R (sh_rotation.h).
void rotateLighting(std::vector<double>& lighting, int degree, const Eigen::Matrix3d& R);

// ---- One lighting for every adapter (the relighting filter and the decoration's PRT mode) ----

// The world axis the lighting frame's zenith goes to. ONE order everywhere, index = axis:
// 0 = +X, 1 = +Y, 2 = +Z (the order of zenithToAxis). Adapters list kUpAxisNames in this order.
enum class UpAxis : int { X = 0, Y = 1, Z = 2 };
inline constexpr int kUpAxisCount = 3;
inline constexpr const char* const kUpAxisNames[kUpAxisCount] = {"+X", "+Y", "+Z"};

enum class PrtLightSource : int { EnvironmentMap = 0, Directional = 1 };

// What the user sets; prtLightingSH turns it into SH coefficients. Both sources get the same
// treatment:
//  - intensity scales the light: the map's radiance, or the directional light's irradiance at
//    normal incidence (colour intensity * (1, 1, 1));
//  - rotationDegrees turns the light about the world up axis, right-handed (counter-clockwise
//    looking down from +up): a light toward d ends up toward AngleAxis(rotation, up) d;
//  - upAxis is where the map's zenith (+Z of environment_map.h) goes, by zenithToAxis (for +Y the
//    map's (x, y, z) becomes the world's (y, z, x), for +X (z, x, y), for +Z unchanged), and the
//    axis of the rotation. The directional light's `direction` is given in the mesh's (world)
//    coordinates, so the up axis affects it only through the rotation.
struct PrtLightingSettings {
    PrtLightSource source = PrtLightSource::Directional;
    UpAxis upAxis = UpAxis::Z;
    double rotationDegrees = 0.0;                          // any finite value
    double intensity = 1.0;                                // finite, >= 0
    Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // toward the light (directional only); finite, non-zero
    // Hanning window width w of the directional light (Sloan 2008): band l is scaled by
    // (1 + cos(pi l / w)) / 2 for l < w and cut for l >= w. 0 means degree + 1 (directionalLightSH's
    // window, every band kept); otherwise finite and > 0. Not used by the map (its own projection).
    double windowWidth = 0.0;
    int degree = 5;  // SH degree of the result, in [0, kMaxHarmonicDegree] (set it to the transfer's)

    bool operator==(const PrtLightingSettings& o) const {
        return source == o.source && upAxis == o.upAxis && rotationDegrees == o.rotationDegrees &&
               intensity == o.intensity && direction == o.direction && windowWidth == o.windowWidth &&
               degree == o.degree;
    }
    bool operator!=(const PrtLightingSettings& o) const { return !(*this == o); }
};

// The SH lighting (3 * (degree + 1)^2, channel-major) of `settings`: for the map, its projection
// (environmentLightSH) turned about its zenith by the rotation, its zenith taken to the up axis
// (zenithToAxis), times the intensity; for the directional light, the Hanning-windowed SH of a
// light of colour intensity * (1, 1, 1) toward the rotated direction. `map` is needed (non-null)
// for the map source only and is not modified. All validation is here: throws std::invalid_argument,
// naming the parameter and its valid range, for a degree outside [0, kMaxHarmonicDegree], an
// up axis or source outside its enum, a non-finite rotation, a non-finite or negative intensity,
// a non-finite or zero direction (directional source), a negative or non-finite window width, or
// a missing map (map source).
std::vector<double> prtLightingSH(const PrtLightingSettings& settings, const EnvironmentMap* map = nullptr);

// Unit vector of the world up axis (throws std::invalid_argument outside the enum).
Eigen::Vector3d upAxisVector(UpAxis axis);

// Exit radiance per vertex and channel: out[3 v + ch] = <t_v(channel), l(ch)>, where a 1-channel
// transfer field is shared by the three channels. degree of `lighting` must be >= the field's
// (extra coefficients of the lighting are ignored). Throws std::invalid_argument on mismatch.
std::vector<float> relightVertices(const float* transfer, std::size_t vertexCount, int transferDegree,
                                   int channels, const std::vector<double>& lighting, int lightingDegree);

}  // namespace rad
