#include "outofcore/vertex_clustering.h"

#include "geometry/mesh_normals.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

namespace rad {

namespace {

constexpr int kMaxCellsPerAxis = 1 << 20;  // keys of three axes fit 63 bits

struct CellData {
    double q[10] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0};  // a2 ab ac ad b2 bc bd c2 cd d2 (plane a x + b y + c z + d)
    double sum[3] = {0, 0, 0};
    std::uint32_t vertices = 0;
    std::uint64_t key = 0;
};

struct TripleHash {
    std::size_t operator()(const std::array<std::uint32_t, 3>& t) const {
        std::uint64_t h = t[0] * 0x9E3779B97F4A7C15ull;
        h ^= (h >> 29) + t[1] * 0xBF58476D1CE4E5B9ull;
        h ^= (h >> 31) + t[2] * 0x94D049BB133111EBull;
        return std::size_t(h ^ (h >> 32));
    }
};

}  // namespace

struct VertexClustering::Cells {
    std::array<std::int64_t, 3> dims{{1, 1, 1}};
    double size = 0.0;
    std::unordered_map<std::uint64_t, std::uint32_t> idOfKey;
    std::vector<CellData> data;
    std::unordered_set<std::array<std::uint32_t, 3>, TripleHash> triangles;
    std::vector<std::array<std::uint32_t, 3>> order;  // kept triangles in the order first seen
    bool begun = false;

    std::uint64_t key(const float* p, const double* origin) const {
        std::int64_t i[3];
        for (int a = 0; a < 3; ++a) {
            const std::int64_t c = std::int64_t(std::floor((double(p[a]) - origin[a]) / size));
            i[a] = std::clamp<std::int64_t>(c, 0, dims[a] - 1);
        }
        return std::uint64_t(i[0]) + std::uint64_t(dims[0]) * (std::uint64_t(i[1]) + std::uint64_t(dims[1]) * std::uint64_t(i[2]));
    }
};

VertexClustering::VertexClustering(const ClusteringOptions& options) : options_(options), cells_(new Cells) {}
VertexClustering::~VertexClustering() = default;

void VertexClustering::addVertices(const float* positions, std::size_t count) {
    if (cells_->begun) throw std::invalid_argument("vertex clustering: vertices after the first triangles");
    if (positions_.size() / 3 + count > 0xffffffffull)
        throw std::invalid_argument("vertex clustering: more than 2^32 - 1 vertices");
    positions_.insert(positions_.end(), positions, positions + 3 * count);
}

