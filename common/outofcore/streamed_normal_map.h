// A normal map of a simplified mesh made by streaming the ORIGINAL points through it (Granier et
// al. 2007, out-of-core part): each point finds its nearest simplified triangle (Embree's BVH,
// raycast/ray_scene.h) and its unit normal is added to the texel there; texels average what they
// received, and the rest is filled. Unlike the in-core bake, nothing here needs the original mesh in
// memory: points come in chunks, in any order, and only the map's accumulators (16 bytes per texel)
// and the simplified mesh's hierarchy are kept.
// Details: docs/out-of-core.md, "`common/outofcore/streamed_normal_map.h`: how it works".
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
