// Measured relighting error of interpolated PRT: Křivánek et al. 2004 ("Adaptive
// Mesh Subdivision for Precomputed Radiance Transfer") eq. 1, |L(x, l) - L_int(x, l)| / L(x, l),
// evaluated at dense sample points and over many lightings instead of estimated per triangle;
// the floor of the Weber normalisation and the statistics are documented in relighting_error.h.
#include "prt/relighting_error.h"

#include "lighting/median_cut_lights.h"  // luminanceRec709
#include "radiance/basis.h"

#include <Eigen/Core>

#include <omp.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>

namespace rad {

namespace {

using Vec3 = Eigen::Vector3d;

[[noreturn]] void refuse(const char* who, const std::string& why) {
    throw std::invalid_argument(std::string(who) + ": " + why);
}

Vec3 readVec3(const std::vector<float>& data, std::size_t index) {
    const float* p = data.data() + 3 * index;
    return {p[0], p[1], p[2]};
}

// Sizes and indices of a mesh; the transfer only when the caller interpolates it.
void checkMesh(const char* who, const char* name, const PrtMesh& mesh, bool needsTransfer) {
    const std::string prefix = std::string(name) + ": ";
    if (mesh.positions.size() % 3 != 0) refuse(who, prefix + "the position count is not a multiple of 3");
    if (mesh.faces.size() % 3 != 0) refuse(who, prefix + "the face index count is not a multiple of 3");
    const std::size_t n = mesh.vertexCount();
    for (std::uint32_t v : mesh.faces)
        if (v >= n) refuse(who, prefix + "face index " + std::to_string(v) + " >= vertex count " + std::to_string(n));
    for (float x : mesh.positions)
        if (!std::isfinite(x)) refuse(who, prefix + "non-finite vertex position");
    if (needsTransfer) {
        if (mesh.width < 1) refuse(who, prefix + "transfer width " + std::to_string(mesh.width) + " < 1");
        if (mesh.transfer.size() != n * static_cast<std::size_t>(mesh.width))
            refuse(who, prefix + "the transfer holds " + std::to_string(mesh.transfer.size()) + " floats, expected " +
                            std::to_string(n) + " x " + std::to_string(mesh.width));
    }
}

// Heitz's area-preserving map of the unit square onto the triangle {x, y >= 0, x + y <= 1}
// (E. Heitz, "A Low-Distortion Map Between Triangle and Square", 2019): two linear pieces of
// Jacobian 1/2, so equal-area cells of the square become equal-area strata of the triangle, less
// sheared than by the usual square-root map.
std::pair<double, double> squareToTriangle(double u, double v) {
    if (v > u) {
        const double x = 0.5 * u;
        return {x, v - x};
    }
    const double y = 0.5 * v;
    return {u - y, y};
}

// A uniform double in [0, 1) from 53 random bits (the same on every standard library, unlike
// std::uniform_real_distribution).
double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

}  // namespace

RelightingSamples makeRelightingSamples(const PrtMesh& input, std::size_t targetCount, const TransferOracle& oracle,
                                        unsigned seed) {
    const char* who = "makeRelightingSamples";
    checkMesh(who, "input mesh", input, false);
    if (input.normals.size() != input.positions.size()) refuse(who, "input mesh: one unit normal per vertex is needed");
    if (input.faceCount() == 0) refuse(who, "the input mesh has no faces");
    if (input.width < 1) refuse(who, "the input mesh's transfer width " + std::to_string(input.width) + " < 1");
    if (!oracle) refuse(who, "no transfer oracle");

    const std::size_t faceCount = input.faceCount();
    std::vector<double> areas(faceCount);
    double totalArea = 0.0;
    for (std::size_t f = 0; f < faceCount; ++f) {
        const Vec3 a = readVec3(input.positions, input.faces[3 * f]), b = readVec3(input.positions, input.faces[3 * f + 1]),
                   c = readVec3(input.positions, input.faces[3 * f + 2]);
        areas[f] = 0.5 * (b - a).cross(c - a).norm();
        totalArea += areas[f];
    }
    if (!(totalArea > 0.0)) refuse(who, "the input mesh has zero area");

    // Count proportional to area, at least one per face that covers any surface: a zero-area face
    // stands for no area and has no interior to sample.
    std::vector<std::size_t> counts(faceCount, 0);
    std::size_t total = 0;
    for (std::size_t f = 0; f < faceCount; ++f) {
        if (areas[f] > 0.0)
            counts[f] = std::max<std::size_t>(
                1, static_cast<std::size_t>(std::llround(static_cast<double>(targetCount) * areas[f] / totalArea)));
        total += counts[f];
    }

    RelightingSamples samples;
    samples.width = input.width;
    samples.inputFace.resize(total);
    samples.positions.resize(3 * total);
    samples.normals.resize(3 * total);
    samples.weights.resize(total);

    // One generator for the whole mesh, faces in order: the same seed gives the same points.
    std::mt19937_64 rng(seed);
    std::size_t s = 0;
    for (std::size_t f = 0; f < faceCount; ++f) {
        const std::size_t n = counts[f];
        if (n == 0) continue;
        const std::uint32_t* idx = input.faces.data() + 3 * f;
        const Vec3 p0 = readVec3(input.positions, idx[0]), p1 = readVec3(input.positions, idx[1]),
                   p2 = readVec3(input.positions, idx[2]);
        const Vec3 n0 = readVec3(input.normals, idx[0]), n1 = readVec3(input.normals, idx[1]),
                   n2 = readVec3(input.normals, idx[2]);
        const Vec3 faceNormal = (p1 - p0).cross(p2 - p0).normalized();
        const float weight = static_cast<float>(areas[f] / static_cast<double>(n));
        // n equal-area cells of the unit square: `rows` rows, row r holding cellsInRow cells of
        // width 1 / cellsInRow and height cellsInRow / n, so every cell has area 1 / n whatever
        // the split of n into rows; one jittered point per cell.
        const std::size_t rows = std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(std::sqrt(double(n)))));
        std::size_t done = 0;
        for (std::size_t r = 0; r < rows; ++r) {
            const std::size_t cellsInRow = n / rows + (r < n % rows ? 1 : 0);
            const double v0 = static_cast<double>(done) / n, height = static_cast<double>(cellsInRow) / n;
            for (std::size_t c = 0; c < cellsInRow; ++c, ++s) {
                const double u = (c + uniform01(rng)) / cellsInRow;
                const double v = std::min(v0 + uniform01(rng) * height, 1.0);
                const auto [b1, b2] = squareToTriangle(u, v);
                const double b0 = std::max(0.0, 1.0 - b1 - b2);
                const Vec3 position = b0 * p0 + b1 * p1 + b2 * p2;
                Vec3 normal = b0 * n0 + b1 * n1 + b2 * n2;
                // Opposite vertex normals can cancel (a crease seen from both sides): the face's
                // own normal is then the only meaningful one.
                normal = normal.norm() > 1e-12 ? Vec3(normal.normalized()) : faceNormal;
                samples.inputFace[s] = static_cast<std::uint32_t>(f);
                for (int k = 0; k < 3; ++k) {
                    samples.positions[3 * s + k] = static_cast<float>(position[k]);
                    samples.normals[3 * s + k] = static_cast<float>(normal[k]);
                }
                samples.weights[s] = weight;
            }
            done += cellsInRow;
        }
    }

    samples.groundTruth.assign(total * static_cast<std::size_t>(samples.width), 0.0f);
    oracle(samples.positions.data(), samples.normals.data(), total, samples.groundTruth.data());
    return samples;
}

