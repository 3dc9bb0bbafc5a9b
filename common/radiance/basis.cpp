#include "radiance/basis.h"

#include "radiance/spherical_harmonics.h"

#include <cctype>

namespace rad {

int BasisSpec::coefficientCount() const {
    if (kind == BasisKind::HemisphericalPolynomial) return (degree + 1) * (degree + 2) / 2;
    return (degree + 1) * (degree + 1);
}

bool BasisSpec::isValid() const {
    if (kind == BasisKind::HemisphericalPolynomial) return degree >= 0 && degree <= kMaxPolynomialDegree;
    if (kind == BasisKind::SphericalHarmonics) return degree >= 0 && degree <= kMaxHarmonicDegree;
    return false;
}

std::string BasisSpec::name() const {
    return (kind == BasisKind::HemisphericalPolynomial ? "PB" : "SH") + std::to_string(degree);
}

std::optional<BasisSpec> BasisSpec::parse(const std::string& text) {
    if (text.size() < 3 || text.size() > 4) return std::nullopt;
    const std::string prefix{static_cast<char>(std::toupper(static_cast<unsigned char>(text[0]))),
                             static_cast<char>(std::toupper(static_cast<unsigned char>(text[1])))};
    BasisSpec spec;
    if (prefix == "PB") spec.kind = BasisKind::HemisphericalPolynomial;
    else if (prefix == "SH") spec.kind = BasisKind::SphericalHarmonics;
    else return std::nullopt;
    int degree = 0;
    for (std::size_t i = 2; i < text.size(); ++i) {
        if (!std::isdigit(static_cast<unsigned char>(text[i]))) return std::nullopt;
        degree = degree * 10 + (text[i] - '0');
    }
    spec.degree = degree;
    if (!spec.isValid()) return std::nullopt;
    return spec;
}

int polynomialIndex(int i, int j) {
    const int total = i + j;
    return total * (total + 1) / 2 + j;
}

namespace {
// PB(d): the monomials u^i v^j, i + j <= d, of the direction's projection (u, v) on the tangent plane.
template <typename Real>
void evaluatePolynomialBasis(int degree, Real u, Real v, Real* out) {
    // Powers of u and v once, then each monomial is one product.
    Real upow[kMaxPolynomialDegree + 1], vpow[kMaxPolynomialDegree + 1];
    upow[0] = vpow[0] = Real(1);
    for (int p = 1; p <= degree; ++p) {
        upow[p] = upow[p - 1] * u;
        vpow[p] = vpow[p - 1] * v;
    }
    int index = 0;
    for (int total = 0; total <= degree; ++total)
        for (int j = 0; j <= total; ++j) out[index++] = upow[total - j] * vpow[j];
}

template <typename Real>
void evaluateAny(const BasisSpec& basis, Real x, Real y, Real z, Real* out) {
    if (basis.kind == BasisKind::HemisphericalPolynomial)
        evaluatePolynomialBasis<Real>(basis.degree, x, y, out);
    else
        evaluateSphericalHarmonics(basis.degree, x, y, z, out);
}
}  // namespace

void evaluateBasis(const BasisSpec& basis, float x, float y, float z, float* out) { evaluateAny(basis, x, y, z, out); }
void evaluateBasis(const BasisSpec& basis, double x, double y, double z, double* out) { evaluateAny(basis, x, y, z, out); }

}  // namespace rad
