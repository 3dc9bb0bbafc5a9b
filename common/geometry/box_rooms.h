// Closed-ish rooms for indirect-light experiments (the irradiance vector grid of Granier et al.
// 2007): a Cornell-box-like room and a room with a plinth for a scan. Walls face INWARD (their
// counter-clockwise normals point into the room), blocks and the plinth OUTWARD; every wall is a
// regular grid of `subdivisions` x `subdivisions` quads (two triangles each) so that per-vertex
// methods have vertices to work with. Albedo: 3 floats per vertex.
#pragma once

#include "geometry/triangle_mesh.h"

#include <array>
#include <vector>

namespace rad {

struct AlbedoMesh {
    TriangleMesh mesh;
    std::vector<float> albedo;  // 3 per vertex, linear reflectance

    // Appends a parallelogram corner + s u + t v (s, t in [0, 1]) facing u x v.
    void addQuad(const std::array<float, 3>& corner, const std::array<float, 3>& u, const std::array<float, 3>& v,
                 int subdivisions, const std::array<float, 3>& rho);
    // Appends an axis-aligned box [lo, hi] with outward faces.
    void addBox(const std::array<float, 3>& lo, const std::array<float, 3>& hi, int subdivisions,
                const std::array<float, 3>& rho);
    // Appends `other` with a constant albedo.
    void addMesh(const TriangleMesh& other, const std::array<float, 3>& rho);
};

// Room [0, 1]^3, z up, open toward -y (the camera's side): red wall at x = 0 (0.63, 0.065, 0.05),
// green at x = 1 (0.14, 0.45, 0.091), white (0.73) floor, ceiling and back wall (Cornell box
// reflectances), a tall and a short white block.
AlbedoMesh makeCornellBox(int subdivisions = 8);

// A `scan` scaled to `height` and standing on a white plinth in the middle of a room [-1, 1]^2 x
// [0, 2], open toward -y; walls light grey (0.7), floor warm (0.6, 0.45, 0.3), one wall blue
// (0.2, 0.3, 0.7) at x = 1, the scan itself 0.75 grey.
// yUp: the scan's up axis is +y (turned to +z, its +z toward the open side).
AlbedoMesh makeScanRoom(const TriangleMesh& scan, float height = 0.9f, int subdivisions = 8, bool yUp = false);

}  // namespace rad
