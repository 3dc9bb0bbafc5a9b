#include "simplify/radiance_quadric.h"

#include "radiance/material_radiance.h"
#include "radiance/radiance_evaluation.h"
#include "radiance/radiance_frame.h"
#include "simplify/vertex_disjoint_face_blocks.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <omp.h>

#include <algorithm>
#include <cstdlib>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace rad {

namespace {

// Layout of the geometric block of one vertex.
constexpr int kA = 0;   // xx, xy, xz, yy, yz, zz
constexpr int kB = 6;   // 3
constexpr int kC = 9;
constexpr int kW = 10;       // 3: the attribute weight of each colour channel
constexpr int kPlanes = 13;  // the plane terms alone: A (6), b (3), c, for placing full collapses
constexpr int kGeometric = 23;
static_assert(kGeometric == 23, "FaceQuadric::geometric holds one vertex's geometric block");

// d sRGB / d linear at L (IEC 61966-2-1), the local scale of an error in 8-bit units.
double srgbSlope(double linear) {
    return linear <= 0.0031308 ? 12.92 : 1.055 / 2.4 * std::pow(linear, 1.0 / 2.4 - 1.0);
}

// Adds weight (n.p + d)^2 to a block laid out as A (6, upper triangle), b (3), c: the plane terms and
// each attribute's (g.p + e)^2 share this form.
void addSquaredLinear(double* block, double weight, const Eigen::Vector3d& n, double d) {
    block[0] += weight * n.x() * n.x();
    block[1] += weight * n.x() * n.y();
    block[2] += weight * n.x() * n.z();
    block[3] += weight * n.y() * n.y();
    block[4] += weight * n.y() * n.z();
    block[5] += weight * n.z() * n.z();
    for (int i = 0; i < 3; ++i) block[6 + i] += weight * d * n[i];
    block[9] += weight * d * d;
}

// p^T A p + 2 b.p + c of such a block.
double evaluateQuadratic(const double* block, const Eigen::Vector3d& p) {
    return block[0] * p.x() * p.x() + block[3] * p.y() * p.y() + block[5] * p.z() * p.z() +
           2.0 * (block[1] * p.x() * p.y() + block[2] * p.x() * p.z() + block[4] * p.y() * p.z()) +
           2.0 * (block[6] * p.x() + block[7] * p.y() + block[8] * p.z()) + block[9];
}

Eigen::Matrix3d symmetric(const double* a) {
    Eigen::Matrix3d m;
    m << a[0], a[1], a[2], a[1], a[3], a[4], a[2], a[4], a[5];
    return m;
}

}  // namespace

// Q_v0 + Q_v1 unpacked: the geometric block and pointers to both vertices' gradients.
struct RadianceQuadricMetric::Sum {
    double g[kGeometric];
    const double* grad0;
    const double* grad1;
};

// One vertex's (or face's) attribute planes G_j.p + E_j: 4 m doubles, one array per component.
RadianceQuadricMetric::GradientBlock RadianceQuadricMetric::gradientBlock(const double* block) const {
    return {block, block + m_, block + 2 * m_, block + 3 * m_};
}

