// Conservative rasterisation of a wedge UV layout (texel_coverage.h).
//
// Edge functions (Pineda, "A parallel algorithm for polygon rasterization", SIGGRAPH 1988) decide
// whether a texel centre is inside a face; the texel square overlaps the triangle when, for every
// edge, the square's corner farthest on the inner side is inside that edge's half plane and the
// bounding boxes overlap (separating axis theorem for two convex polygons: the square's axes are
// the box test, the triangle's edge normals the edge test; conservative rasterisation as in
// Hasselgren et al., GPU Gems 2, ch. 42). The nearest point of a triangle to a centre outside it:
// Ericson, Real-Time Collision Detection, sec. 5.1.5, in 2D.
//
// Work is split into bands of rows; each face is listed in the bands its rows span, and a band is
// rasterised by one thread, so no two threads write the same texel (deterministic output: within
// a band faces are visited in increasing index and ties keep the lower index).
#include "bake/texel_coverage.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace rad {

namespace {

constexpr int kBandRows = 16;

// A face's UV triangle in texel coordinates: x = u W (columns), y = (1 - v) H (rows, downwards).
// Edge function k (opposite corner k) is a[k] x + b[k] y + c[k], >= 0 inside, equal to
// barycentric k times twice the area.
struct TexelTriangle {
    double x[3], y[3];
    double a[3], b[3], c[3];
    double inverseArea2;       // 1 / |twice the area|
    double inverseLength[3];   // 1 / edge length (edge k opposite corner k)
    int column0, column1, row0, row1;  // texels whose square meets the bounding box (clipped)
};

// Minimum |twice the area| in texel^2 for a face to be rasterised.
constexpr double kMinArea2 = 1e-6;

bool setupTriangle(const float* uv, int width, int height, TexelTriangle& t) {
    for (int k = 0; k < 3; ++k) {
        const double u = uv[2 * k], v = uv[2 * k + 1];
        if (!std::isfinite(u) || !std::isfinite(v)) return false;
        t.x[k] = u * width;
        t.y[k] = (1.0 - v) * height;
    }
    const double area2 = (t.x[1] - t.x[0]) * (t.y[2] - t.y[0]) - (t.y[1] - t.y[0]) * (t.x[2] - t.x[0]);
    if (!(std::fabs(area2) >= kMinArea2)) return false;
    const double orientation = area2 > 0 ? 1.0 : -1.0;
    for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;  // edge i -> j, opposite k
        // cross(p_j - p_i, x - p_i), positive on the side of p_k for a counter-clockwise triangle
        const double a = -(t.y[j] - t.y[i]), b = t.x[j] - t.x[i];
        t.a[k] = orientation * a;
        t.b[k] = orientation * b;
        t.c[k] = -orientation * (a * t.x[i] + b * t.y[i]);
        const double length = std::sqrt(a * a + b * b);
        t.inverseLength[k] = length > 0 ? 1.0 / length : 0.0;
    }
    t.inverseArea2 = 1.0 / std::fabs(area2);
    const double xMin = std::min({t.x[0], t.x[1], t.x[2]}), xMax = std::max({t.x[0], t.x[1], t.x[2]});
    const double yMin = std::min({t.y[0], t.y[1], t.y[2]}), yMax = std::max({t.y[0], t.y[1], t.y[2]});
    // The reach square of texel c spans [c + 0.5 - R, c + 0.5 + R]: it meets [xMin, xMax] for
    // xMin - 0.5 - R < c < xMax - 0.5 + R. Exactly these: with the three edge tests below this
    // is the separating-axis test of square against triangle (axes x, y and the edge normals).
    const double reach = TexelCoverage::kBilinearReach;
    const double lo = -1.0, hiX = double(width), hiY = double(height);
    t.column0 = int(std::max(lo, std::floor(xMin - 0.5 - reach) + 1));
    t.column1 = int(std::min(hiX, std::ceil(xMax - 0.5 + reach))) - 1;
    t.row0 = int(std::max(lo, std::floor(yMin - 0.5 - reach) + 1));
    t.row1 = int(std::min(hiY, std::ceil(yMax - 0.5 + reach))) - 1;
    t.column0 = std::max(t.column0, 0);
    t.row0 = std::max(t.row0, 0);
    return t.column0 <= t.column1 && t.row0 <= t.row1;
}

