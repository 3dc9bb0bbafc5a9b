#include "outofcore/streamed_normal_map.h"

#include "bake/map_filling.h"
#include "bake/normal_map_bake.h"
#include "bake/texel_coverage.h"
#include "raycast/ray_scene.h"

#include <Eigen/Dense>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>

namespace rad {

namespace {

// Passes of 8-neighbour growth restricted to texels of the same face (see finish()). Returns the
// number of texels filled.
std::size_t growWithinFaces(std::vector<float>& values, std::vector<std::uint8_t>& valid,
                            const std::vector<std::int32_t>& face, int size) {
    std::size_t total = 0;
    std::vector<std::size_t> frontier;
    std::vector<float> next;
    for (;;) {
        frontier.clear();
        for (int row = 0; row < size; ++row)
            for (int column = 0; column < size; ++column) {
                const std::size_t t = std::size_t(row) * size + column;
                if (valid[t] || face[t] < 0) continue;
                bool reached = false;
                for (int dy = -1; dy <= 1 && !reached; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int r = row + dy, c = column + dx;
                        if (r < 0 || c < 0 || r >= size || c >= size) continue;
                        const std::size_t u = std::size_t(r) * size + c;
                        if (valid[u] && face[u] == face[t]) {
                            reached = true;
                            break;
                        }
                    }
                if (reached) frontier.push_back(t);
            }
        if (frontier.empty()) return total;
        next.assign(3 * frontier.size(), 0.0f);
        for (std::size_t i = 0; i < frontier.size(); ++i) {
            const std::size_t t = frontier[i];
            const int row = int(t / std::size_t(size)), column = int(t % std::size_t(size));
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int r = row + dy, c = column + dx;
                    if (r < 0 || c < 0 || r >= size || c >= size) continue;
                    const std::size_t u = std::size_t(r) * size + c;
                    if (!valid[u] || face[u] != face[t]) continue;
                    for (int k = 0; k < 3; ++k) next[3 * i + k] += values[3 * u + k];
                }
        }
        std::size_t filledThisPass = 0;
        for (std::size_t i = 0; i < frontier.size(); ++i) {
            float* n = &values[3 * frontier[i]];
            const float* m = &next[3 * i];
            const float length = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
            if (!(length > 0.0f)) continue;  // opposite neighbours cancel: left to the pull-push
            for (int k = 0; k < 3; ++k) n[k] = m[k] / length;
            valid[frontier[i]] = 1;
            ++filledThisPass;
        }
        total += filledThisPass;
        if (filledThisPass == 0) return total;
    }
}

}  // namespace

namespace {

// The point of face f whose interpolated vertex normal passes through p ("p = x(b) + t n(b)"), from
// the closest point's barycentrics (b1, b2) by a few Gauss-Newton steps in the face's plane; kept
// only when it converges inside the face (else the closest point stays). This is the correspondence
// of a ray-cast bake (a ray from x(b) along n(b) meets p), so both maps sample the scan at the same
// places; the closest point alone differs from it wherever the vertex normals differ from the face's.
void projectAlongNormals(const TriangleMesh& mesh, std::uint32_t f, const float* p, float& b1, float& b2) {
    if (!mesh.hasNormals()) return;
    const std::uint32_t* c = &mesh.faces[3 * std::size_t(f)];
    const Eigen::Vector3f x0(&mesh.positions[3 * std::size_t(c[0])]), x1(&mesh.positions[3 * std::size_t(c[1])]),
        x2(&mesh.positions[3 * std::size_t(c[2])]);
    const Eigen::Vector3f n0(&mesh.normals[3 * std::size_t(c[0])]), n1(&mesh.normals[3 * std::size_t(c[1])]),
        n2(&mesh.normals[3 * std::size_t(c[2])]);
    const Eigen::Vector3f e1 = x1 - x0, e2 = x2 - x0, target(p[0], p[1], p[2]);
    Eigen::Matrix2f gram;
    gram << e1.dot(e1), e1.dot(e2), e1.dot(e2), e2.dot(e2);
    if (!(std::abs(gram.determinant()) > 1e-20f)) return;
    const Eigen::Matrix2f inverse = gram.inverse();
    float u = b1, v = b2;
    for (int iteration = 0; iteration < 4; ++iteration) {
        const Eigen::Vector3f x = x0 + u * e1 + v * e2;
        const Eigen::Vector3f n = n0 + u * (n1 - n0) + v * (n2 - n0);
        const float nn = n.squaredNorm();
        if (!(nn > 1e-12f)) return;
        // The residual of p against the line x + t n, moved within the plane.
        const Eigen::Vector3f d = target - x;
        const Eigen::Vector3f r = d - (d.dot(n) / nn) * n;
        const Eigen::Vector2f step = inverse * Eigen::Vector2f(e1.dot(r), e2.dot(r));
        u += step[0];
        v += step[1];
    }
    constexpr float slack = 1e-4f;
    if (!(u >= -slack && v >= -slack && u + v <= 1.0f + slack)) return;
    b1 = std::clamp(u, 0.0f, 1.0f);
    b2 = std::clamp(v, 0.0f, 1.0f - b1);
}

}  // namespace

