// Computing the irradiance vector grid (Granier et al. 2007) against answers known independently:
// a lit square floor (the vector integral by quadrature over the floor's area), the inside of a
// sphere lit from its centre (closed form for any bounce count), vertices inside closed objects.
#include "lighting/irradiance_vector_grid_compute.h"

#include "geometry/primitive_meshes.h"
#include "progress/progress_callback.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using rad::IrradianceVectorGrid;
constexpr double kPi = 3.14159265358979323846;

using radtest::floorSquare;

// Grid vertices more than 3 % of the radius outside (invalidOutside) or inside the unit sphere
// must be flagged invalid, those as far on the other side valid (the band around the surface is
// left free: a vertex there may see either side). Returns how many were on the invalid side.
std::size_t checkInvalidOnOneSideOfTheUnitSphere(const IrradianceVectorGrid& grid, const std::vector<std::uint8_t>& invalid,
                                                 bool invalidOutside) {
    std::size_t count = 0;
    for (int k = 0; k <= grid.cells[2]; ++k)
        for (int j = 0; j <= grid.cells[1]; ++j)
            for (int i = 0; i <= grid.cells[0]; ++i) {
                const auto p = grid.vertexPosition(i, j, k);
                const double r = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
                const std::size_t v = grid.vertexIndex(i, j, k);
                const bool farOutside = r > 1.03, farInside = r < 0.97;
                if (invalidOutside ? farOutside : farInside) {
                    EXPECT_EQ(invalid[v], 1) << "vertex at radius " << r;
                    ++count;
                }
                if (invalidOutside ? farInside : farOutside) EXPECT_EQ(invalid[v], 0) << "vertex at radius " << r;
            }
    return count;
}

rad::TriangleMesh insideOut(rad::TriangleMesh m) {
    for (std::size_t f = 0; f < m.faceCount(); ++f) std::swap(m.faces[3 * f + 1], m.faces[3 * f + 2]);
    m.normals.clear();
    return m;
}

// Independent answer for the floor: I_delta(v) = L * integral over the floor's part in the
// hemisphere of delta of w dw, with dw = cos / r^2 dA, by the midpoint rule over the square.
Eigen::Vector3d floorVectorIntegral(double a, const Eigen::Vector3d& v, const Eigen::Vector3d& delta, int steps) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    const double h = 2.0 * a / steps;
    for (int i = 0; i < steps; ++i)
        for (int j = 0; j < steps; ++j) {
            const Eigen::Vector3d p(-a + (i + 0.5) * h, -a + (j + 0.5) * h, 0.0);
            const Eigen::Vector3d d = p - v;
            const double r = d.norm();
            const Eigen::Vector3d w = d / r;
            if (w.dot(delta) <= 0.0) continue;
            const double cosine = v.z() / r;  // between the floor's normal +z and -w
            sum += w * cosine / (r * r) * h * h;
        }
    return sum;
}

