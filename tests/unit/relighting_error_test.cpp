// Tests of prt/relighting_error.h (Křivánek et al. 2004 eq. 1 measured at sample points). References are built
// independently here: areas and barycentrics from cross products, subdivisions split by hand (with
// originFace), transfer fields given in closed form (an affine field is interpolated exactly by
// any subdivision), the Weber-normalised error and the weighted 95th percentile written out from
// their definitions (a brute-force sort), and small examples computed by hand.
#include "prt/relighting_error.h"

#include "prt/prt_lighting.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

namespace {

using Vec3 = Eigen::Vector3d;

// Rec. 709 luminance weights, written out again.
constexpr double kRed = 0.2126, kGreen = 0.7152, kBlue = 0.0722;

using Field = std::function<std::vector<double>(const Vec3& position)>;

Vec3 at(const std::vector<float>& data, std::size_t i) { return {data[3 * i], data[3 * i + 1], data[3 * i + 2]}; }

// An oracle evaluating a closed-form field at the given positions (normals ignored).
rad::TransferOracle oracleOf(const Field& field, int width, int* calls = nullptr) {
    return [field, width, calls](const float* positions, const float*, std::size_t count, float* out) {
        if (calls) ++*calls;
        for (std::size_t i = 0; i < count; ++i) {
            const std::vector<double> t = field(Vec3(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]));
            for (int j = 0; j < width; ++j) out[i * width + j] = static_cast<float>(t[j]);
        }
    };
}

// width 4: affine in position, different per component.
std::vector<double> affineField(const Vec3& x) {
    return {0.5 + x.x() - 2 * x.y() + 0.25 * x.z(), 1.0 - 0.3 * x.x() + 0.7 * x.z(), 2.0 * x.y() + x.z(), 0.1};
}
// width 4: smooth but not affine.
std::vector<double> curvedField(const Vec3& x) {
    return {1.0 + std::sin(3 * x.x()) * std::cos(2 * x.y()), 1.5 + x.x() * x.x() - x.y() * x.z(), std::exp(0.5 * x.y()),
            1.0 + 0.2 * x.z() * x.z()};
}

// Two non-coplanar triangles sharing an edge (a bent quad), plus a small third one elsewhere, with
// vertex normals that differ per vertex.
rad::PrtMesh bentMesh(const Field& field, int width) {
    rad::PrtMesh m;
    m.positions = {0, 0, 0, 2, 0, 0, 0, 1.5f, 0, 1.8f, 1.7f, 0.9f, 3, 3, 3, 3.4f, 3, 3.1f, 3, 3.5f, 2.8f};
    m.faces = {0, 1, 2, 1, 3, 2, 4, 5, 6};
    const std::size_t n = m.vertexCount();
    for (std::size_t v = 0; v < n; ++v) {
        const Vec3 normal = Vec3(0.1 * v, -0.2 + 0.05 * v, 1.0).normalized();
        m.normals.insert(m.normals.end(), {float(normal.x()), float(normal.y()), float(normal.z())});
    }
    m.width = width;
    for (std::size_t v = 0; v < n; ++v) {
        const std::vector<double> t = field(at(m.positions, v));
        for (int j = 0; j < width; ++j) m.transfer.push_back(static_cast<float>(t[j]));
    }
    return m;
}

double faceArea(const rad::PrtMesh& m, std::size_t f) {
    const Vec3 a = at(m.positions, m.faces[3 * f]), b = at(m.positions, m.faces[3 * f + 1]), c = at(m.positions, m.faces[3 * f + 2]);
    return 0.5 * (b - a).cross(c - a).norm();
}

// Barycentrics of x in triangle abc from sub-triangle areas (x projected on the plane).
Vec3 barycentricsOf(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 normal = (b - a).cross(c - a);
    const double twiceArea = normal.squaredNorm();
    return {(c - b).cross(x - b).dot(normal) / twiceArea, (a - c).cross(x - c).dot(normal) / twiceArea,
            (b - a).cross(x - a).dot(normal) / twiceArea};
}

// The input itself as a "subdivision" (every face its own origin).
rad::SubdivisionResult unsplit(const rad::PrtMesh& input) {
    rad::SubdivisionResult r;
    r.mesh = input;
    r.originFace.resize(input.faceCount());
    std::iota(r.originFace.begin(), r.originFace.end(), 0u);
    return r;
}

// Appends a vertex at p with the field's transfer (as the subdivision's oracle would).
std::uint32_t addVertex(rad::PrtMesh& m, const Vec3& p, const Field& field) {
    m.positions.insert(m.positions.end(), {float(p.x()), float(p.y()), float(p.z())});
    m.normals.insert(m.normals.end(), {0.0f, 0.0f, 1.0f});
    const std::vector<double> t = field(p);
    for (int j = 0; j < m.width; ++j) m.transfer.push_back(static_cast<float>(t[j]));
    return static_cast<std::uint32_t>(m.vertexCount() - 1);
}

