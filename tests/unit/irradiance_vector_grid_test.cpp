// The irradiance vector grid's storage, interpolation (Granier et al. 2007), GPU compression and file.
#include "lighting/irradiance_vector_grid.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

namespace {

using rad::IrradianceVectorGrid;
constexpr float kPi = 3.14159265358979f;

// Every vertex and direction holds the irradiance vector of uniform radiance `radiance` per channel
// over the whole sphere: I_delta = integral over the hemisphere of delta of L w dw = pi L delta.
IrradianceVectorGrid uniformSky(const float radiance[3]) {
    IrradianceVectorGrid grid = IrradianceVectorGrid::covering({{0, 0, 0}}, {{2, 1, 1}}, {{2, 1, 1}});
    for (std::size_t v = 0; v < grid.vertexCount(); ++v)
        for (int d = 0; d < 6; ++d) {
            const auto delta = rad::gridDirection(d);
            float* slot = grid.at(v, d);
            for (int c = 0; c < 3; ++c)
                for (int a = 0; a < 3; ++a) slot[3 * c + a] = kPi * radiance[c] * delta[a];
        }
    return grid;
}

std::string tempPath(const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("ivg_test_" + std::to_string(::getpid()) + "_" + name)).string();
}

TEST(IrradianceVectorGrid, CoveringLaysOutVerticesIFastest) {
    const auto grid = IrradianceVectorGrid::covering({{-1, 0, 2}}, {{1, 3, 4}}, {{4, 3, 2}});
    EXPECT_EQ(grid.vertexCount(), 5u * 4u * 3u);
    EXPECT_EQ(grid.vectors.size(), 5u * 4u * 3u * 54u);
    EXPECT_EQ(grid.vertexIndex(1, 0, 0), 1u);
    EXPECT_EQ(grid.vertexIndex(0, 1, 0), 5u);
    EXPECT_EQ(grid.vertexIndex(0, 0, 1), 20u);
    const auto p = grid.vertexPosition(4, 3, 2);
    EXPECT_FLOAT_EQ(p[0], 1.0f);
    EXPECT_FLOAT_EQ(p[1], 3.0f);
    EXPECT_FLOAT_EQ(p[2], 4.0f);
}

TEST(IrradianceVectorGrid, CoveringRefusesBadBoxesAndCounts) {
    EXPECT_THROW(IrradianceVectorGrid::covering({{0, 0, 0}}, {{1, 1, 1}}, {{0, 1, 1}}), rad::IrradianceVectorGridError);
    EXPECT_THROW(IrradianceVectorGrid::covering({{0, 0, 0}}, {{1, 0, 1}}, {{1, 1, 1}}), rad::IrradianceVectorGridError);
    EXPECT_THROW(IrradianceVectorGrid::covering({{0, 0, 0}}, {{1, NAN, 1}}, {{1, 1, 1}}), rad::IrradianceVectorGridError);
    EXPECT_THROW(IrradianceVectorGrid::covering({{0, 0, 0}}, {{1, 1, 1}}, {{1000, 1000, 1000}}), rad::IrradianceVectorGridError);
}

// Under a uniform sky the paper's directional interpolation gives <I_n, n> = pi L sum_a |n_a|^3:
// exact (pi L) along the axes, 1/sqrt(3) of it along a diagonal. The exact answer for any normal
// would be pi L; the test pins the scheme as published, including its known loss off the axes.
TEST(IrradianceVectorGrid, UniformSkyFollowsThePapersDirectionalInterpolation) {
    const float radiance[3] = {1.0f, 0.5f, 2.0f};
    const auto grid = uniformSky(radiance);
    const float albedo[3] = {0.8f, 0.6f, 0.4f};
    const float point[3] = {0.7f, 0.3f, 0.9f};
    const float normals[][3] = {{1, 0, 0}, {0, -1, 0}, {0, 0, 1}, {1, 1, 1}, {-1, 2, 0.5f}};
    for (const auto& normal : normals) {
        const double length = std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
        double cubes = 0;
        for (int a = 0; a < 3; ++a) cubes += std::pow(std::abs(normal[a]) / length, 3.0);
        float rgb[3];
        rad::reflectedRadiance(grid, point, normal, albedo, rgb);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(rgb[c], albedo[c] * radiance[c] * cubes, 1e-5) << c;
    }
}

