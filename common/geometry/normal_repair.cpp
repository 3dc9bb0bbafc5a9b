#include "geometry/normal_repair.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace rad {

namespace {

// Normalises (x, y, z) into out; false when it has no direction (zero or not finite).
bool unitOf(double x, double y, double z, float* out) {
    const double length = std::sqrt(x * x + y * y + z * z);
    if (!(length > 0.0) || !std::isfinite(length)) return false;
    out[0] = static_cast<float>(x / length);
    out[1] = static_cast<float>(y / length);
    out[2] = static_cast<float>(z / length);
    return true;
}

}  // namespace

std::string NormalRepairCounts::describe() const {
    if (repaired() == 0) return {};
    std::ostringstream out;
    out << repaired() << " vertex normal" << (repaired() == 1 ? "" : "s") << " repaired (";
    const char* separator = "";
    if (fromFaces > 0) {
        out << fromFaces << " from their faces";
        separator = ", ";
    }
    if (fromNeighbours > 0) {
        out << separator << fromNeighbours << " from their neighbours";
        separator = ", ";
    }
    if (defaulted > 0) out << separator << defaulted << " isolated, given +Z";
    out << ")";
    return out.str();
}

NormalRepairCounts repairVertexNormals(const std::vector<float>& positions, const std::vector<std::uint32_t>& faces,
                                       std::vector<float>& normals) {
    const std::size_t n = positions.size() / 3;
    if (normals.size() != 3 * n) normals.assign(3 * n, 0.0f);
    NormalRepairCounts counts;
    std::vector<std::uint8_t> known(n, 0);
    for (std::size_t v = 0; v < n; ++v) {
        float* q = &normals[3 * v];
        if (unitOf(q[0], q[1], q[2], q)) {
            known[v] = 1;
            ++counts.kept;
        }
    }
    if (counts.kept == n) return counts;

    // Step 2: angle-weighted face normals of the vertices still unknown.
    std::vector<double> sum(3 * n, 0.0);
    const std::size_t faceCount = faces.size() / 3;
    for (std::size_t f = 0; f < faceCount; ++f) {
        const std::uint32_t* t = &faces[3 * f];
        if (known[t[0]] && known[t[1]] && known[t[2]]) continue;
        double p[3][3];
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 3; ++c) p[k][c] = positions[3 * std::size_t(t[k]) + c];
        const double e1[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
        const double e2[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
        double nf[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        const double length = std::sqrt(nf[0] * nf[0] + nf[1] * nf[1] + nf[2] * nf[2]);
        if (!(length > 0.0) || !std::isfinite(length)) continue;
        for (double& x : nf) x /= length;
        for (int k = 0; k < 3; ++k) {
            if (known[t[k]]) continue;
            const double* a = p[k];
            const double* b = p[(k + 1) % 3];
            const double* c = p[(k + 2) % 3];
            const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
            const double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
            const double cross[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
            const double angle = std::atan2(std::sqrt(cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]),
                                            u[0] * w[0] + u[1] * w[1] + u[2] * w[2]);
            for (int c3 = 0; c3 < 3; ++c3) sum[3 * std::size_t(t[k]) + c3] += angle * nf[c3];
        }
    }
    std::vector<std::uint32_t> unknown;
    for (std::size_t v = 0; v < n; ++v) {
        if (known[v]) continue;
        if (unitOf(sum[3 * v], sum[3 * v + 1], sum[3 * v + 2], &normals[3 * v])) {
            known[v] = 1;
            ++counts.fromFaces;
        } else {
            unknown.push_back(static_cast<std::uint32_t>(v));
        }
    }

    // Step 3: ring by ring from the neighbours over the face edges.
    if (!unknown.empty() && faceCount > 0) {
        std::vector<std::size_t> offsets(n + 1, 0);
        for (std::size_t i = 0; i < 3 * faceCount; ++i) offsets[faces[i] + 1] += 2;
        for (std::size_t v = 0; v < n; ++v) offsets[v + 1] += offsets[v];
        std::vector<std::uint32_t> neighbours(offsets[n]);
        std::vector<std::size_t> fill(offsets.begin(), offsets.end() - 1);
        for (std::size_t f = 0; f < faceCount; ++f)
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t a = faces[3 * f + k], b = faces[3 * f + (k + 1) % 3];
                neighbours[fill[a]++] = b;
                neighbours[fill[b]++] = a;
            }
        std::vector<float> found;
        std::vector<std::uint32_t> stillUnknown, settled;
        while (!unknown.empty()) {
            settled.clear();
            stillUnknown.clear();
            found.clear();
            for (std::uint32_t v : unknown) {
                double s[3] = {0.0, 0.0, 0.0};
                bool any = false;
                for (std::size_t e = offsets[v]; e < offsets[v + 1]; ++e) {
                    const std::uint32_t u = neighbours[e];
                    if (!known[u]) continue;
                    any = true;
                    for (int c = 0; c < 3; ++c) s[c] += normals[3 * std::size_t(u) + c];
                }
                float q[3];
                if (any && unitOf(s[0], s[1], s[2], q)) {
                    settled.push_back(v);
                    found.insert(found.end(), q, q + 3);
                } else {
                    stillUnknown.push_back(v);
                }
            }
            if (settled.empty()) break;
            for (std::size_t i = 0; i < settled.size(); ++i) {
                std::copy(&found[3 * i], &found[3 * i] + 3, &normals[3 * std::size_t(settled[i])]);
                known[settled[i]] = 1;
            }
            counts.fromNeighbours += settled.size();
            unknown.swap(stillUnknown);
        }
    }

    // Step 4.
    for (std::uint32_t v : unknown) {
        normals[3 * std::size_t(v)] = 0.0f;
        normals[3 * std::size_t(v) + 1] = 0.0f;
        normals[3 * std::size_t(v) + 2] = 1.0f;
        ++counts.defaulted;
    }
    return counts;
}

}  // namespace rad
