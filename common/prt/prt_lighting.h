// Distant lightings as spherical-harmonic coefficient vectors for PRT relighting, and the relit
// colour L = <t, l> (transfer_vectors.h).
//
// Layout: 3 * K doubles, channel-major (l[ch * K + k]), K = (degree + 1)^2, like
// lighting/environment_map.h's projectOntoSphericalHarmonics.
//
// Directional light: the SH projection of a delta of irradiance E in direction d is E Y_k(d); cut at a
// low degree it rings (negative lobes, so L < 0 appears in shadows). We multiply band l by the
// Hanning window h_l = (1 + cos(pi l / (degree + 1))) / 2 (P.-P. Sloan, "Stupid Spherical Harmonics
// Tricks", GDC 2008, sec. "windowing"), the "approximation of a point light source" of paper 001
// sec. 4 that is smooth and nearly non-negative. h_0 = 1, so the total power is kept.
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
// `upAxis` (0 = X, 1 = Y, 2 = Z; Z gives the identity): X -> Y -> Z cyclic permutations, proper
// rotations. Throws std::invalid_argument for another axis.
Eigen::Matrix3d zenithToAxis(int upAxis);

// Rotates SH lighting coefficients (3 * (degree + 1)^2, channel-major) in place by R (sh_rotation.h).
void rotateLighting(std::vector<double>& lighting, int degree, const Eigen::Matrix3d& R);

// Exit radiance per vertex and channel: out[3 v + ch] = <t_v(channel), l(ch)>, where a 1-channel
// transfer field is shared by the three channels. degree of `lighting` must be >= the field's
// (extra coefficients of the lighting are ignored). Throws std::invalid_argument on mismatch.
std::vector<float> relightVertices(const float* transfer, std::size_t vertexCount, int transferDegree,
                                   int channels, const std::vector<double>& lighting, int lightingDegree);

}  // namespace rad