// Splits the faces for which `split(face)` holds 1-to-4 at edge midpoints (Fig. 3a), by hand; the
// other faces are copied. Midpoints are exact averages of the float corners.
rad::SubdivisionResult splitByHand(const rad::SubdivisionResult& in, const Field& field,
                                   const std::function<bool(std::size_t)>& split = [](std::size_t) { return true; },
                                   const std::function<bool(std::size_t, int)>& keepChild = [](std::size_t, int) { return true; }) {
    rad::SubdivisionResult out;
    out.mesh.width = in.mesh.width;
    for (std::size_t f = 0; f < in.mesh.faceCount(); ++f) {
        Vec3 p[3];
        for (int k = 0; k < 3; ++k) p[k] = at(in.mesh.positions, in.mesh.faces[3 * f + k]);
        std::uint32_t v[3];
        for (int k = 0; k < 3; ++k) v[k] = addVertex(out.mesh, p[k], field);
        if (!split(f)) {
            out.mesh.faces.insert(out.mesh.faces.end(), {v[0], v[1], v[2]});
            out.originFace.push_back(in.originFace[f]);
            continue;
        }
        std::uint32_t mid[3];  // mid[k] on edge (k, k+1)
        for (int k = 0; k < 3; ++k) mid[k] = addVertex(out.mesh, 0.5 * (p[k] + p[(k + 1) % 3]), field);
        const std::uint32_t children[4][3] = {{v[0], mid[0], mid[2]}, {mid[0], v[1], mid[1]}, {mid[2], mid[1], v[2]}, {mid[0], mid[1], mid[2]}};
        for (int c = 0; c < 4; ++c) {
            if (!keepChild(f, c)) continue;
            out.mesh.faces.insert(out.mesh.faces.end(), {children[c][0], children[c][1], children[c][2]});
            out.originFace.push_back(in.originFace[f]);
        }
    }
    return out;
}

// Splits face f into two at the midpoint of its edge (0, 1) (a Fig. 3b T-vertex fix).
rad::SubdivisionResult bisectByHand(const rad::SubdivisionResult& in, const Field& field, std::size_t face) {
    rad::SubdivisionResult out = in;
    const std::uint32_t a = in.mesh.faces[3 * face], b = in.mesh.faces[3 * face + 1], c = in.mesh.faces[3 * face + 2];
    const std::uint32_t m = addVertex(out.mesh, 0.5 * (at(in.mesh.positions, a) + at(in.mesh.positions, b)), field);
    out.mesh.faces[3 * face + 1] = m;  // (a, m, c)
    out.mesh.faces.insert(out.mesh.faces.end(), {m, b, c});
    out.originFace.push_back(in.originFace[face]);
    return out;
}

double maxAbsDifference(const std::vector<float>& a, const std::vector<float>& b) {
    double d = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, std::fabs(double(a[i]) - b[i]));
    return d;
}

// Samples given directly (for the error statistics): degree-0 transfer, one float per sample.
rad::RelightingSamples scalarSamples(const std::vector<float>& weights, const std::vector<float>& truth) {
    rad::RelightingSamples s;
    s.width = 1;
    s.inputFace.assign(weights.size(), 0);
    s.positions.assign(3 * weights.size(), 0.0f);
    s.normals.assign(3 * weights.size(), 0.0f);
    s.weights = weights;
    s.groundTruth = truth;
    return s;
}

// Weighted 95th percentile from its definition: the smallest e whose cumulative weight (errors
// <= e) reaches 0.95 of the total.
double bruteP95(std::vector<std::pair<double, double>> errorWeight) {
    std::sort(errorWeight.begin(), errorWeight.end());
    double total = 0.0;
    for (const auto& p : errorWeight) total += p.second;
    double cumulative = 0.0;
    for (const auto& p : errorWeight) {
        cumulative += p.second;
        if (cumulative >= 0.95 * total * (1 - 1e-12)) return p.first;
    }
    return errorWeight.back().first;
}

// The error of relighting_error.h from its definition, for every (sample, lighting):
// luminances through <t, l> per channel then Rec. 709.
std::vector<std::vector<double>> bruteErrors(const rad::RelightingSamples& s, const std::vector<float>& interpolated,
                                             int degree, int channels, const std::vector<std::vector<double>>& lightings,
                                             int lightingDegree) {
    const int K = (degree + 1) * (degree + 1), LK = (lightingDegree + 1) * (lightingDegree + 1), width = channels * K;
    const double rec709[3] = {kRed, kGreen, kBlue};
    std::vector<std::vector<double>> errors;
    for (const auto& l : lightings) {
        std::vector<double> Y(s.count()), Yint(s.count());
        for (std::size_t i = 0; i < s.count(); ++i)
            for (int ch = 0; ch < 3; ++ch) {
                const int c = channels == 1 ? 0 : ch;
                double a = 0.0, b = 0.0;
                for (int k = 0; k < K; ++k) {
                    a += double(s.groundTruth[i * width + c * K + k]) * l[ch * LK + k];
                    b += double(interpolated[i * width + c * K + k]) * l[ch * LK + k];
                }
                Y[i] += rec709[ch] * a;
                Yint[i] += rec709[ch] * b;
            }
        double mean = 0.0, total = 0.0;
        for (std::size_t i = 0; i < s.count(); ++i) mean += s.weights[i] * Y[i], total += s.weights[i];
        const double floor = 0.01 * mean / total;
        std::vector<double> e(s.count());
        for (std::size_t i = 0; i < s.count(); ++i) e[i] = std::fabs(Y[i] - Yint[i]) / std::max(Y[i], floor);
        errors.push_back(e);
    }
    return errors;
}

}  // namespace

