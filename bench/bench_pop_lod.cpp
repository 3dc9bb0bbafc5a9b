// bench_pop_lod: popping of the POP buffer (Limper et al. 2013) at its level switches, with and
// without the texture-coordinate correction of Weber & Stamminger (Alg. 1). Prints figures, never
// asserts.
//
// A renderer that keeps a snapped vertex within `tolerance` pixels of its place draws level L while
// the bounding box's diagonal covers at most tolerance * 2^(L+1) pixels (popLevelForScreenSize), so
// it switches from L to L+1 at that size. For each L, levels L and L+1 are rendered at that size
// (orthographic, the diagonal spanning the image) and compared: RMSE in 8-bit levels over the
// pixels both images cover (where texture sliding shows; silhouettes change with or without the
// correction) and over all pixels, plus each level's RMSE against the full mesh at the same size.
//
// Scenes:
//  (a) scan: a real scan (default the armadillo of the data cache, 52k faces) with the per-triangle
//      atlas of the "Bake Normal Map" filter and its object-space normal map baked from itself
//      (bake/normal_baker.h, holes and gutters filled as the filter does), shaded Lambert from the
//      map under a light from the viewer's upper left. The atlas cuts every triangle apart: each
//      corner is corrected with its own triangle's tangent space only.
//  (b) hood: a car-hood-like sheet z = 0.15 sin(3x) cos(2y) on a jittered 160 x 160 grid, one
//      continuous chart uv = (x, y), a checker texture of 24 x 24 squares (1024^2): the case the
//      correction is made for.
//  (c) glossy hood: the same sheet with an object-space normal map of itself plus fine ripples
//      (period 1/48), Blinn-Phong with exponent 80 (a car-paint-like highlight).
// The CPU rasteriser samples the maps with trilinear mip-mapping (per-triangle footprint).
//
// Usage: bench_pop_lod [--mesh armadillo.off] [--tolerance PIXELS] [--map-size N] [--min-size PX]
//                      [--max-size PX]
// Defaults: --mesh $RADIANCE_DATA_CACHE/meshes/armadillo.off (else <repo>/data-cache/...),
//           --tolerance 1, --map-size 2048, --min-size 64, --max-size 2048.
#include "bake/map_filling.h"
#include "bake/normal_baker.h"
#include "bake/texture_atlas.h"
#include "geometry/mesh_normals.h"
#include "io/off_reader.h"
#include "lod/pop_buffer.h"
#include "lod/pop_level.h"
#include "lod/texcoord_correction.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

namespace {

// A mip-mapped float texture (rows top to bottom, texel (x, y) at u = (x + .5) / W, v = 1 - (y + .5) / H).
struct MipTexture {
    int channels = 3;
    std::vector<int> sizes;
    std::vector<std::vector<float>> levels;

    MipTexture(std::vector<float> base, int size, int ch) : channels(ch) {
        sizes.push_back(size);
        levels.push_back(std::move(base));
        while (sizes.back() > 1) {
            const int s = sizes.back() / 2;
            const std::vector<float>& up = levels.back();
            std::vector<float> down(std::size_t(s) * s * ch);
            for (int y = 0; y < s; ++y)
                for (int x = 0; x < s; ++x)
                    for (int c = 0; c < ch; ++c) {
                        const auto at = [&](int xx, int yy) { return up[(std::size_t(yy) * 2 * s + xx) * ch + c]; };
                        down[(std::size_t(y) * s + x) * ch + c] =
                            0.25f * (at(2 * x, 2 * y) + at(2 * x + 1, 2 * y) + at(2 * x, 2 * y + 1) + at(2 * x + 1, 2 * y + 1));
                    }
            sizes.push_back(s);
            levels.push_back(std::move(down));
        }
    }
    void bilinear(int level, double u, double v, float* out) const {
        const int s = sizes[level];
        const double x = u * s - 0.5, y = (1.0 - v) * s - 0.5;
        const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
        const double fx = x - x0, fy = y - y0;
        for (int c = 0; c < channels; ++c) out[c] = 0;
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i) {
                const int xi = std::clamp(x0 + i, 0, s - 1), yj = std::clamp(y0 + j, 0, s - 1);
                const double w = (i ? fx : 1 - fx) * (j ? fy : 1 - fy);
                for (int c = 0; c < channels; ++c) out[c] += float(w * levels[level][(std::size_t(yj) * s + xi) * channels + c]);
            }
    }
    // Trilinear sample for a footprint of `texels` level-0 texels per pixel.
    void sample(double u, double v, double texels, float* out) const {
        const double lod = std::clamp(std::log2(std::max(texels, 1e-9)), 0.0, double(sizes.size() - 1));
        const int l0 = int(std::floor(lod));
        const int l1 = std::min(l0 + 1, int(sizes.size()) - 1);
        const float t = float(lod - l0);
        float a[4], b[4];
        bilinear(l0, u, v, a);
        bilinear(l1, u, v, b);
        for (int c = 0; c < channels; ++c) out[c] = (1 - t) * a[c] + t * b[c];
    }
};

