// Calibrated photographs read from another tool's files (COLMAP, Agisoft Metashape, nerfstudio),
// in one convention: the lens (cameras/lens_model.h) and a world-to-camera pose with OpenCV's axes
// (x right, y down, z forward), as camera/pinhole_camera.h. Each reader converts its tool's own
// conventions into this one (docs/design-notes.md, "Importing cameras").
#pragma once

#include "errors/error_categories.h"

#include "camera/pinhole_camera.h"
#include "cameras/lens_model.h"

#include <Eigen/Core>

#include <stdexcept>
#include <string>
#include <vector>

namespace rad {

// A camera file that cannot be used: the message says what is wrong, where, and what to do.
struct CameraFileError : FileError {
    using FileError::FileError;
};

struct ImportedCamera {
    std::string imageName;  // the photograph, relative to the image folder (as the file names it)
    int width = 0, height = 0;  // the image size the calibration refers to
    LensModel lens;
    // Radians, > 0 when the file gives the field of view instead of a focal length in pixels and an
    // image size (the original NeRF's camera_angle_x, camera_angle_y): the photograph's size then
    // completes the camera (takeSizeFromPhotograph), principal point at the image centre.
    double fieldOfViewX = 0.0, fieldOfViewY = 0.0;
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // world -> camera, rows right, down, forward
    Eigen::Vector3d center = Eigen::Vector3d::Zero();        // optical centre, world coordinates

    bool sizedByPhotograph() const { return fieldOfViewX > 0.0 && width == 0; }
    // Size, focal lengths and principal point from the photograph's size and the field of view:
    // f = (size / 2) / tan(angle / 2), fy = fx when only the horizontal angle is given.
    void takeSizeFromPhotograph(int photographWidth, int photographHeight);

    // Where the lens images world point X (pixels, as LensModel); false behind the camera.
    bool project(const Eigen::Vector3d& X, double& u, double& v) const;
    // The same pose with the lens's pinhole part only (focal lengths and principal point).
    PinholeCamera pinholePart() const;
    // Empty when usable (lens, size, an orthonormal right-handed rotation, finite centre; for a camera
    // sized by its photograph, a field of view in (0, 180) degrees instead of the lens's pinhole part
    // and size); otherwise a sentence naming the image and what is wrong.
    std::string validate() const;

private:
    std::string validatePose(const std::string& who) const;  // finite, and an orthonormal right-handed rotation
};

struct CameraImport {
    std::string format;                    // e.g. "COLMAP binary model"
    std::vector<ImportedCamera> cameras;   // the usable ones, in the file's order
    std::vector<std::string> skipped;      // one sentence per camera left out (disabled, not aligned)
};

// A rotation from a unit quaternion (w, x, y, z), normalised first (COLMAP stores them so).
Eigen::Matrix3d rotationFromQuaternion(double w, double x, double y, double z);

}  // namespace rad