// ---------------------------------------------------------------- samples

TEST(RelightingSamples, TotalWeightIsTheMeshAreaAndEachFaceGetsItsShare) {
    const rad::PrtMesh mesh = bentMesh(affineField, 4);
    const rad::RelightingSamples s = rad::makeRelightingSamples(mesh, 5000, oracleOf(affineField, 4));
    double meshArea = 0.0;
    for (std::size_t f = 0; f < mesh.faceCount(); ++f) meshArea += faceArea(mesh, f);
    double total = 0.0;
    std::vector<double> faceWeight(mesh.faceCount(), 0.0);
    std::vector<std::size_t> faceCount(mesh.faceCount(), 0);
    for (std::size_t i = 0; i < s.count(); ++i) {
        total += s.weights[i];
        faceWeight[s.inputFace[i]] += s.weights[i];
        ++faceCount[s.inputFace[i]];
    }
    EXPECT_NEAR(total, meshArea, 1e-5 * meshArea);
    for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
        EXPECT_NEAR(faceWeight[f], faceArea(mesh, f), 1e-5 * faceArea(mesh, f));
        EXPECT_NEAR(double(faceCount[f]), 5000.0 * faceArea(mesh, f) / meshArea, 1.0) << "face " << f;
    }
    EXPECT_NEAR(double(s.count()), 5000.0, 2.0);
    EXPECT_EQ(s.width, 4);
    EXPECT_EQ(s.groundTruth.size(), s.count() * 4);
}

TEST(RelightingSamples, CountProportionalToAreaWithAtLeastOnePerFace) {
    rad::PrtMesh m;
    // Areas 1, 3 and 1e-6.
    m.positions = {0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 1, 3, 0, 1, 0, 2, 1, 5, 5, 5, 5.001f, 5, 5, 5, 5.002f, 5};
    m.faces = {0, 1, 2, 3, 4, 5, 6, 7, 8};
    m.normals.assign(m.positions.size(), 0.0f);
    for (std::size_t v = 0; v < m.vertexCount(); ++v) m.normals[3 * v + 2] = 1.0f;
    m.width = 4;
    const rad::RelightingSamples s = rad::makeRelightingSamples(m, 4000, oracleOf(affineField, 4));
    std::vector<std::size_t> count(3, 0);
    for (std::uint32_t f : s.inputFace) ++count[f];
    EXPECT_NEAR(double(count[0]), 1000.0, 1.0);
    EXPECT_NEAR(double(count[1]), 3000.0, 1.0);
    EXPECT_EQ(count[2], 1u);  // far below one sample's share, still sampled
}

TEST(RelightingSamples, EverySampleLiesInsideItsFaceWithInterpolatedUnitNormal) {
    const rad::PrtMesh mesh = bentMesh(affineField, 4);
    const rad::RelightingSamples s = rad::makeRelightingSamples(mesh, 3000, oracleOf(affineField, 4), 9);
    for (std::size_t i = 0; i < s.count(); ++i) {
        const std::uint32_t* v = mesh.faces.data() + 3 * s.inputFace[i];
        const Vec3 a = at(mesh.positions, v[0]), b = at(mesh.positions, v[1]), c = at(mesh.positions, v[2]);
        const Vec3 x = at(s.positions, i);
        const Vec3 bary = barycentricsOf(x, a, b, c);
        EXPECT_GE(bary.minCoeff(), -1e-6) << "sample " << i;
        EXPECT_NEAR(bary.sum(), 1.0, 1e-9);
        const Vec3 planeNormal = (b - a).cross(c - a).normalized();
        EXPECT_NEAR((x - a).dot(planeNormal), 0.0, 1e-6) << "sample " << i;
        const Vec3 expectedNormal =
            (bary[0] * at(mesh.normals, v[0]) + bary[1] * at(mesh.normals, v[1]) + bary[2] * at(mesh.normals, v[2])).normalized();
        const Vec3 normal = at(s.normals, i);
        EXPECT_NEAR(normal.norm(), 1.0, 1e-6);
        EXPECT_GT(normal.dot(expectedNormal), 1.0 - 1e-6) << "sample " << i;
    }
}

