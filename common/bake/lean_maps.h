// LEAN covariance maps relative to the averaged normal (Weber and Stamminger, Weber & Stamminger, sec. 3.3,
// Alg. 2; storage without level 0, sec. 3.5) and the specular lobes they are rendered with
// (Alg. 3-4), on the CPU: for the bake, the tests and the reference images.
//
// Per MIP level k >= 1 and texel, over its footprint of 2^k x 2^k level-0 texels:
//   N = normalize(sum of object-space normals), T = the summed tangents made orthogonal to N,
//   frame (T, N x T, N); each footprint normal n goes into that frame, n_tbn = n_frame / z, and
//   mu2 = mean of (x^2, y^2, x y). Level 0's covariance is 0 (a single normal), hence not stored.
// Normals of footprint texels with z <= 0 in the frame (more than 90 degrees from the mean)
// are clamped to a slope of 100 (documented decision: they would divide by ~0).
#pragma once
#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

namespace rad {

struct MipImage {
    int width = 0, height = 0, channels = 3;
    std::vector<float> data;  // row-major, rows top to bottom
};

struct LeanMaps {
    std::vector<MipImage> normals;   // levels 0..K: unit averaged object-space normals (level 0 = input)
    std::vector<MipImage> moments;   // levels 1..K (moments[0] is MIP level 1): (mu2.x, mu2.y, mu2.z) = (xx, yy, xy)
};

// Levels 0..K of the averaged, renormalised normal map (the `normals` member of LeanMaps), for a
// renderer that has only the normal map: level k texel = normalize(sum of its 2^k x 2^k
// footprint). width, height powers of two.
std::vector<MipImage> buildNormalPyramid(const float* normals, int width, int height);

// normals, tangents: 3 floats per texel, object space, every texel filled (map_filling.h);
// width and height powers of two. Levels down to 1 x 1. Parallel.
LeanMaps buildLeanMaps(const float* normals, const float* tangents, int width, int height);

// Alg. 3: specular of the 2D Gaussian in the frame (T, B, N) with B = N x T:
// H_tbn = (H.T, H.B, H.N) / (H.N); Sigma = [[mu2.x + 1/s, mu2.z], [mu2.z, mu2.y + 1/s]];
// spec = exp(-0.5 h^T Sigma^-1 h) / (s sqrt(det Sigma)). H unit half vector; 0 when H.N <= 0.
double leanSpecular(const Eigen::Vector3d& normal, const Eigen::Vector3d& tangent, const Eigen::Vector3d& mu2,
                    const Eigen::Vector3d& halfVector, double shininess);
// Alg. 4: the covariance at fractional MIP level lambda from the stored levels (moments of level
// 1 scaled by lambda when 0 <= lambda < 1; level lambda - 1 of the stored pyramid, trilinear,
// above). Bilinear within a level at texture coordinates (u, v) (texture_atlas.h convention).
Eigen::Vector3d sampleLeanMoments(const LeanMaps& maps, double u, double v, double lambda);
// Blinn-Phong specular with the same normalisation, for comparison: (H.N)^s.
double blinnPhongSpecular(const Eigen::Vector3d& normal, const Eigen::Vector3d& halfVector, double shininess);

// The documented file set (docs/normal-map-baking.md): <base>_lean.exr, a tiled, mip-mapped
// OpenEXR file (ROUND_DOWN, FLOAT R, G, B = mu2.x, mu2.y, mu2.z) whose level i holds MIP level
// i + 1 of the normal map. Throws std::runtime_error naming the file on failure.
void writeLeanMoments(const std::string& path, const LeanMaps& maps);
std::vector<MipImage> readLeanMoments(const std::string& path);

}  // namespace rad
