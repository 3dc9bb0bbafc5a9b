// CPU rendering of a triangle mesh carrying per-vertex radiance functions (RF), by ray casting
// with Embree (raycast/ray_scene.h): the reference renderer for image-space comparisons (fitted RF
// against the photographs, simplified against original meshes).
//
// Vanhoey et al. 2015, sec. 5 ("Rendering") describes two ways to shade a triangle
// (v1, v2, v3) whose vertices carry RF L_i, at a fragment with barycentrics alpha seen from the
// eye e:
//  - PerVertex ("Gouraud-like", the vertex-shader approach): every vertex's RF is evaluated toward
//    the eye, c_i = L_i(normalize(e - p_i)) (border-extended below the tangent plane, sec. 7), and
//    the fragment gets sum_i alpha_i c_i. Highlights inside large triangles fade (Fig. 6 left).
//  - PerFragment, eq. (8): with w = normalize(e - p) the direction from the fragment to the eye and
//    n = normalize(sum_i alpha_i n_i) the interpolated RF normal,
//        L_t(p, w) = sum_i alpha_i L~_i(R_n w),   L~_i(w) = L_i(R_{n_i} w)  (reflected RF, sec. 3.1)
//    (radiance/radiance_interpolation.h, interpolateRadiance), whatever the field's storage (plain
//    or reflected). Highlights are interpolated as Phong shading does (Fig. 6 right). Where n
//    vanishes (exactly opposite normals) the naive sum_i alpha_i L_i(w) is used.
//
// Sampling, as the virtual photographs (acquisition/virtual_photographs.h) so that renderings and
// photographs compare pixel for pixel: NxN rays per pixel through the sub-pixel centres
// (c + (i + 0.5)/N, r + (j + 0.5)/N) of the pinhole image coordinates, averaged (box filter).
// Output: a LINEAR image plus a coverage value per pixel, round(255 * hits / N^2).
//
// Cost: PerVertex evaluates all V vertices once per image (OpenMP), then one ray and one
// barycentric blend per sample; PerFragment evaluates three RF per sample. The scene (Embree BVH)
// is built once per mesh and reused for every view. Parallel over rows, no allocation per pixel.
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
