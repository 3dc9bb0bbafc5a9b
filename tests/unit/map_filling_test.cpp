// Tests of bake/map_filling.h: pull-push keeps valid texels, reproduces constants, obeys a maximum
// principle on a ramp, respects the fill mask and fills nothing without a source; dilation grows
// exactly one Chebyshev ring per pass (checked by brute force) with the mean of the valid
// neighbours; normalisation of texel vectors. Also a speed check at 4096 x 4096 x 3.
#include "bake/map_filling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace {

struct Map {
    int width, height, channels;
    std::vector<float> values;
    std::vector<std::uint8_t> valid;
    Map(int w, int h, int c) : width(w), height(h), channels(c), values(std::size_t(w) * h * c, 0.0f), valid(std::size_t(w) * h, 0) {}
    float* at(int x, int y) { return values.data() + (std::size_t(y) * width + x) * channels; }
    std::uint8_t& ok(int x, int y) { return valid[std::size_t(y) * width + x]; }
};

const float kNaN = std::numeric_limits<float>::quiet_NaN();

// Invalid texels hold NaN: the filling must never read them.
void poisonInvalid(Map& m) {
    for (std::size_t t = 0; t < m.valid.size(); ++t)
        if (!m.valid[t])
            for (int c = 0; c < m.channels; ++c) m.values[t * m.channels + c] = kNaN;
}

// A disc-shaped hole plus a rectangular one, at odd sizes.
bool inHole(int x, int y, int w, int h) {
    const double dx = x - 0.4 * w, dy = y - 0.5 * h;
    return dx * dx + dy * dy < 0.09 * w * h || (x > 0.7 * w && x < 0.9 * w && y > 0.1 * h && y < 0.8 * h);
}

TEST(MapFilling, ValidTexelsAreUnchangedAndEveryHoleIsFilled) {
    for (const auto& size : {std::pair<int, int>{37, 23}, {64, 64}, {1, 9}, {10, 1}, {3, 2}}) {
        Map m(size.first, size.second, 3);
        std::mt19937 rng(unsigned(size.first * 31 + size.second));
        std::uniform_real_distribution<float> u(-1, 1);
        for (int y = 0; y < m.height; ++y)
            for (int x = 0; x < m.width; ++x) {
                m.ok(x, y) = !inHole(x, y, m.width, m.height) || (x == 0 && y == 0);
                for (int c = 0; c < 3; ++c) m.at(x, y)[c] = u(rng);
            }
        poisonInvalid(m);
        const Map before = m;
        const std::size_t holes = std::size_t(std::count(m.valid.begin(), m.valid.end(), 0));
        EXPECT_EQ(rad::fillByPullPush(m.values.data(), 3, m.width, m.height, m.valid), holes);
        for (std::size_t t = 0; t < m.valid.size(); ++t) {
            EXPECT_EQ(m.valid[t], 1);
            for (int c = 0; c < 3; ++c) {
                const float v = m.values[t * 3 + c];
                EXPECT_TRUE(std::isfinite(v));
                if (before.valid[t]) EXPECT_EQ(v, before.values[t * 3 + c]);  // bit-identical
            }
        }
    }
}

TEST(MapFilling, HoleInAConstantImageFillsWithTheConstant) {
    Map m(101, 57, 2);
    for (int y = 0; y < m.height; ++y)
        for (int x = 0; x < m.width; ++x) {
            m.ok(x, y) = !inHole(x, y, m.width, m.height);
            m.at(x, y)[0] = 0.25f;
            m.at(x, y)[1] = -3.5f;
        }
    poisonInvalid(m);
    rad::fillByPullPush(m.values.data(), 2, m.width, m.height, m.valid);
    for (int y = 0; y < m.height; ++y)
        for (int x = 0; x < m.width; ++x) {
            EXPECT_NEAR(m.at(x, y)[0], 0.25f, 1e-6f);
            EXPECT_NEAR(m.at(x, y)[1], -3.5f, 1e-6f);
        }
}