TEST(RelightingSamples, StratifiedUniformOverTheFace) {
    // One triangle, 10^4 samples: the weighted centroid and the second moment of x match the
    // triangle's in closed form far better than independent uniform points would (their centroid
    // error has a standard deviation of about 2e-3 here).
    rad::PrtMesh m;
    m.positions = {0, 0, 0, 1, 0, 0, 0.3f, 0.8f, 0};
    m.faces = {0, 1, 2};
    m.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1};
    m.width = 4;
    const rad::RelightingSamples s = rad::makeRelightingSamples(m, 10000, oracleOf(affineField, 4), 3);
    const Vec3 a = at(m.positions, 0), b = at(m.positions, 1), c = at(m.positions, 2);
    Vec3 centroid = Vec3::Zero();
    double secondMoment = 0.0, total = 0.0;
    for (std::size_t i = 0; i < s.count(); ++i) {
        const Vec3 x = at(s.positions, i);
        centroid += s.weights[i] * x;
        secondMoment += s.weights[i] * x.x() * x.x();
        total += s.weights[i];
    }
    centroid /= total;
    secondMoment /= total;
    EXPECT_LT((centroid - (a + b + c) / 3.0).norm(), 2e-4);
    // Mean of x^2 over a triangle: (sum of x_i^2 + sum of x_i x_j (i < j)) / 6.
    const double exact = (a.x() * a.x() + b.x() * b.x() + c.x() * c.x() + a.x() * b.x() + b.x() * c.x() + c.x() * a.x()) / 6.0;
    EXPECT_NEAR(secondMoment, exact, 2e-4);
}

TEST(RelightingSamples, GroundTruthFromOneOracleCallAndDeterministicSeed) {
    const rad::PrtMesh mesh = bentMesh(curvedField, 4);
    int calls = 0;
    const rad::RelightingSamples s = rad::makeRelightingSamples(mesh, 2000, oracleOf(curvedField, 4, &calls), 5);
    EXPECT_EQ(calls, 1);
    for (std::size_t i = 0; i < s.count(); ++i) {
        const std::vector<double> t = curvedField(at(s.positions, i));
        for (int j = 0; j < 4; ++j) EXPECT_FLOAT_EQ(s.groundTruth[i * 4 + j], static_cast<float>(t[j]));
    }
    const rad::RelightingSamples again = rad::makeRelightingSamples(mesh, 2000, oracleOf(curvedField, 4), 5);
    EXPECT_EQ(again.positions, s.positions);
    EXPECT_EQ(again.normals, s.normals);
    EXPECT_EQ(again.weights, s.weights);
    EXPECT_EQ(again.inputFace, s.inputFace);
    const rad::RelightingSamples other = rad::makeRelightingSamples(mesh, 2000, oracleOf(curvedField, 4), 6);
    EXPECT_EQ(other.count(), s.count());
    EXPECT_NE(other.positions, s.positions);
}

TEST(RelightingSamples, RefusesInvalidInput) {
    rad::PrtMesh mesh = bentMesh(affineField, 4);
    EXPECT_THROW(rad::makeRelightingSamples(mesh, 100, {}), std::invalid_argument);
    rad::PrtMesh noFaces = mesh;
    noFaces.faces.clear();
    EXPECT_THROW(rad::makeRelightingSamples(noFaces, 100, oracleOf(affineField, 4)), std::invalid_argument);
    rad::PrtMesh badIndex = mesh;
    badIndex.faces[0] = 99;
    EXPECT_THROW(rad::makeRelightingSamples(badIndex, 100, oracleOf(affineField, 4)), std::invalid_argument);
    rad::PrtMesh noNormals = mesh;
    noNormals.normals.clear();
    EXPECT_THROW(rad::makeRelightingSamples(noNormals, 100, oracleOf(affineField, 4)), std::invalid_argument);
}

// ---------------------------------------------------------------- interpolation

TEST(InterpolateAtSamples, AffineFieldIsExactOnAnySubdivision) {
    const rad::PrtMesh input = bentMesh(affineField, 4);
    const rad::RelightingSamples s = rad::makeRelightingSamples(input, 4000, oracleOf(affineField, 4), 2);
    std::vector<rad::SubdivisionResult> subdivisions;
    subdivisions.push_back(unsplit(input));
    // Face 0 split 1-to-4, face 1 bisected (a T-vertex fix), face 2 kept.
    subdivisions.push_back(bisectByHand(splitByHand(unsplit(input), affineField, [](std::size_t f) { return f == 0; }),
                                        affineField, 1));
    rad::SubdivisionResult deep = unsplit(input);
    for (int level = 0; level < 4; ++level) deep = splitByHand(deep, affineField);  // 256 sub-faces per face
    subdivisions.push_back(deep);
    for (const auto& sub : subdivisions) {
        const std::vector<float> interpolated = rad::interpolateAtSamples(s, input, sub);
        ASSERT_EQ(interpolated.size(), s.groundTruth.size());
        EXPECT_LT(maxAbsDifference(interpolated, s.groundTruth), 2e-5) << sub.mesh.faceCount() << " faces";
    }
}

