// MikkTSpace tangents (geometry/mikktspace_tangents.h) on cases whose answer is known by hand:
// planar maps with known dP/du, mirrored UVs, the angle weighting of Mikkelsen 2008, UV seams,
// degenerate triangles. The comparison with Blender's own tangents is in
// tests/integration/mikktspace_blender.sh.
#include "geometry/mikktspace_tangents.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Mesh {
    std::vector<float> positions, normals, uv;  // uv per corner unless said otherwise
    std::vector<std::uint32_t> faces;
    rad::TangentSpaceInput input(rad::AttributeRate uvRate = rad::AttributeRate::PerCorner,
                                 rad::AttributeRate normalRate = rad::AttributeRate::PerVertex) const {
        rad::TangentSpaceInput in;
        in.positions = positions.data();
        in.vertexCount = positions.size() / 3;
        in.faces = faces.data();
        in.faceCount = faces.size() / 3;
        in.normals = normals.data();
        in.normalRate = normalRate;
        in.uv = uv.data();
        in.uvRate = uvRate;
        return in;
    }
};

void expectTangent(const rad::CornerTangents& r, std::size_t corner, double x, double y, double z, float sign,
                   double tolerance = 1e-6) {
    const float* t = r.tangents.data() + 4 * corner;
    EXPECT_NEAR(t[0], x, tolerance) << "corner " << corner;
    EXPECT_NEAR(t[1], y, tolerance) << "corner " << corner;
    EXPECT_NEAR(t[2], z, tolerance) << "corner " << corner;
    EXPECT_EQ(t[3], sign) << "corner " << corner;
}

// The rectangle [0, 2] x [0, 1] in the plane z = 0, two triangles, normal +z, with UV = map(x, y).
template <typename Map>
Mesh planarQuad(Map map) {
    Mesh m;
    m.positions = {0, 0, 0, 2, 0, 0, 2, 1, 0, 0, 1, 0};
    m.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    m.faces = {0, 1, 2, 0, 2, 3};
    for (std::uint32_t v : m.faces) {
        float u, w;
        map(m.positions[3 * v], m.positions[3 * v + 1], u, w);
        m.uv.push_back(u);
        m.uv.push_back(w);
    }
    return m;
}

TEST(MikkTSpaceTangents, PlanarQuadTangentIsTheDirectionOfIncreasingU) {
    // u = x / 2, v = y: dP/du = (2, 0, 0), so T = +x everywhere, sign +1.
    const Mesh m = planarQuad([](float x, float y, float& u, float& v) { u = x / 2; v = y; });
    const rad::CornerTangents r = rad::computeMikkTSpaceTangents(m.input());
    ASSERT_EQ(r.tangents.size(), 4u * 6);
    for (std::size_t c = 0; c < 6; ++c) expectTangent(r, c, 1, 0, 0, 1.0f);
    EXPECT_EQ(r.degenerateTriangles, 0u);
    EXPECT_EQ(r.zeroTangentCorners, 0u);
}

TEST(MikkTSpaceTangents, RotatedUvMappingGivesTheRotatedTangent) {
    // u = y, v = 1 - x / 2: increasing u runs along +y, so T = +y; B = N x T = -x is where v
    // increases, and (dP/du, dP/dv, N) is right-handed: sign +1.
    const Mesh m = planarQuad([](float x, float y, float& u, float& v) { u = y; v = 1 - x / 2; });
    const rad::CornerTangents r = rad::computeMikkTSpaceTangents(m.input());
    for (std::size_t c = 0; c < 6; ++c) expectTangent(r, c, 0, 1, 0, 1.0f);
}

TEST(MikkTSpaceTangents, MirroredUvsGiveSignMinusOneAndABitangentTowardsIncreasingV) {
    // u = 1 - x / 2 (mirrored), v = y: T = dP/du direction = -x, sign -1, so that
    // B = sign * (N x T) = -(z x -x) = +y points to increasing v.
    const Mesh m = planarQuad([](float x, float y, float& u, float& v) { u = 1 - x / 2; v = y; });
    const rad::CornerTangents r = rad::computeMikkTSpaceTangents(m.input());
    for (std::size_t c = 0; c < 6; ++c) expectTangent(r, c, -1, 0, 0, -1.0f);
}

