#include "simplify/radiance_collapse_error.h"

#include "radiance/radiance_evaluation.h"
#include "radiance/radiance_frame.h"
#include "radiance/radiance_interpolation.h"
#include "radiance/spherical_harmonics.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

namespace rad {

namespace {

template <typename T>
T* grow(std::vector<T>& buffer, std::size_t n) {
    if (buffer.size() < n) buffer.resize(n);
    return buffer.data();
}

// Per-thread working memory: price*() runs concurrently on different sources. Buffers only grow,
// so after the first few queries no query allocates.
struct Scratch {
    std::vector<double> directions;  // 3P: x[0..P), y[0..P), z[0..P), world directions of Omega(n0)
    std::vector<double> basis;       // K x kChunk: monomials / harmonics of a chunk, times sqrt(weight)
    std::vector<double> sh;          // K
    std::vector<double> sharedHarmonics;  // K x P (chunk-blocked): weighted SH at the directions
    std::vector<double> coefficients;  // 3K, one RF in double
    std::vector<double> interpolated;  // 3K, L~v of a full collapse
    std::vector<double> values;      // (m + 1) columns of 3P: sampled weighted L~, then D_j
    std::vector<double> gram;        // m x m
    std::vector<std::uint32_t> ids;  // the m vertices behind columns 1..m
    std::vector<int> faceColumns;    // 2 per star face: Gram indices of a and b
    std::vector<int> targetColumns;  // Gram index of each target
};
thread_local Scratch tScratch;

// The rule's local points rotated to Omega(n) (frame frameFromNormal(n), as HemisphereIntegrator
// does): same arithmetic as Frame::toWorld, x t + y b + z n.
void hemisphereDirections(const Frame& h, const std::vector<double>& lx, const std::vector<double>& ly,
                          const std::vector<double>& lz, double* out) {
    const int P = static_cast<int>(lx.size());
    double* dx = out;
    double* dy = out + P;
    double* dz = out + 2 * P;
    for (int j = 0; j < P; ++j) {
        dx[j] = lx[j] * h.t.x() + ly[j] * h.b.x() + lz[j] * h.n.x();
        dy[j] = lx[j] * h.t.y() + ly[j] * h.b.y() + lz[j] * h.n.y();
        dz[j] = lx[j] * h.t.z() + ly[j] * h.b.z() + lz[j] * h.n.z();
    }
}

// Points are processed in chunks of kChunk: the monomials / harmonics of a chunk (K x kChunk,
// k-major) stay in L1 and the accumulation below keeps its kChunk sums per channel in registers.
// The rule is padded to a multiple of kChunk with zero-weight points (the pole), which add nothing.
constexpr int kChunk = 8;

using Chunk = Eigen::Array<double, kChunk, 1>;  // Eigen keeps it in SIMD registers

// out[c * P + j] = sum_k coef[c * K + k] * basis[k * kChunk + j], j < kChunk, for the 3 channels.
inline void accumulateChunk(const double* basis, int K, const double* coef, int P, double* out) {
    for (int c = 0; c < kColorChannels; ++c) {
        const double* cc = coef + c * K;
        Chunk sum = cc[0] * Eigen::Map<const Chunk>(basis);
        for (int k = 1; k < K; ++k) sum += cc[k] * Eigen::Map<const Chunk>(basis + k * kChunk);
        Eigen::Map<Chunk>(out + static_cast<std::size_t>(c) * P) = sum;
    }
}

// out[c * P + j] = sqrt(weight_j) * L~_c(w_j): the r-RF (sec. 3.1) of one RF with coefficients
// `coef` (3 channel blocks of K doubles) stored for `frame` in reflected or plain storage, sampled
// at the P directions (P a multiple of kChunk), border-extended about the RF's own normal (sec. 7).
// The direction handling is basisDirection(basis, frame, w, !storedReflected) of
// radiance_evaluation.h, done here for a chunk of directions at once.
void sampleReflected(const BasisSpec& basis, const Frame& frame, bool storedReflected, const double* coef,
                     const double* directions, const double* sqrtWeights, int P, Scratch& s, double* out) {
    const int K = basis.coefficientCount();
    const double* dx = directions;
    const double* dy = directions + P;
    const double* dz = directions + 2 * P;
    double* B = grow(s.basis, static_cast<std::size_t>(K) * kChunk);
    const Frame& f = frame;
    if (basis.usesLocalFrame()) {
        // PB: local (x, y) = (t.w, b.w); below the tangent plane the border direction is (x, y)
        // normalised; plain storage gives L~(w) = C(R_n w) and R_n is (x, y, z) -> (-x, -y, z) locally.
        const double flip = storedReflected ? 1.0 : -1.0;
        for (int j0 = 0; j0 < P; j0 += kChunk) {
            double u[kChunk], v[kChunk];
            for (int j = 0; j < kChunk; ++j) {
                const double wx = dx[j0 + j], wy = dy[j0 + j], wz = dz[j0 + j];
                double x = f.t.x() * wx + f.t.y() * wy + f.t.z() * wz;
                double y = f.b.x() * wx + f.b.y() * wy + f.b.z() * wz;
                double z = f.n.x() * wx + f.n.y() * wy + f.n.z() * wz;
                borderExtendLocal(x, y, z);
                u[j] = flip * x;
                v[j] = flip * y;
            }
            // Monomials u^(t-i) v^i in polynomialIndex order, each one product of an earlier one:
            // (t, i) = u * (t-1, i) for i < t, v * (t-1, t-1) for i = t. Monomial 0 carries
            // sqrt(weight), so every monomial, hence every value, is weighted.
            const Eigen::Map<const Chunk> U(u), V(v);
            const auto monomial = [B](int index) { return Eigen::Map<Chunk>(B + index * kChunk); };
            monomial(0) = Eigen::Map<const Chunk>(sqrtWeights + j0);
            for (int t = 1; t <= basis.degree; ++t) {
                const int row = t * (t + 1) / 2, previous = (t - 1) * t / 2;
                for (int i = 0; i < t; ++i) monomial(row + i) = monomial(previous + i) * U;
                monomial(row + t) = monomial(previous + t - 1) * V;
            }
            accumulateChunk(B, K, coef, P, out + j0);
        }
        return;
    }
    // SH (global frame): border direction normalize(w - (n.w) n) below the tangent plane (the
    // tangent at the opposite pole), then R_n for plain storage. With reflected storage (what the
    // metric uses) L~(w) = C(w) wherever n.w >= 0, so the harmonics at the rule's own directions,
    // evaluated once per hemisphere (s.sharedHarmonics, see prepareHemisphere), serve every RF; only
    // the directions below this RF's horizon (a band of width ~ the tilt between the normals) are
    // re-evaluated at their border direction.
    double* y = grow(s.sh, K);
    const auto column = [&](int j0, int j, Eigen::Vector3d d) {
        d = borderExtendedDirection(f, d);
        if (!storedReflected) d = reflect(f.n, d);
        evaluateSphericalHarmonics(basis.degree, d.x(), d.y(), d.z(), y);
        const double w = sqrtWeights[j0 + j];
        for (int k = 0; k < K; ++k) B[k * kChunk + j] = w * y[k];
    };
    for (int j0 = 0; j0 < P; j0 += kChunk) {
        if (!storedReflected) {
            for (int j = 0; j < kChunk; ++j) column(j0, j, Eigen::Vector3d(dx[j0 + j], dy[j0 + j], dz[j0 + j]));
            accumulateChunk(B, K, coef, P, out + j0);
            continue;
        }
        const double* shared = s.sharedHarmonics.data() + static_cast<std::size_t>(j0) * K;
        bool below = false;
        for (int j = 0; j < kChunk; ++j)
            below |= f.n.x() * dx[j0 + j] + f.n.y() * dy[j0 + j] + f.n.z() * dz[j0 + j] < 0.0;
        if (!below) {
            accumulateChunk(shared, K, coef, P, out + j0);
            continue;
        }
        std::copy(shared, shared + K * kChunk, B);
        for (int j = 0; j < kChunk; ++j) {
            const Eigen::Vector3d d(dx[j0 + j], dy[j0 + j], dz[j0 + j]);
            if (f.n.dot(d) < 0.0) column(j0, j, d);
        }
        accumulateChunk(B, K, coef, P, out + j0);
    }
}

// The rule rotated to Omega(n) (frame h = frameFromNormal(n)) into s.directions, and for SH the
// weighted harmonics at those directions, chunk-blocked like `basis` (K x kChunk per chunk).
void prepareHemisphere(const BasisSpec& basis, const Frame& h, const std::vector<double>& lx,
                       const std::vector<double>& ly, const std::vector<double>& lz, const double* sqrtWeights,
                       Scratch& s) {
    const int P = static_cast<int>(lx.size());
    double* directions = grow(s.directions, 3 * static_cast<std::size_t>(P));
    hemisphereDirections(h, lx, ly, lz, directions);
    if (basis.usesLocalFrame()) return;
    const int K = basis.coefficientCount();
    double* shared = grow(s.sharedHarmonics, static_cast<std::size_t>(K) * P);
    double* y = grow(s.sh, K);
    for (int j = 0; j < P; ++j) {
        evaluateSphericalHarmonics(basis.degree, directions[j], directions[P + j], directions[2 * P + j], y);
        double* block = shared + static_cast<std::size_t>(j / kChunk) * K * kChunk + j % kChunk;
        for (int k = 0; k < K; ++k) block[k * kChunk] = sqrtWeights[j] * y[k];
    }
}

// Columns 1..m of `values` become D_j = column 0 - column j; gram = D^T D (m x m, symmetric, full).
void differenceGram(double* values, int rows, int m, double* gram) {
    const Eigen::Map<const Eigen::VectorXd> target(values, rows);
    for (int j = 1; j <= m; ++j) {
        Eigen::Map<Eigen::VectorXd> column(values + static_cast<std::size_t>(j) * rows, rows);
        column = target - column;
    }
    for (int i = 0; i < m; ++i) {
        const Eigen::Map<const Eigen::VectorXd> di(values + static_cast<std::size_t>(i + 1) * rows, rows);
        for (int j = 0; j <= i; ++j) {
            const Eigen::Map<const Eigen::VectorXd> dj(values + static_cast<std::size_t>(j + 1) * rows, rows);
            gram[i * m + j] = gram[j * m + i] = di.dot(dj);
        }
    }
}

// beta^T G beta over the three Gram indices of a triangle, clamped at 0 (a true squared norm; only
// rounding can make the form negative).
double quadraticForm(const double* gram, int m, const int index[3], const Eigen::Vector3d& beta) {
    double sum = 0.0;
    for (int r = 0; r < 3; ++r) {
        const double* row = gram + static_cast<std::size_t>(index[r]) * m;
        sum += beta[r] * (beta[0] * row[index[0]] + beta[1] * row[index[1]] + beta[2] * row[index[2]]);
    }
    return std::max(0.0, sum);
}

// Index of vertex v among ids[0..m) (appended when absent): linear search, stars are small.
int columnOf(std::uint32_t v, std::uint32_t* ids, int& m) {
    for (int i = 0; i < m; ++i)
        if (ids[i] == v) return i;
    ids[m] = v;
    return m++;
}

void loadCoefficients(const RadianceField& field, std::uint32_t v, double* out) {
    const int count = field.coefficientsPerVertex();
    const float* src = field.vertexCoefficients(v);
    for (int k = 0; k < count; ++k) out[k] = static_cast<double>(src[k]);
}

// Vertex v's reflected RF sampled at the prepared directions (sampleReflected with its stored
// coefficients and frame); `coef` is scratch for the coefficients.
void sampleVertex(const RadianceField& field, std::uint32_t v, const double* directions, const double* sqrtWeights,
                  int P, Scratch& s, double* coef, double* out) {
    loadCoefficients(field, v, coef);
    sampleReflected(field.basis, frameFromStored(field.frame(v)), field.reflected, coef, directions, sqrtWeights, P, s,
                    out);
}

double triangleArea(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    return 0.5 * (b - a).cross(c - a).norm();
}

}  // namespace

int defaultCollapseZNodes(const BasisSpec& basis) { return std::max(0, basis.degree) + 1; }

HemisphereIntegrator defaultCollapseIntegrator(const BasisSpec& basis) {
    const int m = defaultCollapseZNodes(basis);
    return HemisphereIntegrator::gaussProduct(m, 2 * m);
}

RadianceCollapseMetric::RadianceCollapseMetric(RadianceField& field, RadianceCollapseOptions options)
    : field_(field), rule_(options.rule ? std::move(*options.rule) : defaultCollapseIntegrator(field.basis)) {
    const std::string why = field_.validate();
    if (!why.empty()) throw std::invalid_argument("radiance collapse metric: " + why);
    if (rule_.size() == 0) throw std::invalid_argument("radiance collapse metric: empty hemisphere rule");
    for (double w : rule_.weights())
        if (!(w >= 0.0) || !std::isfinite(w))
            throw std::invalid_argument("radiance collapse metric: hemisphere rule weights must be finite and >= 0");
    // Sec. 4.3 / 6: full collapses interpolate SH coefficients of L~ in the global frame.
    if (field_.basis.kind == BasisKind::SphericalHarmonics) setReflectedStorage(field_, true);
    // The rule as flat arrays, padded to a multiple of kChunk with zero-weight points.
    const std::size_t padded = (rule_.size() + kChunk - 1) / kChunk * kChunk;
    for (std::size_t i = 0; i < padded; ++i) {
        const bool real = i < rule_.size();
        localX_.push_back(real ? rule_.localPoints()[i].x() : 0.0);
        localY_.push_back(real ? rule_.localPoints()[i].y() : 0.0);
        localZ_.push_back(real ? rule_.localPoints()[i].z() : 1.0);
        sqrtWeights_.push_back(real ? std::sqrt(rule_.weights()[i]) : 0.0);
    }
}

void RadianceCollapseMetric::checkMesh(const CollapseMesh& mesh) const {
    if (mesh.vertexCount() != field_.vertexCount())
        throw std::invalid_argument("radiance collapse metric: the mesh has " + std::to_string(mesh.vertexCount()) +
                                    " vertices but the radiance field " + std::to_string(field_.vertexCount()));
}

void RadianceCollapseMetric::priceHalfEdges(const CollapseMesh& mesh, const HalfEdgeQuery& query,
                                            double* costs) const {
    checkMesh(mesh);
    if (query.targetCount <= 0) return;
    Scratch& s = tScratch;
    const int P = static_cast<int>(localX_.size());
    const int K = field_.coefficientsPerChannel();
    const int rows = kColorChannels * P;
    const std::uint32_t v0 = query.source;

    // The m distinct vertices other than v0 (ring, then targets that are not in it).
    std::uint32_t* ids = grow(s.ids, 2 * static_cast<std::size_t>(query.starSize) + query.targetCount);
    int* faceColumns = grow(s.faceColumns, 2 * static_cast<std::size_t>(query.starSize));
    int* targetColumns = grow(s.targetColumns, static_cast<std::size_t>(query.targetCount));
    int m = 0;
    for (int f = 0; f < query.starSize; ++f) {
        faceColumns[2 * f] = columnOf(query.star[f].a, ids, m);
        faceColumns[2 * f + 1] = columnOf(query.star[f].b, ids, m);
    }
    for (int t = 0; t < query.targetCount; ++t) targetColumns[t] = columnOf(query.targets[t], ids, m);

    // Sample L~0 and every L~_j once over Omega(n0).
    const Frame frame0 = frameFromStored(field_.frame(v0));
    prepareHemisphere(field_.basis, frameFromNormal(frame0.n), localX_, localY_, localZ_, sqrtWeights_.data(), s);
    const double* directions = s.directions.data();
    double* values = grow(s.values, static_cast<std::size_t>(rows) * (m + 1));
    double* coef = grow(s.coefficients, static_cast<std::size_t>(kColorChannels) * K);
    sampleVertex(field_, v0, directions, sqrtWeights_.data(), P, s, coef, values);
    for (int i = 0; i < m; ++i)
        sampleVertex(field_, ids[i], directions, sqrtWeights_.data(), P, s, coef,
                     values + static_cast<std::size_t>(i + 1) * rows);
    double* gram = grow(s.gram, static_cast<std::size_t>(m) * m);
    differenceGram(values, rows, m, gram);

    // Eq. (7) per target over the post-collapse triangles (v1, a, b).
    const Eigen::Vector3d p0 = mesh.position(v0);
    for (int t = 0; t < query.targetCount; ++t) {
        const std::uint32_t v1 = query.targets[t];
        const Eigen::Vector3d p1 = mesh.position(v1);
        double cost = 0.0;
        for (int f = 0; f < query.starSize; ++f) {
            const StarFace& face = query.star[f];
            if (face.a == v1 || face.b == v1) continue;  // killed by the collapse
            const Eigen::Vector3d pa = mesh.position(face.a), pb = mesh.position(face.b);
            const std::optional<TriangleGradient> gradient = TriangleGradient::create(p1, pa, pb);
            if (!gradient) continue;  // degenerate: see the header
            const int index[3] = {targetColumns[t], faceColumns[2 * f], faceColumns[2 * f + 1]};
            cost += triangleArea(p1, pa, pb) * quadraticForm(gram, m, index, gradient->extrapolationWeights(p0));
        }
        costs[t] = cost;
    }
}

bool RadianceCollapseMetric::supportsFullCollapse(std::string& why) const {
    if (field_.basis.kind == BasisKind::SphericalHarmonics) {
        why.clear();
        return true;
    }
    why = "full edge collapse needs a rotation-invariant basis (SH) to interpolate radiance functions along the "
          "edge (Vanhoey et al. 2015 sec. 4.3); " +
          field_.basis.name() + " lives in per-vertex tangent frames: use half-edge collapses";
    return false;
}

double RadianceCollapseMetric::priceEdge(const CollapseMesh& mesh, const EdgeQuery& query) const {
    if (field_.basis.kind != BasisKind::SphericalHarmonics) return std::numeric_limits<double>::infinity();
    checkMesh(mesh);
    Scratch& s = tScratch;
    const int P = static_cast<int>(localX_.size());
    const int K = field_.coefficientsPerChannel();
    const int rows = kColorChannels * P;
    const int count = kColorChannels * K;
    const double sp = std::min(1.0, std::max(0.0, query.s));

    // The new vertex v: L~v = (1 - s) L~0 + s L~1 on (reflected, global-frame) coefficients, normal
    // nv = normalize((1 - s) n0 + s n1).
    const Frame frame0 = frameFromStored(field_.frame(query.v0));
    const Frame frame1 = frameFromStored(field_.frame(query.v1));
    const Eigen::Vector3d nv = (1.0 - sp) * frame0.n + sp * frame1.n;
    const double length = nv.norm();
    if (!(length >= 1e-12)) return std::numeric_limits<double>::infinity();
    const Frame frameV = frameFromNormal(nv / length);
    double* interpolated = grow(s.interpolated, static_cast<std::size_t>(count));
    {
        const float* c0 = field_.vertexCoefficients(query.v0);
        const float* c1 = field_.vertexCoefficients(query.v1);
        for (int k = 0; k < count; ++k)
            interpolated[k] = (1.0 - sp) * static_cast<double>(c0[k]) + sp * static_cast<double>(c1[k]);
    }

    // Eq. (7) at the old vertex vt over the triangles (v, a, b) of its star, Omega(nt).
    const auto side = [&](std::uint32_t vt, const Frame& frameT, const StarFace* star, int starSize) {
        if (starSize <= 0) return 0.0;
        // Sampled columns: 0 = L~t, 1 = L~v, 2 + i = ring vertex ids[i]; Gram index = column - 1.
        std::uint32_t* ids = grow(s.ids, 2 * static_cast<std::size_t>(starSize));
        int* faceColumns = grow(s.faceColumns, 2 * static_cast<std::size_t>(starSize));
        int ring = 0;
        for (int f = 0; f < starSize; ++f) {
            faceColumns[2 * f] = 1 + columnOf(star[f].a, ids, ring);
            faceColumns[2 * f + 1] = 1 + columnOf(star[f].b, ids, ring);
        }
        const int m = ring + 1;
        prepareHemisphere(field_.basis, frameFromNormal(frameT.n), localX_, localY_, localZ_, sqrtWeights_.data(), s);
        const double* directions = s.directions.data();
        double* values = grow(s.values, static_cast<std::size_t>(rows) * (m + 1));
        double* coef = grow(s.coefficients, static_cast<std::size_t>(count));
        sampleVertex(field_, vt, directions, sqrtWeights_.data(), P, s, coef, values);
        sampleReflected(field_.basis, frameV, true, interpolated, directions, sqrtWeights_.data(), P, s,
                        values + rows);
        for (int i = 0; i < ring; ++i)
            sampleVertex(field_, ids[i], directions, sqrtWeights_.data(), P, s, coef,
                         values + static_cast<std::size_t>(i + 2) * rows);
        double* gram = grow(s.gram, static_cast<std::size_t>(m) * m);
        differenceGram(values, rows, m, gram);
        const Eigen::Vector3d pt = mesh.position(vt);
        double cost = 0.0;
        for (int f = 0; f < starSize; ++f) {
            const Eigen::Vector3d pa = mesh.position(star[f].a), pb = mesh.position(star[f].b);
            const std::optional<TriangleGradient> gradient = TriangleGradient::create(query.position, pa, pb);
            if (!gradient) continue;  // degenerate: see the header
            const int index[3] = {0, faceColumns[2 * f], faceColumns[2 * f + 1]};
            cost += triangleArea(query.position, pa, pb) *
                    quadraticForm(gram, m, index, gradient->extrapolationWeights(pt));
        }
        return cost;
    };
    return side(query.v0, frame0, query.star0, query.star0Size) + side(query.v1, frame1, query.star1, query.star1Size);
}

void RadianceCollapseMetric::onCollapse(const CollapseMesh& mesh, const EdgeQuery& query) {
    const double sp = std::min(1.0, std::max(0.0, query.s));
    if (sp == 1.0) return;  // half-edge collapse (or a full one clamped onto p1): v1 keeps its RF
    if (field_.basis.kind != BasisKind::SphericalHarmonics)
        throw std::logic_error("radiance collapse metric: full edge collapse on a " + field_.basis.name() +
                               " field (sec. 4.3 needs SH)");
    checkMesh(mesh);
    const int count = field_.coefficientsPerVertex();
    const float* c0 = field_.vertexCoefficients(query.v0);
    float* c1 = field_.vertexCoefficients(query.v1);
    for (int k = 0; k < count; ++k)
        c1[k] = static_cast<float>((1.0 - sp) * static_cast<double>(c0[k]) + sp * static_cast<double>(c1[k]));
    const Eigen::Vector3d nv =
        (1.0 - sp) * frameFromStored(field_.frame(query.v0)).n + sp * frameFromStored(field_.frame(query.v1)).n;
    // Opposite normals cannot be interpolated; priceEdge forbids that collapse, so keep v1's frame
    // if another metric made the engine do it anyway.
    if (nv.norm() >= 1e-12) storeFrame(frameFromNormal(nv), field_.frame(query.v1));
}

}  // namespace rad