namespace {

// Counting sort of items by key: items of key k are ids[start[k] .. start[k + 1]). Linear.
struct Buckets {
    std::vector<std::size_t> start;
    std::vector<std::uint32_t> ids;
};
Buckets bucketByKey(const std::vector<std::uint32_t>& keys, std::size_t keyCount) {
    Buckets b;
    b.start.assign(keyCount + 1, 0);
    for (std::uint32_t k : keys) ++b.start[k + 1];
    for (std::size_t k = 0; k < keyCount; ++k) b.start[k + 1] += b.start[k];
    b.ids.resize(keys.size());
    std::vector<std::size_t> next(b.start.begin(), b.start.end() - 1);
    for (std::size_t i = 0; i < keys.size(); ++i) b.ids[next[keys[i]]++] = static_cast<std::uint32_t>(i);
    return b;
}

// Coordinates (b1, b2) of points in the plane of one input face p0 p1 p2: the least-squares
// solution of x - p0 = b1 (p1 - p0) + b2 (p2 - p0), i.e. the barycentrics of x's orthogonal
// projection on the plane. Every sub-face lies in that plane (subdivision does not move the
// surface), so barycentrics inside a sub-face are the same in this 2D chart as in 3D, and the
// chart gives every input face the same scale (its own corners at (0,0), (1,0), (0,1)).
class FaceChart {
public:
    FaceChart(const Vec3& p0, const Vec3& p1, const Vec3& p2) : origin_(p0), e1_(p1 - p0), e2_(p2 - p0) {
        const double a = e1_.dot(e1_), b = e1_.dot(e2_), c = e2_.dot(e2_);
        determinant_ = a * c - b * b;
        inverse_ << c, -b, -b, a;
        inverse_ /= determinant_;
    }
    bool valid() const { return determinant_ > 0.0 && std::isfinite(determinant_); }
    Eigen::Vector2d operator()(const Vec3& x) const {
        const Vec3 d = x - origin_;
        return inverse_ * Eigen::Vector2d(d.dot(e1_), d.dot(e2_));
    }

private:
    Vec3 origin_, e1_, e2_;
    double determinant_ = 0.0;
    Eigen::Matrix2d inverse_;
};

// A sub-face in a face chart: barycentrics of a chart point and its signed distance outside
// (negative) or inside (positive) the triangle, measured in chart units so that one tolerance fits
// sub-faces of every size.
struct ChartTriangle {
    Eigen::Vector2d q[3];
    double twiceArea = 0.0;        // signed
    double inverseEdgeLength[3];   // of the edge opposite corner i

