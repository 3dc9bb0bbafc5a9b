// Weber and Stamminger ("modified LEAN mapping"):
// Alg. 2 (covariance relative to the averaged normal and tangent, per MIP texel), Alg. 3 (the 2D
// Gaussian specular lobe, eq. 4 for the Blinn-Phong equivalence), Alg. 4 and sec. 3.5 (level 0 not
// stored, the covariance of level 1 scaled by lambda below level 1).
//
// Speed: the averaged normals and tangents are summed hierarchically (level k = sum of its
// children at level k - 1, pairwise summation in float); the moments need every level-0 texel once
// per level (the frame differs per level), in a tight loop over rows, parallel over output rows or,
// for the small deep levels, over bands of level-0 rows.
#include "bake/lean_maps.h"

#include <Eigen/Geometry>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfTileDescription.h>
#include <ImfTiledInputFile.h>
#include <ImfThreading.h>
#include <ImfTiledOutputFile.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <stdexcept>
#include <thread>

namespace rad {
namespace {

constexpr double kMaxSlope = 100.0;  // lean_maps.h: slopes of normals at or beyond 90 degrees

bool isPowerOfTwo(int v) { return v > 0 && (v & (v - 1)) == 0; }

void checkSize(int width, int height, const char* what) {
    if (!isPowerOfTwo(width) || !isPowerOfTwo(height))
        throw std::invalid_argument(std::string(what) + ": width and height must be powers of two (got " +
                                    std::to_string(width) + " x " + std::to_string(height) + ")");
}

int levelCount(int width, int height) {  // levels 0..K, K = log2(max(width, height))
    int k = 0;
    while ((std::max(width, height) >> k) > 1) ++k;
    return k + 1;
}

MipImage makeImage(int w, int h) {
    MipImage m;
    m.width = w;
    m.height = h;
    m.channels = 3;
    m.data.assign(static_cast<std::size_t>(w) * h * 3, 0.0f);
    return m;
}

// Level k sums from level k - 1 sums (children: 2 or 1 per direction, where a dimension stopped
// halving at 1).
MipImage sumChildren(const float* fineData, int fineWidth, int fineHeight) {
    const int w = std::max(1, fineWidth / 2), h = std::max(1, fineHeight / 2);
    const int sx = fineWidth / w, sy = fineHeight / h;
    MipImage out = makeImage(w, h);
#pragma omp parallel for schedule(static) if (static_cast<long long>(w) * h > 4096)
    for (int r = 0; r < h; ++r)
        for (int c = 0; c < w; ++c) {
            float s[3] = {0, 0, 0};
            for (int dy = 0; dy < sy; ++dy)
                for (int dx = 0; dx < sx; ++dx) {
                    const float* p = fineData + (static_cast<std::size_t>(r * sy + dy) * fineWidth + c * sx + dx) * 3;
                    s[0] += p[0];
                    s[1] += p[1];
                    s[2] += p[2];
                }
            float* o = out.data.data() + (static_cast<std::size_t>(r) * w + c) * 3;
            o[0] = s[0];
            o[1] = s[1];
            o[2] = s[2];
        }
    return out;
}
MipImage sumChildren(const MipImage& fine) { return sumChildren(fine.data.data(), fine.width, fine.height); }

// A unit copy of a summed image; a zero sum (opposite normals cancelling) becomes (0, 0, 1).
MipImage normalizedCopy(const MipImage& sums) {
    MipImage out = sums;
    const std::size_t n = static_cast<std::size_t>(out.width) * out.height;
    for (std::size_t i = 0; i < n; ++i) {
        float* p = out.data.data() + 3 * i;
        const double len = std::sqrt(double(p[0]) * p[0] + double(p[1]) * p[1] + double(p[2]) * p[2]);
        if (len > 1e-20) {
            for (int a = 0; a < 3; ++a) p[a] = static_cast<float>(p[a] / len);
        } else {
            p[0] = 0.0f;
            p[1] = 0.0f;
            p[2] = 1.0f;
        }
    }
    return out;
}

// Unit T orthogonal to unit n, from a summed tangent t; any perpendicular when t is (nearly)
// parallel to n or zero.
Eigen::Vector3d orthogonalTangent(const Eigen::Vector3d& n, const Eigen::Vector3d& t) {
    Eigen::Vector3d u = t - n * n.dot(t);
    const double len = u.norm();
    if (len > 1e-9 * std::max(1.0, t.norm())) return u / len;
    const Eigen::Vector3d helper = std::fabs(n.x()) < 0.9 ? Eigen::Vector3d(1, 0, 0) : Eigen::Vector3d(0, 1, 0);
    return (helper - n * n.dot(helper)).normalized();
}

// Slope (x, y) / z of a normal whose frame coordinates are (x, y, z), its length clamped at
// kMaxSlope (covers z <= 0, lean_maps.h); added to (xx, yy, xy) in double.
inline void addClampedSlope(float x, float y, float z, double& sxx, double& syy, double& sxy) {
    if (z > 0.0f && x * x + y * y <= float(kMaxSlope * kMaxSlope) * z * z) {
        const double px = double(x) / z, py = double(y) / z;
        sxx += px * px;
        syy += py * py;
        sxy += px * py;
        return;
    }
    const double len = std::sqrt(double(x) * x + double(y) * y);
    if (len > 0.0) {
        const double px = kMaxSlope * x / len, py = kMaxSlope * y / len;
        sxx += px * px;
        syy += py * py;
        sxy += px * py;
    } else {  // exactly opposite: no direction, isotropic slope kMaxSlope
        sxx += 0.5 * kMaxSlope * kMaxSlope;
        syy += 0.5 * kMaxSlope * kMaxSlope;
    }
}

// Alg. 2, second loop, for one row of level-0 texels: adds (x^2, y^2, x y) of each texel's slope
// in the frame of the output texel covering it (output columns 0..w-1, footprint fx columns).
// The common case (every normal within the clamp) runs as a SIMD loop summing in float over at
// most fx texels; a segment holding a clamped normal is redone in scalar code.
inline void accumulateRow(const float* normals, const float* frames /* 9 per output texel: T, B, N */, int w, int fx,
                          double* acc) {
    const float limit = float(kMaxSlope * kMaxSlope);
    for (int C = 0; C < w; ++C) {
        const float* f = frames + 9 * C;
        const float t0 = f[0], t1 = f[1], t2 = f[2], b0 = f[3], b1 = f[4], b2 = f[5], n0 = f[6], n1 = f[7], n2 = f[8];
        const float* n = normals + static_cast<std::size_t>(C) * fx * 3;
        float sxx = 0, syy = 0, sxy = 0;
        int bad = 0;
#pragma omp simd reduction(+ : sxx, syy, sxy) reduction(| : bad)
        for (int i = 0; i < fx; ++i) {
            const float nx = n[3 * i], ny = n[3 * i + 1], nz = n[3 * i + 2];
            const float x = t0 * nx + t1 * ny + t2 * nz;
            const float y = b0 * nx + b1 * ny + b2 * nz;
            const float z = n0 * nx + n1 * ny + n2 * nz;
            bad |= (z <= 0.0f) | (x * x + y * y > limit * z * z);
            const float iz = 1.0f / (z > 0.0f ? z : 1.0f);
            const float px = x * iz, py = y * iz;
            sxx += px * px;
            syy += py * py;
            sxy += px * py;
        }
        if (!bad) {
            acc[3 * C] += sxx;
            acc[3 * C + 1] += syy;
            acc[3 * C + 2] += sxy;
            continue;
        }
        double dxx = 0, dyy = 0, dxy = 0;
        for (int i = 0; i < fx; ++i) {
            const float nx = n[3 * i], ny = n[3 * i + 1], nz = n[3 * i + 2];
            addClampedSlope(t0 * nx + t1 * ny + t2 * nz, b0 * nx + b1 * ny + b2 * nz, n0 * nx + n1 * ny + n2 * nz, dxx, dyy,
                            dxy);
        }
        acc[3 * C] += dxx;
        acc[3 * C + 1] += dyy;
        acc[3 * C + 2] += dxy;
    }
}

}  // namespace

std::vector<MipImage> buildNormalPyramid(const float* normals, int width, int height) {
    checkSize(width, height, "buildNormalPyramid");
    const int levels = levelCount(width, height);
    std::vector<MipImage> out;
    out.reserve(levels);
    MipImage level0;
    level0.width = width;
    level0.height = height;
    level0.data.assign(normals, normals + static_cast<std::size_t>(width) * height * 3);
    out.push_back(std::move(level0));
    MipImage sums;
    for (int k = 1; k < levels; ++k) {
        sums = k == 1 ? sumChildren(normals, width, height) : sumChildren(sums);
        out.push_back(normalizedCopy(sums));
    }
    return out;
}

LeanMaps buildLeanMaps(const float* normals, const float* tangents, int width, int height) {
    checkSize(width, height, "buildLeanMaps");
    const int levels = levelCount(width, height);
    LeanMaps maps;
    maps.normals.reserve(levels);
    maps.moments.reserve(levels - 1);
    MipImage level0;
    level0.width = width;
    level0.height = height;
    level0.data.assign(normals, normals + static_cast<std::size_t>(width) * height * 3);
    maps.normals.push_back(std::move(level0));
    MipImage nSums, tSums;  // unnormalised sums of the current level

    for (int k = 1; k < levels; ++k) {
        // Alg. 2, first loop: the averaged normal and tangent of every texel of level k.
        nSums = k == 1 ? sumChildren(normals, width, height) : sumChildren(nSums);
        tSums = k == 1 ? sumChildren(tangents, width, height) : sumChildren(tSums);
        maps.normals.push_back(normalizedCopy(nSums));
        const MipImage& avg = maps.normals.back();
        const int w = avg.width, h = avg.height;
        const int fx = width / w, fy = height / h;  // the footprint in level-0 texels
        std::vector<float> frames(static_cast<std::size_t>(w) * h * 9);
#pragma omp parallel for schedule(static) if (static_cast<long long>(w) * h > 4096)
        for (long long li = 0; li < static_cast<long long>(w) * h; ++li) {
            const std::size_t i = static_cast<std::size_t>(li);
            const Eigen::Vector3d N(avg.data[3 * i], avg.data[3 * i + 1], avg.data[3 * i + 2]);
            const Eigen::Vector3d T =
                orthogonalTangent(N, Eigen::Vector3d(tSums.data[3 * i], tSums.data[3 * i + 1], tSums.data[3 * i + 2]));
            const Eigen::Vector3d B = N.cross(T);
            for (int a = 0; a < 3; ++a) {
                frames[9 * i + a] = static_cast<float>(T[a]);
                frames[9 * i + 3 + a] = static_cast<float>(B[a]);
                frames[9 * i + 6 + a] = static_cast<float>(N[a]);
            }
        }

        // Alg. 2, second loop. Tasks: (output row, band of its footprint rows); several bands per
        // row only when there are too few rows to keep the threads busy.
        const int bands = h >= 64 ? 1 : std::min(fy, (64 + h - 1) / h);
        const int tasks = h * bands;
        const double inv = 1.0 / (static_cast<double>(fx) * fy);
        MipImage mu = makeImage(w, h);
        // Per-band sums only when a row is split into bands (deep levels: small).
        std::vector<double> bandSums(bands > 1 ? static_cast<std::size_t>(tasks) * w * 3 : 0, 0.0);
#pragma omp parallel
        {
            std::vector<double> rowSums(bands > 1 ? 0 : static_cast<std::size_t>(w) * 3);
#pragma omp for schedule(dynamic, 1)
            for (int task = 0; task < tasks; ++task) {
                const int R = task / bands, b = task % bands;
                const int r0 = R * fy + static_cast<int>(static_cast<long long>(fy) * b / bands);
                const int r1 = R * fy + static_cast<int>(static_cast<long long>(fy) * (b + 1) / bands);
                double* a = bands > 1 ? bandSums.data() + static_cast<std::size_t>(task) * w * 3 : rowSums.data();
                if (bands == 1) std::fill(rowSums.begin(), rowSums.end(), 0.0);
                const float* frameRow = frames.data() + static_cast<std::size_t>(R) * w * 9;
                for (int r = r0; r < r1; ++r)
                    accumulateRow(normals + static_cast<std::size_t>(r) * width * 3, frameRow, w, fx, a);
                if (bands == 1)
                    for (int i = 0; i < 3 * w; ++i)
                        mu.data[static_cast<std::size_t>(R) * w * 3 + i] = static_cast<float>(rowSums[i] * inv);
            }
        }
        if (bands > 1)
            for (int R = 0; R < h; ++R)
                for (int i = 0; i < 3 * w; ++i) {
                    double sum = 0;
                    for (int b = 0; b < bands; ++b) sum += bandSums[(static_cast<std::size_t>(R) * bands + b) * w * 3 + i];
                    mu.data[static_cast<std::size_t>(R) * w * 3 + i] = static_cast<float>(sum * inv);
                }
        maps.moments.push_back(std::move(mu));
    }
    return maps;
}

double leanSpecular(const Eigen::Vector3d& normal, const Eigen::Vector3d& tangent, const Eigen::Vector3d& mu2,
                    const Eigen::Vector3d& halfVector, double shininess) {
    const Eigen::Vector3d N = normal.normalized();
    const Eigen::Vector3d T = orthogonalTangent(N, tangent);
    const Eigen::Vector3d B = N.cross(T);
    const double hn = halfVector.dot(N);
    if (hn <= 0.0) return 0.0;
    const double hx = halfVector.dot(T) / hn, hy = halfVector.dot(B) / hn;
    const double a = mu2.x() + 1.0 / shininess, d = mu2.y() + 1.0 / shininess, b = mu2.z();
    const double det = a * d - b * b;
    if (!(det > 0.0)) return 0.0;
    // h^T Sigma^-1 h with Sigma^-1 = [[d, -b], [-b, a]] / det
    const double q = (d * hx * hx - 2.0 * b * hx * hy + a * hy * hy) / det;
    return std::exp(-0.5 * q) / (shininess * std::sqrt(det));
}

double blinnPhongSpecular(const Eigen::Vector3d& normal, const Eigen::Vector3d& halfVector, double shininess) {
    const double c = normal.normalized().dot(halfVector);
    return c > 0.0 ? std::pow(c, shininess) : 0.0;
}

namespace {
// Bilinear sample (clamp to edge) at (u, v) of one level, texture_atlas.h convention.
Eigen::Vector3d bilinear(const MipImage& m, double u, double v) {
    const double x = u * m.width - 0.5, y = (1.0 - v) * m.height - 0.5;
    const double fx = std::floor(x), fy = std::floor(y);
    const double ax = x - fx, ay = y - fy;
    Eigen::Vector3d out = Eigen::Vector3d::Zero();
    for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
            const int c = std::clamp(static_cast<int>(fx) + dx, 0, m.width - 1);
            const int r = std::clamp(static_cast<int>(fy) + dy, 0, m.height - 1);
            const double wgt = (dx ? ax : 1 - ax) * (dy ? ay : 1 - ay);
            const float* p = m.data.data() + (static_cast<std::size_t>(r) * m.width + c) * m.channels;
            out += wgt * Eigen::Vector3d(p[0], p[1], p[2]);
        }
    return out;
}
}  // namespace

