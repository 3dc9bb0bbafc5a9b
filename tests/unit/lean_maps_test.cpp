// LEAN maps (common/bake/lean_maps.h, Weber and Stamminger Alg. 2-4, sec. 3.5). Oracles are hand-derived
// (tilted normal pairs give slopes +-tan a, the Gaussian integrates to 2 pi / s over the slope
// plane, cos^s vs exp(-s/2 tan^2) differ by at most ~0.54 / s) or recomputed here by brute force
// from the definition, never taken from the code under test.
#include "bake/lean_maps.h"
#include "test_temporary_directory.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

namespace {

const double kPi = 3.14159265358979323846;

std::vector<float> constantMap(int w, int h, const Eigen::Vector3d& v) {
    std::vector<float> out(static_cast<std::size_t>(w) * h * 3);
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = static_cast<float>(v[i % 3]);
    return out;
}

void setTexel(std::vector<float>& m, int w, int c, int r, const Eigen::Vector3d& v) {
    for (int a = 0; a < 3; ++a) m[(static_cast<std::size_t>(r) * w + c) * 3 + a] = static_cast<float>(v[a]);
}

Eigen::Vector3d texel(const rad::MipImage& m, int c, int r) {
    const float* p = m.data.data() + (static_cast<std::size_t>(r) * m.width + c) * 3;
    return {p[0], p[1], p[2]};
}

TEST(LeanMaps, ConstantMapHasZeroMomentsAtEveryLevelIncludingNonSquare) {
    const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.2, 0.9).normalized();
    const int w = 16, h = 4;
    const std::vector<float> normals = constantMap(w, h, n);
    const std::vector<float> tangents = constantMap(w, h, Eigen::Vector3d(1, 0.5, 0));  // not orthogonal to n
    const rad::LeanMaps maps = rad::buildLeanMaps(normals.data(), tangents.data(), w, h);
    ASSERT_EQ(maps.normals.size(), 5u);  // 16x4, 8x2, 4x1, 2x1, 1x1
    ASSERT_EQ(maps.moments.size(), 4u);
    const int widths[5] = {16, 8, 4, 2, 1}, heights[5] = {4, 2, 1, 1, 1};
    for (int k = 0; k < 5; ++k) {
        EXPECT_EQ(maps.normals[k].width, widths[k]);
        EXPECT_EQ(maps.normals[k].height, heights[k]);
        for (int r = 0; r < heights[k]; ++r)
            for (int c = 0; c < widths[k]; ++c) EXPECT_LT((texel(maps.normals[k], c, r) - n).norm(), 1e-6);
        if (k == 0) continue;
        EXPECT_EQ(maps.moments[k - 1].width, widths[k]);
        EXPECT_EQ(maps.moments[k - 1].height, heights[k]);
        for (float v : maps.moments[k - 1].data) EXPECT_NEAR(v, 0.0f, 1e-10f);
    }
    const std::vector<rad::MipImage> pyramid = rad::buildNormalPyramid(normals.data(), w, h);
    ASSERT_EQ(pyramid.size(), 5u);
    EXPECT_EQ(pyramid[4].width, 1);
    EXPECT_LT((texel(pyramid[4], 0, 0) - n).norm(), 1e-6);
}

