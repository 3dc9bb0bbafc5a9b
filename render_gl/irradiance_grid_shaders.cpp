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
    vec3 Ir = vec3(0.0), Ig = vec3(0.0), Ib = vec3(0.0);
    if (n.x >= 0.0) ivgAdd(n.x * n.x, textureLod(uIvgColor0, tc, 0.0).rgb, textureLod(uIvgDirection0, tc, 0.0).rgb, Ir, Ig, Ib);
    else ivgAdd(n.x * n.x, textureLod(uIvgColor1, tc, 0.0).rgb, textureLod(uIvgDirection1, tc, 0.0).rgb, Ir, Ig, Ib);
    if (n.y >= 0.0) ivgAdd(n.y * n.y, textureLod(uIvgColor2, tc, 0.0).rgb, textureLod(uIvgDirection2, tc, 0.0).rgb, Ir, Ig, Ib);
    else ivgAdd(n.y * n.y, textureLod(uIvgColor3, tc, 0.0).rgb, textureLod(uIvgDirection3, tc, 0.0).rgb, Ir, Ig, Ib);
    if (n.z >= 0.0) ivgAdd(n.z * n.z, textureLod(uIvgColor4, tc, 0.0).rgb, textureLod(uIvgDirection4, tc, 0.0).rgb, Ir, Ig, Ib);
    else ivgAdd(n.z * n.z, textureLod(uIvgColor5, tc, 0.0).rgb, textureLod(uIvgDirection5, tc, 0.0).rgb, Ir, Ig, Ib);
    return max(rho * 0.318309886183790672 * vec3(dot(Ir, n), dot(Ig, n), dot(Ib, n)), vec3(0.0));
}
)GLSL";

}  // namespace

std::string irradianceGridGlsl() { return kGlsl; }
const char* irradianceGridColourSampler(int direction) { return kColour[direction]; }
const char* irradianceGridDirectionSampler(int direction) { return kDirection[direction]; }

}  // namespace radgl