RadianceQuadricMetric::RadianceQuadricMetric(const CollapseMesh& mesh, RadianceField& field, RadianceQuadricOptions options)
    : field_(field), options_(options), conversion_(field.basis) {
    if (field.vertexCount() != mesh.vertexCount() || !field.validate().empty())
        throw std::invalid_argument("the radiance field does not match the mesh (one radiance function per vertex)");
    if (!(options.geometryWeight >= 0.0 && std::isfinite(options.geometryWeight)) ||
        !(options.radianceWeight >= 0.0 && std::isfinite(options.radianceWeight)))
        throw std::invalid_argument("the radiance quadric's weights must be finite and >= 0");
    const std::size_t nv = mesh.vertexCount();
    kSh_ = conversion_.worldPerChannel();
    m_ = conversion_.worldPerVertex();

    // Normalised positions: the bounding box of the alive vertices, diagonal 1.
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (std::uint32_t v = 0; v < nv; ++v) {
        if (!mesh.vertexAlive(v)) continue;
        lo = lo.cwiseMin(mesh.position(v));
        hi = hi.cwiseMax(mesh.position(v));
    }
    if (lo.x() <= hi.x()) {
        centre_ = 0.5 * (lo + hi);
        const double diagonal = (hi - lo).norm();
        positionScale_ = diagonal > 0.0 ? 1.0 / diagonal : 1.0;
    }

    // Attributes: L2 coordinates divided by the RMS norm of the field's functions. The conversions run
    // in parallel; the norms are summed in vertex order, so the scale does not depend on the threads.
    const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
    attributes_.resize(nv * m_);
    std::vector<double> squaredNorm(nv, 0.0);
    const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(nv);
#pragma omp parallel for schedule(static) num_threads(threads)
    for (std::ptrdiff_t v = 0; v < count; ++v) {
        float* a = attributes_.data() + std::size_t(v) * m_;
        toMetric(std::size_t(v), a);
        if (!mesh.vertexAlive(static_cast<std::uint32_t>(v))) continue;
        double sum = 0.0;
        for (int j = 0; j < m_; ++j) sum += double(a[j]) * a[j];
        squaredNorm[std::size_t(v)] = sum;
    }
    double sumSquares = 0.0;
    std::size_t counted = 0;
    for (std::size_t v = 0; v < nv; ++v) {
        if (!mesh.vertexAlive(static_cast<std::uint32_t>(v))) continue;
        sumSquares += squaredNorm[v];
        ++counted;
    }
    const double rms = counted > 0 ? std::sqrt(sumSquares / counted) : 0.0;
    attributeScale_ = std::sqrt(options.radianceWeight) / (rms > 0.0 ? rms : 1.0);
    const std::ptrdiff_t values = static_cast<std::ptrdiff_t>(attributes_.size());
#pragma omp parallel for schedule(static) num_threads(threads)
    for (std::ptrdiff_t i = 0; i < values; ++i) attributes_[std::size_t(i)] = static_cast<float>(attributes_[std::size_t(i)] * attributeScale_);

    // Per channel and vertex: how much an error there weighs, (sRGB slope at the vertex's mean colour)
    // ^ perceptualExponent, normalised to mean 1 over the vertices; a face takes its corners' mean.
    const std::vector<float> channelWeight = perceptualChannelWeights(field, options.perceptualExponent);
    buildVertexQuadrics(mesh, channelWeight);
}

std::vector<float> RadianceQuadricMetric::perceptualChannelWeights(const RadianceField& field, double exponent) {
    const std::size_t nv = field.vertexCount();
    std::vector<float> channelWeight(3 * nv, 1.0f);
    if (!(exponent > 0.0)) return channelWeight;
    std::vector<float> mean(3 * nv);
    meanHemisphereColors(field, mean.data());
    double total = 0.0;
    for (std::size_t i = 0; i < 3 * nv; ++i) {
        channelWeight[i] = static_cast<float>(std::pow(srgbSlope(std::max(0.0f, mean[i])), exponent));
        total += channelWeight[i];
    }
    const double norm = total > 0.0 ? 3.0 * nv / total : 1.0;
    for (float& w : channelWeight) w = static_cast<float>(w * norm);
    return channelWeight;
}