// Columns alternate normals tilted by +a and -a toward the tangent (rotation about B): in the frame
// (T, B, N) = ((1,0,0), (0,1,0), (0,0,1)) the slopes are (+-tan a, 0), so mu2 = (tan^2 a, 0, 0).
TEST(LeanMaps, OppositeTiltsGiveTanSquaredAlongTheTangent) {
    const double a = 0.4;
    const int w = 4, h = 2;
    std::vector<float> normals(w * h * 3);
    for (int r = 0; r < h; ++r)
        for (int c = 0; c < w; ++c) setTexel(normals, w, c, r, {(c % 2 ? -1 : 1) * std::sin(a), 0, std::cos(a)});
    const double t2 = std::tan(a) * std::tan(a);
    {
        const rad::LeanMaps maps = rad::buildLeanMaps(normals.data(), constantMap(w, h, {1, 0, 0}).data(), w, h);
        ASSERT_EQ(maps.moments.size(), 2u);  // 2x1 (footprint 2x2), 1x1 (footprint 4x2)
        for (const rad::MipImage& m : maps.moments)
            for (int c = 0; c < m.width; ++c) {
                const Eigen::Vector3d mu = texel(m, c, 0);
                EXPECT_NEAR(mu.x(), t2, 1e-6);
                EXPECT_NEAR(mu.y(), 0.0, 1e-7);
                EXPECT_NEAR(mu.z(), 0.0, 1e-7);
                EXPECT_LT((texel(maps.normals[1], c, 0) - Eigen::Vector3d(0, 0, 1)).norm(), 1e-6);
            }
    }
    {
        // Tangent (0, 1, 0): T = y, B = N x T = -x, so the same tilts are now along B: mu2 = (0, tan^2 a, 0).
        const rad::LeanMaps maps = rad::buildLeanMaps(normals.data(), constantMap(w, h, {0, 1, 0}).data(), w, h);
        const Eigen::Vector3d mu = texel(maps.moments[0], 1, 0);
        EXPECT_NEAR(mu.x(), 0.0, 1e-7);
        EXPECT_NEAR(mu.y(), t2, 1e-6);
        EXPECT_NEAR(mu.z(), 0.0, 1e-7);
    }
    {
        // Tilts along the diagonal (1, 1)/sqrt2: slopes +-tan a (1, 1)/sqrt2, mu2 = tan^2 a (1/2, 1/2, 1/2).
        const double s = std::sin(a) / std::sqrt(2.0);
        std::vector<float> diag(w * h * 3);
        for (int r = 0; r < h; ++r)
            for (int c = 0; c < w; ++c) setTexel(diag, w, c, r, {(c % 2 ? -s : s), (c % 2 ? -s : s), std::cos(a)});
        const rad::LeanMaps maps = rad::buildLeanMaps(diag.data(), constantMap(w, h, {1, 0, 0}).data(), w, h);
        const Eigen::Vector3d mu = texel(maps.moments[1], 0, 0);
        EXPECT_NEAR(mu.x(), t2 / 2, 1e-6);
        EXPECT_NEAR(mu.y(), t2 / 2, 1e-6);
        EXPECT_NEAR(mu.z(), t2 / 2, 1e-6);
    }
}

// Two of four normals more than 90 degrees from the mean (0, 0, 1) (tilted by 100 degrees along
// +-x): their slope is clamped to 100, mu2.x = (0 + 0 + 100^2 + 100^2) / 4 = 5000.
TEST(LeanMaps, NormalsBeyondNinetyDegreesAreClampedToSlope100) {
    const double b = 100.0 * kPi / 180.0;
    std::vector<float> normals(2 * 2 * 3);
    setTexel(normals, 2, 0, 0, {0, 0, 1});
    setTexel(normals, 2, 1, 1, {0, 0, 1});
    setTexel(normals, 2, 1, 0, {std::sin(b), 0, std::cos(b)});
    setTexel(normals, 2, 0, 1, {-std::sin(b), 0, std::cos(b)});
    const rad::LeanMaps maps = rad::buildLeanMaps(normals.data(), constantMap(2, 2, {1, 0, 0}).data(), 2, 2);
    const Eigen::Vector3d mu = texel(maps.moments[0], 0, 0);
    EXPECT_NEAR(mu.x(), 5000.0, 1e-2);
    EXPECT_NEAR(mu.y(), 0.0, 1e-3);
    EXPECT_NEAR(mu.z(), 0.0, 1e-3);
}

