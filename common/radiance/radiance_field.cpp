#include "radiance/radiance_field.h"

#include <cmath>
#include <sstream>

namespace rad {

RadianceField::RadianceField(BasisSpec b, std::size_t vertexCount, bool reflectedStorage)
    : basis(b), reflected(reflectedStorage),
      coefficients(vertexCount * kColorChannels * b.coefficientCount(), 0.0f),
      frames(vertexCount * 6, 0.0f) {}

std::size_t RadianceField::vertexCount() const { return frames.size() / 6; }

std::string RadianceField::validate() const {
    std::ostringstream why;
    if (!basis.isValid()) {
        why << "unsupported radiance basis " << basis.name() << " (PB degrees 0.." << kMaxPolynomialDegree
            << ", SH degrees 0.." << kMaxHarmonicDegree << ")";
        return why.str();
    }
    if (frames.size() % 6 != 0) return "radiance frames are not a whole number of vertices";
    const std::size_t n = vertexCount();
    if (coefficients.size() != n * static_cast<std::size_t>(coefficientsPerVertex())) {
        why << "radiance coefficient array has " << coefficients.size() << " floats, expected "
            << n * coefficientsPerVertex() << " for " << n << " vertices of " << basis.name();
        return why.str();
    }
    for (std::size_t i = 0; i < coefficients.size(); ++i)
        if (!std::isfinite(coefficients[i])) {
            why << "radiance coefficient of vertex " << i / coefficientsPerVertex() << " is not a finite number";
            return why.str();
        }
    for (std::size_t v = 0; v < n; ++v) {
        const float* f = frame(v);
        for (int k = 0; k < 6; ++k)
            if (!std::isfinite(f[k])) {
                why << "frame of vertex " << v << " is not finite";
                return why.str();
            }
        const float nn = f[3] * f[3] + f[4] * f[4] + f[5] * f[5];
        if (std::fabs(nn - 1.0f) > 1e-3f) {
            why << "normal of vertex " << v << " is not unit length (|n|^2 = " << nn << ")";
            return why.str();
        }
    }
    return {};
}

}  // namespace rad