Eigen::Vector3d sampleLeanMoments(const LeanMaps& maps, double u, double v, double lambda) {
    if (maps.moments.empty()) return Eigen::Vector3d::Zero();
    if (lambda < 1.0) {
        // Sec. 3.5: between Sigma_0 = 0 and level 1. Below 0 (magnification) the covariance is
        // that of level 0, i.e. 0 (Alg. 4 read literally would keep level 1 unscaled there).
        return std::max(lambda, 0.0) * bilinear(maps.moments[0], u, v);
    }
    const double stored = std::min(lambda - 1.0, static_cast<double>(maps.moments.size() - 1));
    const int l0 = static_cast<int>(std::floor(stored));
    const int l1 = std::min(l0 + 1, static_cast<int>(maps.moments.size()) - 1);
    const double t = stored - l0;
    const Eigen::Vector3d a = bilinear(maps.moments[l0], u, v);
    return t > 0.0 ? Eigen::Vector3d((1 - t) * a + t * bilinear(maps.moments[l1], u, v)) : a;
}

void writeLeanMoments(const std::string& path, const LeanMaps& maps) {
    if (maps.moments.empty()) throw std::runtime_error(path + ": no LEAN moments to write (a 1 x 1 normal map has none)");
    const MipImage& top = maps.moments[0];
    for (std::size_t i = 0; i < maps.moments.size(); ++i) {
        const MipImage& m = maps.moments[i];
        if (m.channels != 3 || m.width != std::max(1, top.width >> i) || m.height != std::max(1, top.height >> i) ||
            m.data.size() != static_cast<std::size_t>(m.width) * m.height * 3)
            throw std::runtime_error(path + ": LEAN moment level " + std::to_string(i + 1) + " is not a mip chain level");
    }
    if (levelCount(top.width, top.height) != static_cast<int>(maps.moments.size()))
        throw std::runtime_error(path + ": the LEAN moments do not go down to 1 x 1");
    try {
        Imf::Header header(top.width, top.height);
        header.setTileDescription(Imf::TileDescription(64, 64, Imf::MIPMAP_LEVELS, Imf::ROUND_DOWN));
        for (const char* name : {"R", "G", "B"}) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
        // OpenEXR compresses tiles on its own thread pool: use the machine's cores.
        if (Imf::globalThreadCount() == 0) Imf::setGlobalThreadCount(static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
        Imf::TiledOutputFile file(path.c_str(), header, Imf::globalThreadCount());
        for (int level = 0; level < file.numLevels(); ++level) {
            const MipImage& m = maps.moments[static_cast<std::size_t>(level)];
            Imf::FrameBuffer fb;
            const char* names[3] = {"R", "G", "B"};
            for (int c = 0; c < 3; ++c)
                fb.insert(names[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(m.data.data()) + c),
                                               3 * sizeof(float), 3 * sizeof(float) * static_cast<std::size_t>(m.width)));
            file.setFrameBuffer(fb);
            file.writeTiles(0, file.numXTiles(level) - 1, 0, file.numYTiles(level) - 1, level);
        }
    } catch (const std::exception& e) {
        throw std::runtime_error(path + ": cannot write the LEAN moments: " + e.what());
    }
}

