// Per-triangle atlas and UV layout checks (texture_atlas.h).
//
// Layout of a cell (texel indices x to the right, y UP, relative to the cell's lower-left texel;
// every corner on a texel centre): with gutter g, margins m1 = floor((g - 1) / 2) and
// m2 = g - 1 - m1, cell size S and leg L = S - 1 - 2 g,
//   face 2k     (lower-left):  (m1, m1), (m1 + L, m1), (m1, m1 + L)
//   face 2k + 1 (upper-right): (R, R), (R - L, R), (R, R - L) with R = S - 1 - m2
// both counter-clockwise in UV. A texel square that meets (even at a point) a triangle whose
// corners lie on centres is within the triangle's corner columns/rows, or on the hypotenuse side
// with x + y <= 2 m1 + L + 1 (lower) / x + y >= 2 R - L - 1 (upper). Hence, between the texels
// the two charts of a cell touch, the index distance max(|dx|, |dy|) is at least
// (2 R - L - 1 - (2 m1 + L + 1)) / 2 = S - 2 - (m1 + m2) - L = g, and between neighbouring cells
// it is m1 + m2 + 1 = g (also across the texture's border, for a wrapping sampler): at least
// g - 1 empty texels separate any two charts.
#include "bake/texture_atlas.h"

#include "bake/texel_coverage.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace rad {

namespace {
constexpr int kMinLegTexels = 2;

int nextPowerOfTwo(long long n) {
    long long p = 1;
    while (p < n) p *= 2;
    return int(std::min<long long>(p, 1LL << 30));
}
}  // namespace

std::string textureSizeProblem(int size, int minSize, int maxSize) {
    std::ostringstream s;
    if (size < minSize || size > maxSize) {
        s << "Texture size " << size << " is outside [" << minSize << ", " << maxSize
          << "]; choose a power of two in that range";
        return s.str();
    }
    if ((size & (size - 1)) != 0) {
        s << "Texture size " << size << " is not a power of two; choose e.g. " << nextPowerOfTwo(size);
        return s.str();
    }
    return {};
}

std::size_t perTriangleAtlasCapacity(int textureSize, int gutterTexels) {
    if (gutterTexels < 1 || gutterTexels > 64 || textureSize <= 0) return 0;
    const std::size_t perSide = std::size_t(textureSize / (kMinLegTexels + 1 + 2 * gutterTexels));
    return 2 * perSide * perSide;
}

PerTriangleAtlas makePerTriangleAtlas(std::size_t faceCount, int textureSize, int gutterTexels) {
    if (faceCount == 0) throw BakeInputError("the mesh has no faces: there is nothing to lay out in a texture");
    const std::string sizeProblem = textureSizeProblem(textureSize);
    if (!sizeProblem.empty()) throw BakeInputError(sizeProblem);
    if (gutterTexels < 1 || gutterTexels > 64) {
        throw BakeInputError("the gutter between charts must be 1 to 64 texels (got " + std::to_string(gutterTexels) +
                             ")");
    }
    const int g = gutterTexels;
    const int m1 = (g - 1) / 2, m2 = g - 1 - m1;
    const int minCell = kMinLegTexels + 1 + 2 * g;
    const std::size_t cells = (faceCount + 1) / 2;
    long long perSide = (long long)std::ceil(std::sqrt(double(cells)));
    while (perSide * perSide < (long long)cells) ++perSide;
    while (perSide > 1 && (perSide - 1) * (perSide - 1) >= (long long)cells) --perSide;
    const long long cellSize = textureSize / perSide;
    if (cellSize < minCell) {
        const long long needed = perSide * minCell;
        std::ostringstream s;
        s << "a " << textureSize << " x " << textureSize << " texture is too small for a per-triangle atlas of "
          << faceCount << " faces with a " << g << "-texel gutter (each triangle needs legs of at least "
          << kMinLegTexels << " texels); ";
        if (needed <= 16384)
            s << "use a texture of at least " << nextPowerOfTwo(needed) << " x " << nextPowerOfTwo(needed);
        else
            s << "even 16384 x 16384 is too small: simplify the mesh further or give it a parametrization";
        throw BakeInputError(s.str());
    }

    PerTriangleAtlas atlas;
    atlas.cellSize = int(cellSize);
    atlas.cellsPerRow = int(textureSize / cellSize);
    atlas.gutterTexels = g;
    atlas.wedgeUv.resize(6 * faceCount);
    const int leg = atlas.cellSize - 1 - 2 * g;
    const int r = atlas.cellSize - 1 - m2;
    const int lower[3][2] = {{m1, m1}, {m1 + leg, m1}, {m1, m1 + leg}};
    const int upper[3][2] = {{r, r}, {r - leg, r}, {r, r - leg}};
    const double inverse = 1.0 / textureSize;
    for (std::size_t f = 0; f < faceCount; ++f) {
        const std::size_t cell = f / 2;
        const long long x0 = (long long)(cell % std::size_t(atlas.cellsPerRow)) * cellSize;
        const long long y0 = (long long)(cell / std::size_t(atlas.cellsPerRow)) * cellSize;
        const int(*corners)[2] = (f % 2 == 0) ? lower : upper;
        for (int k = 0; k < 3; ++k) {
            atlas.wedgeUv[6 * f + 2 * k] = float((double(x0 + corners[k][0]) + 0.5) * inverse);
            atlas.wedgeUv[6 * f + 2 * k + 1] = float((double(y0 + corners[k][1]) + 0.5) * inverse);
        }
    }
    return atlas;
}