enum class Shading { NormalMapLambert, NormalMapGlossy, Color };

struct View {
    Eigen::Vector3d right, up, forward, center;
    double diagonal = 1;
};

// Renders `mesh` with wedge coordinates into a size x size gray image (0..255, background 0) and a
// coverage mask; the box diagonal spans the image.
void render(const rad::TriangleMesh& mesh, const std::vector<float>& uv, const MipTexture& texture, Shading shading,
            const View& view, int size, std::vector<float>& image, std::vector<std::uint8_t>& covered) {
    image.assign(std::size_t(size) * size, 0.0f);
    covered.assign(std::size_t(size) * size, 0);
    std::vector<float> depth(std::size_t(size) * size, std::numeric_limits<float>::infinity());
    const double scale = size / view.diagonal;
    const Eigen::Vector3d light = (-0.4 * view.right + 0.5 * view.up - view.forward).normalized();
    for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
        double sx[3], sy[3], sz[3];
        for (int k = 0; k < 3; ++k) {
            const float* p = &mesh.positions[3 * mesh.faces[3 * f + k]];
            const Eigen::Vector3d q = Eigen::Vector3d(p[0], p[1], p[2]) - view.center;
            sx[k] = q.dot(view.right) * scale + 0.5 * size;
            sy[k] = -q.dot(view.up) * scale + 0.5 * size;
            sz[k] = q.dot(view.forward);
        }
        const double area = (sx[1] - sx[0]) * (sy[2] - sy[0]) - (sx[2] - sx[0]) * (sy[1] - sy[0]);
        if (std::fabs(area) < 1e-12) continue;
        const float* t = &uv[6 * f];
        // Texture footprint: the affine screen -> uv map of the triangle.
        const double dudx = ((t[2] - t[0]) * (sy[2] - sy[0]) - (t[4] - t[0]) * (sy[1] - sy[0])) / area;
        const double dudy = ((t[4] - t[0]) * (sx[1] - sx[0]) - (t[2] - t[0]) * (sx[2] - sx[0])) / area;
        const double dvdx = ((t[3] - t[1]) * (sy[2] - sy[0]) - (t[5] - t[1]) * (sy[1] - sy[0])) / area;
        const double dvdy = ((t[5] - t[1]) * (sx[1] - sx[0]) - (t[3] - t[1]) * (sx[2] - sx[0])) / area;
        const double footprint =
            texture.sizes[0] * std::max(std::hypot(dudx, dvdx), std::hypot(dudy, dvdy));
        const int x0 = std::max(0, int(std::floor(std::min({sx[0], sx[1], sx[2]}))));
        const int x1 = std::min(size - 1, int(std::ceil(std::max({sx[0], sx[1], sx[2]}))));
        const int y0 = std::max(0, int(std::floor(std::min({sy[0], sy[1], sy[2]}))));
        const int y1 = std::min(size - 1, int(std::ceil(std::max({sy[0], sy[1], sy[2]}))));
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const double px = x + 0.5, py = y + 0.5;
                const double w0 = ((sx[1] - px) * (sy[2] - py) - (sx[2] - px) * (sy[1] - py)) / area;
                const double w1 = ((sx[2] - px) * (sy[0] - py) - (sx[0] - px) * (sy[2] - py)) / area;
                const double w2 = 1 - w0 - w1;
                if (w0 < 0 || w1 < 0 || w2 < 0) continue;
                const float z = float(w0 * sz[0] + w1 * sz[1] + w2 * sz[2]);
                const std::size_t i = std::size_t(y) * size + x;
                if (z >= depth[i]) continue;
                depth[i] = z;
                const double u = w0 * t[0] + w1 * t[2] + w2 * t[4], v = w0 * t[1] + w1 * t[3] + w2 * t[5];
                float value[3];
                texture.sample(u, v, footprint, value);
                float gray;
                if (shading == Shading::NormalMapLambert) {
                    const Eigen::Vector3d n = Eigen::Vector3d(value[0], value[1], value[2]).normalized();
                    gray = float(255.0 * (0.1 + 0.9 * std::max(0.0, n.dot(light))));
                } else if (shading == Shading::NormalMapGlossy) {
                    // Blinn-Phong, exponent 80: a car paint's sharp highlight (orthographic eye).
                    const Eigen::Vector3d n = Eigen::Vector3d(value[0], value[1], value[2]).normalized();
                    const Eigen::Vector3d h = (light - view.forward).normalized();
                    const double ndl = n.dot(light);
                    const double spec = ndl > 0 ? std::pow(std::max(0.0, n.dot(h)), 80.0) : 0.0;
                    gray = float(255.0 * std::min(1.0, 0.05 + 0.35 * std::max(0.0, ndl) + 0.8 * spec));
                } else {
                    gray = 255.0f * value[0];
                }
                image[i] = gray;
                covered[i] = 1;
            }
    }
}

