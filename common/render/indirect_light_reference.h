// CPU images of the INDIRECT light of a diffuse scene seen by a camera, to judge the irradiance
// vector grid (Granier et al. 2007) against a reference and against the alternative a user would
// pick, per-vertex irradiance on a simplified mesh. Every image is the radiance reflected toward
// the camera by the indirect light only (direct light excluded), at the same visible points:
//
//  - reference: per pixel, rho(x) / pi * E_ind(x) with
//        E_ind(x) = integral over the hemisphere of n(x) of L_ind(x <- w) cos dw,
//    L_ind the same quantity the grid stores (lighting/indirect_light_tracer.h, same bounce count),
//    estimated with N cosine-distributed directions (a Hammersley set turned randomly per pixel):
//    radiance = rho / N * sum L_ind(x <- w_i);
//  - grid: rho / pi <I_n(x), n>, the paper's interpolation (reflectedRadiance of
//    irradiance_vector_grid.h), or its variant with weights |n_a| instead of n_a^2 (exact for a
//    uniform incident radiance, where the paper's weights give pi L sum |n_a|^3, down to 0.58 pi L
//    on a diagonal normal);
//  - per vertex: E_ind computed at the vertices of another mesh (the simplified one) along their
//    normals, like the reference; at a visible point, the closest point of that mesh gives the face
//    and barycentrics that interpolate E; radiance rho(x) / pi * E.
// The visible point, its flat face normal and its albedo come from the full scene (one primary ray
// through each pixel's centre); pixels that see nothing or a back face are masked out.
#pragma once

#include "camera/pinhole_camera.h"
#include "image/rgb_image.h"
#include "lighting/indirect_light_tracer.h"
#include "lighting/irradiance_vector_grid.h"
#include "progress/progress_callback.h"

#include <cstdint>
#include <vector>

namespace rad {

struct VisibleSurface {
    int width = 0, height = 0;
    std::vector<float> points, normals, albedo;  // 3 per pixel (zero where masked out)
    std::vector<std::uint8_t> mask;              // 1 = a front face is seen
    std::size_t visiblePixels() const;
};

VisibleSurface traceVisibleSurface(const IndirectLightTracer& tracer, const PinholeCamera& camera);

// The reference image (see the file comment). `raysPerPixel` >= 1.
ImageF renderIndirectReference(const IndirectLightTracer& tracer, const VisibleSurface& surface, int raysPerPixel,
                               std::uint64_t seed = 1, const ProgressCallback& progress = {}, int threads = 0);

// The grid's image, with the paper's directional weights or |n_a| (irradiance_vector_grid.h).
ImageF renderIndirectFromGrid(const IrradianceVectorGrid& grid, const VisibleSurface& surface,
                              DirectionalWeights weights = DirectionalWeights::Squared);

// E_ind (RGB, 3 per vertex) at the vertices of `mesh` (positions and unit normals required), each
// from raysPerVertex cosine-distributed rays leaving position + offset * normal, offset =
// relativeOffset times the tracer's scene diagonal (the simplified surface may lie slightly inside
// the full one).
std::vector<float> computeVertexIndirectIrradiance(const IndirectLightTracer& tracer, const TriangleMesh& mesh,
                                                   int raysPerVertex, double relativeOffset = 1e-3,
                                                   std::uint64_t seed = 1, const ProgressCallback& progress = {},
                                                   int threads = 0);
ImageF renderIndirectFromVertexIrradiance(const TriangleMesh& mesh, const std::vector<float>& vertexIrradiance,
                                          const VisibleSurface& surface);

struct IndirectImageError {
    std::size_t pixels = 0;
    double rmse = 0.0;           // linear radiance, all channels
    double meanReference = 0.0;  // mean of the reference over the same pixels and channels
    double relativeRmse() const { return meanReference > 0.0 ? rmse / meanReference : 0.0; }
};
IndirectImageError indirectImageError(const ImageF& image, const ImageF& reference, const std::vector<std::uint8_t>& mask);

}  // namespace rad