TEST(MikkTSpaceTangents, AMirrorSeamSharedByBothHalvesSplitsTheFrameByOrientation) {
    // Left triangle: u = x; right triangle: u = 2 - x (mirrored about x = 1), v = y for both. The
    // vertices on x = 1 have the same position, normal and UV in both triangles, but the two
    // orientations never share a frame.
    Mesh m;
    m.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 2, 0, 0};
    m.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    m.faces = {0, 1, 2, 1, 3, 2};
    m.uv = {0, 0, 1, 0, 1, 1, /* right */ 1, 0, 0, 0, 1, 1};
    const rad::CornerTangents r = rad::computeMikkTSpaceTangents(m.input());
    for (std::size_t c = 0; c < 3; ++c) expectTangent(r, c, 1, 0, 0, 1.0f);
    for (std::size_t c = 3; c < 6; ++c) expectTangent(r, c, -1, 0, 0, -1.0f);
}

TEST(MikkTSpaceTangents, SharedCornerTakesTheAngleWeightedMeanOfItsTriangles) {
    // Triangle A = (C, P1, P2) with u = x, v = y: dP/du = (1, 0, 0), 90 degrees at C, 45 at P2.
    // Triangle B = (C, P2, P3), P3 = (-1, 1): its UVs (0,0), (0,1), (-1,0) make P = u (1,-1) + v (0,1),
    // dP/du = (1, -1, 0), 45 degrees at C, 90 at P2. C and P2 are shared (same UVs in both).
    Mesh m;
    m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, -1, 1, 0};
    m.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    m.faces = {0, 1, 2, 0, 2, 3};
    m.uv = {0, 0, 1, 0, 0, 1, /* B */ 0, 0, 0, 1, -1, 0};
    const rad::CornerTangents r = rad::computeMikkTSpaceTangents(m.input());
    const double s = 1 / std::sqrt(2.0);
    const auto weighted = [&](double angleA, double angleB, double out[3]) {
        const double x = angleA * 1 + angleB * s, y = angleB * -s, n = std::hypot(x, y);
        out[0] = x / n;
        out[1] = y / n;
        out[2] = 0;
    };
    double atC[3], atP2[3];
    weighted(kPi / 2, kPi / 4, atC);
    weighted(kPi / 4, kPi / 2, atP2);
    expectTangent(r, 0, atC[0], atC[1], atC[2], 1.0f, 1e-6);  // C in A
    expectTangent(r, 3, atC[0], atC[1], atC[2], 1.0f, 1e-6);  // C in B
    expectTangent(r, 2, atP2[0], atP2[1], atP2[2], 1.0f, 1e-6);  // P2 in A
    expectTangent(r, 4, atP2[0], atP2[1], atP2[2], 1.0f, 1e-6);  // P2 in B
    expectTangent(r, 1, 1, 0, 0, 1.0f);                        // P1: A alone
    expectTangent(r, 5, s, -s, 0, 1.0f);                       // P3: B alone
}

// A cylinder of radius 1 around z, `segments` around, u = angle / 2 pi, v = z; the seam at angle 0
// has u = 0 on one side and u = 1 on the other (separate corners).
Mesh cylinder(int segments, rad::AttributeRate& uvRate, bool perVertexUv) {
    Mesh m;
    const int columns = segments + 1;  // the seam column duplicated
    for (int j = 0; j <= 1; ++j)
        for (int i = 0; i < columns; ++i) {
            const double a = 2 * kPi * (i % segments) / segments;
            m.positions.insert(m.positions.end(), {float(std::cos(a)), float(std::sin(a)), float(j)});
            m.normals.insert(m.normals.end(), {float(std::cos(a)), float(std::sin(a)), 0.0f});
        }
    const auto vertex = [&](int i, int j) { return std::uint32_t(j * columns + i); };
    for (int i = 0; i < segments; ++i) {
        m.faces.insert(m.faces.end(), {vertex(i, 0), vertex(i + 1, 0), vertex(i + 1, 1)});
        m.faces.insert(m.faces.end(), {vertex(i, 0), vertex(i + 1, 1), vertex(i, 1)});
    }
    std::vector<float> vertexUv;
    for (int j = 0; j <= 1; ++j)
        for (int i = 0; i < columns; ++i) vertexUv.insert(vertexUv.end(), {float(i) / segments, float(j)});
    if (perVertexUv) {
        m.uv = vertexUv;
        uvRate = rad::AttributeRate::PerVertex;
    } else {
        for (std::uint32_t v : m.faces) m.uv.insert(m.uv.end(), {vertexUv[2 * v], vertexUv[2 * v + 1]});
        uvRate = rad::AttributeRate::PerCorner;
    }
    return m;
}