// Nearest point of the triangle to (px, py): its barycentrics (on corners 1 and 2) and squared
// distance. Ericson 5.1.5 (Voronoi regions of corners, edges, interior), in 2D.
double nearestOnTriangle(const TexelTriangle& t, double px, double py, double& b1, double& b2) {
    const double abx = t.x[1] - t.x[0], aby = t.y[1] - t.y[0];
    const double acx = t.x[2] - t.x[0], acy = t.y[2] - t.y[0];
    const double apx = px - t.x[0], apy = py - t.y[0];
    const auto distance2 = [&](double s1, double s2) {
        const double qx = t.x[0] + s1 * abx + s2 * acx - px, qy = t.y[0] + s1 * aby + s2 * acy - py;
        b1 = s1;
        b2 = s2;
        return qx * qx + qy * qy;
    };
    const double d1 = abx * apx + aby * apy, d2 = acx * apx + acy * apy;
    if (d1 <= 0 && d2 <= 0) return distance2(0, 0);
    const double bpx = px - t.x[1], bpy = py - t.y[1];
    const double d3 = abx * bpx + aby * bpy, d4 = acx * bpx + acy * bpy;
    if (d3 >= 0 && d4 <= d3) return distance2(1, 0);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return distance2(d1 / (d1 - d3), 0);
    const double cpx = px - t.x[2], cpy = py - t.y[2];
    const double d5 = abx * cpx + aby * cpy, d6 = acx * cpx + acy * cpy;
    if (d6 >= 0 && d5 <= d6) return distance2(0, 1);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return distance2(0, d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const double s = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return distance2(1 - s, s);
    }
    const double inverse = 1.0 / (va + vb + vc);
    return distance2(vb * inverse, vc * inverse);
}

}  // namespace

std::size_t TexelCoverage::coveredCount() const {
    std::size_t n = 0;
    for (const std::int32_t f : face) n += f >= 0;
    return n;
}

