#include "render/image_space_error.h"

#include "image/image_io.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

namespace rad {

// ---------------------------------------------------------------------------------------------
// Memory.
// ---------------------------------------------------------------------------------------------

std::size_t frameBytesPerVertex(const BasisSpec& basis) {
    // PB lives in the local frame (tangent + normal); SH only needs the normal, for the reflection /
    // eq. (8) normal (reflected storage) or the border extension (plain storage).
    return basis.usesLocalFrame() ? 24 : 12;
}

std::size_t vertexBytes(const BasisSpec& basis) {
    return kPositionBytes + 4u * kColorChannels * static_cast<std::size_t>(basis.coefficientCount()) +
           frameBytesPerVertex(basis);
}

std::size_t radianceMeshMemoryBytes(std::size_t vertexCount, std::size_t faceCount, const BasisSpec& basis) {
    return vertexCount * vertexBytes(basis) + faceCount * kTriangleBytes;
}

std::size_t radianceMeshMemoryBytes(const RadianceMesh& mesh) {
    if (!mesh.radiance) return mesh.vertexCount() * kPositionBytes + mesh.faceCount() * kTriangleBytes;
    return radianceMeshMemoryBytes(mesh.vertexCount(), mesh.faceCount(), mesh.radiance->basis);
}

// ---------------------------------------------------------------------------------------------
// Helpers.
// ---------------------------------------------------------------------------------------------

namespace {

[[noreturn]] void refuse(const std::string& what) { throw std::invalid_argument("image-space error: " + what); }

void checkMesh(const RadianceMesh& mesh, const std::string& name) {
    if (!mesh.radiance)
        refuse(name + " has no radiance functions (RadianceMesh::radiance is empty): fit or create them first");
    const std::string why = mesh.radiance->validate();
    if (!why.empty()) refuse(name + ": " + why);
    if (mesh.radiance->vertexCount() != mesh.vertexCount())
        refuse(name + " has " + std::to_string(mesh.vertexCount()) + " vertices but radiance functions for " +
               std::to_string(mesh.radiance->vertexCount()));
    if (mesh.faceCount() == 0) refuse(name + " has no face");
}

void checkOptions(const ImageSpaceOptions& o) {
    if (o.viewCount < 1) refuse("the number of views must be at least 1, got " + std::to_string(o.viewCount));
    if (o.width < 1 || o.height < 1)
        refuse("the image size must be positive, got " + std::to_string(o.width) + "x" + std::to_string(o.height));
    if (o.supersampling < 1 || o.supersampling > 16)
        refuse("supersampling must lie in 1..16, got " + std::to_string(o.supersampling));
    if (!o.background.allFinite()) refuse("the background colour is not finite");
}

std::string viewTag(int view, int viewCount) {
    const int digits = std::max(2, static_cast<int>(std::to_string(std::max(0, viewCount - 1)).size()));
    std::string s = std::to_string(view);
    return "view" + std::string(digits - std::min<int>(digits, static_cast<int>(s.size())), '0') + s;
}


// Running sums of one comparison over the views.
struct Accumulator {
    double sumRmseLinear = 0, sumPsnrLinear = 0, sumRmseSrgb8 = 0, sumPsnrSrgb8 = 0;
    double sumSqLinear = 0, sumSqSrgb8 = 0;  // sum_v |M_v| RMSE_v^2
    std::size_t pixels = 0;
    int used = 0;
};

}  // namespace

// ---------------------------------------------------------------------------------------------
// Cameras.
// ---------------------------------------------------------------------------------------------

std::vector<PinholeCamera> imageSpaceCameras(const RadianceMesh& original, const ImageSpaceOptions& options) {
    checkOptions(options);
    const std::size_t n = original.vertexCount();
    if (n == 0) refuse("the original mesh has no vertex");
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (std::size_t v = 0; v < n; ++v) {
        const Eigen::Vector3d p(original.positions[3 * v], original.positions[3 * v + 1], original.positions[3 * v + 2]);
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    const Eigen::Vector3d centre = 0.5 * (lo + hi);
    double radius = 0.0;
    for (std::size_t v = 0; v < n; ++v) {
        const Eigen::Vector3d p(original.positions[3 * v], original.positions[3 * v + 1], original.positions[3 * v + 2]);
        radius = std::max(radius, (p - centre).norm());
    }
    // A single point (or a mesh collapsed to one) still gets a frame of some size.
    if (!(radius > 0.0)) radius = 1.0;
    CameraRigOptions rig;
    rig.count = options.viewCount;
    rig.width = options.width;
    rig.height = options.height;
    rig.horizontalFovDegrees = options.horizontalFovDegrees;
    rig.fillFraction = options.fillFraction;
    rig.minElevationDegrees = options.minElevationDegrees;
    rig.maxElevationDegrees = options.maxElevationDegrees;
    rig.up = options.up;
    rig.jitter = options.jitter;
    rig.seed = options.seed;
    return makeCameraRig(centre, radius, rig);  // throws std::invalid_argument on a bad option
}

// ---------------------------------------------------------------------------------------------
// Heat map.
// ---------------------------------------------------------------------------------------------

Image8 errorHeatmap(const ImageF& a, const ImageF& b, const std::vector<std::uint8_t>& mask, double scale) {
    if (a.width != b.width || a.height != b.height || a.rgb.size() != b.rgb.size())
        refuse("heat map of images of different sizes");
    const std::size_t pixels = static_cast<std::size_t>(a.width) * a.height;
    if (!mask.empty() && mask.size() != pixels) refuse("heat map mask does not have one entry per pixel");
    if (!(scale > 0.0) || !std::isfinite(scale)) refuse("the heat map scale must be positive");
    Image8 out(a.width, a.height);
    for (std::size_t i = 0; i < pixels; ++i) {
        std::uint8_t* p = out.rgb.data() + 3 * i;
        if (!mask.empty() && mask[i] == 0) {
            p[0] = 40;
            p[1] = 60;
            p[2] = 110;
            continue;
        }
        double sq = 0.0;
        for (int c = 0; c < 3; ++c) {
            const double d = double(a.rgb[3 * i + c]) - double(b.rgb[3 * i + c]);
            sq += d * d;
        }
        const double e = std::sqrt(sq / 3.0);
        // "hot" ramp: t in [0, 1] over three equal segments, red then green then blue rising.
        const double t = std::isfinite(e) ? std::clamp(e / scale, 0.0, 1.0) : 1.0;
        const double r = std::clamp(3.0 * t, 0.0, 1.0), g = std::clamp(3.0 * t - 1.0, 0.0, 1.0),
                     bl = std::clamp(3.0 * t - 2.0, 0.0, 1.0);
        p[0] = static_cast<std::uint8_t>(std::lround(255.0 * r));
        p[1] = static_cast<std::uint8_t>(std::lround(255.0 * g));
        p[2] = static_cast<std::uint8_t>(std::lround(255.0 * bl));
    }
    return out;
}

// ---------------------------------------------------------------------------------------------
// Comparison.
// ---------------------------------------------------------------------------------------------

std::vector<ImageSpaceError> compareRadianceMeshes(const RadianceMesh& original,
                                                   const std::vector<const RadianceMesh*>& others,
                                                   const ImageSpaceOptions& options, const ImageSpaceImageOutput& output,
                                                   const ViewRenderingsCallback& callback) {
    checkOptions(options);
    checkMesh(original, "the original mesh");
    for (std::size_t i = 0; i < others.size(); ++i) {
        const std::string name = others.size() == 1 ? "the other mesh" : "other mesh " + std::to_string(i);
        if (others[i] == nullptr) refuse(name + " is a null pointer");
        checkMesh(*others[i], name);
    }
    if (!output.directory.empty() && !(output.heatmapScale > 0.0 && std::isfinite(output.heatmapScale)))
        refuse("the heat map scale must be positive");

    const std::vector<PinholeCamera> cameras = imageSpaceCameras(original, options);
    RenderOptions ro;
    ro.supersampling = options.supersampling;
    ro.background = options.background;

    // One Embree scene per mesh, built once and reused for every view.
    const MeshRenderer originalRenderer(original.positions.data(), original.vertexCount(), original.faces.data(),
                                        original.faceCount());
    std::vector<std::unique_ptr<MeshRenderer>> renderers;
    for (const RadianceMesh* m : others)
        renderers.push_back(
            std::make_unique<MeshRenderer>(m->positions.data(), m->vertexCount(), m->faces.data(), m->faceCount()));

    auto label = [&](std::size_t i) {
        return i < output.labels.size() && !output.labels[i].empty() ? output.labels[i] : "other" + std::to_string(i);
    };
    const bool writeImages = !output.directory.empty();
    const std::string dir = writeImages && output.directory.back() != '/' ? output.directory + "/" : output.directory;

    std::vector<ImageSpaceError> results(others.size());
    std::vector<Accumulator> sums(others.size());
    for (std::size_t i = 0; i < others.size(); ++i) {
        results[i].views.resize(cameras.size());
        results[i].originalMemoryBytes = radianceMeshMemoryBytes(original);
        results[i].otherMemoryBytes = radianceMeshMemoryBytes(*others[i]);
    }

    const std::size_t pixels = static_cast<std::size_t>(options.width) * options.height;
    std::vector<std::uint8_t> mask(pixels);
    for (std::size_t view = 0; view < cameras.size(); ++view) {
        const PinholeCamera& camera = cameras[view];
        const std::string tag = viewTag(static_cast<int>(view), static_cast<int>(cameras.size()));
        const Rendering ref = originalRenderer.renderRadiance(*original.radiance, camera, options.shading, ro);
        std::size_t originalPixels = 0;
        for (std::size_t p = 0; p < pixels; ++p) originalPixels += ref.coverage[p] > 0;
        if (writeImages && output.renders) writePng(dir + "original_" + tag + ".png", encodeToSrgb8(ref.image));

        for (std::size_t i = 0; i < others.size(); ++i) {
            const Rendering r = renderers[i]->renderRadiance(*others[i]->radiance, camera, options.shading, ro);
            ViewImageError& ve = results[i].views[view];
            ve.originalPixels = originalPixels;
            ve.otherPixels = 0;
            // The union of both silhouettes: see the file comment.
            for (std::size_t p = 0; p < pixels; ++p) {
                ve.otherPixels += r.coverage[p] > 0;
                mask[p] = (ref.coverage[p] > 0 || r.coverage[p] > 0) ? 1 : 0;
            }
            ve.errors = compareImages(ref.image, r.image, mask);

            Accumulator& acc = sums[i];
            if (ve.errors.pixelCount > 0) {
                acc.sumRmseLinear += ve.errors.rmseLinear;
                acc.sumPsnrLinear += ve.errors.psnrLinear;
                acc.sumRmseSrgb8 += ve.errors.rmseSrgb8;
                acc.sumPsnrSrgb8 += ve.errors.psnrSrgb8;
                const double m = static_cast<double>(ve.errors.pixelCount);
                acc.sumSqLinear += m * ve.errors.rmseLinear * ve.errors.rmseLinear;
                acc.sumSqSrgb8 += m * ve.errors.rmseSrgb8 * ve.errors.rmseSrgb8;
                acc.pixels += ve.errors.pixelCount;
                ++acc.used;
                const int worst = results[i].worstView;
                if (worst < 0 || ve.errors.rmseLinear > results[i].views[worst].errors.rmseLinear)
                    results[i].worstView = static_cast<int>(view);
            } else {
                ++results[i].emptyViewCount;
            }

            if (writeImages) {
                if (output.heatmaps)
                    writePng(dir + label(i) + "_" + tag + "_heatmap.png",
                             errorHeatmap(ref.image, r.image, mask, output.heatmapScale));
                if (output.renders) writePng(dir + label(i) + "_" + tag + ".png", encodeToSrgb8(r.image));
            }
            if (callback) {
                ViewRenderings vr;
                vr.view = static_cast<int>(view);
                vr.otherIndex = i;
                vr.camera = &camera;
                vr.original = &ref;
                vr.other = &r;
                vr.mask = &mask;
                vr.error = &ve;
                callback(vr);
            }
        }
    }

    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (std::size_t i = 0; i < others.size(); ++i) {
        const Accumulator& acc = sums[i];
        ImageSpaceError& r = results[i];
        const double n = acc.used;
        r.meanRmseLinear = acc.used ? acc.sumRmseLinear / n : nan;
        r.meanPsnrLinear = acc.used ? acc.sumPsnrLinear / n : nan;
        r.meanRmseSrgb8 = acc.used ? acc.sumRmseSrgb8 / n : nan;
        r.meanPsnrSrgb8 = acc.used ? acc.sumPsnrSrgb8 / n : nan;
        r.pooled = acc.pixels == 0 ? imageErrorsFromMeanSquares(0.0, 0.0, 0)
                                    : imageErrorsFromMeanSquares(acc.sumSqLinear / static_cast<double>(acc.pixels),
                                                                 acc.sumSqSrgb8 / static_cast<double>(acc.pixels),
                                                                 acc.pixels);
    }
    return results;
}

ImageSpaceError compareRadianceMeshes(const RadianceMesh& original, const RadianceMesh& other,
                                      const ImageSpaceOptions& options, const ImageSpaceImageOutput& output) {
    return compareRadianceMeshes(original, std::vector<const RadianceMesh*>{&other}, options, output).front();
}

}  // namespace rad
