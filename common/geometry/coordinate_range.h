// The largest coordinate the cores compute with. Beyond it single-precision arithmetic breaks in
// ways that are silent or fatal: squared lengths overflow to infinity above ~1.8e19 (NaN normals in
// the simplification), Embree's ray validity check aborts the process above ~1.8e18 (the bake), and
// scene diagonals and ray offsets lose all meaning. 1e15 keeps squares and products of two
// coordinates finite in float with a wide margin; no physical scan in metres or millimetres comes
// near it, so only broken or wrongly scaled files are refused, with the fix.
#pragma once

#include <cstddef>
#include <string>

namespace rad {

constexpr float kMaxCoordinateMagnitude = 1e15f;

// Empty when every coordinate is finite and within kMaxCoordinateMagnitude; otherwise a sentence
// naming the first offending vertex and the fix.
std::string coordinateRangeProblem(const float* positions, std::size_t vertexCount);

}  // namespace rad