// Alg. 2 recomputed from its definition for a few texels of every level of a random 64 x 32 map.
TEST(LeanMaps, MatchesBruteForceRecomputationAtDeepLevels) {
    const int w = 64, h = 32;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> U(-0.6, 0.6);
    std::vector<float> normals(w * h * 3), tangents(w * h * 3);
    for (int r = 0; r < h; ++r)
        for (int c = 0; c < w; ++c) {
            const Eigen::Vector3d n = Eigen::Vector3d(U(rng), U(rng), 1.0).normalized();
            setTexel(normals, w, c, r, n);
            setTexel(tangents, w, c, r, Eigen::Vector3d(1.0, 0.3 * U(rng), 0.0));
        }
    const rad::LeanMaps maps = rad::buildLeanMaps(normals.data(), tangents.data(), w, h);
    ASSERT_EQ(maps.moments.size(), 6u);
    auto get = [&](const std::vector<float>& m, int c, int r) {
        return Eigen::Vector3d(m[(r * w + c) * 3], m[(r * w + c) * 3 + 1], m[(r * w + c) * 3 + 2]);
    };
    for (int k = 1; k <= 6; ++k) {
        const int lw = std::max(1, w >> k), lh = std::max(1, h >> k);
        const int fx = w / lw, fy = h / lh;
        for (const auto& cr : {std::pair<int, int>{0, 0}, {lw - 1, lh - 1}, {lw / 2, lh / 3}}) {
            const int C = cr.first, R = cr.second;
            Eigen::Vector3d ns = Eigen::Vector3d::Zero(), ts = Eigen::Vector3d::Zero();
            for (int r = R * fy; r < (R + 1) * fy; ++r)
                for (int c = C * fx; c < (C + 1) * fx; ++c) {
                    ns += get(normals, c, r);
                    ts += get(tangents, c, r);
                }
            const Eigen::Vector3d N = ns.normalized();
            const Eigen::Vector3d T = (ts - N * N.dot(ts)).normalized();
            const Eigen::Vector3d B = N.cross(T);
            Eigen::Vector3d mu = Eigen::Vector3d::Zero();
            for (int r = R * fy; r < (R + 1) * fy; ++r)
                for (int c = C * fx; c < (C + 1) * fx; ++c) {
                    const Eigen::Vector3d n = get(normals, c, r);
                    const double x = n.dot(T) / n.dot(N), y = n.dot(B) / n.dot(N);
                    mu += Eigen::Vector3d(x * x, y * y, x * y);
                }
            mu /= double(fx * fy);
            SCOPED_TRACE("level " + std::to_string(k) + " texel " + std::to_string(C) + "," + std::to_string(R));
            EXPECT_LT((texel(maps.normals[k], C, R) - N).norm(), 1e-5);
            EXPECT_LT((texel(maps.moments[k - 1], C, R) - mu).norm(), 1e-5 * (1.0 + mu.norm()));
            EXPECT_GT(mu.x() + mu.y(), 0.01);  // not a trivially zero texel
        }
    }
}

TEST(LeanMaps, RefusesSizesThatAreNotPowersOfTwo) {
    const std::vector<float> n = constantMap(6, 4, {0, 0, 1});
    EXPECT_THROW(rad::buildLeanMaps(n.data(), n.data(), 6, 4), std::invalid_argument);
    EXPECT_THROW(rad::buildNormalPyramid(n.data(), 6, 4), std::invalid_argument);
}

// With mu2 = 0, Sigma = I / s and the lobe is exp(-s/2 |h|^2), |h| = tan(theta) (eq. 4).
TEST(LeanSpecular, ZeroCovarianceIsTheGaussianOfTheTangentOfTheHalfAngle) {
    const Eigen::Vector3d N = Eigen::Vector3d(0.2, 0.1, 1.0).normalized();
    const Eigen::Vector3d T = N.unitOrthogonal(), B = N.cross(T);
    for (double s : {10.0, 200.0})
        for (double theta : {0.0, 0.05, 0.2, 0.7, 1.4})
            for (double phi : {0.0, 1.0, 2.5}) {
                const Eigen::Vector3d H =
                    std::cos(theta) * N + std::sin(theta) * (std::cos(phi) * T + std::sin(phi) * B);
                const double expected = std::exp(-0.5 * s * std::tan(theta) * std::tan(theta));
                EXPECT_NEAR(rad::leanSpecular(N, T, Eigen::Vector3d::Zero(), H, s), expected, 1e-12);
            }
    EXPECT_EQ(rad::leanSpecular(N, T, Eigen::Vector3d::Zero(), -N, 50.0), 0.0);  // H.N <= 0
    EXPECT_EQ(rad::blinnPhongSpecular(N, -N, 50.0), 0.0);
}