// Each vertex's quadric is the sum of its faces'. Each face is computed once and added to its three
// corners. Threads take blocks of consecutive faces (which share corners: the corners' blocks of
// doubles stay in cache), one class of blocks at a time (vertex_disjoint_face_blocks.h), so that no
// two threads write one vertex whatever the vertex order (subdivided or merged scans number the
// corners of one face far apart) and every vertex sums its faces in the same order on any thread count.
void RadianceQuadricMetric::buildVertexQuadrics(const CollapseMesh& mesh, const std::vector<float>& channelWeight) {
    const std::size_t nv = mesh.vertexCount(), nf = mesh.faceCount();
    geometric_.assign(nv * kGeometric, 0.0);
    gradients_.assign(nv * 4 * static_cast<std::size_t>(m_), 0.0);
    const VertexDisjointFaceBlocks blocks = vertexDisjointFaceBlocks(mesh);
    const int threads = options_.threads > 0 ? options_.threads : omp_get_max_threads();
#pragma omp parallel num_threads(threads)
    {
        FaceQuadric face(m_);
        for (std::size_t c = 0; c < blocks.classCount(); ++c) {
            const std::ptrdiff_t begin = static_cast<std::ptrdiff_t>(blocks.offsets[c]),
                                 end = static_cast<std::ptrdiff_t>(blocks.offsets[c + 1]);
#pragma omp for schedule(dynamic, 1)
            for (std::ptrdiff_t i = begin; i < end; ++i) {
                const std::size_t first = std::size_t(blocks.blocks[std::size_t(i)]) * blocks.blockSize,
                                  last = std::min(nf, first + blocks.blockSize);
                for (std::size_t f = first; f < last; ++f) {
                    if (!mesh.faceAlive(static_cast<std::uint32_t>(f))) continue;
                    const std::uint32_t* t = mesh.face(static_cast<std::uint32_t>(f));
                    if (!faceQuadric(mesh, t, channelWeight, face)) continue;  // no area, no weight
                    for (int corner = 0; corner < 3; ++corner) {
                        double* q = geometric_.data() + std::size_t(t[corner]) * kGeometric;
                        for (int k = 0; k < kGeometric; ++k) q[k] += face.geometric[k];
                        double* g = gradients_.data() + std::size_t(t[corner]) * 4 * m_;
                        for (int k = 0; k < 4 * m_; ++k) g[k] += face.gradients[k];
                    }
                }
            }
        }
    }
}

// One face's quadric (Hoppe 1999 sec. 4): its plane, and each attribute's plane g.p + e through the
// corners' values, weighted by the face's area (and the channel's perceptual weight).
bool RadianceQuadricMetric::faceQuadric(const CollapseMesh& mesh, const std::uint32_t* t,
                                        const std::vector<float>& channelWeight, FaceQuadric& out) const {
    const Eigen::Vector3d p0 = normalise(mesh.position(t[0])), p1 = normalise(mesh.position(t[1])),
                          p2 = normalise(mesh.position(t[2]));
    const Eigen::Vector3d e1 = p1 - p0, e2 = p2 - p0;
    const Eigen::Vector3d cross = e1.cross(e2);
    const double doubleArea = cross.norm();
    if (!(doubleArea > 0.0)) return false;
    const double area = 0.5 * doubleArea;
    const Eigen::Vector3d normal = cross / doubleArea;
    const double d = -normal.dot(p0);
    double* q = out.geometric.data();
    std::fill(out.geometric.begin(), out.geometric.end(), 0.0);
    addSquaredLinear(q + kA, area * options_.geometryWeight, normal, d);
    addSquaredLinear(q + kPlanes, area, normal, d);
    double channelArea[3];
    for (int c = 0; c < 3; ++c) {
        channelArea[c] = area * (channelWeight[3 * t[0] + c] + channelWeight[3 * t[1] + c] + channelWeight[3 * t[2] + c]) / 3.0;
        q[kW + c] = channelArea[c];
    }
    // Attribute gradients in the face's plane: g.p_i + e = s_i at the corners.
    const double a11 = e1.dot(e1), a12 = e1.dot(e2), a22 = e2.dot(e2);
    const double det = a11 * a22 - a12 * a12;
    const float* s0 = attributes_.data() + std::size_t(t[0]) * m_;
    const float* s1 = attributes_.data() + std::size_t(t[1]) * m_;
    const float* s2 = attributes_.data() + std::size_t(t[2]) * m_;
    const bool planar = det > 1e-14 * a11 * a22;
    double* gradients = out.gradients.data();
    for (int j = 0; j < m_; ++j) {
        const double weight = channelArea[j / kSh_];
        Eigen::Vector3d grad = Eigen::Vector3d::Zero();
        double offset = (double(s0[j]) + s1[j] + s2[j]) / 3.0;
        if (planar) {
            const double d1 = double(s1[j]) - s0[j], d2 = double(s2[j]) - s0[j];
            const double alpha = (a22 * d1 - a12 * d2) / det, beta = (a11 * d2 - a12 * d1) / det;
            grad = alpha * e1 + beta * e2;
            offset = s0[j] - grad.dot(p0);
        }
        addSquaredLinear(q + kA, weight, grad, offset);
        for (int i = 0; i < 3; ++i) gradients[i * m_ + j] = weight * grad[i];
        gradients[3 * m_ + j] = weight * offset;
    }
    return true;
}

