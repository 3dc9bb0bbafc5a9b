// coordinateRangeProblem (geometry/coordinate_range.h).
#include "geometry/coordinate_range.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace {

TEST(CoordinateRange, AcceptsRealisticScalesUpToTheLimit) {
    // A scan in millimetres, a georeferenced one (UTM metres), and the limit itself.
    const std::vector<float> positions = {1234.5f, -87.25f, 0.001f, 5.6e6f, 4.1e6f, 312.0f, 1e11f, -1e11f, 0.0f};
    EXPECT_EQ(rad::coordinateRangeProblem(positions.data(), 3), "");
    EXPECT_EQ(rad::coordinateRangeProblem(nullptr, 0), "");
}

TEST(CoordinateRange, NamesTheFirstVertexBeyondTheLimitAndTheFix) {
    // 1e13: Embree's triangle test overflows there (the irradiance grid aborted MeshLab at 1e13..1e15).
    const std::vector<float> positions = {0, 0, 0, 1, 2, 3, 0, 1e13f, 0, 1e19f, 0, 0};
    const std::string problem = rad::coordinateRangeProblem(positions.data(), 4);
    EXPECT_NE(problem.find("Vertex 2 has a coordinate of 1e+13"), std::string::npos) << problem;
    EXPECT_NE(problem.find("Transform: Scale, Normalize"), std::string::npos) << problem;
}

TEST(CoordinateRange, RefusesNonFiniteCoordinates) {
    const float inf = std::numeric_limits<float>::infinity();
    const std::vector<float> positions = {0, 0, 0, 0, std::nanf(""), 0, -inf, 0, 0};
    const std::string problem = rad::coordinateRangeProblem(positions.data(), 3);
    EXPECT_NE(problem.find("Vertex 1 has a coordinate that is not a finite number"), std::string::npos) << problem;
}

// A unit square (two triangles) scaled by s and moved by t, plus one vertex no face uses.
std::vector<float> square(float s, float t, float stray) {
    return {t, t, t, t + s, t, t, t + s, t + s, t, t, t + s, t, stray, stray, stray};
}
const std::vector<std::uint32_t> kSquareFaces = {0, 1, 2, 0, 2, 3};

TEST(SceneScale, AcceptsOrdinaryScenes) {
    for (float s : {1e-5f, 1.0f, 1e4f, 1e9f}) {
        const std::vector<float> p = square(s, 0.0f, 0.0f);
        EXPECT_EQ(rad::sceneScaleProblem(p.data(), 5, kSquareFaces.data(), 2), "") << s;
    }
    const std::vector<float> utm = square(100.0f, 5.6e5f, 5.6e5f);  // 100 m at UTM-sized coordinates
    EXPECT_EQ(rad::sceneScaleProblem(utm.data(), 5, kSquareFaces.data(), 2), "");
}

TEST(SceneScale, RefusesTinyScenesWithTheFix) {
    // 1e-20 across: every Embree ray missed (an all-zero irradiance grid, no warning).
    for (float s : {1e-20f, 1e-30f, 1e-7f}) {
        const std::vector<float> p = square(s, 0.0f, 0.0f);
        const std::string problem = rad::sceneScaleProblem(p.data(), 5, kSquareFaces.data(), 2, "The scene");
        EXPECT_EQ(problem.rfind("The scene is ", 0), 0u) << problem;
        EXPECT_NE(problem.find("scale it up"), std::string::npos) << problem;
    }
}

TEST(SceneScale, RefusesAMeshTooSmallForWhereItLies) {
    const std::vector<float> p = square(1.0f, 1e5f, 1e5f);  // 1 unit at 1e5: float steps of 1/128
    const std::string problem = rad::sceneScaleProblem(p.data(), 5, kSquareFaces.data(), 2);
    EXPECT_NE(problem.find("Move it to the origin"), std::string::npos) << problem;
}

TEST(SceneScale, UnreferencedVerticesDoNotCountForTheSizeButForTheRange) {
    // A stray vertex 1e6 away makes the box huge only if counted: the square alone is fine.
    const std::vector<float> stray = square(1e-3f, 0.0f, 1e6f);
    EXPECT_EQ(rad::sceneScaleProblem(stray.data(), 5, kSquareFaces.data(), 2), "");
    double lo[3], hi[3];
    ASSERT_TRUE(rad::referencedBox(stray.data(), 5, kSquareFaces.data(), 2, lo, hi));
    EXPECT_FLOAT_EQ(float(hi[0]), 1e-3f);
    ASSERT_TRUE(rad::referencedBox(stray.data(), 5, nullptr, 0, lo, hi));
    EXPECT_FLOAT_EQ(float(hi[0]), 1e6f);
    // Out of range is refused wherever the vertex is: files with such vertices are broken.
    const std::vector<float> broken = square(1.0f, 0.0f, 1e13f);
    EXPECT_NE(rad::sceneScaleProblem(broken.data(), 5, kSquareFaces.data(), 2).find("Vertex 4"), std::string::npos);
}

}  // namespace
