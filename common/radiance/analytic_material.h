// Ground-truth outgoing radiance of an analytic material under analytic lights, for synthetic
// ("virtually acquired") data whose exact radiance functions the tests know (Vanhoey et al. 2015 sec. 9:
// "The radiance functions attached to the plane and the spheres (Fig. 6 and 8) are fitted on
// virtually acquired photographs of a synthetic scene characterized by point light sources and
// BRDF"; docs data.md: no measured BRDF is packaged, so analytic ones are used).
//
// BRDF (per RGB channel), with h = normalize(w_i + w_o):
//   f(w_i, w_o) = albedo / pi + ks * (e + 8) / (8 pi) * max(0, n.h)^e
// i.e. Lambert + a normalised Blinn-Phong lobe (the (e+8)/(8 pi) factor of Akenine-Moeller, Haines
// & Hoffman, "Real-Time Rendering", 3rd ed.: the lobe's directional albedo at normal incidence is
// ks within 8 % for every e, 2 % for e >= 100; it falls at grazing w_o as Blinn-Phong does).
// Energy is conserved when albedo + ks <= 1 per channel (up to those few percent).
//
// Outgoing radiance at a point p with unit normal n towards unit w_o (pointing away from p):
//   L(p, n, w_o) = albedo * ambient
//                + sum over lights of f(w_i, w_o) * E_i * max(0, n.w_i)
// where, for a directional light, w_i = its unit direction towards the light and E_i its
// irradiance on a surface facing it; for a point light at q with intensity I,
// w_i = (q - p) / |q - p| and E_i = I / |q - p|^2 (inverse-square falloff; a light exactly at p
// contributes nothing).
// The ambient term is the diffuse response to a uniform, unoccluded environment of radiance
// `ambient` (pi * albedo/pi * ambient); the lobe ignores it. It does not depend on w_o.
//
// No shadows and no interreflection: every light reaches every point whose hemisphere it is in.
// Cast shadows come with the virtual acquisition (ray casting with Embree), which can weight
// lightContribution() by a visibility term per light.
//
// Below the horizon (w_o.n < 0) a radiance function is undefined; outgoingRadiance() then uses the
// horizon direction nearest to w_o (w_o with its normal component removed, renormalised; for
// w_o = -n, an arbitrary tangent), so it stays continuous and finite. The projection code calls
// it only for w_o.n >= 0: this is a safety net, not data.
//
// Spatial stripes (Vanhoey et al. 2015 Fig. 8, "a sphere alternating diffuse and specular materials"): with
// stripes enabled, the bands floor((p.axis - offset) / bandWidth) alternate between diffuse only
// (ks = 0) and diffuse + specular; `specularOnOdd` chooses which parity carries the lobe.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace rad {

using Rgb = Eigen::Vector3d;

struct StripePattern {
    bool enabled = false;
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // need not be unit: normalised on use
    double bandWidth = 0.25;                           // > 0, in scene units along the axis
    double offset = 0.0;                               // band 0 is [offset, offset + bandWidth)
    bool specularOnOdd = true;

    // `count` bands of equal width covering [minCoord, maxCoord] along `axis` (e.g. -r..r for a
    // sphere of radius r centred on the origin: Fig. 8 with count = 8).
    static StripePattern covering(const Eigen::Vector3d& axis, double minCoord, double maxCoord, int count,
                                  bool specularOnOdd = true);

    // Band index of point p (may be negative).
    long long band(const Eigen::Vector3d& p) const;
    // Whether the glossy lobe is present at p (always true when the pattern is disabled).
    bool isSpecular(const Eigen::Vector3d& p) const;
};

struct AnalyticMaterial {
    Rgb albedo = Rgb(0.5, 0.5, 0.5);     // Lambert reflectance in [0, 1]
    Rgb specular = Rgb(0.3, 0.3, 0.3);   // ks, the lobe's reflectance at normal incidence
    double exponent = 50.0;              // Blinn-Phong e >= 0
    StripePattern stripes;               // disabled by default: the lobe is everywhere
};

struct DirectionalLight {
    Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // towards the light; normalised on use
    Rgb irradiance = Rgb::Ones();                           // on a surface facing the light
};

struct PointLight {
    Eigen::Vector3d position = Eigen::Vector3d(0.0, 0.0, 2.0);
    Rgb intensity = Rgb::Ones();  // radiant intensity: irradiance I / d^2 at distance d, facing it
};

struct AnalyticLighting {
    std::vector<DirectionalLight> directional;
    std::vector<PointLight> points;
    Rgb ambient = Rgb::Zero();  // uniform environment radiance, seen by the diffuse part only
};

// Empty when the material and lights describe a physical setup; otherwise a sentence for the user
// naming the value and what to choose: reflectances, exponent, irradiances, intensities and ambient
// finite and >= 0, light directions non-zero, light positions finite, a stripe width > 0.
std::string checkAnalyticSetup(const AnalyticMaterial& material, const AnalyticLighting& lighting);

// BRDF value f(w_i, w_o) at p (p only matters for the stripes). n, w_i, w_o unit; no clamping:
// returns zero when w_i is at or below the horizon or w_o below it (n.w_o < -1e-9).
Rgb evaluateBrdf(const AnalyticMaterial& material, const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                 const Eigen::Vector3d& wi, const Eigen::Vector3d& wo);

// f(w_i, w_o) * E * max(0, n.w_i) for one light (w_o already above the horizon, all unit).
Rgb lightContribution(const AnalyticMaterial& material, const DirectionalLight& light, const Eigen::Vector3d& p,
                      const Eigen::Vector3d& n, const Eigen::Vector3d& wo);
Rgb lightContribution(const AnalyticMaterial& material, const PointLight& light, const Eigen::Vector3d& p,
                      const Eigen::Vector3d& n, const Eigen::Vector3d& wo);

// The full L(p, n, w_o) above; n and w_o need not be unit (normalised here; zero vectors give
// zero radiance). w_o below the horizon is moved to the horizon (see the file comment).
Rgb outgoingRadiance(const AnalyticMaterial& material, const AnalyticLighting& lighting, const Eigen::Vector3d& p,
                     const Eigen::Vector3d& n, const Eigen::Vector3d& wo);

// The direction outgoingRadiance() actually evaluates: unit w_o, or its horizon clamp.
Eigen::Vector3d clampToHemisphere(const Eigen::Vector3d& n, const Eigen::Vector3d& wo);

}  // namespace rad
