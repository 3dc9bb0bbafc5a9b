#include "normal_map_shaders.h"

#include "irradiance_grid_shaders.h"
#include "radiance_shaders.h"  // toneMappingGlsl

namespace radgl {
namespace {

const char* const kVertex = R"GLSL(#version 150 compatibility
invariant gl_Position;
uniform int uPopLevel;       // 0: the mesh as uploaded; 1..16: POP-buffer level (Limper et al. 2013)
uniform int uPopCorrection;  // 1: texture-coordinate correction (Weber & Stamminger, Alg. 1)
uniform vec3 uBoxMin;
uniform vec3 uBoxExtent;
out vec3 vObject;
out vec3 vNormal;
out vec2 vUv;
out vec4 vTangent;  // MikkTSpace tangent and bitangent sign of the corner
out vec3 vColor;    // per-vertex albedo (linear), when the renderer has vertex colours
void main() {
    vec3 p = gl_Vertex.xyz;
    vec2 uv = gl_MultiTexCoord0.xy;
    if (uPopLevel > 0) {
        // Level-16 cell (exact integers in float) >> (16 - L), then the cell's centre; a flat axis
        // of the box is not snapped (lod/pop_buffer.h).
        vec3 cell = floor(gl_MultiTexCoord1.xyz / exp2(float(16 - uPopLevel)));
        vec3 q = uBoxMin + (cell + 0.5) * (uBoxExtent / exp2(float(uPopLevel)));
        if (uBoxExtent.x <= 0.0) q.x = p.x;
        if (uBoxExtent.y <= 0.0) q.y = p.y;
        if (uBoxExtent.z <= 0.0) q.z = p.z;
        if (uPopCorrection == 1) {
            vec3 d = q - p;
            uv += vec2(dot(gl_MultiTexCoord2.xyz, d), dot(gl_MultiTexCoord3.xyz, d));
        }
        p = q;
        gl_Position = gl_ModelViewProjectionMatrix * vec4(p, 1.0);
    } else {
        gl_Position = ftransform();
    }
    vObject = p;
    vNormal = gl_Normal;
    vUv = uv;
    vTangent = gl_MultiTexCoord4;  // MikkTSpace tangent and sign (texture coordinates 1-3: the POP buffer's)
    vColor = gl_Color.rgb;
}
)GLSL";

const char* const kFragmentHead = R"GLSL(#version 150 compatibility
)GLSL";

const char* const kFragmentBody = R"GLSL(
uniform sampler2D uNormalMap;
uniform sampler2D uMoments;
uniform int uMode;           // 0 vertex normals, 1 normal map, 2 LEAN
uniform int uTangentSpace;   // 1: the map holds tangent-space normals
uniform int uMikkTSpace;     // 1: ... in MikkTSpace (Mikkelsen 2008), else in the per-face dP/du frame
uniform vec2 uTextureSize;   // level 0 of the normal map, texels
uniform vec3 uEye;           // object space
uniform vec3 uLightDirection;  // toward the light, unit, object space
uniform vec3 uLightColor;
uniform vec3 uAlbedo;
uniform vec3 uSpecular;
uniform vec3 uAmbient;
uniform float uShininess;
uniform int uIndirect;       // IndirectLight: 0 none, 1 indirect alone, 2 direct + indirect
uniform int uVertexAlbedo;   // 1: rho = the interpolated vertex colour, else uAlbedo
uniform sampler2D uDiffuseMap;
uniform int uUseDiffuseMap;  // 1: rho = the diffuse map (linear: an sRGB texture), before the above
in vec3 vColor;
in vec3 vObject;
in vec3 vNormal;
in vec2 vUv;
in vec4 vTangent;

