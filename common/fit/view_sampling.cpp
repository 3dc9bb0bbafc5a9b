#include "fit/view_sampling.h"

#include <algorithm>
#include <bitset>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace rad {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kAutomaticDepthToleranceFraction = 1e-4;

void addCounters(SamplingCounters* to, const SamplingCounters& from) {
    if (!to) return;
    to->facing += from.facing;
    to->inFrame += from.inFrame;
    to->raysCast += from.raysCast;
    to->occluded += from.occluded;
    to->samples += from.samples;
}
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

bool ViewSampler::vertexFrame(std::size_t v, Eigen::Vector3d& X, Eigen::Vector3d& n) const {
    if (v >= vertexCount_) return false;
    X = Eigen::Vector3d(positions_[3 * v], positions_[3 * v + 1], positions_[3 * v + 2]);
    n = Eigen::Vector3d(normals_[3 * v], normals_[3 * v + 1], normals_[3 * v + 2]);
    const double len = n.norm();
    if (!(len > 0.0) || !std::isfinite(len)) return false;
    n /= len;
    return true;
}

bool ViewSampler::facesAndProjects(std::size_t i, const Eigen::Vector3d& X, const Eigen::Vector3d& n, Candidate& c,
                                   SamplingCounters& counters) const {
    const CalibratedView& view = views_[i];
    // Cheapest tests first: facing (a dot product) rejects about half of the views.
    const Eigen::Vector3d toCamera = view.camera.center - X;
    const double distance = toCamera.norm();
    if (!(distance > 0.0)) return false;
    c.w = toCamera / distance;
    c.cosine = n.dot(c.w);
    if (!(c.cosine >= cosGrazing_) || !(c.cosine > 0.0)) return false;
    ++counters.facing;
    if (!view.camera.project(X, c.u, c.v) || !view.camera.isInside(c.u, c.v, margin_)) return false;
    ++counters.inFrame;
    if (!scene_) return true;
    const double tNear = depthTolerance_, tFar = distance - depthTolerance_;
    if (!(tFar > tNear)) return false;  // the camera sits on the surface: no meaningful sample
    c.tNear = static_cast<float>(tNear);
    c.tFar = static_cast<float>(tFar);
    return true;
}

bool ViewSampler::takeSample(std::size_t i, const Candidate& c, DirectionalSample& s) const {
    if (!sampleBilinearLinear(views_[i].image, c.u, c.v, s.rgb)) return false;
    s.direction[0] = static_cast<float>(c.w.x());
    s.direction[1] = static_cast<float>(c.w.y());
    s.direction[2] = static_cast<float>(c.w.z());
    s.weight = static_cast<float>(c.cosine);
    return true;
}

std::size_t ViewSampler::sampleVertex(std::size_t v, DirectionalSample* out, SamplingCounters* counters,
                                      int* viewOfSample) const {
    Eigen::Vector3d X, n;
    if (!vertexFrame(v, X, n)) return 0;
    const Eigen::Vector3f origin = X.cast<float>();
    std::size_t count = 0;
    SamplingCounters local;
    Candidate c;
    for (std::size_t i = 0; i < views_.size(); ++i) {
        if (!facesAndProjects(i, X, n, c, local)) continue;
        if (scene_) {
            ++local.raysCast;
            if (scene_->occluded(origin, c.w.cast<float>(), c.tNear, c.tFar)) {
                ++local.occluded;
                continue;
            }
        }
        if (!takeSample(i, c, out[count])) continue;
        if (viewOfSample) viewOfSample[count] = static_cast<int>(i);
        ++count;
    }
    local.samples = count;
    addCounters(counters, local);
    return count;
}

static_assert(ViewSampler::kBlock <= RayPacket16::kSize, "a block's rays fill one packet");

void ViewSampler::sampleVertexBlock(std::size_t first, int count, DirectionalSample* out, std::size_t* counts,
                                    SamplingCounters* counters, int* viewOfSample) const {
    count = std::max(0, std::min(count, kBlock));
    const std::size_t viewCount = views_.size();
    Eigen::Vector3d X[kBlock], n[kBlock];
    bool usable[kBlock];
    for (int k = 0; k < count; ++k) {
        counts[k] = 0;
        usable[k] = vertexFrame(first + k, X[k], n[k]);
    }
    SamplingCounters local;
    Candidate c[kBlock];
    RayPacket16 rays;
    for (std::size_t i = 0; i < viewCount; ++i) {
        std::uint32_t candidates = 0, cast = 0;
        for (int k = 0; k < count; ++k) {
            if (!usable[k] || !facesAndProjects(i, X[k], n[k], c[k], local)) continue;
            candidates |= 1u << k;
            if (!scene_) continue;
            rays.originX[k] = static_cast<float>(X[k].x());
            rays.originY[k] = static_cast<float>(X[k].y());
            rays.originZ[k] = static_cast<float>(X[k].z());
            rays.directionX[k] = static_cast<float>(c[k].w.x());
            rays.directionY[k] = static_cast<float>(c[k].w.y());
            rays.directionZ[k] = static_cast<float>(c[k].w.z());
            rays.tNear[k] = c[k].tNear;
            rays.tFar[k] = c[k].tFar;
            cast |= 1u << k;
        }
        if (cast) {
            const std::uint32_t occluded = scene_->occluded16(rays, cast);
            local.raysCast += std::bitset<kBlock>(cast).count();
            local.occluded += std::bitset<kBlock>(occluded).count();
            candidates &= ~occluded;
        }
        for (int k = 0; k < count; ++k) {
            if (!((candidates >> k) & 1u)) continue;
            const std::size_t slot = std::size_t(k) * viewCount + counts[k];
            if (!takeSample(i, c[k], out[slot])) continue;
            if (viewOfSample) viewOfSample[slot] = static_cast<int>(i);
            ++counts[k];
        }
    }
    for (int k = 0; k < count; ++k) local.samples += counts[k];
    addCounters(counters, local);
}

}  // namespace rad
