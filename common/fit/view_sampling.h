// Gathering the colour samples of mesh vertices from calibrated photographs (Vanhoey et al. 2015
// sec. 7: radiance functions "are fitted on photographs ... projected onto the mesh") for the
// per-vertex fit of fit/robust_radiance_fit.h. A view gives a vertex a sample when the vertex faces
// it within the grazing cut-off, projects inside the image minus a border margin and is not occluded
// (Embree ray); the sample is the bilinear, sRGB-decoded colour at the projection, weighted by the
// cosine n.w. Vertex-major: sampleVertex fills the caller's buffer for one vertex, so memory is one
// buffer per thread, never all samples of a mesh. Thread-safe.
// Details: docs/fitting.md, "`common/fit/view_sampling.h`: how it works".
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
    // The samples of vertices first .. first + count - 1 (count <= kBlock): the same samples in the
    // same order as sampleVertex gives them one by one, vertex first + k's in out[k * viewCount() ..]
    // (and viewOfSample likewise), their number in counts[k]. The occlusion rays of the block toward
    // one camera go to Embree as one packet: neighbouring vertices' rays to one camera are coherent,
    // and a packet traverses the tree once for all of them.
    static constexpr int kBlock = 16;
    void sampleVertexBlock(std::size_t first, int count, DirectionalSample* out, std::size_t* counts,
                           SamplingCounters* counters = nullptr, int* viewOfSample = nullptr) const;

private:
    // The tests before the occlusion ray: whether view i sees vertex X (unit normal n) facing it,
    // inside its image and, when occlusion is tested, far enough from the camera for an occlusion
    // interval; fills the direction w, the cosine, the projection (u, v) and that interval.
    struct Candidate {
        Eigen::Vector3d w;
        double cosine = 0.0, u = 0.0, v = 0.0;
        float tNear = 0.0f, tFar = 0.0f;
    };
    bool facesAndProjects(std::size_t i, const Eigen::Vector3d& X, const Eigen::Vector3d& n, Candidate& c,
                          SamplingCounters& counters) const;
    // The sample of a candidate that passed the occlusion test: false when the image refuses it.
    bool takeSample(std::size_t i, const Candidate& c, DirectionalSample& s) const;
    // The vertex's position and unit normal; false when its normal is zero or not finite.
    bool vertexFrame(std::size_t v, Eigen::Vector3d& X, Eigen::Vector3d& n) const;

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
