#include "basis_parameters.h"

#include "filter.h"

namespace radml {

void addBasisParameters(RichParameterList& par, const QString& degreeAdvice) {
    par.addParam(RichEnum("basis", 0,
                          QStringList() << "Hemispherical polynomials PB(d), local frame"
                                        << "Spherical harmonics SH(d), global frame",
                          "Basis", "Function basis of the radiance functions (Vanhoey et al. 2015, sec. 6)."));
    par.addParam(RichInt("degree", 4, "Degree",
                         QString("Degree d: PB(d) has (d+1)(d+2)/2 coefficients per channel (0..%1), SH(d) has "
                                 "(d+1)^2 (0..%2). ")
                                 .arg(rad::kMaxPolynomialDegree)
                                 .arg(rad::kMaxHarmonicDegree) +
                             degreeAdvice));
}

rad::BasisSpec basisParameters(const RichParameterList& par) {
    rad::BasisSpec basis;
    basis.kind = par.getEnum("basis") == 0 ? rad::BasisKind::HemisphericalPolynomial
                                           : rad::BasisKind::SphericalHarmonics;
    basis.degree = par.getInt("degree");
    if (!basis.isValid())
        throw Refusal(formatLine("Degree %d is not supported for %s: use PB degrees 0..%d or SH degrees 0..%d.",
                                 basis.degree, basis.kind == rad::BasisKind::SphericalHarmonics ? "SH" : "PB",
                                 rad::kMaxPolynomialDegree, rad::kMaxHarmonicDegree));
    return basis;
}

}  // namespace radml
