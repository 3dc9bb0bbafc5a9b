// Computing the irradiance vector grid of Granier et al. 2007 (storage and interpolation:
// irradiance_vector_grid.h) for a diffuse scene, by Monte Carlo with Embree: per grid vertex and
// direction, the indirect light of indirect_light_tracer.h integrated over the hemisphere with
// uniformly distributed, randomly rotated Hammersley directions. Vertices inside objects or behind
// walls (too many rays reaching back faces) are detected and filled from their valid neighbours.
// Details: docs/irradiance-vector-grid.md, "`common/lighting/irradiance_vector_grid_compute.h`: how it works".
#pragma once

#include "geometry/triangle_mesh.h"
#include "lighting/environment_map.h"
#include "lighting/indirect_light_tracer.h"
#include "lighting/irradiance_vector_grid.h"
#include "progress/progress_callback.h"

#include <array>
#include <cstdint>
#include <vector>

namespace rad {

struct IrradianceGridOptions {
    int resolution = 16;                 // cells along the longest axis of the padded box, 1..512
    double padding = 0.02;               // of the longest side of the scene's box, each side, [0, 1]
    int raysPerDirection = 256;          // R, rays per grid vertex and direction, 1..1,048,576
    IndirectLightSetup light;            // bounces, light samples, ray offset
    double maxBackFaceFraction = 0.05;   // above: the vertex is inside an object or behind a wall
    bool repairInvalid = true;           // false keeps the invalid vertices' own estimates (for tests)
    std::uint64_t seed = 1;
    int threads = 0;                     // 0 = every core
};

struct IrradianceGridReport {
    std::array<int, 3> cells{{0, 0, 0}};
    std::size_t vertices = 0;
    std::size_t invalidVertices = 0;     // back-face fraction above the threshold
    std::size_t repairedVertices = 0;    // invalid ones given their valid neighbours' average
    std::size_t unreachableVertices = 0; // invalid ones with no valid vertex in reach (left zero)
    std::uint64_t samples = 0;           // hemisphere rays of grid vertices (vertices * 6 * R)
    std::uint64_t rays = 0;              // every ray cast: samples, path continuations, shadow rays
    std::uint64_t backFaceSamples = 0;
    std::uint64_t escapedSamples = 0;
    double setupSeconds = 0.0;           // BVH and scene arrays
    double traceSeconds = 0.0;
    double repairSeconds = 0.0;
    double totalSeconds = 0.0;
    double secondsPerMillionSamples() const { return samples ? traceSeconds * 1e6 / double(samples) : 0.0; }
    std::size_t memoryBytes = 0;         // of the uncompressed grid (54 floats per vertex)
};

// The direct light of an environment map as directional lights for the tracer: Debevec's median
// cut (median_cut_lights.h) into the smallest power of two >= lightCount regions (lightCount 1..4096,
// std::invalid_argument otherwise), each region's light scaled by `scale` (> 0). Their summed
// irradiance is the map's sphere integral times the scale.
AnalyticLighting environmentLights(const EnvironmentMap& map, int lightCount, double scale = 1.0);

// The cells of the grid for a box and a resolution (docs/irradiance-vector-grid.md, "Grid
// placement"), without computing.
// Throws IrradianceVectorGridError for a resolution outside 1..512 or a bad box.
IrradianceVectorGrid placeIrradianceGrid(const std::array<float, 3>& boxMin, const std::array<float, 3>& boxMax,
                                         int resolution, double padding);

// The grid of `mesh` lit by `lights` (albedo as IndirectLightTracer: 3 per vertex or empty for
// kDefaultIndirectAlbedo). Throws IndirectLightError / IrradianceVectorGridError / std::invalid_argument
// with a sentence naming the bad value, OperationCancelled when `progress` asks to stop.
IrradianceVectorGrid computeIrradianceVectorGrid(const TriangleMesh& mesh, const std::vector<float>& albedo,
                                                 const AnalyticLighting& lights, const IrradianceGridOptions& options,
                                                 const ProgressCallback& progress = {},
                                                 IrradianceGridReport* report = nullptr);

// Whether every vector of `grid` is finite (a light of 1e38 overflows float: the caller names the
// light's parameter in its refusal).
bool irradianceVectorsFinite(const IrradianceVectorGrid& grid);

// Fills the vertices flagged in `invalid` (one flag per vertex, 1 = invalid) from valid ones, wave
// after wave (a vertex filled in one wave serves the next), per direction delta:
//  - when the next two vertices along delta (v + delta, v + 2 delta) are valid, the linear
//    extrapolation 2 I(v + delta) - I(v + 2 delta), per channel, unless it flips the sign of the
//    vector's component along delta (then I(v + delta)): a surface facing delta next to an invalid
//    vertex (a wall, the floor seen from below it) lies between it and those vertices, and the
//    indirect light near a wall varies about linearly;
//  - else the average of the valid 26-neighbours on delta's side (offset . delta > 0), if any;
//  - else the average of all valid 26-neighbours.
// Returns the count left unfilled (no valid vertex in reach), set to zero.
std::size_t repairInvalidGridVertices(IrradianceVectorGrid& grid, std::vector<std::uint8_t> invalid);

// The same on a given grid geometry (cells, origin, cell size of `grid`; its vectors overwritten),
// with an existing tracer; `invalid` (optional) receives one flag per vertex (1 = invalid before repair).
void computeIrradianceVectors(const IndirectLightTracer& tracer, IrradianceVectorGrid& grid,
                              const IrradianceGridOptions& options, const ProgressCallback& progress,
                              IrradianceGridReport& report, std::vector<std::uint8_t>* invalid = nullptr);

}  // namespace rad
