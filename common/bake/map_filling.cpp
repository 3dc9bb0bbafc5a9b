// Pull-push hole filling and ring dilation of baked maps (see map_filling.h).
//
// Implements the pull-push of Gortler, Grzeszczuk, Szeliski, Cohen, "The Lumigraph" (SIGGRAPH
// 1996, sec. 3.4.1 "Pull-push") in its binary-weight form: a texel of level k + 1 averages the
// valid ones among its (up to) 2 x 2 children of level k and is valid when one of them is
// (Gortler's weight min(1, sum of the children's weights) with 0/1 input weights stays 0/1);
// going back down, every invalid texel of level k takes the bilinear interpolation of the
// (complete) level k + 1 at its centre. Every filled value is a convex combination of valid
// input texels: a filled map never leaves the range of its valid texels (maximum principle).
//
// Odd sizes: level k + 1 has ceil(W / 2) x ceil(H / 2) texels; the last column (row) of an odd
// level has a single child column (row). Levels are made until 1 x 1.
#include "bake/map_filling.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace rad {
namespace {

struct Level {
    int width = 0, height = 0;
    std::vector<float> values;          // width * height * channels
    std::vector<std::uint8_t> valid;    // width * height
};

// Averages the valid children of (src, srcValid, sw x sh) into `dst` (already sized).
void pull(const float* src, const std::uint8_t* srcValid, int sw, int sh, int channels, Level& dst) {
    const int dw = dst.width, dh = dst.height;
#pragma omp parallel for schedule(static)
    for (int y = 0; y < dh; ++y) {
        float sum[16];
        std::vector<float> big;  // channels > 16 (unusual): heap accumulator
        float* acc = channels <= 16 ? sum : (big.resize(std::size_t(channels)), big.data());
        const int y0 = 2 * y, y1 = std::min(2 * y + 1, sh - 1);
        for (int x = 0; x < dw; ++x) {
            const int x0 = 2 * x, x1 = std::min(2 * x + 1, sw - 1);
            std::fill(acc, acc + channels, 0.0f);
            int count = 0;
            const int xs[2] = {x0, x1}, ys[2] = {y0, y1};
            for (int j = 0; j < (y1 != y0 ? 2 : 1); ++j)
                for (int i = 0; i < (x1 != x0 ? 2 : 1); ++i) {
                    const std::size_t t = std::size_t(ys[j]) * sw + xs[i];
                    if (!srcValid[t]) continue;
                    const float* v = src + t * channels;
                    for (int c = 0; c < channels; ++c) acc[c] += v[c];
                    ++count;
                }
            const std::size_t d = std::size_t(y) * dw + x;
            float* out = dst.values.data() + d * channels;
            if (count) {
                const float inv = 1.0f / float(count);
                for (int c = 0; c < channels; ++c) out[c] = acc[c] * inv;
                dst.valid[d] = 1;
            } else {
                for (int c = 0; c < channels; ++c) out[c] = 0.0f;
                dst.valid[d] = 0;
            }
        }
    }
}

// Bilinear taps of the coarse level (size coarseSize) at the centres of the fine texels
// 0..fineSize-1: the fine centre f + 0.5 lies at coarse coordinate (f + 0.5) / 2 - 0.5 (coarse
// texel i covers fine texels 2i and 2i + 1), clamped to the coarse texel centres.
struct Taps {
    std::vector<int> i0, i1;
    std::vector<float> t;
};

Taps makeTaps(int fineSize, int coarseSize) {
    Taps taps;
    taps.i0.resize(std::size_t(fineSize));
    taps.i1.resize(std::size_t(fineSize));
    taps.t.resize(std::size_t(fineSize));
    for (int f = 0; f < fineSize; ++f) {
        float x = (f + 0.5f) * 0.5f - 0.5f;
        x = std::min(std::max(x, 0.0f), float(coarseSize - 1));
        const int i0 = std::min(int(std::floor(x)), coarseSize - 1);
        taps.i0[std::size_t(f)] = i0;
        taps.i1[std::size_t(f)] = std::min(i0 + 1, coarseSize - 1);
        taps.t[std::size_t(f)] = x - float(i0);
    }
    return taps;
}

// Fills the texels of (dst, dstValid, dw x dh) that are invalid and allowed (mask == nullptr or
// mask non-zero) from the complete coarse level. Marks them valid; returns how many.
std::size_t push(const Level& coarse, float* dst, std::uint8_t* dstValid, int dw, int dh, int channels,
                 const std::uint8_t* mask) {
    const Taps tx = makeTaps(dw, coarse.width), ty = makeTaps(dh, coarse.height);
    const int cw = coarse.width;
    const float* cv = coarse.values.data();
    std::size_t filled = 0;
#pragma omp parallel for schedule(static) reduction(+ : filled)
    for (int y = 0; y < dh; ++y) {
        const float fy = ty.t[std::size_t(y)];
        const float* row0 = cv + std::size_t(ty.i0[std::size_t(y)]) * cw * channels;
        const float* row1 = cv + std::size_t(ty.i1[std::size_t(y)]) * cw * channels;
        for (int x = 0; x < dw; ++x) {
            const std::size_t t = std::size_t(y) * dw + x;
            if (dstValid[t] || (mask && !mask[t])) continue;
            const float fx = tx.t[std::size_t(x)];
            const std::size_t a = std::size_t(tx.i0[std::size_t(x)]) * channels;
            const std::size_t b = std::size_t(tx.i1[std::size_t(x)]) * channels;
            const float w00 = (1 - fx) * (1 - fy), w10 = fx * (1 - fy), w01 = (1 - fx) * fy, w11 = fx * fy;
            float* out = dst + t * channels;
            for (int c = 0; c < channels; ++c)
                out[c] = w00 * row0[a + c] + w10 * row0[b + c] + w01 * row1[a + c] + w11 * row1[b + c];
            dstValid[t] = 1;
            ++filled;
        }
    }
    return filled;
}

}  // namespace