struct NormalSplatter::State {
    const TriangleMesh* target = nullptr;
    const std::vector<float>* wedgeUv = nullptr;
    int size = 0;
    std::unique_ptr<RayScene> scene;
    std::vector<float> vertexSum;         // 3 per simplified vertex: the points' normals, by barycentric weight
    std::vector<float> sum;               // 3 per texel
    std::vector<std::uint32_t> count;     // per texel
    std::atomic<std::size_t> splatted{0}, withoutNormal{0};
};

NormalSplatter::NormalSplatter(const TriangleMesh& target, const std::vector<float>& wedgeUv, int size)
    : state_(new State) {
    if (target.faceCount() == 0) throw std::invalid_argument("normal splatting: the simplified mesh has no faces");
    if (wedgeUv.size() != 6 * target.faceCount())
        throw std::invalid_argument("normal splatting: the texture coordinates do not match the faces");
    if (size < 1) throw std::invalid_argument("normal splatting: the map size must be positive");
    State& s = *state_;
    s.target = &target;
    s.wedgeUv = &wedgeUv;
    s.size = size;
    s.scene.reset(new RayScene(target.positions.data(), target.vertexCount(), target.faces.data(), target.faceCount()));
    s.vertexSum.assign(3 * target.vertexCount(), 0.0f);
    s.sum.assign(3 * std::size_t(size) * size, 0.0f);
    s.count.assign(std::size_t(size) * size, 0);
}

NormalSplatter::~NormalSplatter() = default;

void NormalSplatter::splat(const float* positions, const float* normals, std::size_t count) {
    State& s = *state_;
    const int size = s.size;
    const float* uv = s.wedgeUv->data();
    std::size_t skipped = 0;
#pragma omp parallel for schedule(dynamic, 1024) reduction(+ : skipped)
    for (std::int64_t i = 0; i < std::int64_t(count); ++i) {
        const float* n = &normals[3 * std::size_t(i)];
        const float length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!(length > 0.0f) || !std::isfinite(length)) {
            ++skipped;
            continue;
        }
        const float* p = &positions[3 * std::size_t(i)];
        const ClosestPoint nearest = s.scene->closestPoint(Eigen::Vector3f(p[0], p[1], p[2]));
        if (!nearest.found) {
            ++skipped;
            continue;
        }
        const float* w = &uv[6 * std::size_t(nearest.face)];
        float b1 = nearest.u, b2 = nearest.v;
        projectAlongNormals(*s.target, nearest.face, p, b1, b2);
        const float b0 = 1.0f - b1 - b2;
        const float u = b0 * w[0] + b1 * w[2] + b2 * w[4];
        const float v = b0 * w[1] + b1 * w[3] + b2 * w[5];
        const int column = std::clamp(int(std::floor(u * float(size))), 0, size - 1);
        const int row = std::clamp(int(std::floor((1.0f - v) * float(size))), 0, size - 1);
        const std::size_t texel = std::size_t(row) * size + column;
        for (int k = 0; k < 3; ++k) {
#pragma omp atomic
            s.sum[3 * texel + k] += n[k] / length;
        }
#pragma omp atomic
        s.count[texel] += 1;
        const std::uint32_t* corners = &s.target->faces[3 * std::size_t(nearest.face)];
        const float weights[3] = {b0, b1, b2};
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k) {
#pragma omp atomic
                s.vertexSum[3 * std::size_t(corners[c]) + k] += weights[c] * n[k] / length;
            }
    }
    s.withoutNormal += skipped;
    s.splatted += count - skipped;
}