// cos^s(theta) = exp(s ln cos) ~ exp(-s theta^2/2 - s theta^4/12), exp(-s/2 tan^2) ~
// exp(-s theta^2/2 - s theta^4/3): with x = s theta^2 / 2 the difference is about e^-x x^2 / s,
// at most 4 e^-2 / s = 0.54 / s. We allow 0.6 / s.
TEST(LeanSpecular, ApproachesBlinnPhongForLargeShininess) {
    const Eigen::Vector3d N(0, 0, 1), T(1, 0, 0);
    double previous = 1e9;
    for (double s : {50.0, 200.0, 1000.0}) {
        double worst = 0;
        for (int i = 0; i <= 2000; ++i) {
            const double theta = 0.6 * i / 2000.0;
            const Eigen::Vector3d H(std::sin(theta), 0, std::cos(theta));
            const double bp = rad::blinnPhongSpecular(N, H, s);
            EXPECT_NEAR(bp, std::pow(std::cos(theta), s), 1e-12);
            worst = std::max(worst, std::fabs(rad::leanSpecular(N, T, Eigen::Vector3d::Zero(), H, s) - bp));
        }
        EXPECT_LT(worst, 0.6 / s) << "s = " << s;
        EXPECT_GT(worst, 0.3 / s) << "s = " << s;  // the estimate is the right size, not loose
        EXPECT_LT(worst, previous);
        previous = worst;
    }
}

// The lobe is a normalised 2D Gaussian times 2 pi / s over the slope plane h = H_tbn: its integral
// is 2 pi sqrt(det Sigma) / (s sqrt(det Sigma)) = 2 pi / s whatever mu2; its value at h is
// exp(-h^T Sigma^-1 h / 2) / (s sqrt(det Sigma)) with Sigma = [[mu.x + 1/s, mu.z], [mu.z, mu.y + 1/s]].
TEST(LeanSpecular, IntegratesTo2PiOverShininessOverTheSlopePlane) {
    const Eigen::Vector3d N = Eigen::Vector3d(-0.3, 0.4, 1.0).normalized();
    const Eigen::Vector3d T = (Eigen::Vector3d(1, 0, 0) - N * N.x()).normalized(), B = N.cross(T);
    const double s = 40.0;
    for (const Eigen::Vector3d mu : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.04, 0.01, 0.0),
                                     Eigen::Vector3d(0.03, 0.05, -0.02)}) {
        const double L = 2.0, step = 0.004;
        double sum = 0;
        for (double x = -L + step / 2; x < L; x += step)
            for (double y = -L + step / 2; y < L; y += step)
                sum += rad::leanSpecular(N, T, mu, (x * T + y * B + N).normalized(), s);
        sum *= step * step;
        EXPECT_NEAR(sum, 2 * kPi / s, 2e-4 * 2 * kPi / s) << mu.transpose();
        // One point by the closed form.
        const double a = mu.x() + 1 / s, d = mu.y() + 1 / s, b = mu.z(), det = a * d - b * b;
        const double hx = 0.1, hy = -0.15;
        const double expected = std::exp(-0.5 * (d * hx * hx - 2 * b * hx * hy + a * hy * hy) / det) / (s * std::sqrt(det));
        EXPECT_NEAR(rad::leanSpecular(N, T, mu, (hx * T + hy * B + N).normalized(), s), expected, 1e-12);
    }
}

