// Tests of lod/pop_level.h: a level of a POP buffer (Limper et al. 2013) evaluated on the CPU, with
// and without the texture-coordinate correction of Weber & Stamminger (Alg. 1). Oracles: a planar
// mesh whose texture coordinates are a linear map of the position, defined here (the corrected
// coordinates of a snapped vertex are that map at the snapped position, exactly); grid positions
// and degenerate triangles recomputed here from the bounding box with floor().
#include "lod/pop_level.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using rad::TriangleMesh;

// uv = (0.6 x + 0.2 y + 0.1, -0.1 x + 0.5 y + 0.3) on the plane z = 0.25.
double mapU(double x, double y) { return 0.6 * x + 0.2 * y + 0.1; }
double mapV(double x, double y) { return -0.1 * x + 0.5 * y + 0.3; }

// A jittered 24 x 24 grid over [0, 1]^2 at z = 0.25 with wedge coordinates from the map.
void texturedPlane(TriangleMesh& m, std::vector<float>& uv) {
    const int n = 24;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> jitter(-0.35f, 0.35f);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const bool border = i == 0 || j == 0 || i == n - 1 || j == n - 1;
            m.positions.push_back((i + (border ? 0 : jitter(rng))) / (n - 1));
            m.positions.push_back((j + (border ? 0 : jitter(rng))) / (n - 1));
            m.positions.push_back(0.25f);
        }
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            const std::uint32_t v00 = j * n + i, v10 = v00 + 1, v01 = v00 + n, v11 = v01 + 1;
            for (std::uint32_t v : {v00, v10, v11, v00, v11, v01}) m.faces.push_back(v);
        }
    for (std::uint32_t v : m.faces) {
        uv.push_back(float(mapU(m.positions[3 * v], m.positions[3 * v + 1])));
        uv.push_back(float(mapV(m.positions[3 * v], m.positions[3 * v + 1])));
    }
}

TEST(PopLevel, CorrectedCoordinatesAreTheMapAtTheSnappedPosition) {
    TriangleMesh m;
    std::vector<float> uv;
    texturedPlane(m, uv);
    const rad::PopBuffer pop = rad::buildPopBuffer(m);
    const rad::TexCoordDerivatives d = rad::computeTexCoordDerivatives(m, uv);
    for (int level : {3, 4, 5, 8}) {
        rad::PopLevelRequest request;
        request.mesh = &m;
        request.pop = &pop;
        request.level = level;
        request.wedgeUv = &uv;
        request.correction = &d;
        const rad::PopLevelMesh corrected = rad::evaluatePopLevel(request);
        request.correction = nullptr;
        const rad::PopLevelMesh plain = rad::evaluatePopLevel(request);
        ASSERT_GT(corrected.mesh.faceCount(), 0u);
        ASSERT_EQ(plain.mesh.faces, corrected.mesh.faces);
        double plainError = 0;
        for (std::size_t c = 0; c < corrected.mesh.faces.size(); ++c) {
            const std::uint32_t v = corrected.mesh.faces[c];
            const double x = corrected.mesh.positions[3 * v], y = corrected.mesh.positions[3 * v + 1];
            EXPECT_EQ(corrected.mesh.positions[3 * v + 2], 0.25f);  // the flat axis is not snapped
            ASSERT_NEAR(corrected.wedgeUv[2 * c], mapU(x, y), 1e-5) << "level " << level << " corner " << c;
            ASSERT_NEAR(corrected.wedgeUv[2 * c + 1], mapV(x, y), 1e-5) << "level " << level << " corner " << c;
            // Without correction the coordinates are the input's, i.e. the map at the original place.
            const std::uint32_t s = plain.sourceVertex[v];
            EXPECT_NEAR(plain.wedgeUv[2 * c], mapU(m.positions[3 * s], m.positions[3 * s + 1]), 1e-6);
            plainError = std::max(plainError, std::fabs(plain.wedgeUv[2 * c] - mapU(x, y)));
        }
        EXPECT_GT(plainError, 1e-3) << "level " << level << ": the snapping should have moved the texture";
    }
}