TEST(IrradianceVectorGridCompute, FloorUnderADirectionalLightMatchesTheAreaIntegral) {
    const float a = 2.0f, height = 0.5f;
    const rad::TriangleMesh floor = floorSquare(a);
    const std::vector<float> albedo = {0.8f, 0.5f, 0.2f, 0.8f, 0.5f, 0.2f, 0.8f, 0.5f, 0.2f, 0.8f, 0.5f, 0.2f};
    rad::AnalyticLighting lights;
    rad::DirectionalLight sun;
    sun.direction = Eigen::Vector3d(0, 0, 1);
    sun.irradiance = rad::Rgb(1.0, 2.0, 3.0);
    lights.directional.push_back(sun);
    rad::IrradianceGridOptions options;
    options.raysPerDirection = 4096;
    options.repairInvalid = false;
    rad::IndirectLightTracer tracer(floor, albedo, lights, options.light);
    // 2 x 2 x 1 cells whose vertex (1, 1, 0) is at (0, 0, height).
    IrradianceVectorGrid grid = IrradianceVectorGrid::covering({{-0.1f, -0.1f, height}}, {{0.1f, 0.1f, height + 0.1f}},
                                                               {{2, 2, 1}});
    rad::IrradianceGridReport report;
    rad::computeIrradianceVectors(tracer, grid, options, {}, report);
    EXPECT_EQ(report.invalidVertices, 0u);
    EXPECT_EQ(report.samples, grid.vertexCount() * 6u * 4096u);
    const std::size_t v = grid.vertexIndex(1, 1, 0);
    const Eigen::Vector3d position(0, 0, height);
    const double rho[3] = {0.8, 0.5, 0.2}, E[3] = {1, 2, 3};
    for (int d = 0; d < 6; ++d) {
        const auto g = rad::gridDirection(d);
        const Eigen::Vector3d delta(g[0], g[1], g[2]);
        const Eigen::Vector3d geometric = floorVectorIntegral(a, position, delta, 800);
        for (int c = 0; c < 3; ++c) {
            const double L = rho[c] * E[c] / kPi;  // the lit floor's radiance
            const Eigen::Vector3d expected = L * geometric;
            const float* got = grid.at(v, d) + 3 * c;
            const double scale = rho[c] * E[c];  // |I| of an infinite floor
            for (int q = 0; q < 3; ++q)
                EXPECT_NEAR(got[q], expected[q], 0.02 * scale) << "direction " << d << " channel " << c << " axis " << q;
        }
    }
    // Closed form for the -z direction: a point above the centre of a square of half side a at
    // height h sees it with the view factor F = 4 F_corner(a/h, a/h) (parallel rectangle, corner
    // formula), and I_-z = -L pi F z = -rho E F z.
    const double X = a / height;
    const double corner = (1.0 / (2.0 * kPi)) * 2.0 * (X / std::sqrt(1 + X * X)) * std::atan(X / std::sqrt(1 + X * X));
    const double F = 4.0 * corner;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(grid.at(v, 5)[3 * c + 2], -rho[c] * E[c] * F, 0.01 * rho[c] * E[c]);
    // Nothing above the floor: the +z vectors are zero (rays escape).
    for (int q = 0; q < 9; ++q) EXPECT_EQ(grid.at(v, 4)[q], 0.0f);
}

TEST(IrradianceVectorGridCompute, InsideALitSphereEveryBounceAddsRhoTimesThePrevious) {
    // Inside a closed sphere of radius r with albedo rho and a point light of intensity I at its
    // centre, the direct irradiance is E0 = I / r^2 everywhere, the radiance after k bounces is
    // uniform, L_B = rho E0 / pi (1 + rho + ... + rho^(B-1)), and an interior point sees it in every
    // direction: I_delta = pi L_B delta.
    const float radius = 1.0f;
    const rad::TriangleMesh sphere = insideOut(rad::makeIcosphere(4, radius));
    const double rho = 0.6, intensity = 2.0;
    std::vector<float> albedo(3 * sphere.vertexCount(), float(rho));
    rad::AnalyticLighting lights;
    rad::PointLight bulb;
    bulb.position = Eigen::Vector3d(0, 0, 0);
    bulb.intensity = rad::Rgb(intensity, intensity, intensity);
    lights.points.push_back(bulb);
    for (int bounces = 1; bounces <= 3; ++bounces) {
        rad::IrradianceGridOptions options;
        options.resolution = 4;
        options.padding = 0.05;
        options.raysPerDirection = 128;
        options.light.bounces = bounces;
        options.repairInvalid = false;
        rad::IrradianceGridReport report;
        const IrradianceVectorGrid grid = rad::computeIrradianceVectorGrid(sphere, albedo, lights, options, {}, &report);
        const double E0 = intensity / (radius * radius);
        double series = 0.0;
        for (int k = 0; k < bounces; ++k) series += std::pow(rho, k);
        const double expected = rho * E0 * series;  // pi L_B
        int checked = 0;
        for (int k = 0; k <= grid.cells[2]; ++k)
            for (int j = 0; j <= grid.cells[1]; ++j)
                for (int i = 0; i <= grid.cells[0]; ++i) {
                    const auto p = grid.vertexPosition(i, j, k);
                    if (std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) > 0.9) continue;
                    const std::size_t v = grid.vertexIndex(i, j, k);
                    for (int d = 0; d < 6; ++d) {
                        const auto delta = rad::gridDirection(d);
                        for (int c = 0; c < 3; ++c)
                            for (int q = 0; q < 3; ++q)
                                EXPECT_NEAR(grid.at(v, d)[3 * c + q], expected * delta[q], 0.03 * expected)
                                    << "bounces " << bounces << " vertex " << v << " direction " << d;
                    }
                    ++checked;
                }
        EXPECT_GE(checked, 1);
    }
}

