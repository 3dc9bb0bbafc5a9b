// Basis functions for per-vertex radiance functions (RF).
//
// Vanhoey et al. 2015, sec. 6 "Basis functions":
//  - PB(d): hemispherical polynomials of total degree <= d in the coordinates (u, v) of the direction
//    orthogonally projected on the tangent plane, expressed in a per-vertex local frame
//    (x = tangent, y = bitangent, z = normal). (d+1)(d+2)/2 functions per colour channel.
//  - SH(d): real spherical harmonics of band <= d in the global frame, (d+1)^2 functions per channel.
//
// Every evaluation takes a unit direction already expressed in the frame the basis lives in
// (the local frame for PB, the global frame for SH); radiance_frame.h converts.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace rad {

enum class BasisKind : std::uint8_t {
    HemisphericalPolynomial = 0,  // "PB", local tangent frame
    SphericalHarmonics = 1,       // "SH", global frame
};

inline constexpr int kMaxPolynomialDegree = 8;
inline constexpr int kMaxHarmonicDegree = 10;
inline constexpr int kColorChannels = 3;  // RGB, treated separately (Vanhoey et al. 2015 sec. 7)

struct BasisSpec {
    BasisKind kind = BasisKind::HemisphericalPolynomial;
    int degree = 4;

    // Functions per colour channel: (d+1)(d+2)/2 for PB, (d+1)^2 for SH.
    int coefficientCount() const;
    // Degree in the supported range for the kind.
    bool isValid() const;
    // Whether the basis lives in a per-vertex local frame (PB) or the global frame (SH).
    bool usesLocalFrame() const { return kind == BasisKind::HemisphericalPolynomial; }
    // "PB4", "SH6"...
    std::string name() const;
    // Parses "PB4" / "SH6" (case-insensitive); nullopt when malformed or out of range.
    static std::optional<BasisSpec> parse(const std::string& text);

    bool operator==(const BasisSpec& o) const { return kind == o.kind && degree == o.degree; }
    bool operator!=(const BasisSpec& o) const { return !(*this == o); }
};

// Writes the value of every basis function at the unit direction (x, y, z) into out[0..count).
// For PB the direction is in the local frame; only (x, y) are used (the function is the same for
// z and -z, which is what makes the border extension of radiance_evaluation.h necessary).
// For SH the direction is in the global frame.
void evaluateBasis(const BasisSpec& basis, float x, float y, float z, float* out);
void evaluateBasis(const BasisSpec& basis, double x, double y, double z, double* out);

// Index helpers.
// PB: function index of the monomial u^i v^j, ordered by total degree then by j: (0,0),(1,0),(0,1),(2,0),(1,1),(0,2),...
int polynomialIndex(int i, int j);
// SH: index of Y_l^m, l >= 0, -l <= m <= l: l*l + l + m.
inline int harmonicIndex(int l, int m) { return l * l + l + m; }

}  // namespace rad