// The |n_a| weights are exact under a uniform sky for every normal: rho L.
TEST(IrradianceVectorGrid, AbsoluteWeightsAreExactUnderAUniformSky) {
    const float radiance[3] = {1.0f, 0.5f, 2.0f};
    const auto grid = uniformSky(radiance);
    const auto compressed = rad::gpuCompressed(grid);
    const float albedo[3] = {0.8f, 0.6f, 0.4f};
    const float point[3] = {0.7f, 0.3f, 0.9f};
    const float normals[][3] = {{1, 0, 0}, {0, -1, 0}, {1, 1, 1}, {-1, 2, 0.5f}, {0.2f, -0.3f, -0.9f}};
    for (const auto& normal : normals) {
        float rgb[3], gpu[3];
        rad::reflectedRadiance(grid, point, normal, albedo, rgb, rad::DirectionalWeights::Absolute);
        rad::reflectedRadianceCompressed(grid, compressed, point, normal, albedo, gpu, rad::DirectionalWeights::Absolute);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(rgb[c], albedo[c] * radiance[c], 1e-5) << c;
            EXPECT_NEAR(gpu[c], albedo[c] * radiance[c], 1e-5) << c;
        }
    }
}

// Trilinear in space: vectors that are affine in position are reproduced exactly inside the cells.
TEST(IrradianceVectorGrid, AffineFieldIsReproducedByTrilinearInterpolation) {
    auto grid = IrradianceVectorGrid::covering({{0, 0, 0}}, {{3, 2, 1}}, {{3, 2, 1}});
    const auto field = [](const std::array<float, 3>& p, int d, int k) {
        return 0.5f + 0.25f * p[0] - 0.125f * p[1] + 0.375f * p[2] + 0.1f * d + 0.01f * k;
    };
    for (int k = 0; k <= 1; ++k)
        for (int j = 0; j <= 2; ++j)
            for (int i = 0; i <= 3; ++i)
                for (int d = 0; d < 6; ++d)
                    for (int c = 0; c < 9; ++c) grid.at(grid.vertexIndex(i, j, k), d)[c] = field(grid.vertexPosition(i, j, k), d, c);
    const float point[3] = {1.3f, 0.45f, 0.8f};
    const float normal[3] = {0.0f, -1.0f, 0.0f};  // picks -y (direction 3) alone
    float out[9];
    rad::interpolateIrradianceVector(grid, point, normal, out);
    for (int c = 0; c < 9; ++c) EXPECT_NEAR(out[c], field({{point[0], point[1], point[2]}}, 3, c), 1e-5) << c;
    // Outside the box: the value at the nearest point of the box.
    const float outside[3] = {-5.0f, 0.45f, 7.0f};
    rad::interpolateIrradianceVector(grid, outside, normal, out);
    for (int c = 0; c < 9; ++c) EXPECT_NEAR(out[c], field({{0.0f, 0.45f, 1.0f}}, 3, c), 1e-5) << c;
}

TEST(IrradianceVectorGrid, ZeroNormalGivesNoLight) {
    const float radiance[3] = {1, 1, 1};
    const auto grid = uniformSky(radiance);
    const float point[3] = {0.5f, 0.5f, 0.5f}, zero[3] = {0, 0, 0}, albedo[3] = {1, 1, 1};
    float rgb[3] = {9, 9, 9};
    rad::reflectedRadiance(grid, point, zero, albedo, rgb);
    EXPECT_EQ(rgb[0], 0.0f);
    EXPECT_EQ(rgb[2], 0.0f);
}

// The GPU form is exact when the three channels' vectors are parallel (a grey or single-hued
// source) and loses the difference of directions otherwise.
TEST(IrradianceVectorGrid, GpuCompressionIsExactForParallelChannels) {
    const float radiance[3] = {1.0f, 0.25f, 3.0f};
    const auto grid = uniformSky(radiance);
    const auto compressed = rad::gpuCompressed(grid);
    ASSERT_EQ(compressed.size(), grid.vertexCount() * 36);
    // Colour of (vertex 0, +x) = |pi L_c e_x| = pi L_c; direction +x.
    EXPECT_NEAR(compressed[0], kPi * 1.0f, 1e-5);
    EXPECT_NEAR(compressed[2], kPi * 3.0f, 1e-5);
    EXPECT_NEAR(compressed[3], 1.0f, 1e-6);
    EXPECT_NEAR(compressed[6 + 3], -1.0f, 1e-6);  // -x
    const float albedo[3] = {0.5f, 0.5f, 0.5f}, point[3] = {1.2f, 0.4f, 0.6f};
    const float normal[3] = {0.3f, -0.8f, 0.5f};
    float full[3], gpu[3];
    rad::reflectedRadiance(grid, point, normal, albedo, full);
    rad::reflectedRadianceCompressed(grid, compressed, point, normal, albedo, gpu);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(gpu[c], full[c], 1e-5);

    // Red from +y, blue from +z at every vertex's +x slot: the compressed direction is their mean.
    auto mixed = grid;
    for (std::size_t v = 0; v < mixed.vertexCount(); ++v) {
        float* slot = mixed.at(v, 0);
        for (int c = 0; c < 9; ++c) slot[c] = 0.0f;
        slot[1] = 1.0f;  // R along +y
        slot[8] = 1.0f;  // B along +z
    }
    const auto lossy = rad::gpuCompressed(mixed);
    EXPECT_NEAR(lossy[3], 0.0f, 1e-6);
    EXPECT_NEAR(lossy[4], std::sqrt(0.5f), 1e-6);
    EXPECT_NEAR(lossy[5], std::sqrt(0.5f), 1e-6);
}

