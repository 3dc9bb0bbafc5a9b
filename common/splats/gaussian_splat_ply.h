// Reading a 3D Gaussian Splatting scene (Kerbl et al. 2023) from the `.ply` file that the original
// implementation (`point_cloud.ply`) and SuperSplat write: one "vertex" per splat with its centre, SH
// colour (f_dc, f_rest channel-major), logit opacity, log scales and rotation quaternion, found by
// name in any order, any scalar type, ASCII or binary. The SH coefficients are kept exactly as the
// file has them (3DGS convention); splat_radiance_conventions.h converts them. Refused with
// SplatFileError (what is wrong, where, and what to do).
// Details: docs/gaussian-splats.md, "The file".
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