struct Difference {
    double both = 0, all = 0;
};

Difference rmse(const std::vector<float>& a, const std::vector<std::uint8_t>& ca, const std::vector<float>& b,
                const std::vector<std::uint8_t>& cb) {
    double sumBoth = 0, sumAll = 0;
    std::size_t nBoth = 0, nAll = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (!ca[i] && !cb[i]) continue;
        const double d = double(a[i]) - b[i];
        sumAll += d * d;
        ++nAll;
        if (ca[i] && cb[i]) {
            sumBoth += d * d;
            ++nBoth;
        }
    }
    return {nBoth ? std::sqrt(sumBoth / nBoth) : 0.0, nAll ? std::sqrt(sumAll / nAll) : 0.0};
}

View viewOf(const rad::TriangleMesh& mesh, const Eigen::Vector3d& forward, const Eigen::Vector3d& upHint) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e30), hi = -lo;
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], double(mesh.positions[3 * v + k]));
            hi[k] = std::max(hi[k], double(mesh.positions[3 * v + k]));
        }
    View view;
    view.forward = forward.normalized();
    view.right = view.forward.cross(upHint).normalized();
    view.up = view.right.cross(view.forward);
    view.center = 0.5 * (lo + hi);
    view.diagonal = (hi - lo).norm();
    return view;
}

