#include "radiance_shaders.h"

#include "radiance/basis.h"

#include <cmath>

namespace radgl {
namespace {

// Declarations and the RF evaluation shared by the shaded modes (see the header for the layouts).
const char* const kCommon = R"GLSL(#version 150 compatibility
uniform samplerBuffer uFrames;
uniform samplerBuffer uCoefficients;
uniform int uBasisKind;        // 0: PB(d) in the vertex's local frame, 1: SH(d) in the global frame
uniform int uDegree;
uniform int uCoefficientCount; // K, functions per colour channel
uniform float uShNorm[121];    // (kMaxHarmonicDegree + 1)^2
uniform vec3 uEye;             // eye in the mesh's object coordinates

vec3 framePosition(int v) { return texelFetch(uFrames, 3 * v).xyz; }
vec3 frameNormal(int v) { return texelFetch(uFrames, 3 * v + 1).xyz; }
vec3 frameTangent(int v) { return texelFetch(uFrames, 3 * v + 2).xyz; }

// L~_v(d): the reflected RF of vertex v at the unit object-space direction d.
vec3 evalReflected(int v, vec3 d) {
    vec3 n = frameNormal(v);
    vec3 t = frameTangent(v);
    float z = dot(n, d);
    if (z < 0.0) {  // Vanhoey et al. 2015 sec. 7: the border of the hemisphere with the same azimuth
        vec3 p = d - z * n;
        float r = length(p);
        d = (r < 1e-12) ? t : p / r;
    }
    int base = v * uCoefficientCount;
    vec3 sum = vec3(0.0);
    if (uBasisKind == 0) {
        vec3 b = cross(n, t);
        float x = dot(t, d), y = dot(b, d);
        float upow[9];
        float vpow[9];
        upow[0] = 1.0;
        vpow[0] = 1.0;
        for (int p = 1; p <= uDegree; ++p) {
            upow[p] = upow[p - 1] * x;
            vpow[p] = vpow[p - 1] * y;
        }
        int index = base;
        for (int total = 0; total <= uDegree; ++total)
            for (int j = 0; j <= total; ++j) {
                sum += texelFetch(uCoefficients, index).xyz * (upow[total - j] * vpow[j]);
                ++index;
            }
    } else {
        // Y_l^m = N_l^m Q_l^|m|(z) Re/Im (x + i y)^|m|; Q by the three-term recurrence in l.
        float cm = 1.0, sm = 0.0;
        float qmm = 1.0;
        for (int m = 0; m <= uDegree; ++m) {
            if (m > 0) {
                qmm *= float(2 * m - 1);
                float c = cm * d.x - sm * d.y;
                sm = cm * d.y + sm * d.x;
                cm = c;
            }
            float q1 = 0.0, q2 = 0.0;
            for (int l = m; l <= uDegree; ++l) {
                float q;
                if (l == m) q = qmm;
                else if (l == m + 1) q = float(2 * m + 1) * d.z * qmm;
                else q = (float(2 * l - 1) * d.z * q1 - float(l + m - 1) * q2) / float(l - m);
                q2 = q1;
                q1 = q;
                int center = l * l + l;
                if (m == 0) {
                    sum += texelFetch(uCoefficients, base + center).xyz * (uShNorm[center] * q);
                } else {
                    float nq = uShNorm[center + m] * q;
                    sum += texelFetch(uCoefficients, base + center + m).xyz * (nq * cm);
                    sum += texelFetch(uCoefficients, base + center - m).xyz * (nq * sm);
                }
            }
        }
    }
    return sum;
}
)GLSL";

// render/tone_mapping.h, in GLSL (shared with the normal-map renderer: toneMappingGlsl()).
const char* const kToneMapping = R"GLSL(
uniform float uExposureScale;  // 2^stops
uniform int uToneCurve;        // 0: clamp, 1: Reinhard
vec3 displayColor(vec3 L) {
    vec3 v = max(L * uExposureScale, vec3(0.0));
    v = (uToneCurve == 1) ? v / (vec3(1.0) + v) : min(v, vec3(1.0));
    vec3 lo = 12.92 * v;
    vec3 hi = 1.055 * pow(v, vec3(1.0 / 2.4)) - vec3(0.055);
    return mix(lo, hi, step(vec3(0.0031308), v));
}
)GLSL";

const char* const kPerVertexVertex = R"GLSL(
invariant gl_Position;
out vec3 vLinear;
void main() {
    gl_Position = ftransform();
    int v = gl_VertexID;
    vec3 n = frameNormal(v);
    vec3 w = uEye - gl_Vertex.xyz;
    float len = length(w);
    w = (len > 0.0) ? w / len : n;
    vLinear = evalReflected(v, 2.0 * dot(n, w) * n - w);  // L_v(w) = L~_v(R_n w)
}
)GLSL";