TEST(MikkTSpaceTangents, CylinderTangentsFollowTheCircleOnBothSidesOfTheSeam) {
    // By symmetry the angle-weighted mean of the two (or three) triangles around a vertex is the
    // direction of the circle, (-sin a, cos a, 0), also at the seam's two copies of a vertex.
    const int segments = 16;
    rad::AttributeRate uvRate;
    const Mesh m = cylinder(segments, uvRate, false);
    const rad::CornerTangents r = rad::computeMikkTSpaceTangents(m.input(uvRate));
    for (std::size_t c = 0; c < m.faces.size(); ++c) {
        const float* p = m.positions.data() + 3 * m.faces[c];
        const double a = std::atan2(p[1], p[0]);
        expectTangent(r, c, -std::sin(a), std::cos(a), 0, 1.0f, 2e-6);
    }
}

TEST(MikkTSpaceTangents, PerVertexUvsGiveTheSameFramesAsTheSameCoordinatesPerCorner) {
    rad::AttributeRate vertexRate, cornerRate;
    const Mesh perVertex = cylinder(12, vertexRate, true), perCorner = cylinder(12, cornerRate, false);
    ASSERT_EQ(vertexRate, rad::AttributeRate::PerVertex);
    const rad::CornerTangents a = rad::computeMikkTSpaceTangents(perVertex.input(vertexRate));
    const rad::CornerTangents b = rad::computeMikkTSpaceTangents(perCorner.input(cornerRate));
    EXPECT_EQ(a.tangents, b.tangents);
}

