// Which face each texel of a texture belongs to, and where on that face its centre lies: the
// rasterisation of a wedge UV layout that the baker walks (conventions: texture_atlas.h).
//
// Conservative: a texel is covered by a face when the face's UV triangle overlaps the texel's
// square, not only when it contains the centre, so that bilinear filtering at a chart's border
// reads texels baked from the chart itself. A texel whose centre lies inside a face belongs to
// that face (interior); a texel only touched belongs to the face whose triangle is nearest to its
// centre, and its barycentrics are those of the nearest point of that triangle (clamped), so the
// baked value is the chart's value at its border.
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

    std::size_t texelIndex(int column, int row) const { return std::size_t(row) * width + column; }
    std::size_t coveredCount() const;
};

// Faces with a non-finite or degenerate UV triangle cover nothing. Parallel over rows.
TexelCoverage rasterizeTexelCoverage(const float* wedgeUv, std::size_t faceCount, int width, int height);

}  // namespace rad