void VertexClustering::beginTriangles() {
    Cells& cells = *cells_;
    if (cells.begun) return;
    const std::size_t n = positions_.size() / 3;
    if (n == 0) throw std::invalid_argument("vertex clustering: no vertices");
    if (options_.cellSize <= 0.0 && options_.targetTriangles == 0)
        throw std::invalid_argument("vertex clustering: neither a target triangle count nor a cell size");
    double lo[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                    std::numeric_limits<double>::infinity()};
    double hi[3] = {-lo[0], -lo[0], -lo[0]};
    const std::vector<std::uint8_t>* used = options_.referenced;
    if (used && used->size() != n) throw std::invalid_argument("vertex clustering: the referenced flags do not match the vertices");
    const auto counts = [used](std::size_t v) { return !used || (*used)[v] != 0; };
    for (std::size_t v = 0; v < n; ++v)
        if (counts(v))
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], double(positions_[3 * v + a]));
            hi[a] = std::max(hi[a], double(positions_[3 * v + a]));
        }
    if (!(lo[0] <= hi[0])) throw std::invalid_argument("vertex clustering: no vertex is used by a triangle");
    const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-30});
    auto dimsFor = [&](double h, std::array<std::int64_t, 3>& dims) {
        for (int a = 0; a < 3; ++a)
            dims[a] = std::clamp<std::int64_t>(std::int64_t(std::floor((hi[a] - lo[a]) / h)) + 1, 1, kMaxCellsPerAxis);
    };
    const double smallest = extent / (kMaxCellsPerAxis - 1);
    double h = options_.cellSize > 0.0 ? std::max(options_.cellSize, smallest) : extent / 64.0;
    for (int a = 0; a < 3; ++a) origin_[a] = lo[a];
    if (options_.cellSize <= 0.0) {
        // Occupied cells counted on evenly spaced vertices; the grid refined until about
        // target / 2 cells are occupied (cells ~ area / h^2, hence the square root).
        const std::size_t stride = std::max<std::size_t>(1, n / std::max<std::size_t>(options_.sampledVertices, 1));
        const double wanted = std::max(1.0, double(options_.targetTriangles) / 2.0);
        std::vector<std::uint64_t> keys;
        for (int iteration = 0; iteration < 12; ++iteration) {
            cells.size = h;
            dimsFor(h, cells.dims);
            keys.clear();
            for (std::size_t v = 0; v < n; v += stride)
                if (counts(v)) keys.push_back(cells.key(&positions_[3 * v], origin_));
            std::sort(keys.begin(), keys.end());
            // Cells hold many vertices at any useful target, so the cells the sample occupies are
            // (nearly) all the occupied cells: no scaling by the stride.
            const double occupied = double(std::unique(keys.begin(), keys.end()) - keys.begin());
            const double ratio = occupied / wanted;
            if (std::abs(ratio - 1.0) < 0.03) break;
            // Every sampled vertex alone in its cell: finer cells cannot add any.
            if (occupied >= double(keys.size()) * 0.999 && ratio < 1.0) break;
            h = std::max(smallest, h * std::sqrt(std::clamp(ratio, 0.05, 20.0)));
        }
    }
    cells.size = h;
    dimsFor(h, cells.dims);
    stats_.cellSize = h;
    for (int a = 0; a < 3; ++a) stats_.gridCells[a] = int(cells.dims[a]);

    cellOfVertex_.resize(n);
    cells.idOfKey.reserve(std::min<std::size_t>(n, 1 << 22));
    std::vector<std::uint64_t> keys(std::min<std::size_t>(n, 1 << 20));
    for (std::size_t first = 0; first < n; first += keys.size()) {
        const std::size_t count = std::min(keys.size(), n - first);
#pragma omp parallel for schedule(static)
        for (std::int64_t i = 0; i < std::int64_t(count); ++i)
            keys[std::size_t(i)] = cells.key(&positions_[3 * (first + std::size_t(i))], origin_);
        for (std::size_t i = 0; i < count; ++i) {
            if (!counts(first + i)) {
                cellOfVertex_[first + i] = 0xffffffffu;  // no triangle reads it
                continue;
            }
            const auto [it, inserted] = cells.idOfKey.try_emplace(keys[i], std::uint32_t(cells.data.size()));
            if (inserted) {
                cells.data.emplace_back();
                cells.data.back().key = keys[i];
            }
            CellData& c = cells.data[it->second];
            const float* p = &positions_[3 * (first + i)];
            for (int a = 0; a < 3; ++a) c.sum[a] += p[a];
            ++c.vertices;
            cellOfVertex_[first + i] = it->second;
        }
    }
    cells.idOfKey = {};
    stats_.occupiedCells = cells.data.size();
    cells.begun = true;
}