// A 4 x 4 map whose columns tilt +a, -a, +b, -b along x: level 1 (2 x 2) holds tan^2 a on the left
// and tan^2 b on the right, level 2 (1 x 1) their mean (its normal is (0, 0, 1) by symmetry).
TEST(LeanMoments, SamplingFollowsAlgorithm4) {
    const double a = 0.3, b = 0.6;
    std::vector<float> normals(4 * 4 * 3);
    const double tilt[4] = {a, -a, b, -b};
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) setTexel(normals, 4, c, r, {std::sin(tilt[c]), 0, std::cos(tilt[c])});
    const rad::LeanMaps maps = rad::buildLeanMaps(normals.data(), constantMap(4, 4, {1, 0, 0}).data(), 4, 4);
    const double ta = std::pow(std::tan(a), 2), tb = std::pow(std::tan(b), 2), mean = 0.5 * (ta + tb);
    const double uLeft = 0.25, v = 0.75;  // centre of level-1 texel (0, 0)
    EXPECT_NEAR(rad::sampleLeanMoments(maps, uLeft, v, -2.0).x(), 0.0, 1e-12);  // magnified: level 0, Sigma = 0
    EXPECT_NEAR(rad::sampleLeanMoments(maps, uLeft, v, 0.0).x(), 0.0, 1e-12);
    for (double lambda : {0.25, 0.5, 0.9}) EXPECT_NEAR(rad::sampleLeanMoments(maps, uLeft, v, lambda).x(), lambda * ta, 1e-6);
    EXPECT_NEAR(rad::sampleLeanMoments(maps, uLeft, v, 1.0).x(), ta, 1e-6);
    EXPECT_NEAR(rad::sampleLeanMoments(maps, 0.75, v, 1.0).x(), tb, 1e-6);
    EXPECT_NEAR(rad::sampleLeanMoments(maps, 0.5, v, 1.0).x(), mean, 1e-6);  // bilinear between the columns
    EXPECT_NEAR(rad::sampleLeanMoments(maps, uLeft, v, 1.5).x(), 0.5 * ta + 0.5 * mean, 1e-6);  // trilinear
    EXPECT_NEAR(rad::sampleLeanMoments(maps, uLeft, v, 2.0).x(), mean, 1e-6);
    EXPECT_NEAR(rad::sampleLeanMoments(maps, uLeft, v, 7.0).x(), mean, 1e-6);  // beyond the last level
    EXPECT_NEAR(rad::sampleLeanMoments(maps, 0.0, 0.0, 1.0).x(), ta, 1e-6);   // clamp to edge
    EXPECT_NEAR(rad::sampleLeanMoments(maps, 1.0, 1.0, 0.5).y(), 0.0, 1e-9);
}

std::string tmpPath(const std::string& name) { return std::string(RADIANCE_TEST_TMPDIR) + "/" + name; }

TEST(LeanMomentsFile, RoundTripKeepsEveryLevelAndATruncatedFileIsRefused) {
    const int w = 32, h = 16;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> U(-0.5, 0.5);
    std::vector<float> normals(w * h * 3);
    for (int r = 0; r < h; ++r)
        for (int c = 0; c < w; ++c) setTexel(normals, w, c, r, Eigen::Vector3d(U(rng), U(rng), 1.0).normalized());
    const rad::LeanMaps maps = rad::buildLeanMaps(normals.data(), constantMap(w, h, {1, 0, 0}).data(), w, h);
    const std::string path = tmpPath("lean_roundtrip_lean.exr");
    rad::writeLeanMoments(path, maps);
    const std::vector<rad::MipImage> back = rad::readLeanMoments(path);
    ASSERT_EQ(back.size(), 5u);  // MIP levels 1..5: 16x8, 8x4, 4x2, 2x1, 1x1
    EXPECT_EQ(back[0].width, 16);
    EXPECT_EQ(back[0].height, 8);
    EXPECT_EQ(back[4].width, 1);
    EXPECT_EQ(back[4].height, 1);
    for (std::size_t i = 0; i < back.size(); ++i) {
        ASSERT_EQ(back[i].width, maps.moments[i].width);
        ASSERT_EQ(back[i].height, maps.moments[i].height);
        EXPECT_EQ(back[i].data, maps.moments[i].data) << "level " << i + 1;  // FLOAT channels: exact
    }

    std::ifstream in(path, std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string cut = tmpPath("lean_truncated_lean.exr");
    {
        std::ofstream out(cut, std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size() * 2 / 3));
    }
    try {
        rad::readLeanMoments(cut);
        ADD_FAILURE() << "a truncated file was read";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(cut), std::string::npos) << e.what();
    }
    EXPECT_THROW(rad::readLeanMoments(tmpPath("no_such_lean.exr")), std::runtime_error);
    EXPECT_THROW(rad::writeLeanMoments(tmpPath("empty_lean.exr"), rad::LeanMaps{}), std::runtime_error);
}

}  // namespace