    bool degenerate() const { return !(std::fabs(twiceArea) > 0.0); }
    // Returns the smallest signed distance to the three edge lines (>= 0 inside).
    double locate(const Eigen::Vector2d& x, double barycentric[3]) const {
        double margin = std::numeric_limits<double>::infinity();
        for (int i = 0; i < 3; ++i) {
            const Eigen::Vector2d& a = q[(i + 1) % 3];
            const Eigen::Vector2d& b = q[(i + 2) % 3];
            const double cross = (a - x).x() * (b - x).y() - (a - x).y() * (b - x).x();
            barycentric[i] = cross / twiceArea;
            // lambda_i = distance to the opposite edge / the corner's height = d |edge| / (2 A).
            margin = std::min(margin, barycentric[i] * std::fabs(twiceArea) * inverseEdgeLength[i]);
        }
        return margin;
    }
};

struct LocateFailure {
    bool failed = false;
    std::size_t sample = 0;
    std::string message;
};

// Keeps the failure of the lowest sample index, so that the message does not depend on the threads.
void recordFailure(LocateFailure& failure, std::size_t sample, const std::string& why) {
#pragma omp critical(relighting_locate_failure)
    if (!failure.failed || sample < failure.sample) failure = {true, sample, why};
}

void checkInterpolationInput(const char* who, const RelightingSamples& samples, const PrtMesh& input,
                             const SubdivisionResult& mesh) {
    checkMesh(who, "input mesh", input, false);
    checkMesh(who, "subdivided mesh", mesh.mesh, true);
    const std::size_t count = samples.count();
    const int width = samples.width;
    if (mesh.mesh.width != width)
        refuse(who, "the subdivided mesh's transfer width " + std::to_string(mesh.mesh.width) +
                        " differs from the samples' " + std::to_string(width));
    if (samples.positions.size() != 3 * count) refuse(who, "the samples need 3 position floats each");
    const std::size_t inputFaces = input.faceCount(), outputFaces = mesh.mesh.faceCount();
    if (mesh.originFace.size() != outputFaces)
        refuse(who, "originFace has " + std::to_string(mesh.originFace.size()) + " entries for " +
                        std::to_string(outputFaces) + " faces");
    for (std::uint32_t f : mesh.originFace)
        if (f >= inputFaces) refuse(who, "originFace " + std::to_string(f) + " >= input face count " + std::to_string(inputFaces));
    for (std::uint32_t f : samples.inputFace)
        if (f >= inputFaces) refuse(who, "a sample's input face " + std::to_string(f) + " >= input face count " + std::to_string(inputFaces));
}

// What every input face's interpolation reads, and where it writes.
struct InterpolationJob {
    const RelightingSamples& samples;
    const PrtMesh& input;
    const SubdivisionResult& mesh;
    const Buckets& subFaces;     // per input face, its sub-faces
    const Buckets& faceSamples;  // per input face, its samples
    int width;
    float* out;                  // width floats per sample
};

// One thread's buffers, reused from face to face.
struct FaceWorkspace {
    std::vector<ChartTriangle> triangles;
    std::vector<std::uint32_t> triangleFace;
    std::vector<std::size_t> cellStart;
    std::vector<std::uint32_t> cellTriangles;
    std::vector<double> accumulator;
};

// Tolerance in chart units: 1e-5 (relighting_error.h), widened to what float rounding of the vertex
// and sample positions can move a point in the chart (a position error delta moves a barycentric by
// at most delta / the face's smallest height), so that small faces far from the origin are not
// refused for their coordinates' precision.
double chartTolerance(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
    const double maxEdge = std::max({(p1 - p0).norm(), (p2 - p1).norm(), (p0 - p2).norm()});
    const double smallestHeight = (p1 - p0).cross(p2 - p0).norm() / maxEdge;
    const double magnitude = std::max({p0.cwiseAbs().maxCoeff(), p1.cwiseAbs().maxCoeff(), p2.cwiseAbs().maxCoeff()});
    return 1e-5 + 32.0 * FLT_EPSILON * magnitude / smallestHeight;
}

struct ChartBox {
    Eigen::Vector2d lo, hi;
};

// The non-degenerate sub-faces of input face f in its chart (ws.triangles, ws.triangleFace), and
// their bounding box.
ChartBox chartSubFaces(const InterpolationJob& job, std::ptrdiff_t f, const FaceChart& chart, FaceWorkspace& ws) {
    const PrtMesh& mesh = job.mesh.mesh;
    ws.triangles.clear();
    ws.triangleFace.clear();
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (std::size_t i = job.subFaces.start[f]; i < job.subFaces.start[f + 1]; ++i) {
        const std::uint32_t g = job.subFaces.ids[i];
        ChartTriangle t;
        for (int k = 0; k < 3; ++k) t.q[k] = chart(readVec3(mesh.positions, mesh.faces[3 * g + k]));
        const Eigen::Vector2d e1 = t.q[1] - t.q[0], e2 = t.q[2] - t.q[0];
        t.twiceArea = e1.x() * e2.y() - e1.y() * e2.x();
        if (t.degenerate()) continue;  // covers nothing, and has no barycentrics
        for (int k = 0; k < 3; ++k) {
            t.inverseEdgeLength[k] = 1.0 / (t.q[(k + 2) % 3] - t.q[(k + 1) % 3]).norm();
            lo = lo.cwiseMin(t.q[k]);
            hi = hi.cwiseMax(t.q[k]);
        }
        ws.triangles.push_back(t);
        ws.triangleFace.push_back(g);
    }
    return {lo, hi};
}

// A uniform grid over the sub-faces' chart bounding box (widened by the tolerance).
struct ChartGrid {
    Eigen::Vector2d lo, cellScale;
    std::size_t size = 1;  // cells per side

