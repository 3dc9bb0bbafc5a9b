#include "irradiance_grid_shaders.h"

namespace radgl {
namespace {

const char* const kColour[6] = {"uIvgColor0", "uIvgColor1", "uIvgColor2", "uIvgColor3", "uIvgColor4", "uIvgColor5"};
const char* const kDirection[6] = {"uIvgDirection0", "uIvgDirection1", "uIvgDirection2",
                                   "uIvgDirection3", "uIvgDirection4", "uIvgDirection5"};

const char* const kGlsl = R"GLSL(
uniform sampler3D uIvgColor0, uIvgColor1, uIvgColor2, uIvgColor3, uIvgColor4, uIvgColor5;
uniform sampler3D uIvgDirection0, uIvgDirection1, uIvgDirection2, uIvgDirection3, uIvgDirection4, uIvgDirection5;
uniform vec3 uIvgOrigin;
uniform vec3 uIvgCellSize;
uniform vec3 uIvgVertexCounts;
uniform int uIvgAbsoluteWeights;  // 0: n_a^2 (Granier et al. 2007), 1: |n_a| (irradiance_vector_grid.h)

void ivgAdd(float weight, vec3 colour, vec3 direction, inout vec3 Ir, inout vec3 Ig, inout vec3 Ib) {
    Ir += weight * colour.r * direction;
    Ig += weight * colour.g * direction;
    Ib += weight * colour.b * direction;
}

// rho / pi <I_n(p), n> per channel (Granier et al. 2007), p in the grid's (object) coordinates.
vec3 ivgReflected(vec3 p, vec3 normal, vec3 rho) {
    float len = length(normal);
    if (!(len > 0.0)) return vec3(0.0);
    vec3 n = normal / len;
    vec3 tc = ((p - uIvgOrigin) / uIvgCellSize + vec3(0.5)) / uIvgVertexCounts;
    vec3 w = uIvgAbsoluteWeights != 0 ? abs(n) : n * n;
    vec3 Ir = vec3(0.0), Ig = vec3(0.0), Ib = vec3(0.0);
    if (n.x >= 0.0) ivgAdd(w.x, textureLod(uIvgColor0, tc, 0.0).rgb, textureLod(uIvgDirection0, tc, 0.0).rgb, Ir, Ig, Ib);
    else ivgAdd(w.x, textureLod(uIvgColor1, tc, 0.0).rgb, textureLod(uIvgDirection1, tc, 0.0).rgb, Ir, Ig, Ib);
    if (n.y >= 0.0) ivgAdd(w.y, textureLod(uIvgColor2, tc, 0.0).rgb, textureLod(uIvgDirection2, tc, 0.0).rgb, Ir, Ig, Ib);
    else ivgAdd(w.y, textureLod(uIvgColor3, tc, 0.0).rgb, textureLod(uIvgDirection3, tc, 0.0).rgb, Ir, Ig, Ib);
    if (n.z >= 0.0) ivgAdd(w.z, textureLod(uIvgColor4, tc, 0.0).rgb, textureLod(uIvgDirection4, tc, 0.0).rgb, Ir, Ig, Ib);
    else ivgAdd(w.z, textureLod(uIvgColor5, tc, 0.0).rgb, textureLod(uIvgDirection5, tc, 0.0).rgb, Ir, Ig, Ib);
    return max(rho * 0.318309886183790672 * vec3(dot(Ir, n), dot(Ig, n), dot(Ib, n)), vec3(0.0));
}
)GLSL";

}  // namespace

std::string irradianceGridGlsl() { return kGlsl; }
const char* irradianceGridColourSampler(int direction) { return kColour[direction]; }
const char* irradianceGridDirectionSampler(int direction) { return kDirection[direction]; }

}  // namespace radgl