TEST(InterpolateAtSamples, InterpolatesTheContainingSubFacesVertices) {
    // A field that is affine on each child of a 1-to-4 split but whose vertex values are arbitrary
    // per child vertex: each sample must use the three vertices of the child containing it.
    rad::PrtMesh input;
    input.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    input.faces = {0, 1, 2};
    input.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1};
    input.width = 1;
    input.transfer = {0, 0, 0};
    const Field zero = [](const Vec3&) { return std::vector<double>{0.0}; };
    const rad::RelightingSamples s = rad::makeRelightingSamples(input, 400, oracleOf(zero, 1));
    const rad::SubdivisionResult sub = splitByHand(unsplit(input), zero);
    // The children share their corner and midpoint vertices; give each child its own copies, all
    // of value child + 1, so that the interpolated value names the child used.
    rad::SubdivisionResult own = sub;
    own.mesh.positions.clear();
    own.mesh.normals.clear();
    own.mesh.transfer.clear();
    for (std::size_t f = 0; f < sub.mesh.faceCount(); ++f)
        for (int k = 0; k < 3; ++k) {
            const Vec3 p = at(sub.mesh.positions, sub.mesh.faces[3 * f + k]);
            own.mesh.faces[3 * f + k] = addVertex(own.mesh, p, [f](const Vec3&) { return std::vector<double>{double(f + 1)}; });
        }
    const std::vector<float> interpolated = rad::interpolateAtSamples(s, input, own);
    for (std::size_t i = 0; i < s.count(); ++i) {
        const Vec3 x = at(s.positions, i);
        // Child by hand: corner children where one barycentric exceeds 1/2, else the middle one.
        const double b0 = 1 - x.x() - x.y(), b1 = x.x(), b2 = x.y();
        const int child = b0 > 0.5 ? 0 : b1 > 0.5 ? 1 : b2 > 0.5 ? 2 : 3;
        const double margin = std::min({std::fabs(b0 - 0.5), std::fabs(b1 - 0.5), std::fabs(b2 - 0.5)});
        if (margin < 1e-6) continue;  // on a child boundary: either child is right
        EXPECT_FLOAT_EQ(interpolated[i], float(child + 1)) << "sample " << i;
    }
}

TEST(InterpolateAtSamples, NonLinearFieldErrorShrinksUnderRefinement) {
    const rad::PrtMesh input = bentMesh(curvedField, 4);
    const rad::RelightingSamples s = rad::makeRelightingSamples(input, 6000, oracleOf(curvedField, 4), 4);
    // Transfer of width 4 = one channel of degree 1; a lighting with a positive mean.
    const std::vector<double> lighting = {1.0, 0.2, 0.3, -0.1, 0.8, 0.1, 0.2, 0.0, 1.2, -0.2, 0.4, 0.1};
    rad::SubdivisionResult sub = unsplit(input);
    double previousMax = 0.0, previousMean = 0.0;
    for (int level = 0; level < 5; ++level) {
        const std::vector<float> interpolated = rad::interpolateAtSamples(s, input, sub);
        const double maxError = maxAbsDifference(interpolated, s.groundTruth);
        const rad::RelightingErrorStats stats = rad::relightingError(s, interpolated, 1, 1, lighting, 1);
        EXPECT_GT(maxError, 0.0);
        EXPECT_GT(stats.meanRelativeError, 0.0);
        if (level > 0) {
            EXPECT_LT(maxError, previousMax) << "level " << level;
            EXPECT_LT(stats.meanRelativeError, previousMean) << "level " << level;
        }
        if (level > 1) {
            // Once the faces resolve the field (the coarse faces are ~2 wide, sin(3x) turns in
            // ~2), linear interpolation error is O(h^2): about a quarter per halving.
            EXPECT_LT(maxError, 0.35 * previousMax) << "level " << level;
            EXPECT_LT(stats.meanRelativeError, 0.35 * previousMean) << "level " << level;
        }
        previousMax = maxError;
        previousMean = stats.meanRelativeError;
        sub = splitByHand(sub, curvedField);
    }
}

