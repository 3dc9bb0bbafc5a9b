// The per-vertex radiance data every filter shares: one radiance function (RF) per vertex and
// colour channel, stored as contiguous floats, plus the per-vertex frame that defines the RF's
// hemisphere (and, for PB, the local frame the basis lives in).
//
// Layout (flat arrays, hot loops walk them directly):
//   coefficients[(v * kColorChannels + c) * K + k]   K = basis.coefficientCount()
//   frames[v * 6 + 0..2] = tangent t, frames[v * 6 + 3..5] = normal n   (bitangent b = n x t)
// The frame is stored for both bases: for SH it only carries the normal of the hemisphere of
// definition (and the reflection axis when `reflected` is set); the tangent is kept for symmetry.
#pragma once

#include "radiance/basis.h"

#include <cstddef>
#include <string>
#include <vector>

namespace rad {

struct RadianceField {
    BasisSpec basis;
    // True when the coefficients encode the reflected RF L~(w) = L(R_n w) (Vanhoey et al. 2015 sec. 3.1).
    bool reflected = false;
    std::vector<float> coefficients;
    std::vector<float> frames;

    RadianceField() = default;
    RadianceField(BasisSpec b, std::size_t vertexCount, bool reflectedStorage = false);

    int coefficientsPerChannel() const { return basis.coefficientCount(); }
    int coefficientsPerVertex() const { return kColorChannels * basis.coefficientCount(); }
    std::size_t vertexCount() const;

    float* vertexCoefficients(std::size_t v) { return coefficients.data() + v * coefficientsPerVertex(); }
    const float* vertexCoefficients(std::size_t v) const { return coefficients.data() + v * coefficientsPerVertex(); }
    float* channelCoefficients(std::size_t v, int c) { return vertexCoefficients(v) + c * coefficientsPerChannel(); }
    const float* channelCoefficients(std::size_t v, int c) const { return vertexCoefficients(v) + c * coefficientsPerChannel(); }
    float* frame(std::size_t v) { return frames.data() + v * 6; }
    const float* frame(std::size_t v) const { return frames.data() + v * 6; }

    // Empty string when sizes, basis and frames are consistent and every value is finite;
    // otherwise a sentence saying what is wrong.
    std::string validate() const;
};

}  // namespace rad