void runScene(const char* name, const rad::TriangleMesh& mesh, const std::vector<float>& uv, const MipTexture& texture,
              Shading shading, const View& view, double tolerance, int minSize, int maxSize) {
    const rad::PopBuffer pop = rad::buildPopBuffer(mesh);
    const rad::TexCoordDerivatives derivatives = rad::computeTexCoordDerivatives(mesh, uv);
    std::printf("\n(%s) %zu vertices, %zu faces, %zu texture vertices (%zu without a tangent space); tolerance %.3g px\n",
                name, mesh.vertexCount(), mesh.faceCount(), derivatives.textureVertices, derivatives.withoutTangentSpace,
                tolerance);
    std::printf("%5s %7s %9s %9s | %-23s | %-23s | %-23s\n", "L->L+1", "px", "faces L", "faces L+1",
                "pop RMSE (covered/all)", "L vs full (covered)", "L+1 vs full (covered)");
    std::printf("%5s %7s %9s %9s | %11s %11s | %11s %11s | %11s %11s\n", "", "", "", "", "plain", "corrected", "plain",
                "corrected", "plain", "corrected");
    for (int level = rad::kPopMinLevel; level < rad::kPopMaxLevel; ++level) {
        const int size = int(std::lround(tolerance * double(1u << (level + 1))));
        if (size < minSize) continue;
        if (size > maxSize) break;
        std::vector<float> full, img[2][2];
        std::vector<std::uint8_t> fullCov, cov[2][2];
        render(mesh, uv, texture, shading, view, size, full, fullCov);
        std::size_t faces[2] = {0, 0};
        for (int next = 0; next < 2; ++next)
            for (int corrected = 0; corrected < 2; ++corrected) {
                rad::PopLevelRequest request;
                request.mesh = &mesh;
                request.pop = &pop;
                request.level = level + next;
                request.wedgeUv = &uv;
                request.correction = corrected ? &derivatives : nullptr;
                const rad::PopLevelMesh lod = rad::evaluatePopLevel(request);
                faces[next] = lod.mesh.faceCount();
                render(lod.mesh, lod.wedgeUv, texture, shading, view, size, img[next][corrected], cov[next][corrected]);
            }
        const Difference popPlain = rmse(img[0][0], cov[0][0], img[1][0], cov[1][0]);
        const Difference popCorrected = rmse(img[0][1], cov[0][1], img[1][1], cov[1][1]);
        std::printf("%2d->%-2d %7d %9zu %9zu | %5.2f/%5.2f %5.2f/%5.2f | %11.2f %11.2f | %11.2f %11.2f\n", level,
                    level + 1, size, faces[0], faces[1], popPlain.both, popPlain.all, popCorrected.both,
                    popCorrected.all, rmse(img[0][0], cov[0][0], full, fullCov).both,
                    rmse(img[0][1], cov[0][1], full, fullCov).both, rmse(img[1][0], cov[1][0], full, fullCov).both,
                    rmse(img[1][1], cov[1][1], full, fullCov).both);
        std::fflush(stdout);
    }
}

// A curved sheet z = 0.15 sin(3x) cos(2y) over the unit square, 160 x 160 vertices jittered inside
// (deterministic for `seed`), with one continuous chart: uv = (x, y), as wedge coordinates.
void makeHood(unsigned seed, rad::TriangleMesh& hood, std::vector<float>& uv) {
    const int n = 160;
    std::vector<float> uvPerVertex;
    unsigned state = seed;
    const auto jitter = [&]() {
        state = state * 1664525u + 1013904223u;
        return (double(state >> 8) / double(1u << 24) - 0.5) * 0.6;
    };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const bool border = i == 0 || j == 0 || i == n - 1 || j == n - 1;
            const double x = (i + (border ? 0 : jitter())) / (n - 1), y = (j + (border ? 0 : jitter())) / (n - 1);
            hood.positions.insert(hood.positions.end(), {float(x), float(y), float(0.15 * std::sin(3 * x) * std::cos(2 * y))});
            uvPerVertex.insert(uvPerVertex.end(), {float(x), float(y)});
        }
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            const std::uint32_t a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
            hood.faces.insert(hood.faces.end(), {a, b, c, a, c, d});
        }
    for (std::uint32_t v : hood.faces) uv.insert(uv.end(), {uvPerVertex[2 * v], uvPerVertex[2 * v + 1]});
}

}  // namespace