TEST(InterpolateAtSamples, SmallFacesFarFromTheOriginAreNotRefusedForRounding) {
    // Faces of size 0.01 at coordinates ~1000: float positions carry ~1e-4 absolute error, 1e-2
    // of the face; the barycentric tolerance must account for it.
    const Field field = [](const Vec3& x) { return std::vector<double>{x.x() - 1000.0, x.y() - 1000.0}; };
    rad::PrtMesh input;
    input.positions = {1000, 1000, 1000, 1000.01f, 1000, 1000, 1000, 1000.01f, 1000.003f};
    input.faces = {0, 1, 2};
    input.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1};
    input.width = 2;
    for (std::size_t v = 0; v < 3; ++v) {
        const std::vector<double> t = field(at(input.positions, v));
        input.transfer.insert(input.transfer.end(), {float(t[0]), float(t[1])});
    }
    const rad::RelightingSamples s = rad::makeRelightingSamples(input, 2000, oracleOf(field, 2));
    rad::SubdivisionResult sub = unsplit(input);
    for (int level = 0; level < 3; ++level) sub = splitByHand(sub, field);
    EXPECT_NO_THROW(rad::interpolateAtSamples(s, input, sub));
}

TEST(InterpolateAtSamples, SampleOutsideEverySubFaceThrows) {
    const rad::PrtMesh input = bentMesh(affineField, 4);
    const rad::RelightingSamples s = rad::makeRelightingSamples(input, 2000, oracleOf(affineField, 4));
    // Face 0 split 1-to-4 with its middle child left out: the samples there lie in no sub-face.
    const rad::SubdivisionResult holed = splitByHand(unsplit(input), affineField, [](std::size_t) { return true; },
                                                     [](std::size_t f, int child) { return !(f == 0 && child == 3); });
    EXPECT_THROW(rad::interpolateAtSamples(s, input, holed), std::invalid_argument);
    // Sub-faces credited to the wrong input face.
    rad::SubdivisionResult swapped = unsplit(input);
    std::swap(swapped.originFace[0], swapped.originFace[1]);
    EXPECT_THROW(rad::interpolateAtSamples(s, input, swapped), std::invalid_argument);
    // An input face with samples but no sub-face at all.
    rad::SubdivisionResult missing = unsplit(input);
    missing.mesh.faces.resize(6);
    missing.originFace.resize(2);
    EXPECT_THROW(rad::interpolateAtSamples(s, input, missing), std::invalid_argument);
}

TEST(InterpolateAtSamples, RefusesMismatchedSizes) {
    const rad::PrtMesh input = bentMesh(affineField, 4);
    const rad::RelightingSamples s = rad::makeRelightingSamples(input, 500, oracleOf(affineField, 4));
    rad::SubdivisionResult sub = unsplit(input);
    sub.originFace.pop_back();
    EXPECT_THROW(rad::interpolateAtSamples(s, input, sub), std::invalid_argument);
    sub = unsplit(input);
    sub.originFace[0] = 7;
    EXPECT_THROW(rad::interpolateAtSamples(s, input, sub), std::invalid_argument);
    sub = unsplit(input);
    sub.mesh.transfer.pop_back();
    EXPECT_THROW(rad::interpolateAtSamples(s, input, sub), std::invalid_argument);
    sub = unsplit(input);
    sub.mesh.width = 3;
    sub.mesh.transfer.resize(3 * sub.mesh.vertexCount());
    EXPECT_THROW(rad::interpolateAtSamples(s, input, sub), std::invalid_argument);
}

// ---------------------------------------------------------------- error statistics

TEST(RelightingError, ZeroWhenInterpolationEqualsGroundTruth) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const int degree = 2, width = 3 * 9;
    rad::RelightingSamples s;
    s.width = width;
    for (int i = 0; i < 300; ++i) {
        s.inputFace.push_back(0);
        s.weights.push_back(0.1f + u(rng));
        for (int j = 0; j < width; ++j) s.groundTruth.push_back(u(rng));
    }
    s.positions.assign(3 * s.count(), 0.0f);
    s.normals.assign(3 * s.count(), 0.0f);
    const std::vector<double> light = rad::directionalLightSH(3, Eigen::Vector3d(0.3, 0.2, 1.0), Eigen::Vector3d(1, 1, 1));
    const rad::RelightingErrorStats e = rad::relightingError(s, s.groundTruth, degree, 3, light, 3);
    EXPECT_EQ(e.meanRelativeError, 0.0);
    EXPECT_EQ(e.p95RelativeError, 0.0);
    EXPECT_EQ(e.rmsRelativeError, 0.0);
}

TEST(RelightingError, HandComputedTwoSamplesWithTheFloor) {
    // Degree 0, one channel: Y = t * (0.2126 * 1 + 0.7152 * 2 + 0.0722 * 4) = 1.9318 t under the
    // lighting (1, 2, 4).
    const double k = kRed * 1 + kGreen * 2 + kBlue * 4;
    const rad::RelightingSamples s = scalarSamples({1.0f, 3.0f}, {2.0f, 0.001f});
    const std::vector<float> interpolated = {2.5f, 0.003f};
    const rad::RelightingErrorStats e = rad::relightingError(s, interpolated, 0, 1, {1.0, 2.0, 4.0}, 0);
    // Mean luminance (2k * 1 + 0.001k * 3) / 4 = 0.50075k, floor 0.0050075k > Y2 = 0.001k.
    const double floor = 0.01 * (2.0 * k * 1 + double(0.001f) * k * 3) / 4;
    const double e1 = 0.5 * k / (2.0 * k);                                      // 0.25, above the floor
    const double e2 = (double(0.003f) - double(0.001f)) * k / floor;           // ~0.3994, at the floor
    EXPECT_NEAR(e2, 0.002 / 0.0050075, 1e-6);
    EXPECT_NEAR(e.meanRelativeError, (1 * e1 + 3 * e2) / 4, 1e-9);
    EXPECT_NEAR(e.rmsRelativeError, std::sqrt((1 * e1 * e1 + 3 * e2 * e2) / 4), 1e-9);
    EXPECT_NEAR(e.p95RelativeError, e2, 1e-9);  // e1 covers only 1/4 of the weight
}