TexelCoverage rasterizeTexelCoverage(const float* wedgeUv, std::size_t faceCount, int width, int height) {
    TexelCoverage coverage;
    if (width <= 0 || height <= 0) return coverage;
    coverage.width = width;
    coverage.height = height;
    const std::size_t texels = std::size_t(width) * std::size_t(height);
    coverage.face.resize(texels);
    coverage.barycentric.resize(2 * texels);
    coverage.interior.resize(texels);
    if (!wedgeUv) faceCount = 0;

    // Bucket the faces by band (CSR: counts, prefix sums, fill), in increasing face order.
    const int bands = (height + kBandRows - 1) / kBandRows;
    std::vector<std::size_t> bandStart(std::size_t(bands) + 1, 0);
    std::vector<int> faceBands(2 * faceCount, -1);  // first and last band of each face (-1: none)
    for (std::size_t f = 0; f < faceCount; ++f) {
        TexelTriangle t;
        if (!setupTriangle(wedgeUv + 6 * f, width, height, t)) continue;
        faceBands[2 * f] = t.row0 / kBandRows;
        faceBands[2 * f + 1] = t.row1 / kBandRows;
        for (int b = faceBands[2 * f]; b <= faceBands[2 * f + 1]; ++b) ++bandStart[std::size_t(b) + 1];
    }
    for (int b = 0; b < bands; ++b) bandStart[std::size_t(b) + 1] += bandStart[std::size_t(b)];
    std::vector<std::uint32_t> bandFaces(bandStart.back());
    {
        std::vector<std::size_t> cursor(bandStart.begin(), bandStart.end() - 1);
        for (std::size_t f = 0; f < faceCount; ++f)
            for (int b = faceBands[2 * f]; b >= 0 && b <= faceBands[2 * f + 1]; ++b)
                bandFaces[cursor[std::size_t(b)]++] = std::uint32_t(f);
    }

    std::size_t overlapping = 0;
    const double strict = TexelCoverage::kStrictInsideTexels;
#pragma omp parallel reduction(+ : overlapping)
    {
        // Per thread, reused by every band: the winning key per texel (interior: -1 - distance to
        // the nearest edge, so more inside is smaller; touched: distance to the triangle >= 0) and
        // the number of faces whose interior strictly contains the centre.
        std::vector<float> key(std::size_t(kBandRows) * width);
        std::vector<std::uint8_t> strictlyInside(std::size_t(kBandRows) * width);
#pragma omp for schedule(dynamic, 1)
        for (int band = 0; band < bands; ++band) {
            const int rowBegin = band * kBandRows, rowEnd = std::min(height, rowBegin + kBandRows);
            const std::size_t first = coverage.texelIndex(0, rowBegin), last = coverage.texelIndex(0, rowEnd);
            std::fill(coverage.face.begin() + first, coverage.face.begin() + last, -1);
            std::fill(key.begin(), key.end(), std::numeric_limits<float>::infinity());
            std::fill(strictlyInside.begin(), strictlyInside.end(), std::uint8_t(0));
            std::int32_t* faceOut = coverage.face.data();
            float* barycentricOut = coverage.barycentric.data();
            std::uint8_t* interiorOut = coverage.interior.data();

            for (std::size_t k = bandStart[std::size_t(band)]; k < bandStart[std::size_t(band) + 1]; ++k) {
                const std::uint32_t f = bandFaces[k];
                TexelTriangle t;
                setupTriangle(wedgeUv + 6 * std::size_t(f), width, height, t);
                // Edge-function offset of the corner of the square of half-size kBilinearReach
                // around the centre that lies farthest inside each edge.
                const double r = TexelCoverage::kBilinearReach;
                const double halfExtent[3] = {r * (std::fabs(t.a[0]) + std::fabs(t.b[0])),
                                              r * (std::fabs(t.a[1]) + std::fabs(t.b[1])),
                                              r * (std::fabs(t.a[2]) + std::fabs(t.b[2]))};
                const int r0 = std::max(t.row0, rowBegin), r1 = std::min(t.row1, rowEnd - 1);
                for (int r = r0; r <= r1; ++r) {
                    const double py = r + 0.5;
                    const std::size_t local = std::size_t(r - rowBegin) * width;
                    for (int c = t.column0; c <= t.column1; ++c) {
                        const double px = c + 0.5;
                        const double e0 = t.a[0] * px + t.b[0] * py + t.c[0];
                        const double e1 = t.a[1] * px + t.b[1] * py + t.c[1];
                        const double e2 = t.a[2] * px + t.b[2] * py + t.c[2];
                        // The square overlaps the triangle unless it lies wholly outside an edge.
                        if (!(e0 + halfExtent[0] > 0 && e1 + halfExtent[1] > 0 && e2 + halfExtent[2] > 0)) continue;
                        float candidate;
                        double b1, b2;
                        const bool inside = e0 >= 0 && e1 >= 0 && e2 >= 0;
                        if (inside) {
                            const double margin = std::min({e0 * t.inverseLength[0], e1 * t.inverseLength[1],
                                                            e2 * t.inverseLength[2]});
                            if (margin > strict && strictlyInside[local + c] < 255) ++strictlyInside[local + c];
                            candidate = float(-1.0 - margin);
                            b1 = e1 * t.inverseArea2;
                            b2 = e2 * t.inverseArea2;
                        } else {
                            candidate = float(std::sqrt(nearestOnTriangle(t, px, py, b1, b2)));
                        }
                        if (!(candidate < key[local + c])) continue;  // ties keep the lower face index
                        key[local + c] = candidate;
                        const std::size_t texel = coverage.texelIndex(c, r);
                        faceOut[texel] = std::int32_t(f);
                        barycentricOut[2 * texel] = float(b1);
                        barycentricOut[2 * texel + 1] = float(b2);
                        interiorOut[texel] = inside ? 1 : 0;
                    }
                }
            }
            for (std::size_t i = 0; i < std::size_t(rowEnd - rowBegin) * width; ++i)
                overlapping += strictlyInside[i] >= 2;
        }
    }
    coverage.overlappingTexels = overlapping;
    return coverage;
}

}  // namespace rad
