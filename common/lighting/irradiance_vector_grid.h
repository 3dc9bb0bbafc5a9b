// The irradiance vector grid of Granier et al. 2007: a cache of indirect light for a whole scene. An
// axis-aligned grid stores, at each vertex and for each of the six main directions (+x, -x, +y, -y,
// +z, -z), one irradiance vector per colour channel (Arvo 1994); a diffuse surface point is shaded
// by the paper's spatial (trilinear) and directional interpolation, or from the paper's GPU
// compression to one colour and one direction (gpuCompressed, reflectedRadianceCompressed). The
// `.ivg` file is written atomically; readers throw IrradianceVectorGridError.
// Details: docs/irradiance-vector-grid.md, "`common/lighting/irradiance_vector_grid.h`: how it works".
#pragma once

#include "errors/error_categories.h"

#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace rad {

struct IrradianceVectorGridError : FileError {
    using FileError::FileError;
};

struct IrradianceVectorGrid {
    static constexpr int kDirections = 6;                  // +x, -x, +y, -y, +z, -z
    static constexpr int kFloatsPerDirection = 9;          // 3 channels x 3 components
    static constexpr int kFloatsPerVertex = kDirections * kFloatsPerDirection;  // 54

    std::array<int, 3> cells{{0, 0, 0}};                   // Ni, Nj, Nk (>= 1 each)
    std::array<float, 3> origin{{0, 0, 0}};
    std::array<float, 3> cellSize{{1, 1, 1}};
    int bounces = 0;
    int raysPerDirection = 0;
    std::vector<float> vectors;                            // kFloatsPerVertex per vertex, layout: docs/irradiance-vector-grid.md

    // A grid of the given cell counts covering [boxMin, boxMax] (cell sizes from the box), vectors
    // zero. Throws IrradianceVectorGridError for counts < 1, a count product above 2^26 vertices,
    // or an empty, inverted or non-finite box.
    static IrradianceVectorGrid covering(const std::array<float, 3>& boxMin, const std::array<float, 3>& boxMax,
                                         const std::array<int, 3>& cellCounts);

    std::array<int, 3> vertexCounts() const { return {{cells[0] + 1, cells[1] + 1, cells[2] + 1}}; }
    std::size_t vertexCount() const {
        return static_cast<std::size_t>(cells[0] + 1) * (cells[1] + 1) * (cells[2] + 1);
    }
    std::size_t vertexIndex(int i, int j, int k) const {
        return static_cast<std::size_t>(i) + static_cast<std::size_t>(cells[0] + 1) *
                                                 (static_cast<std::size_t>(j) + static_cast<std::size_t>(cells[1] + 1) * k);
    }
    std::array<float, 3> vertexPosition(int i, int j, int k) const {
        return {{origin[0] + i * cellSize[0], origin[1] + j * cellSize[1], origin[2] + k * cellSize[2]}};
    }
    // The 9 floats (R xyz, G xyz, B xyz) of direction `direction` (0..5) at a vertex.
    float* at(std::size_t vertex, int direction) { return vectors.data() + vertex * kFloatsPerVertex + direction * kFloatsPerDirection; }
    const float* at(std::size_t vertex, int direction) const {
        return vectors.data() + vertex * kFloatsPerVertex + direction * kFloatsPerDirection;
    }
    std::size_t memoryBytes() const { return vectors.size() * sizeof(float); }

    // Throws IrradianceVectorGridError when the fields are inconsistent (counts, sizes, vector
    // count) or a value is not finite.
    void validate() const;
};

// Unit direction of index 0..5 (+x, -x, +y, -y, +z, -z).
std::array<float, 3> gridDirection(int direction);

// Step 2's weights. Squared is the paper's n_a^2. Under a uniform incident radiance L it gives
// <I_n, n> = pi L sum_a |n_a|^3, exact on the axes but 1/sqrt(3) of pi L on a diagonal normal;
// Absolute (|n_a|) gives pi L sum_a n_a^2 = pi L for every normal, and equals Squared on the axes.
enum class DirectionalWeights { Squared, Absolute };

// Step 1 and 2 above: I_n(p) per channel, out[9] = R xyz, G xyz, B xyz. Points outside the grid's
// box take the value at the nearest point of the box (clamped). `normal` need not be unit length
// (it is normalised; a zero normal gives zero vectors).
void interpolateIrradianceVector(const IrradianceVectorGrid& grid, const float point[3], const float normal[3], float out[9],
                                 DirectionalWeights weights = DirectionalWeights::Squared);

// Step 3: rho_d / pi <I_n(p), n> per channel (albedo per channel in [0, 1]; radiance never negative:
// a negative dot product, possible with interpolated vectors, gives 0).
void reflectedRadiance(const IrradianceVectorGrid& grid, const float point[3], const float normal[3], const float albedo[3],
                       float outRgb[3], DirectionalWeights weights = DirectionalWeights::Squared);

// The paper's GPU form: per vertex and direction 6 floats, colour (|I_R|, |I_G|, |I_B|) then the
// unit direction of I_R + I_G + I_B (zero when that sum is zero). Size vertexCount() * 6 * 6.
std::vector<float> gpuCompressed(const IrradianceVectorGrid& grid);

// reflectedRadiance() evaluated from gpuCompressed() data (what a shader using the paper's
// compression computes), for the same grid geometry.
void reflectedRadianceCompressed(const IrradianceVectorGrid& grid, const std::vector<float>& compressed, const float point[3],
                                 const float normal[3], const float albedo[3], float outRgb[3],
                                 DirectionalWeights weights = DirectionalWeights::Squared);

// Atomic write (temporary file beside `path`, renamed when complete); std::runtime_error when the
// file cannot be written (no file left behind). Validates the grid first.
void writeIrradianceVectorGrid(const std::string& path, const IrradianceVectorGrid& grid);

// Throws IrradianceVectorGridError naming the file and the problem (not an .ivg file, unknown
// version, missing or malformed header line, data size not matching the header, truncated data,
// non-finite values, a grid larger than the memory it may take). Never allocates more than the
// file's size justifies. memoryLimitBytes 0: what the process has available now
// (memory/available_memory.h).
IrradianceVectorGrid readIrradianceVectorGrid(const std::string& path, std::size_t memoryLimitBytes = 0);

// Why `grid` cannot light a mesh with these vertices, or empty: more than 1 % of them outside the
// grid's box (with half a cell of slack: a stale grid of another scene, or one computed before the
// mesh moved), or a grid less than half the mesh's size (a near-zero cell). Either would be drawn
// as one flat, extrapolated colour.
std::string gridCoverageProblem(const IrradianceVectorGrid& grid, const float* positions, std::size_t vertexCount);

}  // namespace rad