std::size_t fillByPullPush(float* values, int channels, int width, int height, std::vector<std::uint8_t>& valid,
                           const std::uint8_t* fillMask) {
    if (width <= 0 || height <= 0 || channels <= 0) return 0;
    const std::size_t texels = std::size_t(width) * height;
    if (valid.size() != texels) valid.resize(texels, 0);
    bool anyValid = false, anyHole = false;
    for (std::size_t t = 0; t < texels && !(anyValid && anyHole); ++t) {
        if (valid[t]) anyValid = true;
        else if (!fillMask || fillMask[t]) anyHole = true;
    }
    if (!anyValid || !anyHole) return 0;
    if (width == 1 && height == 1) return 0;  // a single texel: valid or not, nothing to do

    // Pull: levels 1..L (level 0 is the caller's image), down to 1 x 1.
    std::vector<Level> levels;
    int w = width, h = height;
    while (w > 1 || h > 1) {
        Level next;
        next.width = (w + 1) / 2;
        next.height = (h + 1) / 2;
        next.values.resize(std::size_t(next.width) * next.height * channels);
        next.valid.resize(std::size_t(next.width) * next.height);
        if (levels.empty()) pull(values, valid.data(), w, h, channels, next);
        else pull(levels.back().values.data(), levels.back().valid.data(), w, h, channels, next);
        levels.push_back(std::move(next));
        w = levels.back().width;
        h = levels.back().height;
    }
    // The 1 x 1 top is valid (some texel is). Push down to level 1: every level becomes complete.
    for (std::size_t k = levels.size() - 1; k-- > 0;) {
        Level& fine = levels[k];
        push(levels[k + 1], fine.values.data(), fine.valid.data(), fine.width, fine.height, channels, nullptr);
    }
    // Level 0: only the allowed holes are written.
    return push(levels.front(), values, valid.data(), width, height, channels, fillMask);
}