    std::size_t cellOf(double x, int axis) const {
        const double c = std::floor((x - lo[axis]) * cellScale[axis]);
        return static_cast<std::size_t>(std::clamp(c, 0.0, double(size - 1)));
    }
};

// Each sub-face is registered in every cell its box widened by the tolerance touches: a sample then
// tests only its cell's few sub-faces, and any sub-face within the tolerance of it is among them.
ChartGrid gridSubFaces(ChartBox box, double tolerance, FaceWorkspace& ws) {
    box.lo.array() -= tolerance;
    box.hi.array() += tolerance;
    ChartGrid grid;
    grid.lo = box.lo;
    grid.size = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(std::sqrt(double(ws.triangles.size())))));
    grid.cellScale = Eigen::Vector2d::Constant(double(grid.size)).cwiseQuotient(box.hi - box.lo);
    const std::size_t gridSize = grid.size;
    ws.cellStart.assign(gridSize * gridSize + 1, 0);
    for (int pass = 0; pass < 2; ++pass) {
        if (pass == 1) {
            for (std::size_t c = 0; c < gridSize * gridSize; ++c) ws.cellStart[c + 1] += ws.cellStart[c];
            ws.cellTriangles.resize(ws.cellStart.back());
        }
        std::vector<std::size_t> next;
        if (pass == 1) next.assign(ws.cellStart.begin(), ws.cellStart.end() - 1);
        for (std::size_t i = 0; i < ws.triangles.size(); ++i) {
            const ChartTriangle& t = ws.triangles[i];
            Eigen::Vector2d tlo = t.q[0].cwiseMin(t.q[1]).cwiseMin(t.q[2]);
            Eigen::Vector2d thi = t.q[0].cwiseMax(t.q[1]).cwiseMax(t.q[2]);
            tlo.array() -= tolerance;
            thi.array() += tolerance;
            for (std::size_t y = grid.cellOf(tlo.y(), 1); y <= grid.cellOf(thi.y(), 1); ++y)
                for (std::size_t x = grid.cellOf(tlo.x(), 0); x <= grid.cellOf(thi.x(), 0); ++x) {
                    const std::size_t cell = y * gridSize + x;
                    if (pass == 0) ++ws.cellStart[cell + 1];
                    else ws.cellTriangles[next[cell]++] = static_cast<std::uint32_t>(i);
                }
        }
    }
    return grid;
}

// The sub-face of the chart point's cell that the point lies in, or else the one it is nearest outside.
struct SubFaceHit {
    double margin = -std::numeric_limits<double>::infinity();  // >= 0 inside
    double barycentric[3] = {0, 0, 0};
    std::uint32_t triangle = 0;
};

SubFaceHit locateInCell(const FaceWorkspace& ws, const ChartGrid& grid, const Eigen::Vector2d& x) {
    const std::size_t cell = grid.cellOf(x.y(), 1) * grid.size + grid.cellOf(x.x(), 0);
    SubFaceHit hit;
    for (std::size_t ci = ws.cellStart[cell]; ci < ws.cellStart[cell + 1]; ++ci) {
        double barycentric[3];
        const double margin = ws.triangles[ws.cellTriangles[ci]].locate(x, barycentric);
        if (margin > hit.margin) {
            hit.margin = margin;
            std::copy(barycentric, barycentric + 3, hit.barycentric);
            hit.triangle = ws.cellTriangles[ci];
            if (margin >= 0.0) break;  // inside: sub-faces do not overlap
        }
    }
    return hit;
}

// Within the tolerance outside, the nearest point of the sub-face (clamped barycentrics) rather than
// an extrapolation.
void writeInterpolatedTransfer(const InterpolationJob& job, std::size_t s, SubFaceHit hit, FaceWorkspace& ws) {
    const int width = job.width;
    double sum = 0.0;
    for (double& b : hit.barycentric) sum += (b = std::max(b, 0.0));
    for (double& b : hit.barycentric) b /= sum;

    std::fill(ws.accumulator.begin(), ws.accumulator.end(), 0.0);
    const std::uint32_t* v = job.mesh.mesh.faces.data() + 3 * ws.triangleFace[hit.triangle];
    for (int k = 0; k < 3; ++k) {
        const float* t = job.mesh.mesh.transfer.data() + static_cast<std::size_t>(v[k]) * width;
        for (int j = 0; j < width; ++j) ws.accumulator[j] += hit.barycentric[k] * t[j];
    }
    float* o = job.out + s * width;
    for (int j = 0; j < width; ++j) o[j] = static_cast<float>(ws.accumulator[j]);
}