TEST(MikkTSpaceTangents, PerCornerNormalsAreUsedWhereGiven) {
    // The planar quad with u = x / 2, v = y, but face 0's corners carry the normal
    // (1, 0, 1) / sqrt 2: their tangent is dP/du = +x projected on that normal's plane,
    // (1, 0, -1) / sqrt 2; face 1 keeps +z and +x. Different normals: no corner is shared.
    Mesh m = planarQuad([](float x, float y, float& u, float& v) { u = x / 2; v = y; });
    const float h = float(1 / std::sqrt(2.0));
    m.normals = {h, 0, h, h, 0, h, h, 0, h, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    const rad::CornerTangents r = rad::computeMikkTSpaceTangents(
        m.input(rad::AttributeRate::PerCorner, rad::AttributeRate::PerCorner));
    for (std::size_t c = 0; c < 3; ++c) expectTangent(r, c, h, 0, -h, 1.0f);
    for (std::size_t c = 3; c < 6; ++c) expectTangent(r, c, 1, 0, 0, 1.0f);
}

TEST(MikkTSpaceTangents, TheSignFollowsTheUvWindingNotTheNormal) {
    // Same UVs, normals flipped to -z: the UV triangle still winds counter-clockwise, so the
    // sign stays +1 and T stays +x (already orthogonal to the normal).
    Mesh m = planarQuad([](float x, float y, float& u, float& v) { u = x / 2; v = y; });
    for (std::size_t i = 2; i < m.normals.size(); i += 3) m.normals[i] = -1;
    const rad::CornerTangents r = rad::computeMikkTSpaceTangents(m.input());
    for (std::size_t c = 0; c < 6; ++c) expectTangent(r, c, 1, 0, 0, 1.0f);
}

TEST(MikkTSpaceTangents, ZeroUvAreaTriangleJoinsItsNeighboursFrame) {
    // Face 1 of the quad gets collinear UVs (vertex 3 given vertex 0's UV): no derivative. It
    // contributes nothing; its corners shared with face 0 (same position, normal, UV) take face
    // 0's frame, and the corner only it has is reached by no group: Blender's default frame
    // T = (1, 0, 0), sign -1, which completeTangents replaces by a unit tangent orthogonal to the
    // normal with sign +1.
    Mesh m = planarQuad([](float x, float y, float& u, float& v) { u = x / 2; v = y; });
    m.uv[2 * 5] = m.uv[2 * 3];
    m.uv[2 * 5 + 1] = m.uv[2 * 3 + 1];
    // Tilt vertex 3's normal so that the default (1, 0, 0) is not orthogonal to it.
    const float h = float(1 / std::sqrt(2.0));
    m.normals[9] = h;
    m.normals[11] = h;
    const rad::TangentSpaceInput in = m.input();
    rad::CornerTangents r = rad::computeMikkTSpaceTangents(in);
    EXPECT_EQ(r.zeroUvAreaTriangles, 1u);
    expectTangent(r, 3, 1, 0, 0, 1.0f);  // vertex 0, shared with face 0
    expectTangent(r, 4, 1, 0, 0, 1.0f);  // vertex 2, shared with face 0
    expectTangent(r, 5, 1, 0, 0, -1.0f);  // vertex 3: the default frame
    EXPECT_EQ(r.reached[5], 0);
    EXPECT_EQ(r.defaultFrameCorners, 1u);
    EXPECT_EQ(rad::completeTangents(r, in), 1u);
    const float* lone = r.tangents.data() + 4 * 5;
    EXPECT_NEAR(std::hypot(lone[0], lone[1], lone[2]), 1.0, 1e-6);
    EXPECT_NEAR(lone[0] * h + lone[2] * h, 0.0, 1e-6);  // orthogonal to vertex 3's normal
    EXPECT_EQ(lone[3], 1.0f);
    EXPECT_EQ(r.defaultFrameCorners, 0u);
    expectTangent(r, 0, 1, 0, 0, 1.0f);  // good corners untouched
    expectTangent(r, 3, 1, 0, 0, 1.0f);
}

TEST(MikkTSpaceTangents, DegenerateTriangleCornersTakeTheFrameOfTheirVertex) {
    // Face 2 has two corners at vertex 1's position (a sliver of zero area): its corners copy the
    // frames of the good corners with the same position, normal and UV.
    Mesh m = planarQuad([](float x, float y, float& u, float& v) { u = x / 2; v = y; });
    m.faces.insert(m.faces.end(), {1, 1, 2});
    m.uv.insert(m.uv.end(), {1, 0, 1, 0, 1, 1});
    const rad::CornerTangents r = rad::computeMikkTSpaceTangents(m.input());
    EXPECT_EQ(r.degenerateTriangles, 1u);
    for (std::size_t c = 6; c < 9; ++c) expectTangent(r, c, 1, 0, 0, 1.0f);
}

TEST(MikkTSpaceTangents, AnIndexOutOfRangeIsRefusedWithTheFaceNamed) {
    Mesh m = planarQuad([](float x, float y, float& u, float& v) { u = x; v = y; });
    m.faces[4] = 7;
    try {
        rad::computeMikkTSpaceTangents(m.input());
        FAIL() << "an index out of range was accepted";
    } catch (const rad::TangentSpaceInputError& e) {
        EXPECT_NE(std::string(e.what()).find("Face 1"), std::string::npos) << e.what();
    }
    Mesh noUv = planarQuad([](float x, float y, float& u, float& v) { u = x; v = y; });
    rad::TangentSpaceInput in = noUv.input();
    in.uv = nullptr;
    EXPECT_THROW(rad::computeMikkTSpaceTangents(in), rad::TangentSpaceInputError);
}

}  // namespace