std::size_t RadianceQuadricMetric::bytes() const {
    return (geometric_.size() + gradients_.size()) * sizeof(double) + attributes_.size() * sizeof(float);
}

void RadianceQuadricMetric::toMetric(std::size_t v, float* attributes) const {
    double world[kColorChannels * kMaxCoefficientsPerChannel];
    conversion_.toWorld(field_.vertexCoefficients(v), field_.frame(v), world);
    for (int j = 0; j < m_; ++j) attributes[j] = static_cast<float>(world[j]);
}

void RadianceQuadricMetric::attributes(std::uint32_t v, double* out) const {
    const float* a = attributes_.data() + std::size_t(v) * m_;
    for (int j = 0; j < m_; ++j) out[j] = a[j];
}

void RadianceQuadricMetric::sumOf(std::uint32_t v0, std::uint32_t v1, Sum& out) const {
    const double* q0 = geometric_.data() + std::size_t(v0) * kGeometric;
    const double* q1 = geometric_.data() + std::size_t(v1) * kGeometric;
    for (int i = 0; i < kGeometric; ++i) out.g[i] = q0[i] + q1[i];
    out.grad0 = gradients_.data() + std::size_t(v0) * 4 * m_;
    out.grad1 = gradients_.data() + std::size_t(v1) * 4 * m_;
}

// Q(p, s) = p^T A p + 2 b.p + c - 2 sum_j s_j (G_j.p + E_j) + W |s|^2.
double RadianceQuadricMetric::evaluateSum(const Sum& q, const Eigen::Vector3d& p, const float* s) const {
    const double* g = q.g;
    double value = evaluateQuadratic(g + kA, p);
    const GradientBlock a = gradientBlock(q.grad0), b = gradientBlock(q.grad1);
    double cross = 0.0, norm[3] = {0.0, 0.0, 0.0};
    for (int j = 0; j < m_; ++j) {
        const double plane = (a.x[j] + b.x[j]) * p.x() + (a.y[j] + b.y[j]) * p.y() + (a.z[j] + b.z[j]) * p.z() +
                             (a.e[j] + b.e[j]);
        cross += s[j] * plane;
        norm[j / kSh_] += double(s[j]) * s[j];
    }
    value += -2.0 * cross;
    for (int c = 0; c < 3; ++c) value += g[kW + c] * norm[c];
    return std::max(0.0, value);
}

