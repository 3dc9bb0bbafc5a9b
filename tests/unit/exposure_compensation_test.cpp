// Tests of fit/exposure_compensation.h: per-view gains recovered from virtual photographs whose
// gains are chosen here (normalised here to a geometric mean of 1 per channel, as the solver's
// answer is defined), with outliers, saturated and dark samples, and views that share no point.
#include "fit/exposure_compensation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace {

struct Virtual {
    std::vector<rad::ExposureSample> samples;
    std::vector<double> gains;  // 3 per view, geometric mean 1 per channel
};

// `points` points of random colour in [0.05, 0.6], each seen by a random 30 % of `views` views;
// value = gain * colour * (1 + noise).
Virtual makeVirtual(std::mt19937& rng, int views, int points, double noise) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::normal_distribution<double> g(0.0, noise);
    Virtual v;
    v.gains.resize(3 * views);
    for (int c = 0; c < 3; ++c) {
        double logSum = 0.0;
        for (int i = 0; i < views; ++i) logSum += std::log(v.gains[3 * i + c] = 0.6 + 0.9 * u(rng));
        for (int i = 0; i < views; ++i) v.gains[3 * i + c] /= std::exp(logSum / views);
    }
    for (int p = 0; p < points; ++p) {
        double colour[3];
        for (double& x : colour) x = 0.05 + 0.55 * u(rng);
        for (int i = 0; i < views; ++i) {
            if (u(rng) > 0.3) continue;
            rad::ExposureSample s{static_cast<std::uint32_t>(p), static_cast<std::uint32_t>(i), {}, float(0.2 + 0.8 * u(rng))};
            for (int c = 0; c < 3; ++c) s.rgb[c] = float(v.gains[3 * i + c] * colour[c] * (1.0 + g(rng)));
            v.samples.push_back(s);
        }
    }
    return v;
}

TEST(ExposureCompensation, RecoversKnownGainsWithinHalfAPercent) {
    std::mt19937 rng(1);
    const Virtual v = makeVirtual(rng, 20, 3000, 0.01);
    const rad::ExposureGains r = rad::solveExposureGains(v.samples, 20);
    ASSERT_EQ(r.gains.size(), v.gains.size());
    for (int i = 0; i < 20; ++i) {
        EXPECT_EQ(r.constrained[i], 1);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.gains[3 * i + c] / v.gains[3 * i + c], 1.0, 0.005) << i << " " << c;
    }
    // Used: the samples of points seen by at least two views (counted here).
    std::vector<int> views(3000, 0);
    for (const auto& s : v.samples) ++views[s.point];
    std::size_t shared = 0;
    for (const auto& s : v.samples) shared += views[s.point] >= 2;
    EXPECT_EQ(r.samplesUsed, shared);
    EXPECT_LT(shared, v.samples.size());
}

TEST(ExposureCompensation, OutliersSaturationAndDarkSamplesDoNotBiasTheGains) {
    std::mt19937 rng(2);
    Virtual v = makeVirtual(rng, 12, 3000, 0.005);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    // 5 % highlights (x 2.5, below saturation), some clipped and some black samples.
    for (std::size_t k = 0; k < v.samples.size(); ++k) {
        rad::ExposureSample& s = v.samples[k];
        const double r = u(rng);
        if (r < 0.05)
            for (float& x : s.rgb) x = std::min(0.95f, 2.5f * x);
        else if (r < 0.08)
            s.rgb[1] = 1.0f;
        else if (r < 0.10)
            s.rgb[2] = 0.0f;
    }
    const rad::ExposureGains r = rad::solveExposureGains(v.samples, 12);
    for (int i = 0; i < 12; ++i)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.gains[3 * i + c] / v.gains[3 * i + c], 1.0, 0.01) << i << " " << c;
    EXPECT_LT(r.samplesUsed, v.samples.size());  // the clipped and black ones were left out
    // Without the Huber passes the highlights do bias them (the test discriminates).
    rad::ExposureOptions plain;
    plain.robustPasses = 0;
    const rad::ExposureGains p = rad::solveExposureGains(v.samples, 12, plain);
    double worst = 0.0;
    for (int i = 0; i < 12; ++i)
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(p.gains[3 * i + c] / v.gains[3 * i + c] - 1.0));
    EXPECT_GT(worst, 0.01);
}

TEST(ExposureCompensation, ViewsSharingNoPointKeepGainOne) {
    std::mt19937 rng(3);
    Virtual v = makeVirtual(rng, 6, 500, 0.0);
    // View 6 sees points nobody else sees; view 7 sees nothing.
    for (std::uint32_t p = 1000; p < 1010; ++p) v.samples.push_back({p, 6, {0.3f, 0.3f, 0.3f}, 1.0f});
    const rad::ExposureGains r = rad::solveExposureGains(v.samples, 8);
    EXPECT_EQ(r.constrained[6], 0);
    EXPECT_EQ(r.constrained[7], 0);
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(r.gains[18 + c], 1.0);
        EXPECT_EQ(r.gains[21 + c], 1.0);
    }
    for (int i = 0; i < 6; ++i)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.gains[3 * i + c] / v.gains[3 * i + c], 1.0, 1e-4);
}

TEST(ExposureCompensation, ALongChainOfViewsIsSolvedExactly) {
    // 60 views, each sharing points only with the next: a view graph where averaging back and forth
    // between points and gains creeps along the chain. Without noise the least-squares solution is
    // the true gains, and the solver reaches it, with one solve per Huber pass.
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const int views = 60;
    std::vector<double> gains(3 * views);
    for (int c = 0; c < 3; ++c) {
        double logSum = 0.0;
        for (int i = 0; i < views; ++i) logSum += std::log(gains[3 * i + c] = 0.5 + u(rng));
        for (int i = 0; i < views; ++i) gains[3 * i + c] /= std::exp(logSum / views);
    }
    std::vector<rad::ExposureSample> samples;
    std::uint32_t point = 0;
    for (int i = 0; i + 1 < views; ++i)
        for (int k = 0; k < 4; ++k, ++point) {
            double colour[3];
            for (double& x : colour) x = 0.05 + 0.4 * u(rng);
            for (int view : {i, i + 1}) {
                rad::ExposureSample s{point, static_cast<std::uint32_t>(view), {}, 1.0f};
                for (int c = 0; c < 3; ++c) s.rgb[c] = float(gains[3 * view + c] * colour[c]);
                samples.push_back(s);
            }
        }
    const rad::ExposureGains r = rad::solveExposureGains(samples, views);
    EXPECT_EQ(r.solves, 1 + rad::ExposureOptions().robustPasses);
    for (int i = 0; i < views; ++i)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.gains[3 * i + c] / gains[3 * i + c], 1.0, 1e-5) << i << " " << c;
}

TEST(ExposureCompensation, BadInputIsRefused) {
    std::vector<rad::ExposureSample> s{{0, 5, {0.3f, 0.3f, 0.3f}, 1.0f}};
    EXPECT_THROW(rad::solveExposureGains(s, 5), std::invalid_argument);
    rad::ExposureOptions o;
    o.saturationLevel = o.darkLevel;
    EXPECT_THROW(rad::solveExposureGains({}, 1, o), std::invalid_argument);
    EXPECT_EQ(rad::solveExposureGains({}, 3).gains, std::vector<double>(9, 1.0));
}

}  // namespace
