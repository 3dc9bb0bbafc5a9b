// A normal map of a simplified mesh made by streaming the ORIGINAL points through it (Granier et
// al. 2007, out-of-core part): the simplified triangles are put in a bounding-volume hierarchy
// (Embree's, through raycast/ray_scene.h's closest-point query: the simplified mesh is small, a
// million triangles take ~100 MB, and Embree's BVH is already built and tested there), each
// original point finds its nearest simplified triangle, the point of that triangle whose
// interpolated normal passes through it (a ray-cast bake's correspondence; the closest point when
// that leaves the triangle), and its unit normal is added to the texel there. Texels average what
// they received (then renormalised). Texels of a triangle that received nothing grow from their
// neighbours of the same triangle; triangles no point reached take the points' normals gathered at
// the simplified vertices, interpolated; the gutters and the background are filled like an in-core
// bake (bake/normal_map_bake.h fillBakedMap: pull-push, Gortler et al. 1996, the diffusion of
// Granier et al.).
//
// Unlike the in-core bake (rays from each texel centre), nothing here needs the original mesh in
// memory: the points come in chunks, in any order, and only the map's accumulators are kept
// (16 bytes per texel) plus the simplified mesh's hierarchy.
#pragma once

#include "geometry/triangle_mesh.h"
#include "progress/progress_callback.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace rad {

struct StreamedNormalMap {
    int size = 0;
    std::vector<float> normals;          // 3 per texel, unit, rows top to bottom, every texel filled
    std::vector<std::uint8_t> valid;     // 1 where points landed (before filling)
    std::vector<std::uint8_t> chart;     // 1 where a face covers the texel (texel_coverage.h)
    std::size_t pointsSplatted = 0;
    std::size_t pointsWithoutNormal = 0; // zero or non-finite normals, skipped
    std::size_t chartTexels = 0, texelsWithPoints = 0, chartTexelsFilled = 0;
};

class NormalSplatter {
public:
    // target: the simplified mesh; wedgeUv: 6 floats per face in [0, 1] (texture_atlas.h); a square
    // map of `size` texels. Throws std::invalid_argument for an empty target or mismatched arrays.
    NormalSplatter(const TriangleMesh& target, const std::vector<float>& wedgeUv, int size);
    ~NormalSplatter();
    NormalSplatter(const NormalSplatter&) = delete;
    NormalSplatter& operator=(const NormalSplatter&) = delete;

    // Adds `count` points with their normals (3 floats each; need not be unit). Parallel (OpenMP).
    void splat(const float* positions, const float* normals, std::size_t count);
    // Averages, fills (gutterRings of dilation around the charts) and returns the map.
    StreamedNormalMap finish(int gutterRings = 4);

private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace rad
