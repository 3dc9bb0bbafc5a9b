// Image-space error between an original radiance mesh and processed versions of it (simplified,
// directionally reduced, refitted): every mesh is rendered on the CPU (render/radiance_renderer.h)
// from the same cameras around the ORIGINAL's bounding sphere, and the renderings are compared over
// the pixels EITHER covers, so silhouette changes count. This is the evaluation of Vanhoey et al.
// 2015 Fig. 7 (simplification against directional reduction at equal memory), and the memory figure
// it uses is defined here: V (12 + 12 K + frame) + 12 F bytes, frame 24 B for PB and 12 B for SH.
// Summaries: means over the views with a non-empty mask, and all masked pixels pooled.
// Details: docs/simplification.md, "`common/render/image_space_error.h`: how it works".
#pragma once

#include "acquisition/camera_rig.h"
#include "camera/pinhole_camera.h"
#include "image/rgb_image.h"
#include "io/radiance_mesh.h"
#include "radiance/basis.h"
#include "render/image_metrics.h"
#include "render/radiance_renderer.h"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace rad {

// ---------------------------------------------------------------------------------------------
// Memory of a representation (see the file comment for the formula).
// ---------------------------------------------------------------------------------------------

inline constexpr std::size_t kPositionBytes = 12;  // 3 floats
inline constexpr std::size_t kTriangleBytes = 12;  // 3 uint32 indices

// 24 for PB, 12 for SH (plain or reflected).
std::size_t frameBytesPerVertex(const BasisSpec& basis);
// Position + coefficients + frame: 12 + 12 K + frameBytesPerVertex(basis).
std::size_t vertexBytes(const BasisSpec& basis);
// V * vertexBytes(basis) + 12 F.
std::size_t radianceMeshMemoryBytes(std::size_t vertexCount, std::size_t faceCount, const BasisSpec& basis);
// The same for a mesh (positions and faces only when it has no radiance).
std::size_t radianceMeshMemoryBytes(const RadianceMesh& mesh);

// ---------------------------------------------------------------------------------------------
// Rendering and comparison.
// ---------------------------------------------------------------------------------------------

struct ImageSpaceOptions {
    int viewCount = 16;
    int width = 512, height = 512;
    RadianceShading shading = RadianceShading::PerFragment;
    int supersampling = 1;                                  // N x N rays per pixel, 1..16
    double minElevationDegrees = -90.0;                     // elevation band of the cameras
    double maxElevationDegrees = 90.0;                      //   (e.g. 0..90: no view from below)
    Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
    double horizontalFovDegrees = 40.0;
    double fillFraction = 0.9;                              // bounding-sphere diameter / smaller side
    double jitter = 0.0;                                    // of the camera spiral, see camera_rig.h
    std::uint64_t seed = 1;
    Eigen::Vector3d background = Eigen::Vector3d::Zero();   // linear colour where no sample hits
};

struct ViewImageError {
    ImageErrors errors;                 // over the mask; pixelCount = |mask|
    std::size_t originalPixels = 0;     // pixels the original touches (coverage > 0)
    std::size_t otherPixels = 0;        // pixels the other mesh touches
};

struct ImageSpaceError {
    std::vector<ViewImageError> views;  // one per camera, in rig order
    // Means over the views with a non-empty mask (see the file comment).
    double meanRmseLinear = 0.0, meanPsnrLinear = 0.0;
    double meanRmseSrgb8 = 0.0, meanPsnrSrgb8 = 0.0;
    // All masked pixels of all views pooled.
    ImageErrors pooled;
    int worstView = -1;                 // largest linear RMSE; -1 when every mask is empty
    int emptyViewCount = 0;
    std::size_t originalMemoryBytes = 0, otherMemoryBytes = 0;  // radianceMeshMemoryBytes
};

// Called once per view and per other mesh with both renderings and the mask used (0/1 per pixel),
// from the calling thread, e.g. to keep images for a figure.
struct ViewRenderings {
    int view = 0;
    std::size_t otherIndex = 0;         // index into the list of other meshes
    const PinholeCamera* camera = nullptr;
    const Rendering* original = nullptr;
    const Rendering* other = nullptr;
    const std::vector<std::uint8_t>* mask = nullptr;
    const ViewImageError* error = nullptr;
};
using ViewRenderingsCallback = std::function<void(const ViewRenderings&)>;

// Optional PNG output (image/image_io.h), nothing when `directory` is empty. File names, with NN
// the view index on two digits (more when needed) and LABEL the other mesh's label:
//   heat maps:  DIR/LABEL_viewNN_heatmap.png   (errorHeatmap with `heatmapScale`)
//   renders:    DIR/original_viewNN.png, DIR/LABEL_viewNN.png   (encodeToSrgb8, exposure 1)
// The directory must exist. Labels default to "other0", "other1"... when `labels` has fewer
// entries than there are other meshes.
struct ImageSpaceImageOutput {
    std::string directory;
    bool heatmaps = true;
    bool renders = false;
    double heatmapScale = 0.1;          // linear RMS difference drawn white, see errorHeatmap
    std::vector<std::string> labels;
};

// The cameras every mesh is rendered from: makeCameraRig around the original's bounding sphere
// (file comment). Throws std::invalid_argument when the mesh has no vertex or an option is out of
// range.
std::vector<PinholeCamera> imageSpaceCameras(const RadianceMesh& original, const ImageSpaceOptions& options);

// Renders `original` and every mesh of `others` from imageSpaceCameras(original) and compares each
// other mesh with the original (one result per other mesh, in order). The original is rendered once
// per view; views are processed one after the other (the renderer is parallel inside).
// \throw std::invalid_argument when a mesh has no radiance field ("... has no radiance functions"),
//        an invalid field, not one RF per vertex, no face, or an option is out of range;
//        ImageFileError when an image cannot be written.
std::vector<ImageSpaceError> compareRadianceMeshes(const RadianceMesh& original,
                                                   const std::vector<const RadianceMesh*>& others,
                                                   const ImageSpaceOptions& options = {},
                                                   const ImageSpaceImageOutput& output = {},
                                                   const ViewRenderingsCallback& callback = {});
// One other mesh.
ImageSpaceError compareRadianceMeshes(const RadianceMesh& original, const RadianceMesh& other,
                                      const ImageSpaceOptions& options = {}, const ImageSpaceImageOutput& output = {});

// Error heat map of two linear images of the same size: for every pixel the RMS over the channels
// of the linear difference, e = sqrt((1/3) sum_c (a_c - b_c)^2), drawn with the colour ramp
// black (e = 0) -> red (e = scale / 3) -> yellow (2 scale / 3) -> white (e >= scale), linear in
// between ("hot" ramp: monotonic in luminance, so it reads in grey too). Pixels outside the mask
// (mask[i] == 0; an empty mask selects every pixel) are drawn mid-blue (40, 60, 110) so that the
// object's outline stays visible and a zero error inside reads as black.
// \throw std::invalid_argument on different sizes, a mask of the wrong size or scale <= 0.
Image8 errorHeatmap(const ImageF& a, const ImageF& b, const std::vector<std::uint8_t>& mask, double scale);

}  // namespace rad
