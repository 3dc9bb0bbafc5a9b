// A mesh with per-vertex radiance functions (RF, Vanhoey et al. 2015) as one glTF 2.0 binary file
// (.glb), so that programs other than MeshLab read the radiance: every glTF viewer shows the RF's
// mean (diffuse) colour as COLOR_0, and a viewer that knows the extension below (ours:
// python/pymeshlab_radiance/viewer) evaluates the full view-dependent colour. Format reference:
// docs/gltf-radiance.md.
//
// Content: one node, one mesh, one triangle primitive with
//  - POSITION (float, with min / max), NORMAL = the RF frame's normal n (the axis of the RF's
//    hemisphere and of the reflection), TANGENT (PB only) = the frame's tangent t with w = +1, so that
//    glTF's bitangent cross(NORMAL, TANGENT.xyz) * w is our b = n x t: the local frame PB lives in;
//  - COLOR_0 (float VEC3, linear) = the RF's mean over its hemisphere (meanHemisphereColors),
//    clamped to glTF's [0, 1];
//  - the coefficients as application-specific attributes (glTF 2.0 sec. 3.7.2.1: names start with an
//    underscore), float VEC3 = (R, G, B) of one basis function each:
//      SH: _RF_SH_DEGREE_<l>_COEF_<l+m>   (the naming of Khronos's KHR_gaussian_splatting draft)
//      PB: _RF_PB_COEF_<k>                 (k = polynomialIndex(i, j) of u^i v^j, basis.h)
//  - 32-bit indices;
// and the extension object "RADIANCE_vertex_radiance_functions" on the primitive (the same object in
// its "extras" for readers that drop unknown extensions): basis, degree, reflected, colour space,
// SH convention, the attribute names in basis order.
//
// SH convention: the coefficients are written so that the evaluation of 3D Gaussian Splatting
// (Kerbl et al. 2023, its eval_sh: real SH WITH the Condon-Shortley phase, evaluated at the viewing
// ray's direction d = normalize(p - eye)) gives our radiance L(w), w = -d. Since our SH have no
// Condon-Shortley phase (spherical_harmonics.h) and Y_l^m(-w) = (-1)^l Y_l^m(w), the written
// coefficient of (l, m) is (-1)^(l+m) times ours (gaussianSplattingShSign). Unlike 3DGS, no 0.5 is
// added and the colour is linear, not display-referred.
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
