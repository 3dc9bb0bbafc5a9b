// Radiance functions as world-frame spherical harmonics, the one space where functions of different
// vertices can be added and compared: a PB(d) field (each vertex in its own frame) is projected onto
// SH(d) in the local frame, exactly (a polynomial of degree d is in the span of SH up to degree d),
// then rotated to the world frame; the way back rotates to the survivor's frame and takes the least
// squares PB(d) over its hemisphere. Fields without local frames pass through unchanged. Used by the
// radiance quadric (simplify/radiance_quadric.h) to compare and average functions of vertices whose
// frames differ.
#pragma once

#include "radiance/radiance_field.h"

#include <vector>

namespace rad {

// The basis's Gram matrix over the hemisphere z >= 0 (integrals divided by 2 pi), K x K, row major:
// what makes sum_k c_k B_k an element of L2 with |f|^2 = c^T M c.
std::vector<double> hemisphereGramMatrix(const BasisSpec& basis);

// The coefficients per colour channel of a basis's functions as world-frame SH: a basis with local
// frames (PB(d)) becomes SH(d); SH stays as it is. Known without building the conversion.
int worldShCoefficientsPerChannel(const BasisSpec& basis);

class WorldShConversion {
public:
    explicit WorldShConversion(const BasisSpec& basis);

    bool convertsFrames() const { return convertsFrames_; }
    int worldPerChannel() const { return kWorld_; }  // world coefficients per colour channel
    int worldPerVertex() const { return kColorChannels * kWorld_; }

    // A function (coefficients in the basis given above, channel after channel; storedFrame: the
    // vertex's frame as RadianceField stores it, read only when convertsFrames()) in world
    // coordinates: worldPerVertex() values, channel after channel.
    void toWorld(const float* coefficients, const float* storedFrame, double* world) const;
    // The reverse, each coefficient divided by `divisor` (the radiance quadric's attribute scale).
    void fromWorld(const double* world, const float* storedFrame, float* coefficients, double divisor = 1.0) const;

private:
    BasisSpec basis_;
    bool convertsFrames_ = false;
    int k_ = 0, kWorld_ = 0;
    std::vector<double> pbToSh_;  // kWorld x K, row major
    std::vector<double> shToPb_;  // K x kWorld, row major
};

}  // namespace rad
