// A mesh with per-vertex radiance functions (RF, Vanhoey et al. 2015) as one glTF 2.0 binary file
// (.glb), so that programs other than MeshLab read the radiance: every glTF viewer shows the RF's
// mean (diffuse) colour as COLOR_0, and a viewer that knows our extension
// RADIANCE_vertex_radiance_functions (python/pymeshlab_radiance/viewer) evaluates the full
// view-dependent colour from the coefficients, stored as application-specific vertex attributes. SH
// coefficients follow the evaluation of 3D Gaussian Splatting (Kerbl et al. 2023): ours times
// (-1)^(l+m), linear colour, no +0.5.
// Details: docs/gltf-radiance.md, "The file" and "Spherical-harmonic convention".
#pragma once

#include "io/radiance_mesh.h"

#include <cstddef>
#include <string>
#include <vector>

namespace rad {

inline constexpr const char* kRadianceGltfExtension = "RADIANCE_vertex_radiance_functions";

struct RadianceGltfOptions {
    std::string name = "mesh";
    std::string generator = "radiance-tools";
};

// The whole .glb file of a mesh with radiance and faces. Throws GltfInputError (gltf_writer.h) with
// what is wrong and what to do: no radiance, no faces, sizes that disagree, an index out of range,
// a non-finite value, a file beyond glTF's 4 GiB.
std::vector<unsigned char> buildRadianceGlb(const RadianceMesh& mesh, const RadianceGltfOptions& options = {});

// The glTF attribute name of basis function `index` (SH: harmonicIndex(l, m); PB: polynomialIndex).
std::string radianceGltfAttributeName(const BasisSpec& basis, int index);

// (-1)^(l+m): our SH coefficient of Y_l^m times this is the coefficient 3D Gaussian Splatting's
// evaluation expects (see above); the map is its own inverse.
inline float gaussianSplattingShSign(int l, int m) { return ((l + m) % 2 == 0) ? 1.0f : -1.0f; }

}  // namespace rad
