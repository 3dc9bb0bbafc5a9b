// Ground-truth outgoing radiance of an analytic material under analytic lights, for synthetic
// ("virtually acquired") data whose exact radiance functions the tests know, as Vanhoey et al. 2015
// fit their plane and spheres on photographs of a synthetic scene. BRDF: Lambert + a normalised
// Blinn-Phong lobe, optionally in alternating diffuse / glossy stripes (their Fig. 8); directional
// and point lights plus an ambient term. No shadows and no interreflection (the virtual acquisition
// adds shadows). Below the horizon the nearest horizon direction is used, so it stays finite.
// Details: docs/fitting.md, "`common/radiance/analytic_material.h`: how it works".
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
