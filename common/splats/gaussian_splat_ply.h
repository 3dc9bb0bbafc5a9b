// Reading a 3D Gaussian Splatting scene (Kerbl et al. 2023) from the `.ply` file that the original
// implementation (`point_cloud.ply`) and SuperSplat write: one element "vertex" per splat with the
// float properties
//   x y z                      centre
//   nx ny nz                   optional (the original writes zeros; ignored)
//   f_dc_0 f_dc_1 f_dc_2       SH band 0 of red, green, blue
//   f_rest_0 .. f_rest_{3K-4}  SH bands 1..d, channel-major (all of red's K-1 coefficients, then green's,
//                              then blue's), K = (d+1)^2: the original's features_rest (N, K-1, 3)
//                              transposed to (N, 3, K-1) and flattened
//   opacity                    logit of the opacity (sigmoid applied on use)
//   scale_0 scale_1 scale_2    log of the standard deviations along the splat's axes (exp on use)
//   rot_0 .. rot_3             rotation quaternion w, x, y, z, not normalised
// Properties are found by name in any order; any scalar PLY type is read (as double, kept as float),
// other properties and elements are ignored. Formats: ascii 1.0, binary_little_endian 1.0,
// binary_big_endian 1.0.
//
// The SH coefficients are kept exactly as the file has them (the 3DGS convention: display-referred
// colour, Condon-Shortley phase, evaluated at the direction from the camera to the splat);
// splat_radiance_conventions.h converts them.
//
// Refused with SplatFileError (what is wrong, where, and what to do): a missing or unreadable file, a
// PLY whose vertices lack the splat properties (not a splat file; PlayCanvas's compressed splat PLY
// is recognised and named), an f_rest count that is not 3 ((d+1)^2 - 1) for an SH degree d, a degree
// above 3, a NaN or infinite value, a zero rotation quaternion, a truncated file, an empty splat set.
#pragma once

#include "errors/error_categories.h"

#include "progress/progress_callback.h"

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace rad {

struct SplatFileError : FileError {
    using FileError::FileError;
};

inline constexpr int kMaxSplatShDegree = 3;  // what 3DGS trains and the splat formats carry

struct GaussianSplats {
    int shDegree = 0;                // d: (d+1)^2 coefficients per channel
    std::vector<float> positions;    // 3 per splat
    std::vector<float> sh;           // 3 * (d+1)^2 per splat: [channel][coefficient], index 0 = f_dc
    std::vector<float> opacityLogit; // 1 per splat, as stored
    std::vector<float> logScale;     // 3 per splat, as stored
    std::vector<float> rotation;     // 4 per splat, w x y z, as stored
    std::size_t count() const { return opacityLogit.size(); }
    int coefficientsPerChannel() const { return (shDegree + 1) * (shDegree + 1); }
};

// Reads and validates the whole file. Progress by splats read; OperationCancelled on a stop request.
GaussianSplats readGaussianSplatPly(const std::string& path, const ProgressCallback& progress = {});

}  // namespace rad
