// Vertex clustering with quadrics (outofcore/vertex_clustering.h, Lindstrom 2000).
#include "outofcore/vertex_clustering.h"

#include "geometry/primitive_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace {

// An n x n grid of squares (two triangles each) in the plane z = height, side `side`.
rad::TriangleMesh flatGrid(int n, float side, float height) {
    rad::TriangleMesh mesh;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            // A slight irregularity in x and y so that grid lines of both meshes never coincide.
            const float jitter = 0.2f * std::sin(float(i * 7 + j * 13)) / float(n);
            mesh.positions.insert(mesh.positions.end(), {side * (float(i) / n + jitter), side * (float(j) / n - jitter), height});
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const std::uint32_t a = std::uint32_t(j * (n + 1) + i);
            mesh.faces.insert(mesh.faces.end(), {a, a + 1, a + std::uint32_t(n) + 2, a, a + std::uint32_t(n) + 2, a + std::uint32_t(n) + 1});
        }
    return mesh;
}

// The surface of the cube [0, 1]^3, each face an n x n grid, outward orientation.
rad::TriangleMesh finelyMeshedCube(int n) {
    rad::TriangleMesh mesh;
    auto add = [&](const float origin[3], const float du[3], const float dv[3]) {
        const std::uint32_t base = std::uint32_t(mesh.vertexCount());
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i)
                for (int k = 0; k < 3; ++k)
                    mesh.positions.push_back(origin[k] + du[k] * float(i) / n + dv[k] * float(j) / n);
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const std::uint32_t a = base + std::uint32_t(j * (n + 1) + i), r = std::uint32_t(n + 1);
                mesh.faces.insert(mesh.faces.end(), {a, a + 1, a + r + 1, a, a + r + 1, a + r});
            }
    };
    const float o0[3] = {0, 0, 0}, x[3] = {1, 0, 0}, y[3] = {0, 1, 0}, z[3] = {0, 0, 1};
    const float ox[3] = {1, 0, 0}, oy[3] = {0, 1, 0}, oz[3] = {0, 0, 1};
    add(o0, y, x);   // z = 0, normal -z
    add(oz, x, y);   // z = 1, normal +z
    add(o0, x, z);   // y = 0, normal -y
    add(oy, z, x);   // y = 1, normal +y
    add(o0, z, y);   // x = 0, normal -x
    add(ox, y, z);   // x = 1, normal +x
    return mesh;
}

double nearestDistance(const rad::TriangleMesh& mesh, const float* p) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
        const float* q = &mesh.positions[3 * v];
        best = std::min(best, std::sqrt(double(p[0] - q[0]) * (p[0] - q[0]) + double(p[1] - q[1]) * (p[1] - q[1]) +
                                        double(p[2] - q[2]) * (p[2] - q[2])));
    }
    return best;
}

TEST(VertexClustering, AFlatGridStaysFlat) {
    const rad::TriangleMesh grid = flatGrid(150, 2.0f, 0.75f);
    rad::ClusteringOptions options;
    options.targetTriangles = 800;
    rad::ClusteringStats stats;
    const rad::TriangleMesh result = rad::clusterVertices(grid, options, &stats);
    ASSERT_GT(result.faceCount(), 100u);
    ASSERT_TRUE(result.validate().empty()) << result.validate();
    for (std::size_t v = 0; v < result.vertexCount(); ++v) {
        EXPECT_NEAR(result.positions[3 * v + 2], 0.75f, 1e-5f) << v;
        EXPECT_NEAR(std::abs(result.normals[3 * v + 2]), 1.0f, 1e-4f) << v;
    }
    // The plane's quadric constrains z only: x and y stay at the cells' means, inside the square.
    for (std::size_t v = 0; v < result.vertexCount(); ++v) {
        EXPECT_GE(result.positions[3 * v], -0.02f);
        EXPECT_LE(result.positions[3 * v], 2.02f);
    }
    EXPECT_EQ(stats.inputTriangles, grid.faceCount());
}