std::size_t dilateValidTexels(float* values, int channels, int width, int height, std::vector<std::uint8_t>& valid,
                              int rings) {
    if (width <= 0 || height <= 0 || channels <= 0 || rings <= 0) return 0;
    const std::size_t texels = std::size_t(width) * height;
    if (valid.size() != texels) valid.resize(texels, 0);
    // ring[t]: the pass that made texel t valid (0: valid on entry), kQueued while it waits in the
    // next pass's list, kNever otherwise. Pass k reads only texels with ring < k and writes only
    // its own candidates, so each pass is the old whole-image sweep restricted to the texels it
    // can change: the frontier, found once by a sweep and then grown from the texels just filled
    // (a map with a large background no longer costs `rings` sweeps of the whole image).
    constexpr std::uint8_t kQueued = 254, kNever = 255;
    std::vector<std::uint8_t> ring(texels);
    for (std::size_t t = 0; t < texels; ++t) ring[t] = valid[t] ? 0 : kNever;
    const auto neighbours = [&](std::size_t t, auto&& visit) {
        const int y = int(t / std::size_t(width)), x = int(t % std::size_t(width));
        const int ya = std::max(y - 1, 0), yb = std::min(y + 1, height - 1);
        const int xa = std::max(x - 1, 0), xb = std::min(x + 1, width - 1);
        for (int yy = ya; yy <= yb; ++yy)
            for (int xx = xa; xx <= xb; ++xx) visit(std::size_t(yy) * width + xx);
    };
    // The first pass's candidates: invalid texels next to a valid one, in row order.
    std::vector<std::size_t> candidates;
    {
        std::vector<std::vector<std::size_t>> perRow(static_cast<std::size_t>(height));
#pragma omp parallel for schedule(static)
        for (int y = 0; y < height; ++y) {
            for (int x = 0; x < width; ++x) {
                const std::size_t t = std::size_t(y) * width + x;
                if (ring[t] == 0) continue;
                bool touches = false;
                neighbours(t, [&](std::size_t n) { touches = touches || ring[n] == 0; });
                if (touches) perRow[std::size_t(y)].push_back(t);
            }
        }
        for (const auto& row : perRow) candidates.insert(candidates.end(), row.begin(), row.end());
    }
    for (const std::size_t t : candidates) ring[t] = kQueued;

    std::size_t total = 0;
    std::vector<std::uint8_t> filledNow;
    std::vector<float> averaged;
    for (int pass = 1; pass <= rings && !candidates.empty(); ++pass) {
        const std::uint8_t k = std::uint8_t(std::min(pass, 253));
        filledNow.assign(candidates.size(), 0);
        averaged.resize(candidates.size() * std::size_t(channels));
#pragma omp parallel for schedule(static)
        for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(candidates.size()); ++i) {
            float sum[16];
            std::vector<float> big;
            float* acc = channels <= 16 ? sum : (big.resize(std::size_t(channels)), big.data());
            int count = 0;
            neighbours(candidates[std::size_t(i)], [&](std::size_t n) {
                if (ring[n] >= k) return;  // not valid before this pass (also the texel itself)
                const float* v = values + n * channels;
                if (count == 0) std::copy(v, v + channels, acc);
                else
                    for (int c = 0; c < channels; ++c) acc[c] += v[c];
                ++count;
            });
            if (!count) continue;
            const float inv = 1.0f / float(count);
            float* out = averaged.data() + std::size_t(i) * channels;
            for (int c = 0; c < channels; ++c) out[c] = acc[c] * inv;
            filledNow[std::size_t(i)] = 1;
        }
        // Commit, then queue the still invalid neighbours of the texels just filled.
        std::vector<std::size_t> next;
        std::size_t filled = 0;
        for (std::size_t i = 0; i < candidates.size(); ++i) {
            const std::size_t t = candidates[i];
            if (!filledNow[i]) {
                ring[t] = kNever;
                continue;
            }
            std::copy(averaged.data() + i * channels, averaged.data() + (i + 1) * channels, values + t * channels);
            ring[t] = k;
            valid[t] = 1;
            ++filled;
        }
        for (std::size_t i = 0; i < candidates.size(); ++i) {
            if (!filledNow[i]) continue;
            neighbours(candidates[i], [&](std::size_t n) {
                if (ring[n] != kNever) return;
                ring[n] = kQueued;
                next.push_back(n);
            });
        }
        total += filled;
        if (!filled) break;
        candidates.swap(next);
    }
    return total;
}

void normalizeTexelVectors(float* values, std::size_t texelCount) {
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t t = 0; t < std::ptrdiff_t(texelCount); ++t) {
        float* v = values + 3 * t;
        const float n2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        if (!(n2 > 0.0f) || !std::isfinite(n2)) continue;
        const float inv = 1.0f / std::sqrt(n2);
        v[0] *= inv;
        v[1] *= inv;
        v[2] *= inv;
    }
}

}  // namespace rad
