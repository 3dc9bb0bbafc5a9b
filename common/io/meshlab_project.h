// MeshLab projects (.mlp): calibrated photographs as MeshLab "raster layers", and the meshes of the
// project. Written by the virtual acquisition (tools/virtual_acquisition.cpp) so that the fitting
// filter is exercised exactly as on a user's photogrammetry project, and read back by the tools and
// benchmarks, which have no MeshLab. The format is the one MeshLab 2020.09 reads; every camera value
// is rounded to float32 as MeshLab stores it, so what our tools read is exactly what MeshLab reads.
// Render virtual photographs with the camera as stored (storedCamera()), so that they agree exactly.
// Details: docs/camera-import.md, "`common/io/meshlab_project.h`: how it works".
#pragma once

#include "errors/error_categories.h"

#include "camera/pinhole_camera.h"

#include <Eigen/Core>

#include <stdexcept>
#include <string>
#include <vector>

namespace rad {

// Every failure of reading or writing a project; what() names the file (and the line for syntax
// errors) and says what is wrong.
struct MeshLabProjectError : FileError {
    using FileError::FileError;
};

// The values of a <VCGCamera> element (docs/camera-import.md), in double.
struct VcgCamera {
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // rows: right, up, backwards
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();   // -C
    double focalMm = 1.0;
    Eigen::Vector2d pixelSizeMm = Eigen::Vector2d(0.01, 0.01);
    Eigen::Vector2d centerPx = Eigen::Vector2d::Zero();      // y from the bottom
    int viewportWidth = 0, viewportHeight = 0;
    Eigen::Vector2d lensDistortion = Eigen::Vector2d::Zero();
    int cameraType = 0;  // 0 perspective, 1 orthographic

    // MeshLab's projection (vcg::Shot, docs/camera-import.md), with continuous px, py; false
    // when X is not in front of the camera.
    bool project(const Eigen::Vector3d& X, double& px, double& py) const;
};

// PinholeCamera -> VCGCamera values, exact up to double rounding. PixelSizeMm.x = pixelSizeMm
// (MeshLab's importers use 0.01), FocalMm = fx * pixelSizeMm, PixelSizeMm.y = FocalMm / fy.
VcgCamera toVcgCamera(const PinholeCamera& camera, double pixelSizeMm = 0.01);
// VCGCamera -> PinholeCamera. Throws MeshLabProjectError when the camera is orthographic, has a
// non-zero lens distortion (images must be undistorted), or non-positive size/focal/pixel size.
PinholeCamera fromVcgCamera(const VcgCamera& camera);
// Every value rounded to float32, as a project file stores it.
VcgCamera roundedToFloat(const VcgCamera& camera);
// fromVcgCamera(roundedToFloat(toVcgCamera(camera))): the camera exactly as a project stores it.
PinholeCamera storedCamera(const PinholeCamera& camera, double pixelSizeMm = 0.01);

struct ProjectMesh {
    std::string label;
    std::string fileName;   // as in the file (relative to the project's folder)
    std::string path;       // resolved: project folder / fileName (set by the reader)
    Eigen::Matrix4d transform = Eigen::Matrix4d::Identity();  // MLMatrix44, row-major in the file
    bool visible = true;
};

struct ProjectRaster {
    std::string label;
    std::string imageFile;  // fileName of the first Plane, as in the file (relative to the project)
    std::string imagePath;  // resolved: project folder / imageFile (set by the reader)
    VcgCamera camera;
};

struct MeshLabProject {
    std::vector<ProjectMesh> meshes;    // empty: an empty MeshGroup (load the mesh with -i instead)
    std::vector<ProjectRaster> rasters;
};

// Writes the project (text cameras, BinaryData="0"); file names are written as given (give them
// relative to the project's folder). Throws MeshLabProjectError when the file cannot be written or
// a value is not finite.
void writeMeshLabProject(const std::string& path, const MeshLabProject& project);
// The text writeMeshLabProject writes.
std::string formatMeshLabProject(const MeshLabProject& project);

// Reads a project; throws MeshLabProjectError on malformed XML, a missing or malformed VCGCamera
// attribute, a VCGCamera that is not the raster's first child, a raster without a Plane, a comment
// inside MeshGroup, or a missing file.
MeshLabProject readMeshLabProject(const std::string& path);
// Same from text; `baseDirectory` resolves the file names, `sourceName` prefixes the messages.
MeshLabProject parseMeshLabProject(const std::string& text, const std::string& baseDirectory,
                                   const std::string& sourceName = "<project>");

}  // namespace rad