void VertexClustering::addTriangles(const std::uint32_t* indices, std::size_t count, float* accumulatedNormals) {
    beginTriangles();
    Cells& cells = *cells_;
    const std::size_t n = positions_.size() / 3;
    for (std::size_t t = 0; t < count; ++t) {
        const std::uint32_t i0 = indices[3 * t], i1 = indices[3 * t + 1], i2 = indices[3 * t + 2];
        if (i0 >= n || i1 >= n || i2 >= n) throw std::out_of_range("vertex clustering: triangle index out of range");
        const float* a = &positions_[3 * std::size_t(i0)];
        const float* b = &positions_[3 * std::size_t(i1)];
        const float* c = &positions_[3 * std::size_t(i2)];
        const double e1[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
        const double e2[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
        const double cr[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        if (accumulatedNormals)
            for (std::uint32_t v : {i0, i1, i2})
                for (int k = 0; k < 3; ++k) accumulatedNormals[3 * std::size_t(v) + k] += float(cr[k]);
        ++stats_.inputTriangles;
        const double twiceArea = std::sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
        const std::uint32_t c0 = cellOfVertex_[i0], c1 = cellOfVertex_[i1], c2 = cellOfVertex_[i2];
        if (twiceArea > 0.0) {
            // Plane (nx, ny, nz, d) weighted by the area: Q = area * p p^T.
            const double nx = cr[0] / twiceArea, ny = cr[1] / twiceArea, nz = cr[2] / twiceArea;
            const double d = -(nx * a[0] + ny * a[1] + nz * a[2]);
            const double w = 0.5 * twiceArea;
            const double q[10] = {w * nx * nx, w * nx * ny, w * nx * nz, w * nx * d, w * ny * ny,
                                  w * ny * nz, w * ny * d,  w * nz * nz, w * nz * d, w * d * d};
            for (std::uint32_t cell : {c0, c1, c2}) {
                double* target = cells.data[cell].q;
                for (int k = 0; k < 10; ++k) target[k] += q[k];
            }
        }
        if (c0 == c1 || c1 == c2 || c0 == c2) continue;
        // Rotated so that the smallest id comes first: the same oriented triangle has one key.
        std::array<std::uint32_t, 3> key{{c0, c1, c2}};
        if (c1 < c0 && c1 < c2) key = {{c1, c2, c0}};
        else if (c2 < c0 && c2 < c1) key = {{c2, c0, c1}};
        if (cells.triangles.insert(key).second) cells.order.push_back(key);
        else ++stats_.duplicateTriangles;
    }
}

TriangleMesh VertexClustering::finish() {
    beginTriangles();
    Cells& cells = *cells_;
    cellOfVertex_ = {};
    cells.triangles = {};
    std::vector<std::uint32_t> newIndex(cells.data.size(), 0xffffffffu);
    TriangleMesh mesh;
    for (const auto& t : cells.order)
        for (std::uint32_t c : t)
            if (newIndex[c] == 0xffffffffu) {
                newIndex[c] = std::uint32_t(mesh.positions.size() / 3);
                const CellData& cell = cells.data[c];
                const Eigen::Vector3d mean = Eigen::Vector3d(cell.sum[0], cell.sum[1], cell.sum[2]) / double(cell.vertices);
                Eigen::Matrix3d A;
                A << cell.q[0], cell.q[1], cell.q[2], cell.q[1], cell.q[4], cell.q[5], cell.q[2], cell.q[5], cell.q[7];
                const Eigen::Vector3d b(cell.q[3], cell.q[6], cell.q[8]);
                // Minimise x^T A x + 2 b^T x + c: A x = -b, solved about the mean with the
                // pseudo-inverse (small eigenvalues dropped) so unconstrained directions keep the mean.
                Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
                eigen.computeDirect(A);
                const Eigen::Vector3d lambda = eigen.eigenvalues();
                const Eigen::Matrix3d U = eigen.eigenvectors();
                const double largest = std::max(std::abs(lambda[0]), std::max(std::abs(lambda[1]), std::abs(lambda[2])));
                const Eigen::Vector3d residual = -b - A * mean;
                Eigen::Vector3d x = mean;
                int used = 0;
                for (int k = 0; k < 3; ++k)
                    if (largest > 0.0 && std::abs(lambda[k]) > 1e-3 * largest) {
                        x += U.col(k) * (U.col(k).dot(residual) / lambda[k]);
                        ++used;
                    }
                if (used == 0 || !x.allFinite()) {
                    x = mean;
                    ++stats_.meanFallbacks;
                }
                // Clamp to the cell grown by half a cell on each side.
                std::uint64_t key = cell.key;
                const std::int64_t ix = std::int64_t(key % std::uint64_t(cells.dims[0]));
                key /= std::uint64_t(cells.dims[0]);
                const std::int64_t iy = std::int64_t(key % std::uint64_t(cells.dims[1]));
                const std::int64_t iz = std::int64_t(key / std::uint64_t(cells.dims[1]));
                const std::int64_t index[3] = {ix, iy, iz};
                bool clamped = false;
                for (int a = 0; a < 3; ++a) {
                    const double low = origin_[a] + (double(index[a]) - 0.5) * cells.size;
                    const double high = origin_[a] + (double(index[a]) + 1.5) * cells.size;
                    if (x[a] < low || x[a] > high) {
                        x[a] = std::clamp(x[a], low, high);
                        clamped = true;
                    }
                }
                if (clamped) ++stats_.clampedVertices;
                for (int a = 0; a < 3; ++a) mesh.positions.push_back(float(x[a]));
            }
    mesh.faces.reserve(3 * cells.order.size());
    for (const auto& t : cells.order)
        for (std::uint32_t c : t) mesh.faces.push_back(newIndex[c]);
    stats_.keptTriangles = cells.order.size();
    cells.order = {};
    cells.data = {};
    computeAreaWeightedNormals(mesh);
    // A vertex whose faces cancel (a fold of the coarse mesh) gets the normal of its first face, so
    // that the bake finds no zero normal.
    for (std::size_t f = 0; f < mesh.faceCount(); ++f)
        for (int k = 0; k < 3; ++k) {
            float* nv = &mesh.normals[3 * std::size_t(mesh.faces[3 * f + k])];
            if (nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2] > 0.5f) continue;
            float fn[3];
            faceNormal(mesh, f, fn);
            if (fn[0] * fn[0] + fn[1] * fn[1] + fn[2] * fn[2] > 0.5f) std::copy(fn, fn + 3, nv);
        }
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
        float* nv = &mesh.normals[3 * v];
        if (!(nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2] > 0.5f)) nv[0] = 0.0f, nv[1] = 0.0f, nv[2] = 1.0f;
    }
    return mesh;
}

TriangleMesh clusterVertices(const TriangleMesh& mesh, const ClusteringOptions& options, ClusteringStats* stats) {
    VertexClustering clustering(options);
    clustering.addVertices(mesh.positions.data(), mesh.vertexCount());
    clustering.addTriangles(mesh.faces.data(), mesh.faceCount());
    TriangleMesh result = clustering.finish();
    if (stats) *stats = clustering.stats();
    return result;
}

}  // namespace rad
