// Filling the texels a bake could not compute, and the empty texels between charts.
//
// Granier et al. 2007 (sec. "simplification"): texels of a baked normal map that received
// no sample are filled by diffusion from their neighbours. We use pull-push (Gortler et al. 1996,
// the standard fast form of that diffusion): the valid texels are averaged down a pyramid
// (pull), then every hole takes the coarser levels' value, blended bilinearly (push). It is
// linear in the texel count and leaves valid texels untouched.
//
// Dilation: after the charts are complete, rings of texels around them take the mean of their
// already-filled 8-neighbours, so that the gutter carries each chart's own border values; the
// rest of the texture is then pull-push filled, so no texel stays empty and mip-mapping never
// averages in an empty (black) texel.
//
// Images are float, `channels` values per texel, row-major, rows top to bottom; `valid` holds one
// byte per texel (non-zero = holds a value) and is updated as texels are filled.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rad {

// Fills every invalid texel for which fillMask is non-zero (fillMask == nullptr: every invalid
// texel) by pull-push from the valid texels. Every valid texel is a source, wherever it is;
// texels outside fillMask are never written. Returns the number filled.
// When no texel is valid nothing is filled (returns 0).
std::size_t fillByPullPush(float* values, int channels, int width, int height, std::vector<std::uint8_t>& valid,
                           const std::uint8_t* fillMask = nullptr);

// `rings` passes of 8-neighbour dilation: each pass, every invalid texel with at least one valid
// neighbour takes the mean of those neighbours (computed from the state before the pass).
// Returns the number of texels filled.
std::size_t dilateValidTexels(float* values, int channels, int width, int height, std::vector<std::uint8_t>& valid,
                              int rings);

// Renormalises 3-vectors in place (for normal maps after averaging); zero vectors are left alone.
void normalizeTexelVectors(float* values, std::size_t texelCount);

}  // namespace rad