// A linear ramp along x with a hole: filled values stay within the range of the valid texels (a
// maximum principle), and within the range of the hole's own border columns for a hole that spans
// full rows' interior (the hole's values come from its surroundings, which are nearby columns).
TEST(MapFilling, HoleInARampStaysWithinTheValidRange) {
    const int w = 80, h = 50;
    Map m(w, h, 1);
    float lo = 1e9f, hi = -1e9f;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool hole = x >= 30 && x < 50 && y >= 10 && y < 40;
            m.ok(x, y) = !hole;
            m.at(x, y)[0] = 2.0f + 0.1f * x;
            if (!hole) lo = std::min(lo, m.at(x, y)[0]), hi = std::max(hi, m.at(x, y)[0]);
        }
    poisonInvalid(m);
    rad::fillByPullPush(m.values.data(), 1, w, h, m.valid);
    double sumError = 0;
    for (int y = 10; y < 40; ++y)
        for (int x = 30; x < 50; ++x) {
            const float v = m.at(x, y)[0];
            EXPECT_GE(v, lo);
            EXPECT_LE(v, hi);
            // Between the ramp's values on the hole's border columns (29: 4.9, 50: 7.0).
            EXPECT_GE(v, 4.9f - 1e-5f);
            EXPECT_LE(v, 7.0f + 1e-5f);
            sumError += std::fabs(v - (2.0f + 0.1f * x));
        }
    // Not exact (pull-push is not harmonic), but it follows the ramp: mean error below a quarter
    // of the hole's value span (2.0).
    EXPECT_LT(sumError / (20 * 30), 0.5);
    // Random valid sets on random data: the maximum principle, per channel.
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-7, 3);
    for (int trial = 0; trial < 5; ++trial) {
        Map r(33 + trial, 17 + 3 * trial, 2);
        float mn[2] = {1e9f, 1e9f}, mx[2] = {-1e9f, -1e9f};
        for (std::size_t t = 0; t < r.valid.size(); ++t) {
            r.valid[t] = (rng() % 10) == 0;
            for (int c = 0; c < 2; ++c) {
                r.values[2 * t + c] = u(rng);
                if (r.valid[t]) mn[c] = std::min(mn[c], r.values[2 * t + c]), mx[c] = std::max(mx[c], r.values[2 * t + c]);
            }
        }
        poisonInvalid(r);
        rad::fillByPullPush(r.values.data(), 2, r.width, r.height, r.valid);
        for (std::size_t t = 0; t < r.valid.size(); ++t)
            for (int c = 0; c < 2; ++c) {
                EXPECT_GE(r.values[2 * t + c], mn[c] - 1e-5f);
                EXPECT_LE(r.values[2 * t + c], mx[c] + 1e-5f);
            }
    }
}

TEST(MapFilling, FillMaskIsRespected) {
    const int w = 41, h = 29;
    Map m(w, h, 3);
    std::vector<std::uint8_t> mask(std::size_t(w) * h, 0);
    std::size_t allowedHoles = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            m.ok(x, y) = inHole(x, y, w, h) ? 0 : (x + y) % 3 == 0;
            for (int c = 0; c < 3; ++c) m.at(x, y)[c] = float(x - c * y);
            mask[std::size_t(y) * w + x] = x < w / 2;
            if (!m.ok(x, y) && x < w / 2) ++allowedHoles;
        }
    poisonInvalid(m);
    const Map before = m;
    EXPECT_EQ(rad::fillByPullPush(m.values.data(), 3, w, h, m.valid, mask.data()), allowedHoles);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t t = std::size_t(y) * w + x;
            if (x < w / 2) {
                EXPECT_EQ(m.valid[t], 1);
            } else {
                EXPECT_EQ(m.valid[t], before.valid[t]);  // outside the mask: never written
                for (int c = 0; c < 3; ++c) {
                    if (before.valid[t]) EXPECT_EQ(m.values[3 * t + c], before.values[3 * t + c]);
                    else EXPECT_TRUE(std::isnan(m.values[3 * t + c]));
                }
            }
        }
}

TEST(MapFilling, NoValidTexelFillsNothing) {
    Map m(16, 9, 3);
    poisonInvalid(m);
    EXPECT_EQ(rad::fillByPullPush(m.values.data(), 3, 16, 9, m.valid), 0u);
    EXPECT_EQ(rad::dilateValidTexels(m.values.data(), 3, 16, 9, m.valid, 4), 0u);
    for (const auto v : m.valid) EXPECT_EQ(v, 0);
    for (const float v : m.values) EXPECT_TRUE(std::isnan(v));
}

// After k rings exactly the texels within Chebyshev distance k of the initial valid set are valid.
TEST(MapFilling, DilationGrowsOneChebyshevRingPerPass) {
    const int w = 45, h = 31;
    Map m(w, h, 1);
    std::mt19937 rng(11);
    std::vector<std::pair<int, int>> seeds;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            m.ok(x, y) = (rng() % 97) == 0 || (x >= 20 && x < 24 && y >= 12 && y < 15);
            m.at(x, y)[0] = 1.0f;
            if (m.ok(x, y)) seeds.emplace_back(x, y);
        }
    ASSERT_FALSE(seeds.empty());
    poisonInvalid(m);
    std::size_t validCount = seeds.size();
    for (int k = 1; k <= 6; ++k) {
        const std::size_t filled = rad::dilateValidTexels(m.values.data(), 1, w, h, m.valid, 1);
        std::size_t expectedCount = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                int d = 1 << 30;
                for (const auto& s : seeds) d = std::min(d, std::max(std::abs(x - s.first), std::abs(y - s.second)));
                const bool expected = d <= k;
                expectedCount += expected;
                EXPECT_EQ(bool(m.ok(x, y)), expected) << "ring " << k << " at " << x << "," << y;
                if (expected) EXPECT_FLOAT_EQ(m.at(x, y)[0], 1.0f);
            }
        EXPECT_EQ(filled, expectedCount - validCount);
        validCount = expectedCount;
    }
    // Several rings at once give the same as one at a time.
    Map again(w, h, 1);
    for (const auto& s : seeds) again.ok(s.first, s.second) = 1, again.at(s.first, s.second)[0] = 1.0f;
    rad::dilateValidTexels(again.values.data(), 1, w, h, again.valid, 6);
    EXPECT_EQ(again.valid, m.valid);
}

