// Small generated scenes with exact normals, for tests, benchmarks and synthetic acquisitions.
//
//  - icosphere / UV sphere: the sphere of Vanhoey et al. 2015 Fig. 8 (stripes of diffuse and specular
//    material are painted on it by radiance/analytic_material.h, not here);
//  - the toy quad of Vanhoey et al. 2015 Fig. 6: four vertices, two triangles, normals diverging outwards;
//  - the 'column' scene of Křivánek et al. 2004 Fig. 1: a capped cylinder standing on a ground plane
//    (200 vertices / 246 triangles in the paper; ~200 vertices here with the defaults);
//  - a torus (genus 1, a closed surface with negative curvature).
//
// Conventions: z is up; every mesh is counter-clockwise seen from outside (normals point out of
// the solid, up for the ground and the quad); normals are unit and analytic (not averaged), so a
// sharp edge (cylinder rim) duplicates its vertices, one copy per side.
// The generators throw std::invalid_argument on out-of-range parameters.
#pragma once

#include "geometry/triangle_mesh.h"

namespace rad {

// Icosahedron subdivided `level` times (each triangle split in four, new vertices pushed onto the
// sphere). Level L has 10 * 4^L + 2 vertices, 20 * 4^L faces, 30 * 4^L edges. 0 <= level <= 9.
// Normals are the unit positions (before scaling by `radius`); the sphere is centred on the origin.
TriangleMesh makeIcosphere(int level, float radius = 1.0f);
std::size_t icosphereVertexCount(int level);
std::size_t icosphereFaceCount(int level);

// Latitude / longitude sphere: `stacks` bands from pole to pole (>= 2), `slices` around the z axis
// (>= 3). One vertex per pole, no seam duplication (the mesh is closed):
// (stacks - 1) * slices + 2 vertices, 2 * slices * (stacks - 1) faces.
TriangleMesh makeUvSphere(int stacks, int slices, float radius = 1.0f);

// Vanhoey et al. 2015 Fig. 6: the square [-halfSize, halfSize]^2 in the plane z = 0, two triangles, the normal
// of each corner tilted away from +z by `tiltRadians` towards that corner (outwards), so the four
// normals diverge. Vertex order: (-,-), (+,-), (+,+), (-,+); faces (0,1,2), (0,2,3).
// |tiltRadians| < pi/2 (a negative tilt makes the normals converge).
TriangleMesh makeDivergingQuad(float tiltRadians, float halfSize = 1.0f);

// Křivánek et al. 2004 Fig. 1: a column (cylinder with both caps) standing on a square ground plane at z = 0,
// its axis the z axis. Separate components (the column is not stitched into the ground).
struct ColumnSceneOptions {
    int segments = 16;          // around the axis, >= 3
    int heightRings = 4;        // side subdivisions along the axis, >= 1
    float radius = 0.15f;
    float height = 1.0f;
    int groundResolution = 8;   // ground cells per side, >= 1: (n+1)^2 vertices, 2 n^2 faces
    float groundHalfSize = 1.0f;
};
// Counts: side segments * (heightRings + 1) vertices and 2 * segments * heightRings faces; each
// cap segments + 1 vertices (centre + rim, rim duplicated from the side with the cap's normal) and
// `segments` faces; ground (groundResolution + 1)^2 vertices, 2 * groundResolution^2 faces.
// Defaults: 80 + 2 * 17 + 81 = 195 vertices, 128 + 2 * 16 + 128 = 288 faces.
// The vertices come in this order: side, top cap, bottom cap, ground.
TriangleMesh makeColumnOnPlane(const ColumnSceneOptions& options = {});
std::size_t columnOnPlaneVertexCount(const ColumnSceneOptions& options);
std::size_t columnOnPlaneFaceCount(const ColumnSceneOptions& options);

// Torus around the z axis: tube centre at distance majorRadius from the axis, tube radius
// minorRadius (0 < minorRadius < majorRadius). majorSegments x minorSegments vertices (each >= 3),
// twice as many faces; Euler characteristic 0.
TriangleMesh makeTorus(float majorRadius = 1.0f, float minorRadius = 0.35f, int majorSegments = 48,
                       int minorSegments = 24);

}  // namespace rad