TEST(IrradianceVectorGrid, FileRoundTripIsExact) {
    const float radiance[3] = {0.1f, 0.2f, 0.3f};
    auto grid = uniformSky(radiance);
    grid.bounces = 2;
    grid.raysPerDirection = 128;
    grid.vectors[17] = 1.0e-30f;
    grid.vectors[18] = -123.456f;
    const std::string path = tempPath("roundtrip.ivg");
    rad::writeIrradianceVectorGrid(path, grid);
    const auto back = rad::readIrradianceVectorGrid(path);
    EXPECT_EQ(back.cells, grid.cells);
    EXPECT_EQ(back.origin, grid.origin);
    EXPECT_EQ(back.cellSize, grid.cellSize);
    EXPECT_EQ(back.bounces, 2);
    EXPECT_EQ(back.raysPerDirection, 128);
    EXPECT_EQ(back.vectors, grid.vectors);
    // No temporary left beside it.
    for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(path).parent_path()))
        EXPECT_EQ(entry.path().filename().string().find("roundtrip.ivg.part"), std::string::npos);
    std::remove(path.c_str());
}

TEST(IrradianceVectorGrid, WriteRefusesNonFiniteValuesAndLeavesNoFile) {
    const float radiance[3] = {1, 1, 1};
    auto grid = uniformSky(radiance);
    grid.vectors[5] = NAN;
    const std::string path = tempPath("nan.ivg");
    EXPECT_THROW(rad::writeIrradianceVectorGrid(path, grid), rad::IrradianceVectorGridError);
    EXPECT_FALSE(std::filesystem::exists(path));
}

class IrradianceVectorGridFile : public ::testing::Test {
protected:
    void SetUp() override {
        const float radiance[3] = {1, 2, 3};
        path = tempPath("hostile.ivg");
        rad::writeIrradianceVectorGrid(path, uniformSky(radiance));
        bytes = radtest::readBytes(path);
    }
    void TearDown() override { std::remove(path.c_str()); }
    std::string readError(const std::vector<char>& content) {
        radtest::writeBytes(path, content);
        try {
            rad::readIrradianceVectorGrid(path);
        } catch (const rad::IrradianceVectorGridError& e) {
            return e.what();
        }
        return "";
    }
    std::string replaced(const std::string& from, const std::string& to) {
        std::string text(bytes.begin(), bytes.end());
        const auto at = text.find(from);
        EXPECT_NE(at, std::string::npos);
        return text.replace(at, from.size(), to);
    }
    std::string path;
    std::vector<char> bytes;
};

TEST_F(IrradianceVectorGridFile, TruncatedDataIsRefused) {
    for (std::size_t cut : {std::size_t(1), std::size_t(4), bytes.size() / 2}) {
        std::vector<char> shorter(bytes.begin(), bytes.end() - cut);
        const std::string message = readError(shorter);
        EXPECT_FALSE(message.empty()) << cut;
    }
    std::vector<char> header(bytes.begin(), bytes.begin() + 20);
    EXPECT_NE(readError(header).find("truncated"), std::string::npos);
}

TEST_F(IrradianceVectorGridFile, TrailingDataIsRefused) {
    auto longer = bytes;
    longer.push_back(0);
    EXPECT_NE(readError(longer).find("trailing"), std::string::npos);
}