void interpolateFaceSamples(const InterpolationJob& job, std::ptrdiff_t f, FaceWorkspace& ws, LocateFailure& failure) {
    const std::size_t s0 = job.faceSamples.start[f], s1 = job.faceSamples.start[f + 1];
    if (s0 == s1) return;
    const std::uint32_t* corner = job.input.faces.data() + 3 * f;
    const Vec3 p0 = readVec3(job.input.positions, corner[0]), p1 = readVec3(job.input.positions, corner[1]),
               p2 = readVec3(job.input.positions, corner[2]);
    const FaceChart chart(p0, p1, p2);
    if (!chart.valid()) {
        recordFailure(failure, job.faceSamples.ids[s0], "input face " + std::to_string(f) + " is degenerate but holds samples");
        return;
    }
    const double tolerance = chartTolerance(p0, p1, p2);
    const ChartBox box = chartSubFaces(job, f, chart, ws);
    if (ws.triangles.empty()) {
        recordFailure(failure, job.faceSamples.ids[s0],
                      "input face " + std::to_string(f) + " holds samples but no sub-face of the "
                      "subdivided mesh has it as originFace");
        return;
    }
    const ChartGrid grid = gridSubFaces(box, tolerance, ws);
    for (std::size_t si = s0; si < s1; ++si) {
        const std::size_t s = job.faceSamples.ids[si];
        const SubFaceHit hit = locateInCell(ws, grid, chart(readVec3(job.samples.positions, s)));
        const double best = hit.margin;
        if (!(best >= -tolerance)) {
            recordFailure(failure, s,
                          "sample " + std::to_string(s) + " of input face " + std::to_string(f) + " lies in none of its " +
                              std::to_string(ws.triangles.size()) + " sub-faces (" +
                              (std::isfinite(best) ? "nearest at " + std::to_string(-best) : std::string("none near")) +
                              " in the face's barycentric units, tolerance " + std::to_string(tolerance) +
                              "): the mesh is not a subdivision of the sampled input, or its originFace is wrong");
            continue;
        }
        writeInterpolatedTransfer(job, s, hit, ws);
    }
}

}  // namespace

std::vector<float> interpolateAtSamples(const RelightingSamples& samples, const PrtMesh& input,
                                        const SubdivisionResult& mesh) {
    const char* who = "interpolateAtSamples";
    checkInterpolationInput(who, samples, input, mesh);
    const int width = samples.width;
    const std::size_t inputFaces = input.faceCount();

    // Per input face: its sub-faces and its samples, each list built once by counting sort.
    const Buckets subFaces = bucketByKey(mesh.originFace, inputFaces);
    const Buckets faceSamples = bucketByKey(samples.inputFace, inputFaces);

    std::vector<float> out(samples.count() * static_cast<std::size_t>(width), 0.0f);
    const InterpolationJob job{samples, input, mesh, subFaces, faceSamples, width, out.data()};
    LocateFailure failure;
    const auto faceTotal = static_cast<std::ptrdiff_t>(inputFaces);

#pragma omp parallel
    {
        FaceWorkspace ws;
        ws.accumulator.resize(static_cast<std::size_t>(width));

#pragma omp for schedule(dynamic, 4)
        for (std::ptrdiff_t f = 0; f < faceTotal; ++f) interpolateFaceSamples(job, f, ws, failure);
    }
    if (failure.failed) refuse(who, failure.message);
    return out;
}