TEST(VertexClustering, TheCubesCornersSurvive) {
    const rad::TriangleMesh cube = finelyMeshedCube(40);
    rad::ClusteringOptions options;
    options.targetTriangles = 600;
    const rad::TriangleMesh result = rad::clusterVertices(cube, options);
    ASSERT_GT(result.faceCount(), 12u);
    for (int corner = 0; corner < 8; ++corner) {
        const float p[3] = {float(corner & 1), float((corner >> 1) & 1), float((corner >> 2) & 1)};
        EXPECT_LT(nearestDistance(result, p), 1e-4) << "corner " << corner;
    }
    // Every vertex lies on the cube's surface (each cell's quadric holds only the cube's planes).
    for (std::size_t v = 0; v < result.vertexCount(); ++v) {
        const float* q = &result.positions[3 * v];
        float toSurface = 1.0f;
        for (int k = 0; k < 3; ++k) toSurface = std::min(toSurface, std::min(std::abs(q[k]), std::abs(q[k] - 1.0f)));
        EXPECT_LT(toSurface, 1e-4f) << v;
    }
}

TEST(VertexClustering, OutputTriangleCountNearTheTarget) {
    const rad::TriangleMesh sphere = rad::makeIcosphere(6);  // 81,920 triangles
    for (std::size_t target : {std::size_t(2000), std::size_t(10000)}) {
        rad::ClusteringOptions options;
        options.targetTriangles = target;
        const rad::TriangleMesh result = rad::clusterVertices(sphere, options);
        EXPECT_GT(double(result.faceCount()), 0.7 * double(target)) << target;
        EXPECT_LT(double(result.faceCount()), 1.3 * double(target)) << target;
        // Representatives stay on the sphere (within a fraction of a cell).
        for (std::size_t v = 0; v < result.vertexCount(); ++v) {
            const float* q = &result.positions[3 * v];
            EXPECT_NEAR(std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]), 1.0f, 0.02f);
        }
    }
}

TEST(VertexClustering, TargetHoldsWhenOnlyASampleOfTheVerticesChoosesTheGrid) {
    // Large scans choose the grid on every k-th vertex: the count must not depend on k.
    const rad::TriangleMesh sphere = rad::makeIcosphere(6);  // 40,962 vertices
    for (std::size_t sample : {std::size_t(4000), std::size_t(10000)}) {
        rad::ClusteringOptions options;
        options.targetTriangles = 2000;
        options.sampledVertices = sample;
        const rad::TriangleMesh result = rad::clusterVertices(sphere, options);
        EXPECT_GT(double(result.faceCount()), 0.7 * 2000) << sample;
        EXPECT_LT(double(result.faceCount()), 1.3 * 2000) << sample;
    }
}

TEST(VertexClustering, AMeshSmallerThanTheGridComesBackUnchanged) {
    const rad::TriangleMesh sphere = rad::makeIcosphere(2);  // 320 triangles, 162 vertices
    rad::ClusteringOptions options;
    options.targetTriangles = 100000;
    const rad::TriangleMesh result = rad::clusterVertices(sphere, options);
    EXPECT_EQ(result.faceCount(), sphere.faceCount());
    EXPECT_EQ(result.vertexCount(), sphere.vertexCount());
    for (std::size_t v = 0; v < result.vertexCount(); ++v)
        EXPECT_LT(nearestDistance(sphere, &result.positions[3 * v]), 1e-5) << v;
}

TEST(VertexClustering, CellSizeGivesTheGrid) {
    const rad::TriangleMesh cube = finelyMeshedCube(10);
    rad::ClusteringOptions options;
    options.cellSize = 0.25;
    rad::ClusteringStats stats;
    rad::clusterVertices(cube, options, &stats);
    EXPECT_DOUBLE_EQ(stats.cellSize, 0.25);
    EXPECT_EQ(stats.gridCells[0], 5);  // floor(1 / 0.25) + 1
    EXPECT_EQ(stats.gridCells[2], 5);
}

TEST(VertexClustering, BadUseIsRefused) {
    rad::ClusteringOptions none;
    rad::VertexClustering empty(none);
    const float p[3] = {0, 0, 0};
    empty.addVertices(p, 1);
    EXPECT_THROW(empty.beginTriangles(), std::invalid_argument);
    rad::ClusteringOptions options;
    options.targetTriangles = 10;
    rad::VertexClustering clustering(options);
    clustering.addVertices(p, 1);
    const std::uint32_t triangle[3] = {0, 0, 1};
    EXPECT_THROW(clustering.addTriangles(triangle, 1), std::out_of_range);
    EXPECT_THROW(clustering.addVertices(p, 1), std::invalid_argument);
}

}  // namespace
