// coordinateRangeProblem (geometry/coordinate_range.h).
#include "geometry/coordinate_range.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace {

TEST(CoordinateRange, AcceptsRealisticScalesUpToTheLimit) {
    // A scan in millimetres, a georeferenced one (UTM metres), and the limit itself.
    const std::vector<float> positions = {1234.5f, -87.25f, 0.001f, 5.6e6f, 4.1e6f, 312.0f, 1e15f, -1e15f, 0.0f};
    EXPECT_EQ(rad::coordinateRangeProblem(positions.data(), 3), "");
    EXPECT_EQ(rad::coordinateRangeProblem(nullptr, 0), "");
}

TEST(CoordinateRange, NamesTheFirstVertexBeyondTheLimitAndTheFix) {
    const std::vector<float> positions = {0, 0, 0, 1, 2, 3, 0, 2e15f, 0, 1e19f, 0, 0};
    const std::string problem = rad::coordinateRangeProblem(positions.data(), 4);
    EXPECT_NE(problem.find("Vertex 2 has a coordinate of 2e+15"), std::string::npos) << problem;
    EXPECT_NE(problem.find("Transform: Scale, Normalize"), std::string::npos) << problem;
}

TEST(CoordinateRange, RefusesNonFiniteCoordinates) {
    const float inf = std::numeric_limits<float>::infinity();
    const std::vector<float> positions = {0, 0, 0, 0, std::nanf(""), 0, -inf, 0, 0};
    const std::string problem = rad::coordinateRangeProblem(positions.data(), 3);
    EXPECT_NE(problem.find("Vertex 1 has a coordinate that is not a finite number"), std::string::npos) << problem;
}

}  // namespace
