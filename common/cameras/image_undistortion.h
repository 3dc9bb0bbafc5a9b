// Photographs with lens distortion -> exact pinhole images, so that every MeshLab filter (ours and
// MeshLab's own, which know only pinhole cameras) sees them as the calibration does.
//
// The map is exact and the image is resampled once: for each pixel of the pinhole image, the ideal
// ray through its centre is pushed through the lens's forward model (cameras/lens_model.h), which
// gives the point of the photograph to sample (Keys cubic convolution on linear-light values, which
// blurs less than bilinear interpolation). No inverse of the distortion is approximated. The pinhole image has the photograph's size and principal point;
// its focal lengths are the lens's times a zoom >= 1, the smallest (in 1 % steps) for which every
// pinhole pixel maps inside the photograph and the map is monotonic along every ray from the
// principal point: barrel and fisheye lenses lose a thin border instead of getting black corners
// that the fit would read as colour, or folded-over parts where a polynomial model stops being
// valid.
#pragma once

#include "camera/pinhole_camera.h"
#include "cameras/imported_camera.h"
#include "image/rgb_image.h"
#include "progress/progress_callback.h"

#include <Eigen/Core>

#include <string>

namespace rad {

struct UndistortionPlan {
    LensModel lens;          // the calibration's lens, scaled to the photograph's size
    PinholeCamera target;    // the pinhole image's camera (pose of the calibration, size of the photograph)
    double zoom = 1.0;       // target focal lengths / lens focal lengths
    bool resample = false;   // false: the photograph is already that pinhole image (no distortion, no skew)

    // The point of the photograph that pinhole pixel coordinates (u, v) show.
    Eigen::Vector2d sourcePixel(double u, double v) const;
};

// Empty when a photograph of width x height can carry the calibration of `camera` (its size, or
// the same aspect scaled: a resized copy, within a pixel on each axis); otherwise a sentence.
std::string imageSizeProblem(const ImportedCamera& camera, int width, int height);

// The plan for `camera`'s photograph of width x height (imageSizeProblem must be empty). Throws
// std::invalid_argument when no pinhole image up to 10x zoom shows the lens's image (a fisheye
// near or beyond 180 degrees): the message names the image.
UndistortionPlan planUndistortion(const ImportedCamera& camera, int width, int height);

// The pinhole image of `photograph` (the plan's size). Both cores (OpenMP). A stop request from
// `progress` throws OperationCancelled.
Image8 undistortImage(const ImageView8& photograph, const UndistortionPlan& plan, const ProgressCallback& progress = {});

// The cache's file name for the pinhole image of `imageName`: the name (folders flattened with
// "__", extension dropped) + a 64-bit hash of everything that decides the pixels: the plan (lens,
// target, zoom) and `sourceIdentity` (the caller's description of the photograph file: size and
// modification time), so that a changed calibration or photograph never reuses a stale image.
std::string undistortedFileName(const std::string& imageName, const UndistortionPlan& plan, const std::string& sourceIdentity);

}  // namespace rad
