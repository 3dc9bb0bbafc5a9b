#include "lighting/irradiance_vector_grid.h"

#include "io/atomic_file.h"
#include "memory/available_memory.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace rad {
namespace {

constexpr std::size_t kMaxVertices = std::size_t(1) << 26;
constexpr float kInvPi = 0.318309886183790671538f;

bool finite3(const std::array<float, 3>& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

std::string fail(const std::string& where, const std::string& what) { return where + ": " + what; }

// Cell index and fraction along one axis, the point clamped into the grid.
inline void locate(float x, float origin, float size, int cells, int& index, float& fraction) {
    float u = (x - origin) / size;
    if (!(u > 0.0f)) u = 0.0f;  // also NaN
    if (u > static_cast<float>(cells)) u = static_cast<float>(cells);
    index = std::min(static_cast<int>(u), cells - 1);
    fraction = u - static_cast<float>(index);
}

// Trilinear blend of `floats` values per (vertex, direction) slot of `data` (stride floats per
// vertex, `offset` into it) at the cell located by (i, j, k, fx, fy, fz); out[floats].
template <int floats>
inline void trilinear(const float* data, std::size_t stride, std::size_t offset, const IrradianceVectorGrid& grid, int i,
                      int j, int k, float fx, float fy, float fz, float* out) {
    for (int c = 0; c < floats; ++c) out[c] = 0.0f;
    for (int corner = 0; corner < 8; ++corner) {
        const int di = corner & 1, dj = (corner >> 1) & 1, dk = (corner >> 2) & 1;
        const float w = (di ? fx : 1.0f - fx) * (dj ? fy : 1.0f - fy) * (dk ? fz : 1.0f - fz);
        if (w == 0.0f) continue;
        const float* v = data + grid.vertexIndex(i + di, j + dj, k + dk) * stride + offset;
        for (int c = 0; c < floats; ++c) out[c] += w * v[c];
    }
}

inline float directionalWeight(float component, DirectionalWeights weights) {
    return weights == DirectionalWeights::Squared ? component * component : std::fabs(component);
}

bool unitNormal(const float normal[3], float n[3]) {
    const float length = std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
    if (!(length > 0.0f) || !std::isfinite(length)) return false;
    for (int a = 0; a < 3; ++a) n[a] = normal[a] / length;
    return true;
}

}  // namespace

IrradianceVectorGrid IrradianceVectorGrid::covering(const std::array<float, 3>& boxMin, const std::array<float, 3>& boxMax,
                                                    const std::array<int, 3>& cellCounts) {
    if (!finite3(boxMin) || !finite3(boxMax))
        throw IrradianceVectorGridError("irradiance vector grid: the box has a non-finite corner");
    for (int a = 0; a < 3; ++a) {
        if (cellCounts[a] < 1)
            throw IrradianceVectorGridError("irradiance vector grid: " + std::to_string(cellCounts[a]) +
                                            " cells along an axis; use at least 1");
        if (!(boxMax[a] > boxMin[a]))
            throw IrradianceVectorGridError("irradiance vector grid: the box is empty or inverted along axis " +
                                            std::to_string(a) + "; pad a flat scene's box");
    }
    const double vertices = double(cellCounts[0] + 1) * double(cellCounts[1] + 1) * double(cellCounts[2] + 1);
    if (vertices > double(kMaxVertices))
        throw IrradianceVectorGridError("irradiance vector grid: " + std::to_string(static_cast<long long>(vertices)) +
                                        " grid vertices, more than the 2^26 supported; use fewer cells");
    IrradianceVectorGrid grid;
    grid.cells = cellCounts;
    grid.origin = boxMin;
    for (int a = 0; a < 3; ++a) grid.cellSize[a] = (boxMax[a] - boxMin[a]) / static_cast<float>(cellCounts[a]);
    grid.vectors.assign(grid.vertexCount() * kFloatsPerVertex, 0.0f);
    return grid;
}

void IrradianceVectorGrid::validate() const {
    const std::string where = "irradiance vector grid";
    for (int a = 0; a < 3; ++a) {
        if (cells[a] < 1) throw IrradianceVectorGridError(fail(where, "a cell count is below 1"));
        if (!(cellSize[a] > 0.0f) || !std::isfinite(cellSize[a]))
            throw IrradianceVectorGridError(fail(where, "a cell size is not a positive finite number"));
    }
    if (!finite3(origin)) throw IrradianceVectorGridError(fail(where, "the origin is not finite"));
    const double vertices = double(cells[0] + 1) * double(cells[1] + 1) * double(cells[2] + 1);
    if (vertices > double(kMaxVertices)) throw IrradianceVectorGridError(fail(where, "more than 2^26 grid vertices"));
    if (vectors.size() != vertexCount() * kFloatsPerVertex)
        throw IrradianceVectorGridError(fail(where, std::to_string(vectors.size()) + " values for " +
                                                        std::to_string(vertexCount()) + " vertices, expected " +
                                                        std::to_string(vertexCount() * kFloatsPerVertex)));
    for (float v : vectors)
        if (!std::isfinite(v)) throw IrradianceVectorGridError(fail(where, "a vector component is not finite"));
}

std::array<float, 3> gridDirection(int direction) {
    std::array<float, 3> d{{0, 0, 0}};
    d[direction / 2] = (direction % 2 == 0) ? 1.0f : -1.0f;
    return d;
}

void interpolateIrradianceVector(const IrradianceVectorGrid& grid, const float point[3], const float normal[3], float out[9],
                                 DirectionalWeights weights) {
    for (int c = 0; c < 9; ++c) out[c] = 0.0f;
    float n[3];
    if (!unitNormal(normal, n)) return;
    int index[3];
    float fraction[3];
    for (int a = 0; a < 3; ++a) locate(point[a], grid.origin[a], grid.cellSize[a], grid.cells[a], index[a], fraction[a]);
    for (int a = 0; a < 3; ++a) {
        const float weight = directionalWeight(n[a], weights);
        if (weight == 0.0f) continue;
        const int direction = 2 * a + (n[a] >= 0.0f ? 0 : 1);
        float v[9];
        trilinear<9>(grid.vectors.data(), IrradianceVectorGrid::kFloatsPerVertex,
                     direction * IrradianceVectorGrid::kFloatsPerDirection, grid, index[0], index[1], index[2], fraction[0],
                     fraction[1], fraction[2], v);
        for (int c = 0; c < 9; ++c) out[c] += weight * v[c];
    }
}

void reflectedRadiance(const IrradianceVectorGrid& grid, const float point[3], const float normal[3], const float albedo[3],
                       float outRgb[3], DirectionalWeights weights) {
    float vectors[9];
    interpolateIrradianceVector(grid, point, normal, vectors, weights);
    float n[3] = {0, 0, 0};
    unitNormal(normal, n);
    for (int c = 0; c < 3; ++c) {
        const float dot = vectors[3 * c] * n[0] + vectors[3 * c + 1] * n[1] + vectors[3 * c + 2] * n[2];
        outRgb[c] = std::max(0.0f, albedo[c] * kInvPi * dot);
    }
}

std::vector<float> gpuCompressed(const IrradianceVectorGrid& grid) {
    const std::size_t slots = grid.vertexCount() * IrradianceVectorGrid::kDirections;
    std::vector<float> compressed(slots * 6, 0.0f);
    for (std::size_t s = 0; s < slots; ++s) {
        const float* v = grid.vectors.data() + s * IrradianceVectorGrid::kFloatsPerDirection;
        float* out = compressed.data() + s * 6;
        float sum[3] = {0, 0, 0};
        for (int c = 0; c < 3; ++c) {
            out[c] = std::sqrt(v[3 * c] * v[3 * c] + v[3 * c + 1] * v[3 * c + 1] + v[3 * c + 2] * v[3 * c + 2]);
            for (int a = 0; a < 3; ++a) sum[a] += v[3 * c + a];
        }
        const float length = std::sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
        if (length > 0.0f)
            for (int a = 0; a < 3; ++a) out[3 + a] = sum[a] / length;
    }
    return compressed;
}

void reflectedRadianceCompressed(const IrradianceVectorGrid& grid, const std::vector<float>& compressed, const float point[3],
                                 const float normal[3], const float albedo[3], float outRgb[3], DirectionalWeights weights) {
    outRgb[0] = outRgb[1] = outRgb[2] = 0.0f;
    float n[3];
    if (!unitNormal(normal, n)) return;
    if (compressed.size() != grid.vertexCount() * IrradianceVectorGrid::kDirections * 6)
        throw IrradianceVectorGridError("irradiance vector grid: compressed data does not match the grid");
    int index[3];
    float fraction[3];
    for (int a = 0; a < 3; ++a) locate(point[a], grid.origin[a], grid.cellSize[a], grid.cells[a], index[a], fraction[a]);
    // A shader samples colour and direction textures separately (each trilinearly filtered) and
    // rebuilds I_c = colour_c * direction; the same here.
    float vectors[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    for (int a = 0; a < 3; ++a) {
        const float weight = directionalWeight(n[a], weights);
        if (weight == 0.0f) continue;
        const int direction = 2 * a + (n[a] >= 0.0f ? 0 : 1);
        float slot[6];
        trilinear<6>(compressed.data(), IrradianceVectorGrid::kDirections * 6, direction * 6, grid, index[0], index[1],
                     index[2], fraction[0], fraction[1], fraction[2], slot);
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k) vectors[3 * c + k] += weight * slot[c] * slot[3 + k];
    }
    for (int c = 0; c < 3; ++c) {
        const float dot = vectors[3 * c] * n[0] + vectors[3 * c + 1] * n[1] + vectors[3 * c + 2] * n[2];
        outRgb[c] = std::max(0.0f, albedo[c] * kInvPi * dot);
    }
}

void writeIrradianceVectorGrid(const std::string& path, const IrradianceVectorGrid& grid) {
    grid.validate();
    std::ostringstream header;
    header.precision(9);
    header << "RADIANCE_IVG 1\n"
           << "cells " << grid.cells[0] << ' ' << grid.cells[1] << ' ' << grid.cells[2] << '\n'
           << "origin " << grid.origin[0] << ' ' << grid.origin[1] << ' ' << grid.origin[2] << '\n'
           << "cell_size " << grid.cellSize[0] << ' ' << grid.cellSize[1] << ' ' << grid.cellSize[2] << '\n'
           << "bounces " << grid.bounces << '\n'
           << "rays " << grid.raysPerDirection << '\n'
           << "comment irradiance vector grid, Granier et al. 2007\n"
           << "data float32 little_endian\n"
           << "end_header\n";
    const std::string text = header.str();
    static_assert(sizeof(float) == 4, "float32 expected");
#if defined(__BYTE_ORDER__) && (__BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__)
#error "writeIrradianceVectorGrid assumes a little-endian machine"
#endif
    writeFileAtomically(path, {{text.data(), text.size()}, {grid.vectors.data(), grid.vectors.size() * sizeof(float)}});
}

IrradianceVectorGrid readIrradianceVectorGrid(const std::string& path, std::size_t memoryLimitBytes) {
    const std::string where = "cannot read the irradiance vector grid '" + path + "'";
    std::ifstream file(path, std::ios::binary);
    if (!file) throw IrradianceVectorGridError(where + ": cannot open the file; check the path");
    std::error_code sizeError;
    const auto fileSize = std::filesystem::file_size(path, sizeError);
    if (sizeError) throw IrradianceVectorGridError(where + ": cannot get the file's size");

    // Header: at most 64 lines of at most 4096 characters.
    std::string line;
    const auto nextLine = [&](bool required) -> bool {
        line.clear();
        char c;
        while (file.get(c)) {
            if (c == '\n') return true;
            if (line.size() >= 4096) throw IrradianceVectorGridError(where + ": a header line is too long; not an .ivg file");
            line += c;
        }
        if (required) throw IrradianceVectorGridError(where + ": the header ends before 'end_header' (truncated file?)");
        return false;
    };
    nextLine(true);
    if (line.rfind("RADIANCE_IVG", 0) != 0)
        throw IrradianceVectorGridError(where + ": not an irradiance vector grid file (it must start with 'RADIANCE_IVG')");
    if (line != "RADIANCE_IVG 1")
        throw IrradianceVectorGridError(where + ": unknown version '" + line + "'; this build reads version 1");
    IrradianceVectorGrid grid;
    bool haveCells = false, haveOrigin = false, haveSize = false, haveData = false;
    for (int count = 0;; ++count) {
        if (count > 64) throw IrradianceVectorGridError(where + ": more than 64 header lines; not an .ivg file");
        nextLine(true);
        if (line == "end_header") break;
        std::istringstream in(line);
        std::string key;
        in >> key;
        const auto parsed = [&](auto&... values) {
            (in >> ... >> values);
            std::string rest;
            if (!in || (in >> rest)) throw IrradianceVectorGridError(where + ": malformed header line '" + line + "'");
        };
        if (key == "cells") {
            parsed(grid.cells[0], grid.cells[1], grid.cells[2]);
            haveCells = true;
        } else if (key == "origin") {
            parsed(grid.origin[0], grid.origin[1], grid.origin[2]);
            haveOrigin = true;
        } else if (key == "cell_size") {
            parsed(grid.cellSize[0], grid.cellSize[1], grid.cellSize[2]);
            haveSize = true;
        } else if (key == "bounces") {
            parsed(grid.bounces);
        } else if (key == "rays") {
            parsed(grid.raysPerDirection);
        } else if (key == "comment") {
        } else if (key == "data") {
            if (line != "data float32 little_endian")
                throw IrradianceVectorGridError(where + ": unsupported data encoding '" + line +
                                                "'; expected 'data float32 little_endian'");
            haveData = true;
        } else {
            throw IrradianceVectorGridError(where + ": unknown header line '" + line + "'");
        }
    }
    if (!haveCells || !haveOrigin || !haveSize || !haveData)
        throw IrradianceVectorGridError(where + ": the header lacks one of 'cells', 'origin', 'cell_size', 'data'");
    for (int a = 0; a < 3; ++a)
        if (grid.cells[a] < 1 || grid.cells[a] > (1 << 26))
            throw IrradianceVectorGridError(where + ": cell count " + std::to_string(grid.cells[a]) + " out of range");
    const double vertices = double(grid.cells[0] + 1) * double(grid.cells[1] + 1) * double(grid.cells[2] + 1);
    if (vertices > double(kMaxVertices)) throw IrradianceVectorGridError(where + ": more than 2^26 grid vertices");
    const std::size_t values = grid.vertexCount() * IrradianceVectorGrid::kFloatsPerVertex;
    const auto dataStart = static_cast<std::uintmax_t>(file.tellg());
    const std::uintmax_t expected = dataStart + values * sizeof(float);
    if (fileSize != expected)
        throw IrradianceVectorGridError(where + ": the file has " + std::to_string(fileSize) + " bytes, the header announces " +
                                        std::to_string(expected) + (fileSize < expected ? " (truncated file)" : " (trailing data)"));
    // A grid of 2^26 vertices is 14.5 GB: refused with the figures before the allocation fails
    // (a sparse file passes the size check without using the disk).
    const double bytes = double(values) * sizeof(float);
    const std::size_t available = memoryLimitBytes > 0 ? memoryLimitBytes : availableMemoryBytes();
    if (available > 0 && bytes > double(available))
        throw IrradianceVectorGridError(where + ": the grid (" + std::to_string(grid.cells[0]) + " x " +
                                        std::to_string(grid.cells[1]) + " x " + std::to_string(grid.cells[2]) +
                                        " cells) needs " + describeBytes(bytes) + " of memory and " +
                                        describeBytes(double(available)) +
                                        " are available: compute a grid of lower resolution");
    grid.vectors.resize(values);
    if (!file.read(reinterpret_cast<char*>(grid.vectors.data()), static_cast<std::streamsize>(values * sizeof(float))))
        throw IrradianceVectorGridError(where + ": the data is truncated");
    try {
        grid.validate();
    } catch (const IrradianceVectorGridError& e) {
        throw IrradianceVectorGridError(where + ": " + e.what());
    }
    return grid;
}

std::string gridCoverageProblem(const IrradianceVectorGrid& grid, const float* positions, std::size_t vertexCount) {
    if (vertexCount == 0) return {};
    double lo[3], hi[3], layerLo[3], layerHi[3];
    for (int a = 0; a < 3; ++a) {
        // Half a cell of slack: the grid's box is padded around its scene anyway.
        lo[a] = double(grid.origin[a]) - 0.5 * grid.cellSize[a];
        hi[a] = double(grid.origin[a]) + (grid.cells[a] + 0.5) * double(grid.cellSize[a]);
        layerLo[a] = std::numeric_limits<double>::infinity();
        layerHi[a] = -std::numeric_limits<double>::infinity();
    }
    std::size_t outside = 0;
    for (std::size_t v = 0; v < vertexCount; ++v) {
        bool in = true;
        for (int a = 0; a < 3; ++a) {
            const double x = positions[3 * v + a];
            in = in && x >= lo[a] && x <= hi[a];
            layerLo[a] = std::min(layerLo[a], x);
            layerHi[a] = std::max(layerHi[a], x);
        }
        if (!in) ++outside;
    }
    double gridSide = 0.0, layerSide = 0.0;
    for (int a = 0; a < 3; ++a) {
        gridSide = std::max(gridSide, double(grid.cells[a]) * grid.cellSize[a]);
        layerSide = std::max(layerSide, layerHi[a] - layerLo[a]);
    }
    std::ostringstream why;
    const auto box = [&](const double* l, const double* h) {
        std::ostringstream b;
        b << "(" << l[0] << ", " << l[1] << ", " << l[2] << ") to (" << h[0] << ", " << h[1] << ", " << h[2] << ")";
        return b.str();
    };
    if (double(outside) > 0.01 * double(vertexCount)) {
        why << "the grid spans " << box(lo, hi) << " but " << 100.0 * double(outside) / double(vertexCount)
            << " % of the layer's vertices lie outside it (the layer spans " << box(layerLo, layerHi)
            << "): it was computed for another scene or before the layer moved, and would light it with one flat "
               "colour. Compute the grid again for this layer ('Compute Irradiance Vector Grid'), or name its own grid";
    } else if (layerSide > 0.0 && gridSide < 0.5 * layerSide) {
        why << "the grid is " << gridSide << " units across and the layer " << layerSide
            << ": a grid that small cannot hold the layer's light. Compute the grid again for this layer ('Compute "
               "Irradiance Vector Grid')";
    }
    return why.str();
}

}  // namespace rad