std::vector<MipImage> readLeanMoments(const std::string& path) {
    std::vector<MipImage> out;
    try {
        Imf::TiledInputFile file(path.c_str());
        const Imf::Header& header = file.header();
        if (file.levelMode() != Imf::MIPMAP_LEVELS || header.tileDescription().roundingMode != Imf::ROUND_DOWN)
            throw std::runtime_error("not a ROUND_DOWN mip-mapped file");
        const Imath::Box2i dw = header.dataWindow();
        if (dw.min.x != 0 || dw.min.y != 0) throw std::runtime_error("the data window does not start at (0, 0)");
        const char* names[3] = {"R", "G", "B"};
        for (const char* name : names)
            if (!header.channels().findChannel(name)) throw std::runtime_error(std::string("no channel ") + name);
        for (int level = 0; level < file.numLevels(); ++level) {
            const int w = file.levelWidth(level), h = file.levelHeight(level);
            MipImage m = makeImage(w, h);
            Imf::FrameBuffer fb;
            for (int c = 0; c < 3; ++c)
                fb.insert(names[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(m.data.data() + c), 3 * sizeof(float),
                                               3 * sizeof(float) * static_cast<std::size_t>(w)));
            file.setFrameBuffer(fb);
            file.readTiles(0, file.numXTiles(level) - 1, 0, file.numYTiles(level) - 1, level);
            out.push_back(std::move(m));
        }
    } catch (const std::exception& e) {
        throw std::runtime_error(path + ": cannot read the LEAN moments: " + e.what());
    }
    return out;
}

}  // namespace rad
