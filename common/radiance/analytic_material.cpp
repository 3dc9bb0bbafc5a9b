#include "radiance/analytic_material.h"

#include <algorithm>
#include <cmath>

namespace rad {

namespace {

constexpr double kPi = 3.14159265358979323846;

Eigen::Vector3d normalizedOrZero(const Eigen::Vector3d& v) {
    const double len = v.norm();
    if (!(len > 0.0) || !std::isfinite(len)) return Eigen::Vector3d::Zero();
    return v / len;
}

}  // namespace

StripePattern StripePattern::covering(const Eigen::Vector3d& axis, double minCoord, double maxCoord, int count,
                                      bool specularOnOdd) {
    StripePattern s;
    s.enabled = true;
    s.axis = axis;
    s.offset = minCoord;
    s.bandWidth = count > 0 ? (maxCoord - minCoord) / count : 0.0;
    s.specularOnOdd = specularOnOdd;
    return s;
}

std::string checkAnalyticSetup(const AnalyticMaterial& material, const AnalyticLighting& lighting) {
    const auto usable = [](const Rgb& c) { return c.allFinite() && (c.array() >= 0.0).all(); };
    if (!usable(material.albedo))
        return "The albedo must be a colour with finite, non-negative channels (e.g. 0.5 0.5 0.5).";
    if (!usable(material.specular))
        return "The specular strength and colour must be finite and >= 0 (e.g. strength 0.3, white).";
    if (!(material.exponent >= 0.0) || !std::isfinite(material.exponent))
        return "The shininess (Blinn-Phong exponent) must be finite and >= 0 (e.g. 50).";
    if (material.stripes.enabled && !(material.stripes.bandWidth > 0.0 && std::isfinite(material.stripes.bandWidth)))
        return "The stripes need a finite, positive width: give the mesh an extent along the stripe axis, or "
               "choose 0 stripes.";
    for (const DirectionalLight& light : lighting.directional) {
        if (!light.direction.allFinite() || light.direction.norm() < 1e-12)
            return "The direction toward a directional light must be a finite, non-zero vector (e.g. 0 0 1).";
        if (!usable(light.irradiance)) return "The light intensity must be finite and >= 0 (e.g. 1).";
    }
    for (const PointLight& light : lighting.points) {
        if (!light.position.allFinite()) return "The position of a point light must be finite.";
        if (!usable(light.intensity)) return "The light intensity must be finite and >= 0 (e.g. 1).";
    }
    if (!usable(lighting.ambient)) return "The ambient radiance must be finite and >= 0 (e.g. 0.05).";
    return {};
}

long long StripePattern::band(const Eigen::Vector3d& p) const {
    if (!(bandWidth > 0.0)) return 0;
    const double t = (p.dot(normalizedOrZero(axis)) - offset) / bandWidth;
    return static_cast<long long>(std::floor(t));
}

bool StripePattern::isSpecular(const Eigen::Vector3d& p) const {
    if (!enabled) return true;
    const bool odd = (band(p) % 2) != 0;  // -1 % 2 == -1: still "odd"
    return odd == specularOnOdd;
}

Rgb evaluateBrdf(const AnalyticMaterial& material, const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                 const Eigen::Vector3d& wi, const Eigen::Vector3d& wo) {
    // The tolerance keeps a horizon direction from clampToHemisphere() (n.w_o ~ -1e-17) above.
    if (n.dot(wi) <= 0.0 || n.dot(wo) < -1e-9) return Rgb::Zero();
    Rgb f = material.albedo / kPi;
    if (material.stripes.isSpecular(p) && !material.specular.isZero()) {
        const Eigen::Vector3d h = normalizedOrZero(wi + wo);
        const double cosH = std::max(0.0, n.dot(h));
        const double lobe = (material.exponent + 8.0) / (8.0 * kPi) * std::pow(cosH, material.exponent);
        f += material.specular * lobe;
    }
    return f;
}

Rgb lightContribution(const AnalyticMaterial& material, const DirectionalLight& light, const Eigen::Vector3d& p,
                      const Eigen::Vector3d& n, const Eigen::Vector3d& wo) {
    const Eigen::Vector3d wi = normalizedOrZero(light.direction);
    const double cosI = n.dot(wi);
    if (cosI <= 0.0) return Rgb::Zero();
    return evaluateBrdf(material, p, n, wi, wo).cwiseProduct(light.irradiance) * cosI;
}

Rgb lightContribution(const AnalyticMaterial& material, const PointLight& light, const Eigen::Vector3d& p,
                      const Eigen::Vector3d& n, const Eigen::Vector3d& wo) {
    const Eigen::Vector3d d = light.position - p;
    const double d2 = d.squaredNorm();
    if (!(d2 > 0.0)) return Rgb::Zero();
    const Eigen::Vector3d wi = d / std::sqrt(d2);
    const double cosI = n.dot(wi);
    if (cosI <= 0.0) return Rgb::Zero();
    return evaluateBrdf(material, p, n, wi, wo).cwiseProduct(light.intensity) * (cosI / d2);
}

Eigen::Vector3d clampToHemisphere(const Eigen::Vector3d& n, const Eigen::Vector3d& wo) {
    const Eigen::Vector3d w = normalizedOrZero(wo);
    const double c = n.dot(w);
    if (c >= 0.0) return w;
    const Eigen::Vector3d tangential = w - c * n;
    if (tangential.norm() > 1e-9) return tangential.normalized();
    // w = -n: every horizon direction is as near; take one perpendicular to n.
    const Eigen::Vector3d helper = std::fabs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    return n.cross(helper).normalized();
}

Rgb outgoingRadiance(const AnalyticMaterial& material, const AnalyticLighting& lighting, const Eigen::Vector3d& p,
                     const Eigen::Vector3d& n, const Eigen::Vector3d& wo) {
    const Eigen::Vector3d nn = normalizedOrZero(n);
    if (nn.isZero() || normalizedOrZero(wo).isZero()) return Rgb::Zero();
    const Eigen::Vector3d w = clampToHemisphere(nn, wo);
    Rgb L = material.albedo.cwiseProduct(lighting.ambient);
    for (const DirectionalLight& light : lighting.directional) L += lightContribution(material, light, p, nn, w);
    for (const PointLight& light : lighting.points) L += lightContribution(material, light, p, nn, w);
    return L;
}

}  // namespace rad
