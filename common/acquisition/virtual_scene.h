// A shaded synthetic scene for "virtual acquisition": a triangle mesh with unit vertex normals, a
// spatially varying analytic material (radiance/analytic_material.h) and analytic lights, with cast
// shadows by Embree shadow rays (the ambient term unshadowed, no interreflection). Photographs of it
// (virtual_photographs.h) exercise the radiance fitting exactly as a user's calibrated photographs
// do, and radiance() at the vertices is the ground truth the fitting benchmarks compare to (Vanhoey
// et al. 2015 sec. 7 fit on "virtually acquired photographs of a synthetic scene").
// Details: docs/fitting.md, "`common/acquisition/virtual_scene.h`: how it works".
#pragma once

#include "errors/error_categories.h"

#include "geometry/triangle_mesh.h"
#include "radiance/analytic_material.h"
#include "raycast/ray_scene.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <memory>
#include <stdexcept>
#include <string>

namespace rad {

struct VirtualSceneError : InputError {
    using InputError::InputError;
};

// Smooth procedural variation of the material over position. Each modulation is
//   s_k(p) = (1/3) sum_{j=0..2} sin(2 pi d_j . (p - c) / wavelength + phi_kj)   in [-1, 1]
// with three fixed, non-axis-aligned unit directions d_j, the bounding-box centre c and fixed
// phases phi_kj distinct per modulation k (0, 1, 2: albedo R, G, B; 3: albedo brightness; 4: ks).
// Then, per channel c,
//   albedo_c(p) = clamp(albedo_c * (1 + albedoAmplitude * (0.75 s_3(p) + 0.25 s_c(p))), 0, 1)
//   ks_c(p)     = clamp(ks_c * (1 + specularAmplitude * s_4(p)), 0, 1)
// i.e. mostly a brightness change with a milder change of hue, and an independent change of
// glossiness. Smooth on purpose: with the default wavelength (a quarter of the bounding-box
// diagonal) a scan of ~40k vertices has dozens of vertices per period, so a per-vertex radiance
// function interpolated over the triangles can represent it (the stripes of StripePattern, being
// discontinuous, cannot).
struct SmoothVariation {
    bool enabled = true;
    double wavelength = 0.0;         // scene units; <= 0: 0.25 * bounding-box diagonal
    double albedoAmplitude = 0.35;   // relative modulation of the albedo, in [0, 1]
    double specularAmplitude = 0.6;  // relative modulation of ks, in [0, 1]
};

struct VirtualSceneOptions {
    SmoothVariation variation;
    bool castShadows = true;       // false: every light reaches every point facing it
    double shadowOffset = 1e-4;    // shadow-ray origin offset along n, relative to the bbox diagonal
};

// s_k(p) of SmoothVariation for modulation k = `which` in 0..4 (std::out_of_range otherwise), given
// the centre c and the wavelength.
double smoothModulation(int which, const Eigen::Vector3d& p, const Eigen::Vector3d& centre, double wavelength);

class VirtualScene {
public:
    // The mesh needs faces; normals are normalised here, or computed (area-weighted,
    // geometry/mesh_normals.h) when the mesh has none. Throws VirtualSceneError when the mesh is
    // invalid or empty, a normal is zero, the material or a light is not finite, or an option is
    // out of range; RayCastError when Embree fails.
    VirtualScene(TriangleMesh mesh, AnalyticMaterial material, AnalyticLighting lighting,
                 VirtualSceneOptions options = {});

    VirtualScene(VirtualScene&&) noexcept = default;
    VirtualScene& operator=(VirtualScene&&) noexcept = default;

    const TriangleMesh& mesh() const { return mesh_; }
    const RayScene& rays() const { return *rays_; }
    const AnalyticMaterial& baseMaterial() const { return material_; }
    const AnalyticLighting& lighting() const { return lighting_; }
    const VirtualSceneOptions& options() const { return options_; }
    const Eigen::AlignedBox3d& bounds() const { return bounds_; }
    double diagonal() const { return bounds_.diagonal().norm(); }
    // The wavelength actually used by the variation (the default resolved).
    double variationWavelength() const { return wavelength_; }

    // The material at p: the base material with albedo and ks modulated by SmoothVariation.
    AnalyticMaterial materialAt(const Eigen::Vector3d& p) const;

    // Whether the shadow ray from p + eps n towards the light is unobstructed (always true when
    // castShadows is off). n unit.
    bool reaches(const DirectionalLight& light, const Eigen::Vector3d& p, const Eigen::Vector3d& n) const;
    bool reaches(const PointLight& light, const Eigen::Vector3d& p, const Eigen::Vector3d& n) const;

    // Outgoing radiance L(p, n, w_o) (docs/fitting.md), the ground truth at vertices. n and w_o
    // need not be unit (zero vectors give zero radiance). Thread-safe.
    Rgb radiance(const Eigen::Vector3d& p, const Eigen::Vector3d& n, const Eigen::Vector3d& wo) const;

private:
    TriangleMesh mesh_;
    AnalyticMaterial material_;
    AnalyticLighting lighting_;
    VirtualSceneOptions options_;
    Eigen::AlignedBox3d bounds_;
    double wavelength_ = 1.0;
    double offset_ = 0.0;  // absolute shadow-ray offset
    std::unique_ptr<RayScene> rays_;
};

// ---- Sample scenes (tools/virtual_acquisition.cpp): the same presets rebuild the ground truth of
// a virtual acquisition in a benchmark. `up` is the world up axis, (east, north, up) the
// right-handed frame of sampleFrame().
enum class SampleMaterial {
    Glossy,   // albedo (0.60, 0.45, 0.32), ks 0.18, exponent 30
    Diffuse,  // same albedo, no lobe
    Stripes,  // Glossy with 8 bands along `up` over the bounding box alternating diffuse / glossy
};
// "glossy", "diffuse", "stripes"; throws std::invalid_argument otherwise.
SampleMaterial parseSampleMaterial(const std::string& name);
AnalyticMaterial makeSampleMaterial(SampleMaterial kind, const Eigen::AlignedBox3d& bounds, const Eigen::Vector3d& up);
// Two horizontal axes completing unit `up`: east = the world axis least aligned with up, made
// perpendicular; north = up x east.
void sampleFrame(const Eigen::Vector3d& up, Eigen::Vector3d& east, Eigen::Vector3d& north);
// A warm key light (directional, irradiance (2.0, 1.92, 1.8), from normalize(0.45 e - 0.35 n + u)),
// a cool point fill light at centre + 2.5 radius normalize(-0.8 e + 0.5 n + 0.4 u) giving
// irradiance (0.4, 0.45, 0.55) at the centre, and ambient 0.05. With the Glossy material only the
// brightest highlights exceed 1 (clip in 8-bit photographs); virtual_acquisition prints how many.
AnalyticLighting makeSampleLighting(const Eigen::Vector3d& centre, double radius, const Eigen::Vector3d& up);

}  // namespace rad
