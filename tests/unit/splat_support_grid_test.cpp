// The splat support grid against a brute-force scan: boxes of sizes over five orders of magnitude,
// every box containing a query point found once, none that does not.
#include "splats/splat_support_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <stdexcept>

namespace {

TEST(SplatSupportGrid, FindsExactlyTheContainingBoxesAcrossScales) {
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> u(-1.0, 1.0), logSize(-5.0, 0.0);
    std::vector<rad::SupportBox> boxes(3000);
    for (auto& b : boxes) {
        const Eigen::Vector3d centre(u(rng), u(rng), u(rng));
        const Eigen::Vector3d half(std::pow(10.0, logSize(rng)), std::pow(10.0, logSize(rng)), std::pow(10.0, logSize(rng)));
        b = {centre - half, centre + half};
    }
    const rad::SplatSupportGrid grid(boxes);
    EXPECT_GE(grid.levelCount(), 4);  // sizes over 5 decades use several levels
    std::size_t hits = 0;
    for (int q = 0; q < 2000; ++q) {
        // Half the queries at box centres (sure hits), half anywhere.
        const Eigen::Vector3d p = q % 2 ? Eigen::Vector3d(u(rng), u(rng), u(rng))
                                        : Eigen::Vector3d(0.5 * (boxes[q].lo + boxes[q].hi));
        std::vector<std::uint32_t> found, expected;
        grid.forEachContaining(p, [&](std::uint32_t i) { found.push_back(i); });
        for (std::uint32_t i = 0; i < boxes.size(); ++i)
            if ((p.array() >= boxes[i].lo.array()).all() && (p.array() <= boxes[i].hi.array()).all()) expected.push_back(i);
        std::sort(found.begin(), found.end());
        ASSERT_EQ(found, expected) << "query " << q;
        hits += found.size();
    }
    EXPECT_GT(hits, 1000u);
}

TEST(SplatSupportGrid, BoxesOnTheCornerOfACellAndDegenerateBoxes) {
    // A zero-size box is found at its own point; boxes straddling cell boundaries from every side.
    std::vector<rad::SupportBox> boxes = {{Eigen::Vector3d(0.5, 0.5, 0.5), Eigen::Vector3d(0.5, 0.5, 0.5)},
                                          {Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(0, 0, 0)},
                                          {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1)}};
    const rad::SplatSupportGrid grid(boxes);
    std::vector<std::uint32_t> found;
    grid.forEachContaining(Eigen::Vector3d(0.5, 0.5, 0.5), [&](std::uint32_t i) { found.push_back(i); });
    std::sort(found.begin(), found.end());
    EXPECT_EQ(found, (std::vector<std::uint32_t>{0, 2}));
    found.clear();
    grid.forEachContaining(Eigen::Vector3d(0, 0, 0), [&](std::uint32_t i) { found.push_back(i); });
    std::sort(found.begin(), found.end());
    EXPECT_EQ(found, (std::vector<std::uint32_t>{1, 2}));
}

TEST(SplatSupportGrid, RefusesNonFiniteOrInvertedBoxes) {
    EXPECT_THROW(rad::SplatSupportGrid({{Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 1)}}), std::invalid_argument);
    EXPECT_THROW(rad::SplatSupportGrid({{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(INFINITY, 1, 1)}}), std::invalid_argument);
}

}  // namespace
