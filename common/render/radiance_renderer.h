// CPU rendering of a triangle mesh carrying per-vertex radiance functions (RF), by ray casting with
// Embree (raycast/ray_scene.h): the reference renderer for image-space comparisons (fitted RF against
// the photographs, simplified against original meshes). Shading as Vanhoey et al. 2015 sec. 5:
// per vertex (each RF evaluated toward the eye, colours interpolated) or per fragment, eq. (8). N x N
// rays per pixel, box-filtered as the virtual photographs are, so that renderings and photographs
// compare pixel for pixel; the output is a linear image plus a coverage value per pixel. The Embree
// scene is built once per mesh; rendering is parallel over rows.
// Details: docs/decorate-radiance.md, "`common/render/radiance_renderer.h`: how it works".
#pragma once

#include "camera/pinhole_camera.h"
#include "geometry/triangle_mesh.h"
#include "image/rgb_image.h"
#include "radiance/radiance_field.h"
#include "raycast/ray_scene.h"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace rad {

enum class RadianceShading {
    PerVertex,    // sec. 5, evaluate at vertices, interpolate colours
    PerFragment,  // eq. (8), interpolate reflected RF per sample
};

struct RenderOptions {
    int supersampling = 1;                                 // N: N x N rays per pixel, 1..16
    Eigen::Vector3d background = Eigen::Vector3d::Zero();  // linear colour of samples that miss
};

struct Rendering {
    ImageF image;                        // linear
    std::vector<std::uint8_t> coverage;  // per pixel (row-major): round(255 * hits / N^2)

    // 0/1 mask of the pixels whose coverage is at least `minimum` (255: fully covered, 1: touched),
    // for image_metrics.h.
    std::vector<std::uint8_t> mask(std::uint8_t minimum = 255) const;
};

class MeshRenderer {
public:
    // Copies positions and faces and builds the Embree scene. Throws std::invalid_argument on an
    // invalid mesh (TriangleMesh::validate, no faces), RayCastError when Embree fails.
    explicit MeshRenderer(const TriangleMesh& mesh);
    MeshRenderer(const float* positions, std::size_t vertexCount, const std::uint32_t* faces, std::size_t faceCount);

    std::size_t vertexCount() const { return positions_.size() / 3; }

    // The mesh with the field's RF (one per vertex, the renderer's vertex order). Throws
    // std::invalid_argument when the field is invalid (RadianceField::validate), does not have one
    // RF per vertex, the camera is invalid or an option out of range.
    Rendering renderRadiance(const RadianceField& field, const PinholeCamera& camera, RadianceShading shading,
                             const RenderOptions& options = {}) const;

    // Plain per-vertex colours (3 linear floats per vertex) interpolated with the barycentrics.
    Rendering renderVertexColors(const float* linearRgb, const PinholeCamera& camera,
                                 const RenderOptions& options = {}) const;

private:
    template <typename Shade>
    Rendering trace(const PinholeCamera& camera, const RenderOptions& options, const Shade& shade) const;

    std::vector<float> positions_;
    std::vector<std::uint32_t> faces_;
    std::unique_ptr<RayScene> rays_;
};

}  // namespace rad