const char* const kLinearColourFragment = R"GLSL(
in vec3 vLinear;
void main() { gl_FragColor = vec4(displayColor(vLinear), 1.0); }
)GLSL";

const char* const kPerFragmentVertex = R"GLSL(
invariant gl_Position;
out vec3 vObject;
void main() {
    gl_Position = ftransform();
    vObject = gl_Vertex.xyz;
}
)GLSL";

const char* const kPerFragmentFragment = R"GLSL(
uniform usamplerBuffer uFaces;
in vec3 vObject;
void main() {
    int f = gl_PrimitiveID;
    int i0 = int(texelFetch(uFaces, 3 * f).r);
    int i1 = int(texelFetch(uFaces, 3 * f + 1).r);
    int i2 = int(texelFetch(uFaces, 3 * f + 2).r);
    vec3 p0 = framePosition(i0);
    vec3 e1 = framePosition(i1) - p0, e2 = framePosition(i2) - p0, e = vObject - p0;
    float d00 = dot(e1, e1), d01 = dot(e1, e2), d11 = dot(e2, e2), d20 = dot(e, e1), d21 = dot(e, e2);
    float den = d00 * d11 - d01 * d01;
    vec3 alpha = vec3(1.0 / 3.0);
    if (den > 0.0) {
        float a1 = (d11 * d20 - d01 * d21) / den;
        float a2 = (d00 * d21 - d01 * d20) / den;
        alpha = max(vec3(1.0 - a1 - a2, a1, a2), vec3(0.0));  // fragments on edges may fall just outside
        alpha /= (alpha.x + alpha.y + alpha.z);
    }
    vec3 n0 = frameNormal(i0), n1 = frameNormal(i1), n2 = frameNormal(i2);
    vec3 nsum = alpha.x * n0 + alpha.y * n1 + alpha.z * n2;
    float nlen = length(nsum);
    vec3 w = uEye - vObject;
    float len = length(w);
    w = (len > 0.0) ? w / len : ((nlen > 0.0) ? nsum / nlen : n0);
    vec3 L;
    if (nlen > 1e-12) {
        vec3 n = nsum / nlen;
        vec3 r = 2.0 * dot(n, w) * n - w;  // eq. (8): sum_i alpha_i L~_i(R_n w)
        L = alpha.x * evalReflected(i0, r) + alpha.y * evalReflected(i1, r) + alpha.z * evalReflected(i2, r);
    } else {  // opposite normals cancel: sum_i alpha_i L_i(w)
        L = alpha.x * evalReflected(i0, 2.0 * dot(n0, w) * n0 - w) + alpha.y * evalReflected(i1, 2.0 * dot(n1, w) * n1 - w)
          + alpha.z * evalReflected(i2, 2.0 * dot(n2, w) * n2 - w);
    }
    gl_FragColor = vec4(displayColor(L), 1.0);
}
)GLSL";

const char* const kVertexColoursVertex = R"GLSL(
invariant gl_Position;
in vec3 aLinear;   // bound to attribute location 1 (0 aliases gl_Vertex)
out vec3 vLinear;
void main() {
    gl_Position = ftransform();
    vLinear = aLinear;
}
)GLSL";

}  // namespace

std::string vertexShaderSource(GlShading shading) {
    std::string s = kCommon;
    switch (shading) {
        case GlShading::PerVertex: return s + kPerVertexVertex;
        case GlShading::PerFragment: return s + kPerFragmentVertex;
        case GlShading::VertexColors: return s + kVertexColoursVertex;
    }
    return s;
}

std::string fragmentShaderSource(GlShading shading) {
    std::string s = std::string(kCommon) + kToneMapping;
    return s + (shading == GlShading::PerFragment ? kPerFragmentFragment : kLinearColourFragment);
}

std::string toneMappingGlsl() { return kToneMapping; }

std::vector<float> shNormalisationConstants(int degree) {
    const int count = (rad::kMaxHarmonicDegree + 1) * (rad::kMaxHarmonicDegree + 1);
    std::vector<float> out(count, 0.0f);
    const double pi = 3.14159265358979323846;
    for (int l = 0; l <= degree && l <= rad::kMaxHarmonicDegree; ++l)
        for (int m = 0; m <= l; ++m) {
            // K_l^m = sqrt((2l+1)/(4 pi) (l-m)!/(l+m)!)
            double ratio = 1.0;
            for (int k = l - m + 1; k <= l + m; ++k) ratio /= k;
            const double K = std::sqrt((2 * l + 1) / (4 * pi) * ratio);
            if (m == 0) {
                out[l * l + l] = static_cast<float>(K);
            } else {
                out[l * l + l + m] = static_cast<float>(std::sqrt(2.0) * K);
                out[l * l + l - m] = static_cast<float>(std::sqrt(2.0) * K);
            }
        }
    return out;
}

}  // namespace radgl