namespace {

// Weighted quantiles without storing every (sample, lighting) error (1M samples x 50 lightings
// would be 400 MB): pass 1 accumulates the weights in a histogram over the bit pattern of the
// error (for positive doubles the bits are monotone in the value: exponent then mantissa, 4 bins
// per octave), which locates the bin holding the quantile; pass 2 recomputes the errors (same
// function, same values bit for bit) and keeps only those of that bin, sorted for the exact value.
constexpr int kMantissaBitsDropped = 50;
constexpr std::size_t kBins = (std::size_t(1) << (63 - kMantissaBitsDropped)) + 1;
constexpr double kQuantile = 0.95;
// Cumulative weights are sums of floats in double; this much relative shortfall still counts as
// reaching the quantile, so that e.g. 95 weights of 0.01 reach 0.95 of 100 such weights.
constexpr double kQuantileSlack = 1e-12;

std::size_t binOf(double error) {
    if (error == 0.0) return 0;  // its own bin: a quantile at 0 needs no second pass
    std::uint64_t bits;
    std::memcpy(&bits, &error, sizeof bits);
    return 1 + static_cast<std::size_t>(bits >> kMantissaBitsDropped);
}

struct ErrorProblem {
    const RelightingSamples* samples = nullptr;
    const std::vector<float>* interpolated = nullptr;
    int width = 0;
    int lightingCount = 0;
    // Luminance lighting per lighting l: Y = <t, v_l> (Rec. 709 weights folded into the colour
    // channels of l), stored coefficient-major v[k * lightingCount + l] so that the innermost loop
    // runs over lightings, contiguous and vectorisable without reordering a reduction.
    std::vector<double> luminanceLighting;
    std::vector<double> floor;  // per lighting (MeanLuminance: the mean luminance itself)
    bool absolute = false;      // RelightingErrorNormalisation::MeanLuminance
};

// e(x, l) of samples [begin, end) for every lighting: errors[(s - begin) * L + l]. Both passes call
// this one function, so they see identical values.
void errorsOfBlock(const ErrorProblem& p, std::size_t begin, std::size_t end, double* errors, double* luminance) {
    const int L = p.lightingCount;
    for (std::size_t s = begin; s < end; ++s) {
        const float* truth = p.samples->groundTruth.data() + s * p.width;
        const float* interpolated = p.interpolated->data() + s * p.width;
        double* e = errors + (s - begin) * L;
        std::fill(luminance, luminance + L, 0.0);
        std::fill(e, e + L, 0.0);  // holds the luminance difference until the division
        for (int k = 0; k < p.width; ++k) {
            // The difference of two floats is exact in double: no cancellation between two
            // separately rounded dot products.
            const double t = truth[k], d = static_cast<double>(truth[k]) - static_cast<double>(interpolated[k]);
            const double* v = p.luminanceLighting.data() + static_cast<std::size_t>(k) * L;
            for (int l = 0; l < L; ++l) {
                luminance[l] += t * v[l];
                e[l] += d * v[l];
            }
        }
        if (p.absolute)
            for (int l = 0; l < L; ++l) e[l] = std::fabs(e[l]) / p.floor[l];
        else
            for (int l = 0; l < L; ++l) e[l] = std::fabs(e[l]) / std::max(luminance[l], p.floor[l]);
    }
}

constexpr std::size_t kBlock = 256;

// Computes the errors of block b (kBlock samples) and hands visit(s, errors of s for every lighting)
// each sample in order. Both passes go through it, so they visit the same values in the same order.
template <typename Visit>
void forEachSampleOfBlock(const ErrorProblem& problem, std::ptrdiff_t b, std::vector<double>& errors,
                          std::vector<double>& luminance, Visit&& visit) {
    const std::size_t count = problem.samples->count();
    const std::size_t begin = b * kBlock, end = std::min(count, begin + kBlock);
    errorsOfBlock(problem, begin, end, errors.data(), luminance.data());
    for (std::size_t s = begin; s < end; ++s) visit(s, errors.data() + (s - begin) * problem.lightingCount);
}

void checkErrorInput(const char* who, const RelightingSamples& samples, const std::vector<float>& interpolated,
                     int degree, int channels, const std::vector<std::vector<double>>& lightings, int lightingDegree) {
    if (degree < 0 || degree > kMaxHarmonicDegree || lightingDegree < 0 || lightingDegree > kMaxHarmonicDegree)
        refuse(who, "degrees must lie in [0, " + std::to_string(kMaxHarmonicDegree) + "]");
    if (lightingDegree < degree)
        refuse(who, "the lighting degree " + std::to_string(lightingDegree) + " is below the transfer's " + std::to_string(degree));
    if (channels != 1 && channels != kColorChannels) refuse(who, "channels must be 1 or 3");
    const int K = (degree + 1) * (degree + 1), lightingK = (lightingDegree + 1) * (lightingDegree + 1);
    const int width = channels * K;
    if (samples.width != width)
        refuse(who, "the samples carry " + std::to_string(samples.width) + " floats each, the transfer (" +
                        std::to_string(channels) + " channel(s) of degree " + std::to_string(degree) + ") " +
                        std::to_string(width));
    const std::size_t count = samples.count();
    if (count == 0) refuse(who, "no samples");
    if (samples.weights.size() != count || samples.groundTruth.size() != count * width)
        refuse(who, "the samples' weights or ground truth do not match their count");
    if (interpolated.size() != count * width)
        refuse(who, "the interpolated transfer holds " + std::to_string(interpolated.size()) + " floats, expected " +
                        std::to_string(count * width));
    if (lightings.empty()) refuse(who, "no lightings");
    for (std::size_t l = 0; l < lightings.size(); ++l) {
        if (lightings[l].size() != static_cast<std::size_t>(kColorChannels) * lightingK)
            refuse(who, "lighting " + std::to_string(l) + " has " + std::to_string(lightings[l].size()) +
                            " coefficients, expected 3 x " + std::to_string(lightingK));
        for (double c : lightings[l])
            if (!std::isfinite(c)) refuse(who, "lighting " + std::to_string(l) + " has a non-finite coefficient");
    }
    // Non-finite transfer would give NaN errors, which have no place in a sorted quantile.
    for (float v : samples.groundTruth)
        if (!std::isfinite(v)) refuse(who, "non-finite ground-truth transfer");
    for (float v : interpolated)
        if (!std::isfinite(v)) refuse(who, "non-finite interpolated transfer");
}

double checkedTotalWeight(const char* who, const RelightingSamples& samples) {
    double totalWeight = 0.0;
    for (float w : samples.weights) {
        if (!(w >= 0.0f) || !std::isfinite(w)) refuse(who, "sample weights must be finite and >= 0");
        totalWeight += w;
    }
    if (!(totalWeight > 0.0)) refuse(who, "the sample weights sum to zero");
    return totalWeight;
}

// The problem without its floors (setWeberFloors adds them).
ErrorProblem makeErrorProblem(const RelightingSamples& samples, const std::vector<float>& interpolated, int degree,
                              int channels, const std::vector<std::vector<double>>& lightings, int lightingDegree,
                              RelightingErrorNormalisation normalisation) {
    const int K = (degree + 1) * (degree + 1), lightingK = (lightingDegree + 1) * (lightingDegree + 1);
    const int width = channels * K;
    const int L = static_cast<int>(lightings.size());
    ErrorProblem problem;
    problem.absolute = normalisation == RelightingErrorNormalisation::MeanLuminance;
    problem.samples = &samples;
    problem.interpolated = &interpolated;
    problem.width = width;
    problem.lightingCount = L;
    problem.luminanceLighting.assign(static_cast<std::size_t>(width) * L, 0.0);
    const double rec709[3] = {luminanceRec709(1, 0, 0), luminanceRec709(0, 1, 0), luminanceRec709(0, 0, 1)};
    for (int l = 0; l < L; ++l)
        for (int ch = 0; ch < kColorChannels; ++ch)
            for (int k = 0; k < K; ++k) {
                // A 1-channel transfer serves the three channels: its luminance lighting is the
                // Rec. 709 mix of the channels' coefficients.
                const int row = (channels == 1 ? 0 : ch * K) + k;
                problem.luminanceLighting[static_cast<std::size_t>(row) * L + l] +=
                    rec709[ch] * lightings[l][static_cast<std::size_t>(ch) * lightingK + k];
            }
    return problem;
}

// Floors: the area-weighted mean luminance is <mean ground-truth transfer, v_l>.
void setWeberFloors(const char* who, ErrorProblem& problem, double totalWeight, int threads) {
    const RelightingSamples& samples = *problem.samples;
    const int width = problem.width, L = problem.lightingCount;
    const auto sampleTotal = static_cast<std::ptrdiff_t>(samples.count());
    std::vector<std::vector<double>> partialMeans(threads, std::vector<double>(width, 0.0));
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t s = 0; s < sampleTotal; ++s) {
        std::vector<double>& mean = partialMeans[omp_get_thread_num()];
        const float* t = samples.groundTruth.data() + s * width;
        for (int k = 0; k < width; ++k) mean[k] += static_cast<double>(samples.weights[s]) * t[k];
    }
    std::vector<double> meanTransfer(width, 0.0);
    for (const auto& partial : partialMeans)
        for (int k = 0; k < width; ++k) meanTransfer[k] += partial[k] / totalWeight;
    problem.floor.assign(L, 0.0);
    for (int l = 0; l < L; ++l) {
        double meanLuminance = 0.0;
        for (int k = 0; k < width; ++k) meanLuminance += meanTransfer[k] * problem.luminanceLighting[std::size_t(k) * L + l];
        problem.floor[l] = (problem.absolute ? 1.0 : kWeberFloorFraction) * meanLuminance;
        if (!(problem.floor[l] > 0.0))
            refuse(who, "lighting " + std::to_string(l) + " gives a mean luminance of " + std::to_string(meanLuminance) +
                            " over the samples: the Weber-normalised error needs a positive adaptation level");
    }
}