TEST_F(IrradianceVectorGridFile, HeaderProblemsAreNamed) {
    const auto asBytes = [](const std::string& s) { return std::vector<char>(s.begin(), s.end()); };
    EXPECT_NE(readError(asBytes("ply\nformat ascii 1.0\n")).find("not an irradiance vector grid"), std::string::npos);
    EXPECT_NE(readError(asBytes(replaced("RADIANCE_IVG 1", "RADIANCE_IVG 7"))).find("unknown version"), std::string::npos);
    EXPECT_NE(readError(asBytes(replaced("cells 2 1 1", "cells 2 x 1"))).find("malformed"), std::string::npos);
    EXPECT_NE(readError(asBytes(replaced("cells 2 1 1", "cells 2 0 1"))).find("out of range"), std::string::npos);
    // A header announcing a huge grid is refused from the file size, before any allocation.
    EXPECT_NE(readError(asBytes(replaced("cells 2 1 1", "cells 500 500 500"))).find("more than 2^26"), std::string::npos);
    EXPECT_NE(readError(asBytes(replaced("cells 2 1 1", "cells 20 20 20"))).find("truncated"), std::string::npos);
    EXPECT_NE(readError(asBytes(replaced("data float32 little_endian", "data float64 big_endian"))).find("unsupported"),
              std::string::npos);
    EXPECT_NE(readError(asBytes(replaced("bounces", "colour"))).find("unknown header line"), std::string::npos);
}

TEST_F(IrradianceVectorGridFile, NonFiniteValueIsRefused) {
    auto hostile = bytes;
    const float nan = NAN;
    std::memcpy(hostile.data() + hostile.size() - 4, &nan, 4);
    EXPECT_NE(readError(hostile).find("not finite"), std::string::npos);
}

// A sparse file passes the size check without using the disk: a grid of 301^3 vertices (5.9 GB) is
// refused with the figures before the allocation (a bare std::bad_alloc in the GUI, before).
TEST_F(IrradianceVectorGridFile, GridLargerThanTheMemoryLimitIsRefusedWithTheFigures) {
    const std::string withBigCells = replaced("cells 2 1 1", "cells 300 300 300");
    const std::string header = withBigCells.substr(0, withBigCells.find("end_header\n") + 11);
    radtest::writeBytes(path, std::vector<char>(header.begin(), header.end()));
    const std::uintmax_t vertices = 301ull * 301ull * 301ull, floatsPerVertex = 6 * 9;
    std::filesystem::resize_file(path, header.size() + vertices * floatsPerVertex * sizeof(float));
    const std::string message = radtest::refusalMessage<rad::IrradianceVectorGridError>(
        [&] { rad::readIrradianceVectorGrid(path, std::size_t(64) << 20); });
    ASSERT_FALSE(message.empty()) << "a 5.9 GB grid was read under a 64 MiB limit";
    EXPECT_NE(message.find("(300 x 300 x 300 cells) needs 5.9 GB of memory and 67 MB are available"),
              std::string::npos) << message;
    EXPECT_NE(message.find("compute a grid of lower resolution"), std::string::npos) << message;
}

TEST(IrradianceVectorGridFileMissing, MissingFileIsNamed) {
    try {
        rad::readIrradianceVectorGrid(tempPath("does_not_exist.ivg"));
        FAIL() << "no error";
    } catch (const rad::IrradianceVectorGridError& e) {
        EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos);
    }
}

// The decoration drew a stale grid 1000 units away, or one with a near-zero cell, in one flat colour
// without a word: gridCoverageProblem says why such a grid does not fit the layer.
TEST(IrradianceVectorGrid, CoverageOfTheLayerIsChecked) {
    const rad::IrradianceVectorGrid grid = rad::IrradianceVectorGrid::covering({{-1, -1, -1}}, {{1, 1, 1}}, {{4, 4, 4}});
    const std::vector<float> inside = {-0.9f, 0.0f, 0.5f, 0.9f, -0.9f, -1.1f, 0.0f, 0.0f, 0.0f};
    EXPECT_EQ(rad::gridCoverageProblem(grid, inside.data(), 3), "");
    std::vector<float> far = inside;
    for (std::size_t i = 0; i < far.size(); i += 3) far[i] += 1000.0f;
    const std::string stale = rad::gridCoverageProblem(grid, far.data(), 3);
    EXPECT_NE(stale.find("100 % of the layer's vertices lie outside"), std::string::npos) << stale;
    const rad::IrradianceVectorGrid speck =
        rad::IrradianceVectorGrid::covering({{-1e-6f, -1e-6f, -1e-6f}}, {{1e-6f, 1e-6f, 1e-6f}}, {{2, 2, 2}});
    const std::vector<float> around = {-1e-6f, 0.0f, 0.0f, 1e-6f, 0.0f, 0.0f, 0.0f, 0.0f, 5e-7f, 2.0f, 2.0f, 2.0f};
    const std::string small = rad::gridCoverageProblem(speck, around.data(), 4);
    EXPECT_FALSE(small.empty());
}

}  // namespace