TEST(RelightingError, ThreeChannelTransferUsesItsOwnChannelPerColour) {
    // Degree 0, three channels; lighting white (1, 1, 1): Y = 0.2126 R + 0.7152 G + 0.0722 B.
    rad::RelightingSamples s;
    s.width = 3;
    s.inputFace = {0, 0};
    s.positions.assign(6, 0.0f);
    s.normals.assign(6, 0.0f);
    s.weights = {1.0f, 1.0f};
    s.groundTruth = {1.0f, 1.0f, 1.0f, 0.5f, 2.0f, 1.0f};
    const std::vector<float> interpolated = {2.0f, 1.0f, 1.0f, 0.5f, 2.0f, 3.0f};  // red up by 1, blue up by 2
    const rad::RelightingErrorStats e = rad::relightingError(s, interpolated, 0, 3, {1.0, 1.0, 1.0}, 0);
    const double Y1 = kRed + kGreen + kBlue, Y2 = 0.5 * kRed + 2 * kGreen + kBlue;
    const double e1 = kRed / Y1, e2 = 2 * kBlue / Y2;
    EXPECT_NEAR(e.meanRelativeError, (e1 + e2) / 2, 1e-7);
    EXPECT_NEAR(e.p95RelativeError, std::max(e1, e2), 1e-7);
}

TEST(RelightingError, WeightedP95OfAKnownDistribution) {
    // 128 equal weights, errors i/128 (exact in float): the 95th percentile is the smallest error
    // with 95% of the weight at or below it, i.e. the 122nd (121.6 rounded up) = 122/128.
    std::vector<float> weights(128, 1.0f), truth(128, 1.0f), interpolated(128);
    for (int i = 0; i < 128; ++i) interpolated[i] = 1.0f + float(i + 1) / 128.0f;
    const rad::RelightingSamples s = scalarSamples(weights, truth);
    const std::vector<double> white = {1.0, 1.0, 1.0};
    rad::RelightingErrorStats e = rad::relightingError(s, interpolated, 0, 1, white, 0);
    EXPECT_NEAR(e.p95RelativeError, 122.0 / 128.0, 1e-12);
    EXPECT_NEAR(e.meanRelativeError, 129.0 / 256.0, 1e-12);  // mean of 1..128 over 128
    // Unequal weights: 0.9 at error 0.125 and 0.1 at 0.5 -> 0.5; 0.96 / 0.04 -> 0.125.
    e = rad::relightingError(scalarSamples({0.9f, 0.1f}, {1.0f, 1.0f}), {1.125f, 1.5f}, 0, 1, white, 0);
    EXPECT_NEAR(e.p95RelativeError, 0.5, 1e-12);
    e = rad::relightingError(scalarSamples({0.96f, 0.04f}, {1.0f, 1.0f}), {1.125f, 1.5f}, 0, 1, white, 0);
    EXPECT_NEAR(e.p95RelativeError, 0.125, 1e-12);
    // Mostly exact: 96% of the weight has no error at all.
    e = rad::relightingError(scalarSamples({0.96f, 0.04f}, {1.0f, 1.0f}), {1.0f, 1.5f}, 0, 1, white, 0);
    EXPECT_EQ(e.p95RelativeError, 0.0);
}