TEST(PopLevel, VerticesLieOnTheGridAndFacesAreTheNonDegenerateOnes) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> coord(-2.0f, 3.0f), step(-0.2f, 0.2f);
    TriangleMesh m;
    for (int t = 0; t < 2000; ++t) {
        const float x = coord(rng), y = coord(rng), z = coord(rng);
        const auto base = std::uint32_t(m.vertexCount());
        m.positions.insert(m.positions.end(), {x, y, z, x + step(rng), y + step(rng), z, x, y + step(rng), z + step(rng)});
        m.faces.insert(m.faces.end(), {base, base + 1, base + 2});
    }
    std::array<double, 3> lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        lo[i % 3] = std::min(lo[i % 3], double(m.positions[i]));
        hi[i % 3] = std::max(hi[i % 3], double(m.positions[i]));
    }
    const rad::PopBuffer pop = rad::buildPopBuffer(m);
    for (int level : {2, 5, 7, 10}) {
        rad::PopLevelRequest request;
        request.mesh = &m;
        request.pop = &pop;
        request.level = level;
        const rad::PopLevelMesh out = rad::evaluatePopLevel(request);
        const double cells = std::ldexp(1.0, level);
        const auto cellOf = [&](std::uint32_t v, int k) {
            const double t = (double(m.positions[3 * v + k]) - lo[k]) / (hi[k] - lo[k]);
            return std::min(long(std::floor(t * cells)), long(cells) - 1);
        };
        std::set<std::uint32_t> expectedFaces;
        for (std::uint32_t f = 0; f < m.faceCount(); ++f) {
            std::array<std::array<long, 3>, 3> c;
            for (int j = 0; j < 3; ++j)
                for (int k = 0; k < 3; ++k) c[j][k] = cellOf(m.faces[3 * f + j], k);
            if (c[0] != c[1] && c[1] != c[2] && c[0] != c[2]) expectedFaces.insert(f);
        }
        EXPECT_EQ(std::set<std::uint32_t>(out.sourceFace.begin(), out.sourceFace.end()), expectedFaces);
        EXPECT_EQ(out.mesh.faceCount(), expectedFaces.size());
        std::size_t moved = 0;
        for (std::size_t v = 0; v < out.mesh.vertexCount(); ++v) {
            const std::uint32_t s = out.sourceVertex[v];
            bool differs = false;
            for (int k = 0; k < 3; ++k) {
                const double cell = (hi[k] - lo[k]) / cells;
                const double expected = lo[k] + (cellOf(s, k) + 0.5) * cell;
                ASSERT_NEAR(out.mesh.positions[3 * v + k], expected, 2e-6) << "level " << level;
                differs |= out.mesh.positions[3 * v + k] != m.positions[3 * s + k];
            }
            moved += differs;
        }
        EXPECT_EQ(out.movedVertices, moved);
        // Faces refer to the copied vertices of the same input face.
        for (std::size_t f = 0; f < out.mesh.faceCount(); ++f)
            for (int k = 0; k < 3; ++k)
                EXPECT_EQ(out.sourceVertex[out.mesh.faces[3 * f + k]], m.faces[3 * out.sourceFace[f] + k]);
    }
}

void expectRefusal(const rad::PopLevelRequest& r, const std::string& words) {
    try {
        rad::evaluatePopLevel(r);
        ADD_FAILURE() << "accepted a request that should be refused (" << words << ")";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
}

TEST(PopLevel, RefusesBadRequests) {
    TriangleMesh m;
    std::vector<float> uv;
    texturedPlane(m, uv);
    const rad::PopBuffer pop = rad::buildPopBuffer(m);
    const rad::TexCoordDerivatives d = rad::computeTexCoordDerivatives(m, uv);
    rad::PopLevelRequest r;
    r.mesh = &m;
    r.pop = &pop;
    r.level = 0;
    expectRefusal(r, "levels are 1 to 16");
    r.level = 17;
    expectRefusal(r, "levels are 1 to 16");
    r.level = 4;
    r.correction = &d;
    expectRefusal(r, "needs texture coordinates");
    r.wedgeUv = &uv;
    TriangleMesh other = m;
    other.faces.resize(other.faces.size() - 3);
    r.mesh = &other;
    expectRefusal(r, "built from another mesh");
    r.mesh = &m;
    std::vector<float> shortUv(uv.begin(), uv.end() - 6);
    r.wedgeUv = &shortUv;
    expectRefusal(r, "6 per face");
}

}  // namespace