vec3 anyPerpendicular(vec3 n) {
    vec3 h = abs(n.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    return normalize(h - n * dot(n, h));
}

// Unit t - n (n.t), or any perpendicular to n when t is (nearly) parallel to n.
vec3 orthogonalTangent(vec3 n, vec3 t) {
    vec3 u = t - n * dot(n, t);
    float len = length(u);
    return len > 1e-6 * max(length(t), 1e-30) ? u / len : anyPerpendicular(n);
}

void main() {
    vec3 diffuse = texture(uDiffuseMap, vUv).rgb;  // in uniform control flow (implicit derivatives)
    vec3 nv = normalize(vNormal);
    vec3 dpdx = dFdx(vObject), dpdy = dFdy(vObject);
    vec2 dtdx = dFdx(vUv), dtdy = dFdy(vUv);
    // [dp/dx dp/dy] = [dP/du dP/dv] J, J = [[du/dx, du/dy], [dv/dx, dv/dy]]; directions only, so
    // the inverse is taken up to the positive factor 1 / |det J|.
    float det = dtdx.x * dtdy.y - dtdx.y * dtdy.x;
    float detSign = det < 0.0 ? -1.0 : 1.0;
    vec3 dPdu = detSign * (dpdx * dtdy.y - dpdy * dtdx.y);
    vec3 dPdv = detSign * (dpdy * dtdx.x - dpdx * dtdy.x);
    vec2 fx = dtdx * uTextureSize, fy = dtdy * uTextureSize;
    float lambda = clamp(log2(max(max(length(fx), length(fy)), 1e-30)), -32.0, 32.0);

    vec3 n = nv;
    if (uMode != 0) {
        vec3 t = textureLod(uNormalMap, vUv, lambda).xyz;
        if (uTangentSpace == 1 && uMikkTSpace == 1) {
            // MikkTSpace decoding: interpolated T and N, not renormalised (normal_baker.h).
            vec3 T = vTangent.xyz;
            vec3 B = (vTangent.w < 0.0 ? -1.0 : 1.0) * cross(vNormal, T);
            t = t.x * T + t.y * B + t.z * vNormal;
        } else if (uTangentSpace == 1) {  // normal_baker.h per-face frame
            vec3 T = orthogonalTangent(nv, dPdu);
            float s = dot(cross(dPdu, dPdv), nv) < 0.0 ? -1.0 : 1.0;
            vec3 B = s * cross(nv, T);
            t = t.x * T + t.y * B + t.z * nv;
        }
        float len = length(t);
        n = len > 0.0 ? t / len : nv;
    }

    vec3 L = uLightDirection;
    vec3 V = uEye - vObject;
    V = length(V) > 0.0 ? normalize(V) : n;
    vec3 H = normalize(L + V);
    float ndl = dot(n, L);
    float hn = dot(H, n);
    float spec = 0.0;
    if (hn > 0.0) {
        if (uMode == 2) {
            // Alg. 4: the stored pyramid starts at MIP level 1.
            vec3 mu = textureLod(uMoments, vUv, max(lambda - 1.0, 0.0)).xyz;
            if (lambda < 1.0) mu *= max(lambda, 0.0);
            // Alg. 3 in the frame (T, N x T, N), T = dP/du orthogonalised against the averaged normal.
            vec3 T = orthogonalTangent(n, dPdu);
            vec3 B = cross(n, T);
            vec2 h = vec2(dot(H, T), dot(H, B)) / hn;
            float inv = 1.0 / uShininess;
            float a = mu.x + inv, d = mu.y + inv, b = mu.z;
            float sdet = a * d - b * b;
            if (sdet > 0.0) {
                float q = (d * h.x * h.x - 2.0 * b * h.x * h.y + a * h.y * h.y) / sdet;
                spec = exp(-0.5 * q) / (uShininess * sqrt(sdet));
            }
        } else {
            spec = pow(hn, uShininess);
        }
    }
    if (ndl <= 0.0) spec = 0.0;
    vec3 rho = uUseDiffuseMap == 1 ? diffuse : uVertexAlbedo == 1 ? vColor : uAlbedo;
    vec3 linear = vec3(0.0);
    if (uIndirect != 1) linear = uAmbient * rho + uLightColor * (rho * max(ndl, 0.0) + uSpecular * spec);
    if (uIndirect != 0) linear += ivgReflected(vObject, n, rho);
    gl_FragColor = vec4(displayColor(linear), 1.0);
}
)GLSL";

}  // namespace

std::string normalMapVertexShaderSource() { return kVertex; }

std::string normalMapFragmentShaderSource() { return std::string(kFragmentHead) + toneMappingGlsl() + irradianceGridGlsl() + kFragmentBody; }

}  // namespace radgl
