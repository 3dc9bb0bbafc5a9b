#include "fit/view_sampling.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace rad {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kAutomaticDepthToleranceFraction = 1e-4;
}  // namespace

std::string checkView(const CalibratedView& view) {
    std::ostringstream why;
    const std::string camera = view.camera.validate();
    const ImageView8& im = view.image;
    if (!camera.empty()) {
        why << "its camera is not usable: " << camera;
    } else if (im.empty()) {
        why << "it has no image (the photograph is missing or could not be read)";
    } else if (im.pixelStride < 1 || std::llabs(static_cast<long long>(im.rowStride)) <
                                         static_cast<long long>(im.width) * im.pixelStride) {
        why << "its image has an inconsistent pixel layout (pixel stride " << im.pixelStride << ", row stride "
            << im.rowStride << " bytes for " << im.width << " pixels)";
    } else if (im.channelOffset[0] < 0 || im.channelOffset[1] < 0 || im.channelOffset[2] < 0 ||
               im.channelOffset[0] >= im.pixelStride || im.channelOffset[1] >= im.pixelStride ||
               im.channelOffset[2] >= im.pixelStride) {
        why << "its image has channel offsets outside the pixel";
    } else if (view.camera.width != im.width || view.camera.height != im.height) {
        why << "its camera is calibrated for " << view.camera.width << " x " << view.camera.height
            << " pixels but its image is " << im.width << " x " << im.height
            << " (use the photograph the camera was calibrated on, at full resolution)";
    }
    return why.str();
}

std::string ViewSamplingOptions::validate() const {
    std::ostringstream why;
    if (!std::isfinite(depthTolerance))
        why << "the depth tolerance must be a finite number (negative: automatic), got " << depthTolerance;
    else if (!(grazingAngleDegrees > 0.0 && grazingAngleDegrees < 90.0))
        why << "the grazing angle must be in (0, 90) degrees (got " << grazingAngleDegrees << ")";
    else if (!(borderMarginPixels >= 0.0) || !std::isfinite(borderMarginPixels))
        why << "the border margin must be a finite number of pixels >= 0 (got " << borderMarginPixels << ")";
    return why.str();
}

ViewSampler::ViewSampler(const TriangleMesh& mesh, std::vector<CalibratedView> views, const ViewSamplingOptions& options)
    : views_(std::move(views)) {
    std::string why = options.validate();
    if (why.empty()) why = mesh.validate();
    if (why.empty() && mesh.normals.size() != mesh.positions.size()) why = "the mesh has no per-vertex normals";
    if (!why.empty()) throw std::invalid_argument("view sampling: " + why);
    for (std::size_t i = 0; i < views_.size(); ++i) {
        const std::string problem = checkView(views_[i]);
        if (!problem.empty())
            throw std::invalid_argument("view sampling: view " + std::to_string(i) + " is not usable: " + problem);
    }
    positions_ = mesh.positions.data();
    normals_ = mesh.normals.data();
    vertexCount_ = mesh.vertexCount();
    cosGrazing_ = std::cos(options.grazingAngleDegrees * kPi / 180.0);
    margin_ = options.borderMarginPixels;

    depthTolerance_ = options.depthTolerance;
    if (depthTolerance_ < 0.0) {
        Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = Eigen::Vector3d::Constant(-INFINITY);
        for (std::size_t v = 0; v < vertexCount_; ++v)
            for (int k = 0; k < 3; ++k) {
                lo[k] = std::min(lo[k], double(positions_[3 * v + k]));
                hi[k] = std::max(hi[k], double(positions_[3 * v + k]));
            }
        depthTolerance_ = vertexCount_ > 0 ? kAutomaticDepthToleranceFraction * (hi - lo).norm() : 0.0;
    }
    if (mesh.faceCount() > 0)
        scene_ = std::make_unique<RayScene>(mesh.positions.data(), vertexCount_, mesh.faces.data(), mesh.faceCount());
}

ViewSampler::~ViewSampler() = default;

std::size_t ViewSampler::sampleVertex(std::size_t v, DirectionalSample* out, SamplingCounters* counters,
                                      int* viewOfSample) const {
    if (v >= vertexCount_) return 0;
    const Eigen::Vector3d X(positions_[3 * v], positions_[3 * v + 1], positions_[3 * v + 2]);
    Eigen::Vector3d n(normals_[3 * v], normals_[3 * v + 1], normals_[3 * v + 2]);
    const double len = n.norm();
    if (!(len > 0.0) || !std::isfinite(len)) return 0;
    n /= len;
    const Eigen::Vector3f origin = X.cast<float>();
    std::size_t count = 0;
    SamplingCounters local;
    for (std::size_t i = 0; i < views_.size(); ++i) {
        const CalibratedView& view = views_[i];
        // Cheapest tests first: facing (a dot product) rejects about half of the views.
        const Eigen::Vector3d toCamera = view.camera.center - X;
        const double distance = toCamera.norm();
        if (!(distance > 0.0)) continue;
        const Eigen::Vector3d w = toCamera / distance;
        const double cosine = n.dot(w);
        if (!(cosine >= cosGrazing_) || !(cosine > 0.0)) continue;
        ++local.facing;
        double u, vv;
        if (!view.camera.project(X, u, vv) || !view.camera.isInside(u, vv, margin_)) continue;
        ++local.inFrame;
        if (scene_) {
            const double tNear = depthTolerance_, tFar = distance - depthTolerance_;
            if (!(tFar > tNear)) continue;  // the camera sits on the surface: no meaningful sample
            ++local.raysCast;
            if (scene_->occluded(origin, w.cast<float>(), static_cast<float>(tNear), static_cast<float>(tFar))) {
                ++local.occluded;
                continue;
            }
        }
        DirectionalSample& s = out[count];
        if (!sampleBilinearLinear(view.image, u, vv, s.rgb)) continue;
        s.direction[0] = static_cast<float>(w.x());
        s.direction[1] = static_cast<float>(w.y());
        s.direction[2] = static_cast<float>(w.z());
        s.weight = static_cast<float>(cosine);
        if (viewOfSample) viewOfSample[count] = static_cast<int>(i);
        ++count;
    }
    local.samples = count;
    if (counters) {
        counters->facing += local.facing;
        counters->inFrame += local.inFrame;
        counters->raysCast += local.raysCast;
        counters->occluded += local.occluded;
        counters->samples += local.samples;
    }
    return count;
}

}  // namespace rad