TEST(IrradianceVectorGridCompute, VerticesOutsideTheRoomAreFlaggedAndRepaired) {
    // The inside-out sphere is a room: grid vertices outside it see its walls from behind.
    const rad::TriangleMesh sphere = insideOut(rad::makeIcosphere(3, 1.0f));
    rad::AnalyticLighting lights;
    rad::PointLight bulb;
    bulb.position = Eigen::Vector3d(0, 0, 0);
    lights.points.push_back(bulb);
    rad::IrradianceGridOptions options;
    options.resolution = 6;
    options.padding = 0.05;
    options.raysPerDirection = 64;
    options.repairInvalid = false;
    rad::IndirectLightTracer tracer(sphere, {}, lights, options.light);
    IrradianceVectorGrid grid = rad::placeIrradianceGrid({{-1, -1, -1}}, {{1, 1, 1}}, 6, 0.05);
    rad::IrradianceGridReport report;
    std::vector<std::uint8_t> invalid;
    rad::computeIrradianceVectors(tracer, grid, options, {}, report, &invalid);
    EXPECT_GT(checkInvalidOnOneSideOfTheUnitSphere(grid, invalid, /*invalidOutside=*/true), 0u);
    EXPECT_EQ(report.invalidVertices, std::size_t(std::count(invalid.begin(), invalid.end(), 1)));

    // Repaired: every invalid vertex takes its valid neighbours' average. Inside the sphere every
    // valid vertex holds the same vectors (uniform radiance), so the repaired ones must too, within
    // the estimate's noise, instead of the dark values they had.
    options.repairInvalid = true;
    IrradianceVectorGrid repaired = grid;
    rad::IrradianceGridReport repairReport;
    rad::computeIrradianceVectors(tracer, repaired, options, {}, repairReport);
    EXPECT_EQ(repairReport.repairedVertices + repairReport.unreachableVertices, repairReport.invalidVertices);
    EXPECT_EQ(repairReport.unreachableVertices, 0u);
    const double expected = 0.5 * 1.0;  // rho E0, default albedo, E0 = 1 / 1^2
    for (std::size_t v = 0; v < repaired.vertexCount(); ++v)
        EXPECT_NEAR(repaired.at(v, 4)[2], expected, 0.05 * expected) << "vertex " << v;  // +z, red, z
}

TEST(IrradianceVectorGridCompute, VerticesInsideAClosedObjectAreInvalid) {
    const rad::TriangleMesh ball = rad::makeIcosphere(3, 1.0f);
    rad::AnalyticLighting lights;
    lights.directional.push_back(rad::DirectionalLight{});
    rad::IrradianceGridOptions options;
    options.raysPerDirection = 32;
    options.repairInvalid = false;
    rad::IndirectLightTracer tracer(ball, {}, lights, options.light);
    IrradianceVectorGrid grid = rad::placeIrradianceGrid({{-1, -1, -1}}, {{1, 1, 1}}, 6, 0.2);
    rad::IrradianceGridReport report;
    std::vector<std::uint8_t> invalid;
    rad::computeIrradianceVectors(tracer, grid, options, {}, report, &invalid);
    EXPECT_GT(checkInvalidOnOneSideOfTheUnitSphere(grid, invalid, /*invalidOutside=*/false), 0u);
}

TEST(IrradianceVectorGridCompute, PlacementHasCubicCellsAndTheResolutionAlongTheLongestAxis) {
    const IrradianceVectorGrid grid = rad::placeIrradianceGrid({{0, 0, 0}}, {{4, 2, 1}}, 8, 0.0);
    EXPECT_EQ(grid.cells[0], 8);
    EXPECT_EQ(grid.cells[1], 4);
    EXPECT_EQ(grid.cells[2], 2);
    for (int a = 0; a < 3; ++a) EXPECT_FLOAT_EQ(grid.cellSize[a], 0.5f);
    const IrradianceVectorGrid padded = rad::placeIrradianceGrid({{0, 0, 0}}, {{4, 2, 1}}, 8, 0.1);
    EXPECT_LE(padded.origin[0], -0.4f + 1e-5f);
    EXPECT_LE(padded.origin[2], -0.4f + 1e-5f);
    EXPECT_GE(padded.origin[2] + padded.cells[2] * padded.cellSize[2], 1.4f - 1e-5f);
    EXPECT_THROW(rad::placeIrradianceGrid({{0, 0, 0}}, {{1, 1, 1}}, 0, 0.0), rad::IrradianceVectorGridError);
}

