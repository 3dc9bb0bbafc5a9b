// The coordinate range and the scale the cores compute with, checked in one place for every
// filter and tool (docs/design-notes.md, "Coordinate range and scale").
//
// Largest coordinate: Embree's robust triangle test (Pluecker coordinates relative to the ray's
// origin) multiplies three coordinate differences in single precision; beyond ~7e12 the product
// overflows to infinity, Embree reports a hit at t = inf and the next ray starts at infinity, which
// Embree's own check aborts the process on (the irradiance grid at 1e13..1e15). Squared lengths
// overflow above ~1.8e19 (NaN normals in the simplification). 1e11 keeps the cube of the largest
// difference (2 sqrt(3) 1e11)^3 ~ 4e34 four orders below the float maximum; no physical scan in
// metres or millimetres comes near it.
//
// Smallest extent and relative extent: the same products underflow below ~1e-13 (Embree then
// misses every triangle: an all-zero irradiance grid), quadrics (fourth powers) far earlier, and
// a mesh lying far from the origin compared with its size has coordinates only a few float steps
// apart (vertex clustering puts every point in one cell, normals turn to noise).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace rad {

constexpr float kMaxCoordinateMagnitude = 1e11f;
// The longest side of the box of the referenced vertices must be at least this...
constexpr double kMinSceneExtent = 1e-6;
// ... and at least this fraction of the largest coordinate magnitude (float steps there are then
// below 6e-4 of the mesh's size).
constexpr double kMinRelativeExtent = 1e-4;

// Empty when every coordinate is finite and within kMaxCoordinateMagnitude; otherwise a sentence
// naming the first offending vertex and the fix.
std::string coordinateRangeProblem(const float* positions, std::size_t vertexCount);

// Empty when the vertices the faces refer to (every vertex when faces is null) are within range
// (coordinateRangeProblem) and their box is neither too small nor too small for where it lies (see
// above); otherwise a sentence naming the size, the position and the fix. `what` names the mesh in
// the sentence ("The mesh", "The source layer"). Unreferenced vertices play no part: a stray point
// far away does not make the mesh look large.
std::string sceneScaleProblem(const float* positions, std::size_t vertexCount, const std::uint32_t* faces,
                              std::size_t faceCount, const std::string& what = "The mesh");

// The size part of sceneScaleProblem for a box already known (lo, hi of the used vertices).
std::string boxScaleProblem(const double lo[3], const double hi[3], const std::string& what = "The mesh");

// The box of the referenced vertices (every vertex when faces is null): lo, hi; false when none.
bool referencedBox(const float* positions, std::size_t vertexCount, const std::uint32_t* faces, std::size_t faceCount,
                   double lo[3], double hi[3]);

}  // namespace rad