std::string UvLayoutReport::problem() const {
    const std::string fix = "; MeshLab's \"Parametrization: Trivial Per-Triangle\" makes a layout that can be baked into";
    std::ostringstream s;
    if (faceCount == 0) return "the mesh has no faces to bake into";
    if (nonFiniteFaces > 0) {
        s << nonFiniteFaces << " of " << faceCount << " faces have NaN or infinite texture coordinates" << fix;
    } else if (outOfRangeFaces > 0) {
        s << outOfRangeFaces << " of " << faceCount << " faces have texture coordinates outside [0, 1]" << fix;
    } else if (degenerateFaces > 0) {
        s << degenerateFaces << " of " << faceCount
          << " faces have a degenerate texture triangle (area below a hundredth of a texel)" << fix;
    } else if (overlappingTexels > 0) {
        s << overlappingTexels << " texels lie inside two or more faces (overlapping charts)" << fix;
    }
    return s.str();
}

UvLayoutReport checkUvLayout(const float* wedgeUv, std::size_t faceCount, int textureSize) {
    UvLayoutReport report;
    report.faceCount = faceCount;
    if (faceCount == 0 || !wedgeUv || textureSize <= 0) return report;
    const double texelArea = 1.0 / (double(textureSize) * textureSize);
    for (std::size_t f = 0; f < faceCount; ++f) {
        const float* uv = wedgeUv + 6 * f;
        bool finite = true, inRange = true;
        for (int k = 0; k < 6; ++k) {
            finite = finite && std::isfinite(uv[k]);
            // Rounding in other tools' unwraps (Blender's torus has u = -4e-16) is not a layout
            // problem: a hundred-thousandth of the texture is under a texel at 16384^2.
            inRange = inRange && uv[k] >= -1e-5f && uv[k] <= 1.0f + 1e-5f;
        }
        if (!finite) {
            ++report.nonFiniteFaces;
            continue;
        }
        if (!inRange) ++report.outOfRangeFaces;
        const double area = 0.5 * std::fabs((double(uv[2]) - uv[0]) * (double(uv[5]) - uv[1]) -
                                            (double(uv[3]) - uv[1]) * (double(uv[4]) - uv[0]));
        if (area < 0.01 * texelArea) ++report.degenerateFaces;
    }
    report.overlappingTexels = rasterizeTexelCoverage(wedgeUv, faceCount, textureSize, textureSize).overlappingTexels;
    return report;
}

}  // namespace rad