// min over s of Q(p, s) = p^T A p + 2 b.p + c - sum_j (G_j.p + E_j)^2 / W_c(j), itself a quadric in p:
// A - sum_j G_j G_j^T / W, b - sum_j E_j G_j / W, c - sum_j E_j^2 / W. Reduced once per edge (O(m)),
// it prices every candidate position in O(1).
void RadianceQuadricMetric::reduce(const Sum& q, double* reduced) const {
    std::copy(q.g + kA, q.g + kA + 10, reduced);
    const GradientBlock a = gradientBlock(q.grad0), b = gradientBlock(q.grad1);
    for (int c = 0; c < kColorChannels; ++c) {
        const double w = q.g[kW + c];
        if (!(w > 0.0)) continue;
        // sum_j (G_j.p + E_j)^2 as a block A, b, c: ten sums over the channel's attributes, laid
        // out one array per component so that they vectorise.
        double xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0, ex = 0, ey = 0, ez = 0, ee = 0;
        const int begin = c * kSh_, end = (c + 1) * kSh_;
#pragma omp simd reduction(+ : xx, xy, xz, yy, yz, zz, ex, ey, ez, ee)
        for (int j = begin; j < end; ++j) {
            const double gx = a.x[j] + b.x[j], gy = a.y[j] + b.y[j], gz = a.z[j] + b.z[j], e = a.e[j] + b.e[j];
            xx += gx * gx;
            xy += gx * gy;
            xz += gx * gz;
            yy += gy * gy;
            yz += gy * gz;
            zz += gz * gz;
            ex += e * gx;
            ey += e * gy;
            ez += e * gz;
            ee += e * e;
        }
        const double channel[10] = {xx, xy, xz, yy, yz, zz, ex, ey, ez, ee};
        for (int i = 0; i < 10; ++i) reduced[i] -= channel[i] / w;
    }
}

double RadianceQuadricMetric::evaluateOptimal(const double* reduced, const Eigen::Vector3d& p) {
    return std::max(0.0, evaluateQuadratic(reduced, p));
}

double RadianceQuadricMetric::evaluate(std::uint32_t v, const Eigen::Vector3d& worldPosition, const double* attributes) const {
    Sum q;
    const double* gv = geometric_.data() + std::size_t(v) * kGeometric;
    for (int i = 0; i < kGeometric; ++i) q.g[i] = gv[i];
    static const std::vector<double> zeros(4096, 0.0);
    q.grad0 = gradients_.data() + std::size_t(v) * 4 * m_;
    q.grad1 = zeros.data();
    std::vector<float> s(attributes, attributes + m_);
    return evaluateSum(q, normalise(worldPosition), s.data());
}

void RadianceQuadricMetric::priceHalfEdges(const CollapseMesh& mesh, const HalfEdgeQuery& query, double* costs) const {
    Sum q;
    for (int i = 0; i < query.targetCount; ++i) {
        const std::uint32_t v1 = query.targets[i];
        sumOf(query.source, v1, q);
        costs[i] = evaluateSum(q, normalise(mesh.position(v1)), attributes_.data() + std::size_t(v1) * m_);
    }
}

bool RadianceQuadricMetric::placeEdge(const CollapseMesh& mesh, std::uint32_t v0, std::uint32_t v1,
                                      Eigen::Vector3d& position) const {
    Sum q;
    sumOf(v0, v1, q);
    double reduced[10];
    reduce(q, reduced);
    const Eigen::Vector3d p0 = normalise(mesh.position(v0)), p1 = normalise(mesh.position(v1));
    // Candidates: the two ends and, when well conditioned, the minimiser of the plane terms. No
    // midpoint: at an end the attribute planes of that end's faces all pass through its own function,
    // so s* leans to it; at a midpoint s* averages the two ends', and the averages blur the radiance
    // (measured: docs/design-notes.md, "Placing the survivor: no midpoint").
    Eigen::Vector3d best = p1;
    double bestCost = evaluateOptimal(reduced, p1);
    const auto consider = [&](const Eigen::Vector3d& p) {
        const double cost = evaluateOptimal(reduced, p);
        if (cost < bestCost) {
            bestCost = cost;
            best = p;
        }
    };
    consider(p0);
    // The position minimising the distances to the planes alone (Garland & Heckbert 1997): with the
    // attribute terms in, the attribute planes of curved neighbourhoods pull the vertex off the
    // surface (their gradients are tangent to faces that are not the surface at p), which costs
    // far more in images than it saves in the quadric.
    const Eigen::Matrix3d a = symmetric(q.g + kPlanes);
    const Eigen::Vector3d b(q.g[kPlanes + 6], q.g[kPlanes + 7], q.g[kPlanes + 8]);
    const double scale = a.trace();
    if (scale > 0.0 && std::abs(a.determinant()) > 1e-9 * scale * scale * scale) {
        const Eigen::Vector3d optimum = a.fullPivLu().solve(-b);
        // Only near the edge: far placements are where a flat region's quadric is ill-conditioned.
        const double length = (p1 - p0).norm();
        const Eigen::Vector3d mid = 0.5 * (p0 + p1);
        if (optimum.allFinite() && (optimum - mid).norm() <= 2.0 * length) consider(optimum);
    }
    position = centre_ + best / positionScale_;
    lastPlacement() = {this, collapses_, v0, v1, position, bestCost};
    return true;
}

