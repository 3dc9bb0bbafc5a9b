// Gathering the colour samples of mesh vertices from calibrated photographs (Vanhoey et al. 2015 sec. 7:
// radiance functions "are fitted on photographs ... projected onto the mesh"), for the robust
// per-vertex fit of fit/robust_radiance_fit.h.
//
// A view (camera + image) gives vertex X with unit normal n a sample when ALL of these hold:
//  1. front-facing within the grazing cut-off: n.w >= cos(grazingAngleDegrees), w = (C - X)/|C - X|
//     the unit direction from the vertex toward the camera centre C;
//  2. X is in front of the camera (camera-space depth > 0) and projects inside the image shrunk by
//     borderMarginPixels on every side (pinhole_camera.h conventions);
//  3. not occluded: the Embree ray X + t w hits nothing for t in [depthTolerance, |C - X| -
//     depthTolerance] (the lower bound skips the faces around X itself and absorbs small geometric
//     noise; the upper bound keeps a camera that sits on the surface from counting as occluded).
// The sample is the bilinear interpolation of the sRGB-decoded (linear) pixels at the projection
// (sampleBilinearLinear of image/rgb_image.h), direction w, weight cos(angle(n, w)) = n.w: views
// seen at grazing angles see the surface foreshortened (fewer pixels per unit area, so more
// blur and more sensitivity to calibration and normal errors), and the cosine is the standard
// confidence of projective texturing; it is also > 0 by (1), as the fit requires.
//
// Vertex-major: ViewSampler::sampleVertex fills the caller's buffer (<= viewCount() samples) for one
// vertex, so a whole mesh is fitted vertex by vertex without ever storing all samples (1M vertices x
// 50 views would be 1.4 GB of samples): memory is one buffer per thread. Thread-safe.
#pragma once

#include "camera/pinhole_camera.h"
#include "fit/robust_radiance_fit.h"
#include "geometry/triangle_mesh.h"
#include "image/rgb_image.h"
#include "raycast/ray_scene.h"

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace rad {

// A photograph and the pinhole camera that took it (undistorted; camera.width/height must be the
// image's size). The image is a zero-copy view: its pixels must outlive every use of the view.
struct CalibratedView {
    PinholeCamera camera;
    ImageView8 image;
};

// Empty when the view is usable; otherwise a sentence saying what is wrong (invalid camera, empty
// image, camera size different from the image size, inconsistent pixel layout).
std::string checkView(const CalibratedView& view);

struct ViewSamplingOptions {
    // World units; < 0: automatic, 1e-4 x the diagonal of the mesh's bounding box.
    double depthTolerance = -1.0;
    // Maximum angle between the vertex normal and the direction to the camera, in (0, 90) degrees.
    double grazingAngleDegrees = 80.0;
    // Projections closer than this to the image border are ignored (pixels, >= 0).
    double borderMarginPixels = 2.0;

    // Empty when usable; otherwise a sentence naming the bad option.
    std::string validate() const;
};

// Optional statistics of sampleVertex (per call; add them up per thread).
struct SamplingCounters {
    std::size_t facing = 0;     // views passing the facing / grazing test
    std::size_t inFrame = 0;    // ... and projecting inside the image
    std::size_t raysCast = 0;   // occlusion rays cast (= inFrame when the mesh has faces)
    std::size_t occluded = 0;
    std::size_t samples = 0;
};

class ViewSampler {
public:
    // `mesh` must be valid (TriangleMesh::validate) with one non-zero finite normal per vertex, and
    // must outlive the sampler (positions and normals are read in place); every view must pass
    // checkView. Throws std::invalid_argument otherwise, RayCastError when Embree fails. A mesh
    // without faces (a point cloud) is sampled without occlusion test.
    ViewSampler(const TriangleMesh& mesh, std::vector<CalibratedView> views, const ViewSamplingOptions& options = {});
    ~ViewSampler();
    ViewSampler(const ViewSampler&) = delete;
    ViewSampler& operator=(const ViewSampler&) = delete;

    std::size_t viewCount() const { return views_.size(); }
    std::size_t vertexCount() const { return vertexCount_; }
    // The depth tolerance in use (the automatic one resolved).
    double depthTolerance() const { return depthTolerance_; }
    bool testsOcclusion() const { return scene_ != nullptr; }

    // Writes the samples of vertex v (in view order) into out[0 .. viewCount()) and returns how many.
    // `viewOfSample`, when not null, receives the view index of each sample. Returns 0 for v out of
    // range. Thread-safe; no allocation.
    std::size_t sampleVertex(std::size_t v, DirectionalSample* out, SamplingCounters* counters = nullptr,
                             int* viewOfSample = nullptr) const;

private:
    const float* positions_ = nullptr;
    const float* normals_ = nullptr;
    std::size_t vertexCount_ = 0;
    std::vector<CalibratedView> views_;
    std::unique_ptr<RayScene> scene_;
    double depthTolerance_ = 0.0;
    double cosGrazing_ = 0.0;
    double margin_ = 0.0;
};

}  // namespace rad
