// Which face each texel of a texture belongs to, and where on that face its centre lies: the
// rasterisation of a wedge UV layout that the baker walks (conventions: texture_atlas.h).
//
// Conservative to the reach of bilinear filtering: a texel is covered by a face when the face's UV
// triangle overlaps the square of half-size kBilinearReach (1 texel) around the texel's centre,
// i.e. when a bilinear lookup at some point of the face reads that texel. So a lookup anywhere in
// a face reads texels baked from the face (or from a nearer one), never a filled-in blend. A
// texel whose centre lies inside a face belongs to that face (interior); a texel only reached
// belongs to the face whose triangle is nearest to its centre, and its barycentrics are those of
// the nearest point of that triangle (clamped), so the baked value is the chart's value at its
// border. (Measured on a MeshLab "Trivial Per-Triangle" layout, whose triangles are two texels
// apart with corners on texel corners: with the half-texel footprint the gap texels were dilation
// blends of both neighbours, and the map's mean error against the scan was 1.71 degrees instead
// of 0.6x; see the README.)
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rad {

struct TexelCoverage {
    int width = 0, height = 0;
    std::vector<std::int32_t> face;       // per texel (row-major, rows top to bottom); -1 = empty
    std::vector<float> barycentric;       // 2 per texel: (b1, b2), point = (1-b1-b2) p0 + b1 p1 + b2 p2
    std::vector<std::uint8_t> interior;   // per texel: 1 when the centre is inside its face
    // Texel centres strictly inside two or more faces, farther than kStrictInsideTexels from the
    // edges of each (so that centres on a shared edge do not count): what checkUvLayout reports.
    std::size_t overlappingTexels = 0;
    static constexpr double kStrictInsideTexels = 1e-2;
    static constexpr double kBilinearReach = 1.0;

    std::size_t texelIndex(int column, int row) const { return std::size_t(row) * width + column; }
    std::size_t coveredCount() const;
};

// Faces with a non-finite or degenerate UV triangle cover nothing. Parallel over rows.
TexelCoverage rasterizeTexelCoverage(const float* wedgeUv, std::size_t faceCount, int width, int height);

}  // namespace rad
