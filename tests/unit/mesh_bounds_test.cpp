// The bounding box of positions and the largest distance from its centre.
#include "geometry/mesh_bounds.h"

#include <gtest/gtest.h>

#include <cmath>

TEST(MeshBounds, BoxAndFarthestPositionFromItsCentre) {
    // Box [0, 4] x [0, 2] x [-1, 1], centre (2, 1, 0); no position sits at a corner.
    const std::vector<float> positions = {0, 0, 0, 4, 0.5f, 0, 1, 2, 1, 3, 1, -1};
    const rad::MeshBounds bounds = rad::meshBounds(positions);
    EXPECT_DOUBLE_EQ(bounds.box.min().x(), 0.0);
    EXPECT_DOUBLE_EQ(bounds.box.max().x(), 4.0);
    EXPECT_DOUBLE_EQ(bounds.box.min().y(), 0.0);
    EXPECT_DOUBLE_EQ(bounds.box.max().y(), 2.0);
    EXPECT_DOUBLE_EQ(bounds.box.min().z(), -1.0);
    EXPECT_DOUBLE_EQ(bounds.box.max().z(), 1.0);
    // From the centre (2, 1, 0): (0, 0, 0) at sqrt(5), (4, 0.5, 0) at sqrt(4.25), (1, 2, 1) at sqrt(3),
    // (3, 1, -1) at sqrt(2).
    EXPECT_DOUBLE_EQ(bounds.farthestFromCentre, std::sqrt(5.0));
}

TEST(MeshBounds, NoPositionsGiveAnEmptyBoxAndRadiusZero) {
    const rad::MeshBounds bounds = rad::meshBounds({});
    EXPECT_TRUE(bounds.box.isEmpty());
    EXPECT_EQ(bounds.farthestFromCentre, 0.0);
}