// Pass 1's results. Histogram h < L is lighting h's, h == L the one over all (sample, lighting) pairs.
struct FirstPass {
    std::vector<std::vector<double>> sums;  // per thread: weighted sum of e and of e^2 per lighting
    std::vector<double> histogram;          // (L + 1) x kBins weights, merged over the threads
};

// Sums and histograms, per thread (static schedule, merged in thread order: the same result for the
// same thread count).
FirstPass sumAndHistogramErrors(const ErrorProblem& problem, int threads) {
    const RelightingSamples& samples = *problem.samples;
    const int L = problem.lightingCount, histograms = L + 1;
    const std::size_t count = samples.count();
    const auto blockTotal = static_cast<std::ptrdiff_t>((count + kBlock - 1) / kBlock);
    FirstPass result;
    result.sums.assign(threads, std::vector<double>(2 * static_cast<std::size_t>(L), 0.0));
    std::vector<std::vector<double>> weightHistograms(threads);
#pragma omp parallel
    {
        const int thread = omp_get_thread_num();
        std::vector<double>& histogram = weightHistograms[thread];
        histogram.assign(static_cast<std::size_t>(histograms) * kBins, 0.0);
        std::vector<double>& sum = result.sums[thread];
        std::vector<double> errors(kBlock * L), luminance(L);
#pragma omp for schedule(static)
        for (std::ptrdiff_t b = 0; b < blockTotal; ++b)
            forEachSampleOfBlock(problem, b, errors, luminance, [&](std::size_t s, const double* e) {
                const double w = samples.weights[s];
                for (int l = 0; l < L; ++l) {
                    sum[2 * l] += w * e[l];
                    sum[2 * l + 1] += w * e[l] * e[l];
                    const std::size_t bin = binOf(e[l]);
                    histogram[static_cast<std::size_t>(l) * kBins + bin] += w;
                    histogram[static_cast<std::size_t>(L) * kBins + bin] += w;
                }
            });
    }
    for (std::size_t t = 1; t < weightHistograms.size(); ++t)
        for (std::size_t i = 0; i < weightHistograms[0].size(); ++i) weightHistograms[0][i] += weightHistograms[t][i];
    result.histogram = std::move(weightHistograms[0]);
    return result;
}

// Per histogram: the bin holding its quantile, the weight below that bin and the weight to reach.
struct QuantileBins {
    std::vector<std::size_t> bin;
    std::vector<double> weightBelow, target;
};

QuantileBins findQuantileBins(const std::vector<double>& histogram, double totalWeight, int L) {
    const int histograms = L + 1;
    QuantileBins q;
    q.bin.resize(histograms);
    q.weightBelow.resize(histograms);
    q.target.resize(histograms);
    for (int h = 0; h < histograms; ++h) {
        q.target[h] = kQuantile * totalWeight * (h == L ? L : 1) * (1.0 - kQuantileSlack);
        const double* row = histogram.data() + static_cast<std::size_t>(h) * kBins;
        double cumulative = 0.0;
        std::size_t bin = 0;
        while (bin + 1 < kBins && cumulative + row[bin] < q.target[h]) cumulative += row[bin++];
        q.bin[h] = bin;
        q.weightBelow[h] = cumulative;
    }
    return q;
}

using WeightedErrors = std::vector<std::pair<double, float>>;