TEST(IrradianceVectorGridCompute, RefusesBadInputAndStopsWhenCancelled) {
    const rad::TriangleMesh floor = floorSquare(1.0f);
    rad::AnalyticLighting none;
    rad::IrradianceGridOptions options;
    options.raysPerDirection = 16;
    EXPECT_THROW(rad::computeIrradianceVectorGrid(floor, {}, none, options), rad::IndirectLightError);
    rad::AnalyticLighting lights;
    lights.directional.push_back(rad::DirectionalLight{});
    EXPECT_THROW(rad::computeIrradianceVectorGrid(floor, {0.5f}, lights, options), rad::IndirectLightError);
    rad::IrradianceGridOptions bad = options;
    bad.light.bounces = 0;
    EXPECT_THROW(rad::computeIrradianceVectorGrid(floor, {}, lights, bad), rad::IndirectLightError);
    bad = options;
    bad.raysPerDirection = 0;
    EXPECT_THROW(rad::computeIrradianceVectorGrid(floor, {}, lights, bad), std::invalid_argument);
    bad = options;
    bad.resolution = 0;
    EXPECT_THROW(rad::computeIrradianceVectorGrid(floor, {}, lights, bad), std::invalid_argument);
    int calls = 0;
    const rad::ProgressCallback stopAtOnce = [&](double, const char*) { return ++calls < 2; };
    EXPECT_THROW(rad::computeIrradianceVectorGrid(floor, {}, lights, options, stopAtOnce), rad::OperationCancelled);
}

}  // namespace

namespace {

TEST(IrradianceVectorGridCompute, RepairExtrapolatesLinearlyAlongEachDirection) {
    // 4 x 1 x 1 cells; the +x red vector's x component grows linearly with i: 1 + i. Vertices i = 0
    // (both j, k) invalid: +x continues the line (2 * 2 - 3 = 1); -x has nothing beyond on its side
    // and takes the average of all valid neighbours.
    IrradianceVectorGrid grid = IrradianceVectorGrid::covering({{0, 0, 0}}, {{4, 1, 1}}, {{4, 1, 1}});
    std::vector<std::uint8_t> invalid(grid.vertexCount(), 0);
    for (int k = 0; k <= 1; ++k)
        for (int j = 0; j <= 1; ++j)
            for (int i = 0; i <= 4; ++i) {
                const std::size_t v = grid.vertexIndex(i, j, k);
                grid.at(v, 0)[0] = 1.0f + i;       // +x, red, x
                grid.at(v, 1)[0] = -(2.0f + i);    // -x, red, x
                if (i == 0) {
                    invalid[v] = 1;
                    grid.at(v, 0)[0] = -100.0f;  // garbage that must not survive
                    grid.at(v, 1)[0] = -100.0f;
                }
            }
    EXPECT_EQ(rad::repairInvalidGridVertices(grid, invalid), 0u);
    for (int k = 0; k <= 1; ++k)
        for (int j = 0; j <= 1; ++j) {
            const std::size_t v = grid.vertexIndex(0, j, k);
            EXPECT_FLOAT_EQ(grid.at(v, 0)[0], 1.0f);
            EXPECT_FLOAT_EQ(grid.at(v, 1)[0], -3.0f);  // the valid neighbours all have i = 1
        }
    // A line that would flip the component's sign is not followed: 2 * 0.5 - 3 < 0.
    IrradianceVectorGrid flip = IrradianceVectorGrid::covering({{0, 0, 0}}, {{2, 1, 1}}, {{2, 1, 1}});
    std::vector<std::uint8_t> bad(flip.vertexCount(), 0);
    for (int k = 0; k <= 1; ++k)
        for (int j = 0; j <= 1; ++j) {
            flip.at(flip.vertexIndex(1, j, k), 0)[0] = 0.5f;
            flip.at(flip.vertexIndex(2, j, k), 0)[0] = 3.0f;
            bad[flip.vertexIndex(0, j, k)] = 1;
        }
    rad::repairInvalidGridVertices(flip, bad);
    EXPECT_FLOAT_EQ(flip.at(flip.vertexIndex(0, 0, 0), 0)[0], 0.5f);
    // Nothing valid at all: zero, counted.
    std::vector<std::uint8_t> all(flip.vertexCount(), 1);
    EXPECT_EQ(rad::repairInvalidGridVertices(flip, all), flip.vertexCount());
    EXPECT_EQ(flip.at(0, 0)[0], 0.0f);
}

}  // namespace