// Hand-made: a 4 x 3 image with valid texels A = (0,0) = 2, B = (2,0) = 6, C = (3,2) = 10.
TEST(MapFilling, DilatedValueIsTheMeanOfTheValidNeighbours) {
    Map m(4, 3, 2);
    auto set = [&](int x, int y, float v) { m.ok(x, y) = 1, m.at(x, y)[0] = v, m.at(x, y)[1] = -v; };
    set(0, 0, 2.0f);
    set(2, 0, 6.0f);
    set(3, 2, 10.0f);
    poisonInvalid(m);
    EXPECT_EQ(rad::dilateValidTexels(m.values.data(), 2, 4, 3, m.valid, 1), 7u);  // all but the seeds and (0,2), (1,2)
    EXPECT_FLOAT_EQ(m.at(1, 0)[0], 4.0f);                  // A, B
    EXPECT_FLOAT_EQ(m.at(1, 1)[0], 4.0f);                  // A, B
    EXPECT_FLOAT_EQ(m.at(3, 0)[0], 6.0f);                  // B
    EXPECT_FLOAT_EQ(m.at(3, 1)[0], 8.0f);                  // B, C
    EXPECT_FLOAT_EQ(m.at(2, 1)[0], 8.0f);                  // B, C
    EXPECT_FLOAT_EQ(m.at(2, 2)[0], 10.0f);                 // C
    EXPECT_FLOAT_EQ(m.at(0, 1)[0], 2.0f);                  // A
    EXPECT_FLOAT_EQ(m.at(1, 1)[1], -4.0f);                 // second channel too
    EXPECT_FALSE(m.ok(0, 2));                              // no valid neighbour in ring 1
    EXPECT_FALSE(m.ok(1, 2));
    // Ring 2 uses ring 1's values: (0,2) sees (0,1) = 2 and (1,1) = 4; (1,2) sees (0,1), (1,1),
    // (2,1) = 8 and (2,2) = 10.
    EXPECT_EQ(rad::dilateValidTexels(m.values.data(), 2, 4, 3, m.valid, 1), 2u);
    EXPECT_FLOAT_EQ(m.at(0, 2)[0], 3.0f);
    EXPECT_FLOAT_EQ(m.at(1, 2)[0], 6.0f);
}

TEST(MapFilling, NormalizeTexelVectors) {
    std::vector<float> v = {3, 0, 4, 0, 0, 0, -1, 2, 2};
    rad::normalizeTexelVectors(v.data(), 3);
    EXPECT_FLOAT_EQ(v[0], 0.6f);
    EXPECT_FLOAT_EQ(v[2], 0.8f);
    EXPECT_EQ(v[3], 0.0f);  // zero vectors left alone
    EXPECT_EQ(v[4], 0.0f);
    EXPECT_EQ(v[5], 0.0f);
    EXPECT_FLOAT_EQ(v[6], -1.0f / 3);
    EXPECT_FLOAT_EQ(v[8], 2.0f / 3);
}

// 4096 x 4096 x 3 with a per-triangle-atlas-like pattern of holes (every 8th row and column, plus
// the upper-left triangle of every 16-texel cell): every texel is filled, and a constant field stays
// that constant. The time of a 4096^2 fill is printed by bench/bench_bake_normals (fill column).
TEST(MapFilling, FillsEveryTexelOfA4096Map) {
    const int w = 4096, h = 4096;
    std::vector<float> values(std::size_t(w) * h * 3, 0.5f);
    std::vector<std::uint8_t> valid(std::size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            valid[std::size_t(y) * w + x] = (x % 8 != 0) && (y % 8 != 0) && ((x % 16) + (y % 16) > 15);
    const std::size_t filled = rad::fillByPullPush(values.data(), 3, w, h, valid);
    EXPECT_GT(filled, std::size_t(w) * h / 3);
    EXPECT_EQ(std::count(valid.begin(), valid.end(), 0), 0);
    const auto [lowest, highest] = std::minmax_element(values.begin(), values.end());
    EXPECT_FLOAT_EQ(*lowest, 0.5f);
    EXPECT_FLOAT_EQ(*highest, 0.5f);
}

}  // namespace