int main(int argc, char** argv) {
    const char* cache = std::getenv("RADIANCE_DATA_CACHE");
    std::string meshPath = (cache ? std::string(cache) : std::string(RADIANCE_SOURCE_DIR) + "/data-cache") +
                           "/meshes/armadillo.off";
    double tolerance = 1.0;
    int mapSize = 2048, minSize = 64, maxSize = 2048;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string a = argv[i];
        if (a == "--mesh") meshPath = argv[i + 1];
        else if (a == "--tolerance") tolerance = std::atof(argv[i + 1]);
        else if (a == "--map-size") mapSize = std::atoi(argv[i + 1]);
        else if (a == "--min-size") minSize = std::atoi(argv[i + 1]);
        else if (a == "--max-size") maxSize = std::atoi(argv[i + 1]);
        else {
            std::fprintf(stderr, "unknown option %s\n", a.c_str());
            return 2;
        }
    }
    try {
        std::printf("bench_pop_lod: POP-buffer popping at the level switches, without / with the texture-coordinate "
                    "correction (RMSE in 8-bit levels)\n");
        {   // (b) hood: one continuous chart and a checker texture.
            rad::TriangleMesh hood;
            std::vector<float> uv;
            makeHood(12345u, hood, uv);
            const int texSize = 1024;
            std::vector<float> checker(std::size_t(texSize) * texSize);
            for (int y = 0; y < texSize; ++y)
                for (int x = 0; x < texSize; ++x)
                    checker[std::size_t(y) * texSize + x] = ((x * 24 / texSize + y * 24 / texSize) % 2) ? 0.9f : 0.15f;
            const MipTexture texture(checker, texSize, 1);
            runScene("hood: continuous chart, checker texture", hood, uv, texture, Shading::Color,
                     viewOf(hood, Eigen::Vector3d(0.3, 0.5, -1.0), Eigen::Vector3d(0, 1, 0)), tolerance, minSize,
                     maxSize);
        }
        {   // (c) glossy hood: the same sheet, one chart, an object-space normal map of the sheet with
            // fine ripples (period 1/48), Blinn-Phong: the highlight and the ripples should not slide.
            rad::TriangleMesh hood;
            std::vector<float> uv;
            makeHood(777u, hood, uv);
            const int texSize = 1024;
            const double pi = 3.14159265358979323846, w = 2 * pi * 48, ripple = 0.004;
            std::vector<float> normalMap(std::size_t(texSize) * texSize * 3);
            for (int r = 0; r < texSize; ++r)
                for (int c = 0; c < texSize; ++c) {
                    const double x = (c + 0.5) / texSize, y = 1.0 - (r + 0.5) / texSize;  // uv = (x, y)
                    const double dzdx = 0.45 * std::cos(3 * x) * std::cos(2 * y) + ripple * w * std::cos(w * x) * std::sin(w * y);
                    const double dzdy = -0.3 * std::sin(3 * x) * std::sin(2 * y) + ripple * w * std::sin(w * x) * std::cos(w * y);
                    const Eigen::Vector3d nn = Eigen::Vector3d(-dzdx, -dzdy, 1.0).normalized();
                    for (int k = 0; k < 3; ++k) normalMap[(std::size_t(r) * texSize + c) * 3 + k] = float(nn[k]);
                }
            const MipTexture texture(normalMap, texSize, 3);
            runScene("glossy hood: continuous chart, rippled object-space normal map, Blinn-Phong", hood, uv, texture,
                     Shading::NormalMapGlossy, viewOf(hood, Eigen::Vector3d(0.3, 0.5, -1.0), Eigen::Vector3d(0, 1, 0)),
                     tolerance, minSize, maxSize);
        }
        {   // (a) scan: per-triangle atlas, normal map baked from the scan itself.
            rad::TriangleMesh scan = rad::readOff(meshPath);
            rad::computeAreaWeightedNormals(scan);
            const rad::PerTriangleAtlas atlas = rad::makePerTriangleAtlas(scan.faceCount(), mapSize);
            rad::NormalBakeOptions options;
            options.width = options.height = mapSize;
            rad::NormalBakeResult bake = rad::bakeNormalMap(scan, atlas.wedgeUv.data(), scan, nullptr, options);
            rad::fillByPullPush(bake.normals.data(), 3, mapSize, mapSize, bake.valid, bake.chart.data());
            rad::dilateValidTexels(bake.normals.data(), 3, mapSize, mapSize, bake.valid, 4);
            rad::fillByPullPush(bake.normals.data(), 3, mapSize, mapSize, bake.valid);
            const MipTexture texture(bake.normals, mapSize, 3);
            std::printf("\nscan: %s, per-triangle atlas %d^2 (cells of %d texels), object-space normal map baked in %.1f s\n",
                        meshPath.c_str(), mapSize, atlas.cellSize, bake.seconds);
            runScene("scan: per-triangle atlas, baked normal map, Lambert", scan, atlas.wedgeUv, texture,
                     Shading::NormalMapLambert, viewOf(scan, Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(0, 1, 0)),
                     tolerance, minSize, maxSize);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_pop_lod: %s\n", e.what());
        return 1;
    }
    return 0;
}