// The engine prices an edge right after placing it, at that place: the cost placing found is reused.
RadianceQuadricMetric::Placement& RadianceQuadricMetric::lastPlacement() {
    thread_local Placement last;
    return last;
}

double RadianceQuadricMetric::priceEdge(const CollapseMesh& mesh, const EdgeQuery& query) const {
    const Placement& last = lastPlacement();
    if (last.metric == this && last.collapses == collapses_ && last.v0 == query.v0 && last.v1 == query.v1 &&
        last.position == query.position)
        return last.cost;
    Sum q;
    sumOf(query.v0, query.v1, q);
    double reduced[10];
    reduce(q, reduced);
    return evaluateOptimal(reduced, normalise(query.position));
}

void RadianceQuadricMetric::onCollapse(const CollapseMesh& mesh, const EdgeQuery& query) {
    ++collapses_;
    const std::uint32_t v0 = query.v0, v1 = query.v1;
    double* q0 = geometric_.data() + std::size_t(v0) * kGeometric;
    double* q1 = geometric_.data() + std::size_t(v1) * kGeometric;
    for (int i = 0; i < kGeometric; ++i) q1[i] += q0[i];
    const double* g0 = gradients_.data() + std::size_t(v0) * 4 * m_;
    double* g1 = gradients_.data() + std::size_t(v1) * 4 * m_;
    for (int i = 0; i < 4 * m_; ++i) g1[i] += g0[i];
    if (query.halfEdge) return;

    // Full collapse: the survivor's function is s* at its new position (the area-weighted average
    // of every original face's attribute plane there); without area, the edge interpolation.
    const Eigen::Vector3d p = normalise(query.position);
    float* a1 = attributes_.data() + std::size_t(v1) * m_;
    const float* a0 = attributes_.data() + std::size_t(v0) * m_;
    thread_local std::vector<double> optimal;
    optimal.resize(m_);
    const GradientBlock g = gradientBlock(g1);
    for (int j = 0; j < m_; ++j) {
        const double w = q1[kW + j / kSh_];
        optimal[j] = w > 0.0 ? (g.x[j] * p.x() + g.y[j] * p.y() + g.z[j] * p.z() + g.e[j]) / w
                             : (1.0 - query.s) * a0[j] + query.s * a1[j];
    }
    for (int j = 0; j < m_; ++j) a1[j] = static_cast<float>(optimal[j]);
    // The survivor's normal follows it along the edge (the two frames' normals slerped by where it
    // was placed): eq. 8 reflects about the interpolated normals, so a survivor placed between the
    // ends that kept v1's normal would shift the highlights around it. Reflected
    // storage keeps v1's frame: its coefficients are defined about that normal.
    if (!field_.reflected) {
        const Frame f0 = frameFromStored(field_.frame(v0)), f1 = frameFromStored(field_.frame(v1));
        storeFrame(frameFromNormalAndTangent(slerpNormal(f0.n, f1.n, query.s), f1.t), field_.frame(v1));
    }
    conversion_.fromWorld(optimal.data(), field_.frame(v1), field_.vertexCoefficients(v1), attributeScale_);
}

}  // namespace rad