// Pass 2: per thread and histogram, the (error, weight) pairs falling in the histogram's quantile bin.
std::vector<std::vector<WeightedErrors>> collectQuantileBins(const ErrorProblem& problem, const QuantileBins& q,
                                                             int threads) {
    const RelightingSamples& samples = *problem.samples;
    const int L = problem.lightingCount, histograms = L + 1;
    const std::size_t count = samples.count();
    const auto blockTotal = static_cast<std::ptrdiff_t>((count + kBlock - 1) / kBlock);
    const std::vector<std::size_t>& quantileBin = q.bin;
    std::vector<std::vector<WeightedErrors>> collected(threads, std::vector<WeightedErrors>(histograms));
#pragma omp parallel
    {
        auto& mine = collected[omp_get_thread_num()];
        std::vector<double> errors(kBlock * L), luminance(L);
#pragma omp for schedule(static)
        for (std::ptrdiff_t b = 0; b < blockTotal; ++b)
            forEachSampleOfBlock(problem, b, errors, luminance, [&](std::size_t s, const double* e) {
                const float w = samples.weights[s];
                for (int l = 0; l < L; ++l) {
                    const std::size_t bin = binOf(e[l]);
                    if (bin == 0) continue;
                    if (bin == quantileBin[l]) mine[l].emplace_back(e[l], w);
                    if (bin == quantileBin[L]) mine[L].emplace_back(e[l], w);
                }
            });
    }
    return collected;
}

// The exact quantile of histogram h from its bin's errors, sorted.
double quantileInBin(std::vector<std::vector<WeightedErrors>>& collected, const QuantileBins& q, int h) {
    WeightedErrors values;
    for (auto& perThread : collected) {
        values.insert(values.end(), perThread[h].begin(), perThread[h].end());
        perThread[h].clear();
        perThread[h].shrink_to_fit();
    }
    std::sort(values.begin(), values.end());
    double cumulative = q.weightBelow[h];
    double value = values.empty() ? 0.0 : values.back().first;
    for (const auto& [e, w] : values) {
        cumulative += w;
        if (cumulative >= q.target[h]) {
            value = e;
            break;
        }
    }
    return value;
}

// The quantile of every histogram. Bin 0 holds only exact zeros: a quantile there needs no second pass.
std::vector<double> exactQuantiles(const ErrorProblem& problem, const QuantileBins& q, int threads) {
    const int histograms = problem.lightingCount + 1;
    std::vector<double> quantiles(histograms, 0.0);
    bool anyToCollect = false;
    for (int h = 0; h < histograms; ++h) anyToCollect = anyToCollect || q.bin[h] != 0;
    if (!anyToCollect) return quantiles;
    std::vector<std::vector<WeightedErrors>> collected = collectQuantileBins(problem, q, threads);
    for (int h = 0; h < histograms; ++h)
        if (q.bin[h] != 0) quantiles[h] = quantileInBin(collected, q, h);
    return quantiles;
}

RelightingErrorReport assembleReport(const FirstPass& pass, const std::vector<double>& quantiles, double totalWeight,
                                     int L) {
    RelightingErrorReport report;
    report.perLighting.resize(L);
    double meanOfMeans = 0.0, meanOfSquares = 0.0;
    for (int l = 0; l < L; ++l) {
        double sumError = 0.0, sumSquare = 0.0;
        for (const auto& sum : pass.sums) {
            sumError += sum[2 * l];
            sumSquare += sum[2 * l + 1];
        }
        RelightingErrorStats& stats = report.perLighting[l];
        stats.meanRelativeError = sumError / totalWeight;
        stats.rmsRelativeError = std::sqrt(sumSquare / totalWeight);
        stats.p95RelativeError = quantiles[l];
        meanOfMeans += stats.meanRelativeError / L;
        meanOfSquares += sumSquare / totalWeight / L;
    }
    // Every lighting weighs the same total (the mesh area), so the pair-weighted mean is the mean
    // of the per-lighting means, and the RMS that of their mean squares.
    report.overall.meanRelativeError = meanOfMeans;
    report.overall.rmsRelativeError = std::sqrt(meanOfSquares);
    report.overall.p95RelativeError = quantiles[L];
    return report;
}

}  // namespace

RelightingErrorReport relightingErrorOverLightings(const RelightingSamples& samples,
                                                   const std::vector<float>& interpolated, int degree, int channels,
                                                   const std::vector<std::vector<double>>& lightings,
                                                   int lightingDegree, RelightingErrorNormalisation normalisation) {
    const char* who = "relightingError";
    checkErrorInput(who, samples, interpolated, degree, channels, lightings, lightingDegree);
    const double totalWeight = checkedTotalWeight(who, samples);
    const int threads = omp_get_max_threads();
    ErrorProblem problem =
        makeErrorProblem(samples, interpolated, degree, channels, lightings, lightingDegree, normalisation);
    setWeberFloors(who, problem, totalWeight, threads);
    const FirstPass pass = sumAndHistogramErrors(problem, threads);
    const QuantileBins bins = findQuantileBins(pass.histogram, totalWeight, problem.lightingCount);
    const std::vector<double> quantiles = exactQuantiles(problem, bins, threads);
    return assembleReport(pass, quantiles, totalWeight, problem.lightingCount);
}

RelightingErrorStats relightingError(const RelightingSamples& samples, const std::vector<float>& interpolated,
                                     int degree, int channels, const std::vector<double>& lighting,
                                     int lightingDegree) {
    return relightingErrorOverLightings(samples, interpolated, degree, channels, {lighting}, lightingDegree)
        .perLighting.front();
}

}  // namespace rad
