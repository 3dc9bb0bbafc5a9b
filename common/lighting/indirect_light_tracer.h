// Indirect light of a diffuse scene by path tracing with Embree: the one estimator behind the
// irradiance vector grid (irradiance_vector_grid_compute.h) and its CPU reference
// (render/indirect_light_reference.h), so that both integrate exactly the same quantity: radiance
// reflected diffusely at least once after leaving a light, up to B bounces; escaping rays give 0 and
// rays reaching a back face are reported. Rays go 16 at a time (Embree packets).
// Thread-safe: trace() is const; each thread passes its own random generator.
// Details: docs/irradiance-vector-grid.md, "`common/lighting/indirect_light_tracer.h`: how it works".
#pragma once

#include "errors/error_categories.h"

#include "geometry/triangle_mesh.h"
#include "radiance/analytic_material.h"
#include "raycast/ray_scene.h"

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace rad {

// The albedo of a scene without vertex colours: a mid grey, the usual "clay" of a scan viewer.
constexpr float kDefaultIndirectAlbedo = 0.5f;

struct IndirectLightError : InputError {
    using InputError::InputError;
};

// A small, fast generator (PCG32, O'Neill 2014) for per-thread streams: the path directions and
// the light choices. Deterministic for a given seed.
struct Pcg32 {
    std::uint64_t state = 0x853c49e6748fea9bULL, increment = 0xda3e39cb94b95bdbULL;
    Pcg32() = default;
    Pcg32(std::uint64_t seed, std::uint64_t stream) {
        increment = (stream << 1u) | 1u;
        state = 0;
        next();
        state += seed;
        next();
    }
    std::uint32_t next() {
        const std::uint64_t old = state;
        state = old * 6364136223846793005ULL + increment;
        const std::uint32_t xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
        const std::uint32_t rot = static_cast<std::uint32_t>(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
    }
    // Uniform in [0, 1).
    float uniform() { return static_cast<float>(next() >> 8) * (1.0f / 16777216.0f); }
};

struct IndirectLightSetup {
    int bounces = 1;             // B >= 1
    int lightSamples = 8;        // lights drawn per hit when there are more; 0 = always every light
    double relativeRayOffset = 1e-4;  // of the scene's bounding-box diagonal: shadow/continuation ray offset
};

// Counts of one trace() call (callers add them up).
struct IndirectTraceCounts {
    std::uint64_t rays = 0;       // every ray cast: the given ones, continuations and shadow rays
    std::uint64_t backFaces = 0;  // given rays whose first hit is a back face
    std::uint64_t escaped = 0;    // given rays that hit nothing
};

class IndirectLightTracer {
public:
    // mesh: positions and counter-clockwise faces (normals unused: the flat face normal shades).
    // albedo: 3 floats per vertex in [0, 1] (clamped), or empty for kDefaultIndirectAlbedo.
    // Throws IndirectLightError for an invalid mesh (message from TriangleMesh::validate), no faces,
    // a scene out of range or scale (sceneScaleProblem, geometry/coordinate_range.h), an albedo array of the
    // wrong size, no light or a light with a non-finite or negative value, a
    // zero direction, bounces < 1 or > 16, lightSamples < 0, an offset outside (0, 0.01).
    IndirectLightTracer(const TriangleMesh& mesh, const std::vector<float>& albedo, const AnalyticLighting& lights,
                        const IndirectLightSetup& setup);
    ~IndirectLightTracer();
    IndirectLightTracer(const IndirectLightTracer&) = delete;
    IndirectLightTracer& operator=(const IndirectLightTracer&) = delete;

    // L_ind along each active ray of `rays` (unit directions), per lane R G B into radiance[3 * lane];
    // inactive lanes get 0. backFaceMask: the active lanes whose first hit is a back face.
    void trace(const RayPacket16& rays, std::uint32_t activeMask, Pcg32& rng, float radiance[3 * RayPacket16::kSize],
               std::uint32_t& backFaceMask, IndirectTraceCounts& counts) const;

    // The first hit of one ray, for the renderers: false when it escapes. faceNormal is the unit
    // counter-clockwise normal, albedo the interpolated one.
    bool firstHit(const float origin[3], const float direction[3], float point[3], float faceNormal[3], float albedo[3],
                  bool& backFace) const;

    // Direct irradiance E_d at a surface point with unit normal n (shadow rays; exact sum over every
    // light, whatever lightSamples), per channel.
    void directIrradiance(const float point[3], const float normal[3], float out[3]) const;

    const RayScene& rayScene() const { return *scene_; }
    float rayOffset() const { return rayOffset_; }
    float sceneDiagonal() const { return diagonal_; }
    const IndirectLightSetup& setup() const { return setup_; }
    std::size_t lightCount() const { return lights_.size(); }

private:
    struct Light {
        bool point = false;
        float position[3] = {0, 0, 0};  // point lights
        float direction[3] = {0, 0, 1}; // directional lights: unit, toward the light
        float value[3] = {0, 0, 0};     // irradiance (directional) or intensity (point)
    };
    void accumulateDirect(const float* px, const float* py, const float* pz, const float* nx, const float* ny,
                          const float* nz, const float* weight, std::uint32_t mask, Pcg32& rng, float* out,
                          IndirectTraceCounts& counts) const;

    std::unique_ptr<RayScene> scene_;
    std::vector<float> faceNormals_;  // 3 per face, unit (zero for degenerate faces)
    std::vector<float> albedo_;       // 3 per vertex
    std::vector<std::uint32_t> faces_;
    std::vector<Light> lights_;
    std::vector<float> lightCdf_;     // cumulative selection probabilities
    std::vector<float> lightProbability_;
    IndirectLightSetup setup_;
    float rayOffset_ = 0.0f;
    float diagonal_ = 0.0f;
};

}  // namespace rad