StreamedNormalMap NormalSplatter::finish(int gutterRings) {
    State& s = *state_;
    s.scene.reset();
    StreamedNormalMap map;
    map.size = s.size;
    const std::size_t texels = std::size_t(s.size) * s.size;
    std::vector<std::int32_t> faceOfTexel;
    std::vector<float> barycentric;
    {
        TexelCoverage coverage = rasterizeTexelCoverage(s.wedgeUv->data(), s.target->faceCount(), s.size, s.size);
        faceOfTexel = std::move(coverage.face);
        barycentric = std::move(coverage.barycentric);
    }
    map.chart.resize(texels);
    for (std::size_t t = 0; t < texels; ++t) map.chart[t] = faceOfTexel[t] >= 0 ? 1 : 0;
    map.valid.assign(texels, 0);
    for (std::size_t t = 0; t < texels; ++t) {
        map.chartTexels += map.chart[t];
        if (s.count[t] == 0) continue;
        float* n = &s.sum[3 * t];
        const float length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!(length > 0.0f)) {
            n[0] = n[1] = n[2] = 0.0f;
            continue;
        }
        for (int k = 0; k < 3; ++k) n[k] /= length;
        map.valid[t] = 1;
        ++map.texelsWithPoints;
    }
    s.count = {};
    map.normals = std::move(s.sum);
    // Texels of a triangle that no point reached take the mean of their neighbours of the SAME
    // triangle, ring after ring: a hole is filled from its own chart, never from the neighbouring
    // charts of the atlas (which are other places of the surface). Only triangles no point reached
    // at all are left to the pull-push below.
    std::vector<std::uint8_t> filledValid = map.valid;
    map.chartTexelsFilled = growWithinFaces(map.normals, filledValid, faceOfTexel, s.size);
    // Triangles no point reached at all (small ones, or whose points all found a nearer triangle):
    // the scan's normals gathered at the simplified vertices, interpolated; the simplified mesh's own
    // vertex normal where no point reached a vertex either. Never another chart's values.
    for (std::size_t v = 0; v < s.target->vertexCount(); ++v) {
        float* n = &s.vertexSum[3 * v];
        float length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!(length > 0.0f) && s.target->hasNormals()) {
            for (int k = 0; k < 3; ++k) n[k] = s.target->normals[3 * v + k];
            length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        }
        if (length > 0.0f)
            for (int k = 0; k < 3; ++k) n[k] /= length;
    }
    for (std::size_t t = 0; t < texels; ++t) {
        if (filledValid[t] || faceOfTexel[t] < 0) continue;
        const std::uint32_t* corners = &s.target->faces[3 * std::size_t(faceOfTexel[t])];
        const float b1 = barycentric[2 * t], b2 = barycentric[2 * t + 1];
        const float weights[3] = {1.0f - b1 - b2, b1, b2};
        float n[3] = {0, 0, 0};
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k) n[k] += weights[c] * s.vertexSum[3 * std::size_t(corners[c]) + k];
        const float length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!(length > 0.0f)) continue;
        for (int k = 0; k < 3; ++k) map.normals[3 * t + k] = n[k] / length;
        filledValid[t] = 1;
        ++map.chartTexelsFilled;
    }
    faceOfTexel = {};
    barycentric = {};
    const BakedMapFillCounts filled = fillBakedMap(map.normals, s.size, s.size, filledValid, map.chart, gutterRings);
    map.chartTexelsFilled += filled.holes;
    normalizeTexelVectors(map.normals.data(), texels);
    map.pointsSplatted = s.splatted;
    map.pointsWithoutNormal = s.withoutNormal;
    return map;
}

}  // namespace rad
