// The rooms of the indirect-light benchmark: walls face inward, blocks outward, albedo per vertex.
#include "geometry/box_rooms.h"

#include "geometry/mesh_normals.h"
#include "geometry/primitive_meshes.h"

#include <gtest/gtest.h>

namespace {

// Signed volume of a closed outward mesh (divergence theorem): > 0 outward, < 0 inward.
double signedVolume(const rad::TriangleMesh& m, std::size_t firstFace, std::size_t endFace) {
    double volume = 0.0;
    for (std::size_t f = firstFace; f < endFace; ++f) {
        const float* a = &m.positions[3 * m.faces[3 * f]];
        const float* b = &m.positions[3 * m.faces[3 * f + 1]];
        const float* c = &m.positions[3 * m.faces[3 * f + 2]];
        volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0;
    }
    return volume;
}

TEST(BoxRooms, CornellWallsFaceInwardAndBlocksOutward) {
    const int n = 4;
    const rad::AlbedoMesh box = rad::makeCornellBox(n);
    EXPECT_EQ(box.mesh.validate(), "");
    EXPECT_EQ(box.albedo.size(), 3 * box.mesh.vertexCount());
    const std::size_t wallFaces = 5 * 2 * n * n;
    // Every wall face's normal points toward the room's centre.
    for (std::size_t f = 0; f < wallFaces; ++f) {
        float normal[3];
        rad::faceNormal(box.mesh, f, normal);
        const float* a = &box.mesh.positions[3 * box.mesh.faces[3 * f]];
        const double toCentre = (0.5 - a[0]) * normal[0] + (0.5 - a[1]) * normal[1] + (0.5 - a[2]) * normal[2];
        EXPECT_GT(toCentre, 0.0) << "wall face " << f;
    }
    // The two blocks are closed and outward: volumes 0.3 x 0.3 x 0.3 and 0.3 x 0.3 x 0.6.
    const std::size_t blockFaces = 6 * 2 * 1 * 1;  // subdivisions n / 4 = 1
    EXPECT_NEAR(signedVolume(box.mesh, wallFaces, wallFaces + blockFaces), 0.027, 1e-5);
    EXPECT_NEAR(signedVolume(box.mesh, wallFaces + blockFaces, wallFaces + 2 * blockFaces), 0.054, 1e-5);
    // Red on the left (x = 0), green on the right.
    for (std::size_t v = 0; v < box.mesh.vertexCount(); ++v) {
        if (box.mesh.positions[3 * v] == 0.0f && box.albedo[3 * v] == 0.63f) EXPECT_EQ(box.albedo[3 * v + 1], 0.065f);
    }
}

TEST(BoxRooms, ScanStandsOnThePlinthAtTheGivenHeight) {
    const rad::TriangleMesh ball = rad::makeIcosphere(2, 3.0f);
    const rad::AlbedoMesh room = rad::makeScanRoom(ball, 0.9f, 2);
    EXPECT_EQ(room.mesh.validate(), "");
    const std::size_t first = room.mesh.vertexCount() - ball.vertexCount();
    float lo = 1e9f, hi = -1e9f;
    for (std::size_t v = first; v < room.mesh.vertexCount(); ++v) {
        lo = std::min(lo, room.mesh.positions[3 * v + 2]);
        hi = std::max(hi, room.mesh.positions[3 * v + 2]);
    }
    EXPECT_NEAR(lo, 0.5f, 2e-3f);
    EXPECT_NEAR(hi - lo, 0.9f, 1e-4f);
    // The ball keeps its outward orientation.
    const std::size_t firstFace = room.mesh.faceCount() - ball.faceCount();
    EXPECT_GT(signedVolume(room.mesh, firstFace, room.mesh.faceCount()), 0.0);
}

}  // namespace
