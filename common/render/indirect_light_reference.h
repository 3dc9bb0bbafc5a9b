// CPU images of the INDIRECT light of a diffuse scene seen by a camera, to judge the irradiance
// vector grid (Granier et al. 2007) against a reference and against the alternative a user would
// pick, per-vertex irradiance on a simplified mesh. Every image is the radiance reflected toward the
// camera by the indirect light only, at the same visible points (one primary ray per pixel centre;
// pixels that see nothing or a back face are masked out): the reference by path tracing
// (lighting/indirect_light_tracer.h), the grid's interpolation, and per-vertex irradiance.
// Details: docs/irradiance-vector-grid.md, "`common/render/indirect_light_reference.h`: how it works".
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

// The reference image: per pixel rho / N * sum L_ind(x <- w_i) over N = `raysPerPixel` >= 1
// cosine-distributed directions.
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