TEST(RelightingError, ManyLightingsMatchTheDefinitionOnRandomData) {
    // Random transfers and lightings (degree 2, both channel counts), many samples with random
    // weights: every statistic against the brute-force definition (one sort per quantile).
    std::mt19937 rng(21);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::normal_distribution<double> g;
    const int degree = 2, K = 9, lightingDegree = 3;
    for (int channels : {1, 3}) {
        const int width = channels * K;
        rad::RelightingSamples s;
        s.width = width;
        std::vector<float> interpolated;
        for (int i = 0; i < 20000; ++i) {
            s.inputFace.push_back(0);
            s.weights.push_back(u(rng) < 0.05f ? 0.0f : 0.01f + u(rng));
            for (int j = 0; j < width; ++j) {
                const float t = (j % K == 0 ? 1.0f : 0.3f * (u(rng) - 0.5f));
                s.groundTruth.push_back(t);
                // A third of the samples exact, the rest with errors spread over decades.
                const float scale = i % 3 == 0 ? 0.0f : std::pow(10.0f, -4.0f * u(rng));
                interpolated.push_back(t + scale * (u(rng) - 0.5f));
            }
        }
        s.positions.assign(3 * s.count(), 0.0f);
        s.normals.assign(3 * s.count(), 0.0f);
        std::vector<std::vector<double>> lightings;
        for (int l = 0; l < 7; ++l) {
            std::vector<double> light(3 * 16);
            for (double& c : light) c = 0.3 * g(rng);
            for (int ch = 0; ch < 3; ++ch) light[ch * 16] = 2.0 + u(rng);  // positive mean
            lightings.push_back(light);
        }
        const rad::RelightingErrorReport report =
            rad::relightingErrorOverLightings(s, interpolated, degree, channels, lightings, lightingDegree);
        const auto errors = bruteErrors(s, interpolated, degree, channels, lightings, lightingDegree);
        ASSERT_EQ(report.perLighting.size(), lightings.size());
        double total = 0.0;
        for (float w : s.weights) total += w;
        std::vector<std::pair<double, double>> allPairs;
        double meanOfMeans = 0.0, meanOfSquares = 0.0;
        for (std::size_t l = 0; l < lightings.size(); ++l) {
            double mean = 0.0, square = 0.0;
            std::vector<std::pair<double, double>> pairs;
            for (std::size_t i = 0; i < s.count(); ++i) {
                mean += s.weights[i] * errors[l][i];
                square += s.weights[i] * errors[l][i] * errors[l][i];
                pairs.emplace_back(errors[l][i], s.weights[i]);
            }
            mean /= total;
            square /= total;
            const rad::RelightingErrorStats& stats = report.perLighting[l];
            EXPECT_NEAR(stats.meanRelativeError, mean, 1e-9 * mean + 1e-15);
            EXPECT_NEAR(stats.rmsRelativeError, std::sqrt(square), 1e-9 * std::sqrt(square) + 1e-15);
            EXPECT_NEAR(stats.p95RelativeError, bruteP95(pairs), 1e-9 * bruteP95(pairs) + 1e-15);
            // The single-lighting entry point agrees.
            const rad::RelightingErrorStats single =
                rad::relightingError(s, interpolated, degree, channels, lightings[l], lightingDegree);
            EXPECT_NEAR(single.p95RelativeError, stats.p95RelativeError, 1e-12 * stats.p95RelativeError);
            EXPECT_NEAR(single.meanRelativeError, stats.meanRelativeError, 1e-12 * mean);
            meanOfMeans += mean / lightings.size();
            meanOfSquares += square / lightings.size();
            allPairs.insert(allPairs.end(), pairs.begin(), pairs.end());
        }
        EXPECT_NEAR(report.overall.meanRelativeError, meanOfMeans, 1e-9 * meanOfMeans);
        EXPECT_NEAR(report.overall.rmsRelativeError, std::sqrt(meanOfSquares), 1e-9 * std::sqrt(meanOfSquares));
        const double p95 = bruteP95(allPairs);
        EXPECT_GT(p95, 0.0);
        EXPECT_NEAR(report.overall.p95RelativeError, p95, 1e-9 * p95) << channels << " channel(s)";
    }
}

TEST(RelightingError, RefusesInvalidInput) {
    const rad::RelightingSamples s = scalarSamples({1.0f, 1.0f}, {1.0f, 1.0f});
    const std::vector<float> interpolated = {1.0f, 1.0f};
    const std::vector<double> white = {1.0, 1.0, 1.0};
    EXPECT_NO_THROW(rad::relightingError(s, interpolated, 0, 1, white, 0));
    // A black lighting has no adaptation level: no Weber normalisation.
    EXPECT_THROW(rad::relightingError(s, interpolated, 0, 1, {0.0, 0.0, 0.0}, 0), std::invalid_argument);
    EXPECT_THROW(rad::relightingError(s, {1.0f}, 0, 1, white, 0), std::invalid_argument);
    EXPECT_THROW(rad::relightingError(s, interpolated, 0, 1, {1.0, 1.0}, 0), std::invalid_argument);
    EXPECT_THROW(rad::relightingError(s, interpolated, 1, 1, std::vector<double>(12, 1.0), 1), std::invalid_argument);
    EXPECT_THROW(rad::relightingError(s, interpolated, 0, 3, white, 0), std::invalid_argument);
    EXPECT_THROW(rad::relightingError(s, {1.0f, NAN}, 0, 1, white, 0), std::invalid_argument);
    EXPECT_THROW(rad::relightingErrorOverLightings(s, interpolated, 0, 1, {}, 0), std::invalid_argument);
    EXPECT_THROW(rad::relightingError(scalarSamples({0.0f, 0.0f}, {1.0f, 1.0f}), interpolated, 0, 1, white, 0),
                 std::invalid_argument);
}
