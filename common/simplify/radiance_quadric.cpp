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

// Layout of the block of doubles of one vertex. A quadric block is A (6, upper triangle: xx, xy, xz,
// yy, yz, zz), b (3), c: x^T A x + 2 b.x + c.
constexpr int kW = 0;        // 3: the attribute weight of each colour channel
constexpr int kPlanes = 3;   // the faces' planes in normalised coordinates (the geometry term is
                             // geometryWeight times them; placing uses them alone)
constexpr int kLocal = 13;   // the attribute planes' squares about the vertex's reference and origin
constexpr int kSummed = 13;  // the part of the block that two quadrics add as they are (kLocal moves)
constexpr int kGeometric = 23;
constexpr double kBoundaryPlaneWeight = 1000.0;  // addBoundaryPlanes
static_assert(kGeometric == 23, "FaceQuadric::geometric holds one vertex's block");

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

// A vertex's local block moved by t to a new origin and taken against a new reference: q(d + t)
// plus the terms of the change of reference (RadianceQuadricMetric::referenceShift).
template <class Shift>
void moveLocalBlock(const double* q, const Eigen::Vector3d& t, const Shift& shift, double* out) {
    const Eigen::Matrix3d X = symmetric(q);
    const Eigen::Vector3d y(q[6], q[7], q[8]), xt = X * t;
    for (int i = 0; i < 6; ++i) out[i] = q[i];
    for (int i = 0; i < 3; ++i) out[6 + i] = y[i] + xt[i] + shift.g[i];
    out[9] = q[9] + 2.0 * y.dot(t) + t.dot(xt) + 2.0 * shift.e + shift.w;
}

}  // namespace

// Q_v0 + Q_v1 unpacked, about v1's origin and reference: the summed part of the blocks, and
// pointers to both vertices' planes, references and local blocks. v0's planes there are
// G0_j.(p - o_v1) + E0_j + G0_j.shift + W0_c (r0_j - r1_j), shift = o_v1 - o_v0.
struct RadianceQuadricMetric::Sum {
    double g[kSummed];
    const float *grad0, *grad1, *reference0, *reference1;
    const double *local0, *local1;
    double weight0[3];
    Eigen::Vector3d origin, shift;
};

// One vertex's attribute planes G_j.(p - o_v) + E_j: 4 m floats, one array per component.
RadianceQuadricMetric::GradientBlock RadianceQuadricMetric::gradientBlock(const float* block) const {
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
    gradients_.assign(nv * 4 * static_cast<std::size_t>(m_), 0.0f);
    origins_.resize(3 * nv);
    for (std::size_t v = 0; v < nv; ++v) {
        const Eigen::Vector3d o = normalise(mesh.position(static_cast<std::uint32_t>(v)));
        for (int i = 0; i < 3; ++i) origins_[3 * v + i] = o[i];
    }
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
                        addFacePlanes(face, t[corner]);
                    }
                    if (options_.boundaryPlanes) addBoundaryPlanes(mesh, t);
                }
            }
        }
    }
}

// Boundary constraint planes (Garland & Heckbert 1997 sec. 5): for each edge of the face that no
// other face shares, the plane through the edge perpendicular to the face, added to both ends. The
// face planes do not see a boundary vertex slide along the surface, so without these a collapse
// along a curved boundary would cut its corners for free. Weighted by the edge's squared length
// times kBoundaryPlaneWeight (in the face planes' units, an area: a strong penalty, as Garland &
// Heckbert advise; measured against 100: docs/design-notes.md, "Collapsing along the boundary").
void RadianceQuadricMetric::addBoundaryPlanes(const CollapseMesh& mesh, const std::uint32_t* t) {
    for (int e = 0; e < 3; ++e) {
        const std::uint32_t a = t[e], b = t[(e + 1) % 3];
        if (mesh.edgeFaceCount(a, b) != 1) continue;
        const Eigen::Vector3d p0 = normalise(mesh.position(t[0])), p1 = normalise(mesh.position(t[1])),
                              p2 = normalise(mesh.position(t[2]));
        const Eigen::Vector3d faceNormal = (p1 - p0).cross(p2 - p0);
        const Eigen::Vector3d pa = normalise(mesh.position(a)), edge = normalise(mesh.position(b)) - pa;
        const Eigen::Vector3d across = edge.cross(faceNormal);
        const double length = across.norm();
        if (!(length > 0.0)) continue;
        const Eigen::Vector3d normal = across / length;
        const double weight = kBoundaryPlaneWeight * edge.squaredNorm();
        for (const std::uint32_t v : {a, b})
            addSquaredLinear(geometric_.data() + std::size_t(v) * kGeometric + kPlanes, weight, normal, -normal.dot(pa));
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
    out.firstCorner = p0;
    for (int j = 0; j < m_; ++j) {
        const double weight = channelArea[j / kSh_];
        Eigen::Vector3d grad = Eigen::Vector3d::Zero();
        double atFirst = (double(s0[j]) + s1[j] + s2[j]) / 3.0;  // no plane: the corners' mean
        if (planar) {
            const double d1 = double(s1[j]) - s0[j], d2 = double(s2[j]) - s0[j];
            const double alpha = (a22 * d1 - a12 * d2) / det, beta = (a11 * d2 - a12 * d1) / det;
            grad = alpha * e1 + beta * e2;
            atFirst = s0[j];
        }
        // The squares' A part is the same at every corner; b and c depend on the corner's origin and
        // reference (addFacePlanes).
        addSquaredLinear(q + kLocal, weight, grad, 0.0);
        for (int i = 0; i < 3; ++i) gradients[i * m_ + j] = weight * grad[i];
        out.cornerValues[j] = weight * atFirst;
    }
    return true;
}

// The face's planes about v's origin o_v and reference r_v (its own function): w (a_j(o_v) - r_vj),
// which is 0 at the corner the planes pass through.
void RadianceQuadricMetric::addFacePlanes(const FaceQuadric& face, std::uint32_t v) {
    const Eigen::Vector3d t = origin(v) - face.firstCorner;
    const double* gx = face.gradients.data();
    const double *gy = gx + m_, *gz = gx + 2 * m_;
    const float* r = attributes_.data() + std::size_t(v) * m_;
    float* g = gradients_.data() + std::size_t(v) * 4 * m_;
    double* local = geometric_.data() + std::size_t(v) * kGeometric + kLocal;
    double y[3] = {0.0, 0.0, 0.0}, z = 0.0;
    for (int c = 0; c < kColorChannels; ++c) {
        const double w = face.geometric[kW + c];  // area x the channel's perceptual weight
        if (!(w > 0.0)) continue;
        double yx = 0.0, yy = 0.0, yz = 0.0, zz = 0.0;
        for (int j = c * kSh_; j < (c + 1) * kSh_; ++j) {
            const double e = face.cornerValues[j] + gx[j] * t.x() + gy[j] * t.y() + gz[j] * t.z() - w * r[j];
            g[j] += static_cast<float>(gx[j]);
            g[m_ + j] += static_cast<float>(gy[j]);
            g[2 * m_ + j] += static_cast<float>(gz[j]);
            g[3 * m_ + j] += static_cast<float>(e);
            yx += e * gx[j];
            yy += e * gy[j];
            yz += e * gz[j];
            zz += e * e;
        }
        y[0] += yx / w;
        y[1] += yy / w;
        y[2] += yz / w;
        z += zz / w;
    }
    for (int i = 0; i < 3; ++i) local[6 + i] += y[i];
    local[9] += z;
}

std::size_t RadianceQuadricMetric::bytes() const {
    return (geometric_.size() + origins_.size()) * sizeof(double) + (gradients_.size() + attributes_.size()) * sizeof(float);
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
    for (int i = 0; i < kSummed; ++i) out.g[i] = q0[i] + q1[i];
    out.grad0 = gradients_.data() + std::size_t(v0) * 4 * m_;
    out.grad1 = gradients_.data() + std::size_t(v1) * 4 * m_;
    out.reference0 = attributes_.data() + std::size_t(v0) * m_;
    out.reference1 = attributes_.data() + std::size_t(v1) * m_;
    out.local0 = q0 + kLocal;
    out.local1 = q1 + kLocal;
    for (int c = 0; c < 3; ++c) out.weight0[c] = q0[kW + c];
    out.origin = origin(v1);
    out.shift = out.origin - origin(v0);
}

void RadianceQuadricMetric::sumLocal(const Sum& q, double* out) const {
    moveLocalBlock(q.local0, q.shift, referenceShift(q.grad0, q.reference0, q.reference1, q.weight0, q.shift), out);
    for (int i = 0; i < 10; ++i) out[i] += q.local1[i];
}

RadianceQuadricMetric::ReferenceShift RadianceQuadricMetric::referenceShift(const float* planes, const float* reference,
                                                                            const float* newReference,
                                                                            const double* weight,
                                                                            const Eigen::Vector3d& t) const {
    const GradientBlock a = gradientBlock(planes);
    const double tx = t.x(), ty = t.y(), tz = t.z();
    ReferenceShift out;
    for (int c = 0; c < kColorChannels; ++c) {
        double dx = 0, dy = 0, dz = 0, de = 0, dd = 0;
#pragma omp simd reduction(+ : dx, dy, dz, de, dd)
        for (int j = c * kSh_; j < (c + 1) * kSh_; ++j) {
            const double ax = a.x[j], ay = a.y[j], az = a.z[j];
            const double delta = double(reference[j]) - double(newReference[j]);
            dx += delta * ax;
            dy += delta * ay;
            dz += delta * az;
            de += delta * (double(a.e[j]) + ax * tx + ay * ty + az * tz);
            dd += delta * delta;
        }
        out.g += Eigen::Vector3d(dx, dy, dz);
        out.e += de;
        out.w += weight[c] * dd;
    }
    return out;
}

// Q(p, s) = geometry(p) + C(d) - 2 sum_j u_j (G_j.d + E_j) + W |u|^2, d = p - o_v1, u = s - r_v1.
double RadianceQuadricMetric::evaluateSum(const Sum& q, const Eigen::Vector3d& p, const float* s) const {
    const GradientBlock a = gradientBlock(q.grad0), b = gradientBlock(q.grad1);
    const Eigen::Vector3d d = p - q.origin, t = q.shift;
    double cross = 0.0, norm[3] = {0.0, 0.0, 0.0};
    for (int c = 0; c < kColorChannels; ++c) {
        const double w0 = q.weight0[c];
        for (int j = c * kSh_; j < (c + 1) * kSh_; ++j) {
            const double ax = a.x[j], ay = a.y[j], az = a.z[j];
            const double delta = double(q.reference0[j]) - q.reference1[j], at = ax * t.x() + ay * t.y() + az * t.z();
            const double plane = (ax + b.x[j]) * d.x() + (ay + b.y[j]) * d.y() + (az + b.z[j]) * d.z() +
                                 (double(a.e[j]) + at + w0 * delta + b.e[j]);
            const double u = double(s[j]) - q.reference1[j];
            cross += u * plane;
            norm[c] += u * u;
        }
    }
    double local[10];
    sumLocal(q, local);
    double value = options_.geometryWeight * evaluateQuadratic(q.g + kPlanes, p) + evaluateQuadratic(local, d) - 2.0 * cross;
    for (int c = 0; c < 3; ++c) value += q.g[kW + c] * norm[c];
    return std::max(0.0, value);
}

// min over s of Q(p, s) = geometry(p) + C(d) - sum_j (G_j.d + E_j)^2 / W_c(j), d = p - o_v1: the
// attribute part is a quadric in d, summed once per edge (O(m)) about v1's origin and reference
// (where its terms are of the size of the radiance's changes, not of the radiance, so that floats
// hold them), then moved to normalised coordinates (O(1)); it prices every candidate position in O(1).
void RadianceQuadricMetric::reduce(const Sum& q, double* reduced) const {
    double planes[10] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0};  // sum_j (G_j.d + E_j)^2 / W as A, b, c in d
    const GradientBlock a = gradientBlock(q.grad0), b = gradientBlock(q.grad1);
    const double tx = q.shift.x(), ty = q.shift.y(), tz = q.shift.z();
    // The summed planes in doubles, one array per component: the pass below then vectorises (mixed
    // float and double operands in one loop with ten sums do not).
    thread_local std::vector<double> scratch;
    scratch.resize(5 * std::size_t(m_));
    double* __restrict gx = scratch.data();
    double* __restrict gy = gx + m_;
    double* __restrict gz = gy + m_;
    double* __restrict e0 = gz + m_;  // v0's offsets at v1's origin
    double* __restrict delta = e0 + m_;
    for (int j = 0; j < m_; ++j) {
        const double ax = a.x[j], ay = a.y[j], az = a.z[j];
        gx[j] = ax + double(b.x[j]);
        gy[j] = ay + double(b.y[j]);
        gz[j] = az + double(b.z[j]);
        e0[j] = double(a.e[j]) + ax * tx + ay * ty + az * tz;
        delta[j] = double(q.reference0[j]) - double(q.reference1[j]);
    }
    for (int c = 0; c < kColorChannels; ++c) {
        const double w = q.g[kW + c], w0 = q.weight0[c];
        if (!(w > 0.0)) continue;  // no face weighs this channel: every plane and weight is 0
        double xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0, ex = 0, ey = 0, ez = 0, ee = 0;
        const int begin = c * kSh_, end = (c + 1) * kSh_;
#pragma omp simd reduction(+ : xx, xy, xz, yy, yz, zz, ex, ey, ez, ee)
        for (int j = begin; j < end; ++j) {
            const double e = e0[j] + w0 * delta[j] + double(b.e[j]);
            xx += gx[j] * gx[j];
            xy += gx[j] * gy[j];
            xz += gx[j] * gz[j];
            yy += gy[j] * gy[j];
            yz += gy[j] * gz[j];
            zz += gz[j] * gz[j];
            ex += e * gx[j];
            ey += e * gy[j];
            ez += e * gz[j];
            ee += e * e;
        }
        const double channel[10] = {xx, xy, xz, yy, yz, zz, ex, ey, ez, ee};
        for (int i = 0; i < 10; ++i) planes[i] += channel[i] / w;
    }
    double local[10];
    sumLocal(q, local);
    for (int i = 0; i < 10; ++i) local[i] -= planes[i];
    // In normalised coordinates: with d = p - o, d^T X d + 2 y.d + z = p^T X p + 2 (y - X o).p +
    // (z - 2 y.o + o^T X o).
    const Eigen::Matrix3d X = symmetric(local);
    const Eigen::Vector3d y(local[6], local[7], local[8]), xo = X * q.origin;
    const double* g = q.g + kPlanes;
    const double geometry = options_.geometryWeight;
    for (int i = 0; i < 6; ++i) reduced[i] = geometry * g[i] + local[i];
    for (int i = 0; i < 3; ++i) reduced[6 + i] = geometry * g[6 + i] + y[i] - xo[i];
    reduced[9] = geometry * g[9] + local[9] - 2.0 * y.dot(q.origin) + q.origin.dot(xo);
}

double RadianceQuadricMetric::evaluateOptimal(const double* reduced, const Eigen::Vector3d& p) {
    return std::max(0.0, evaluateQuadratic(reduced, p));
}

double RadianceQuadricMetric::evaluate(std::uint32_t v, const Eigen::Vector3d& worldPosition, const double* attributes) const {
    // v's quadric alone: the "other end" has no planes, no weight and v's reference.
    Sum q;
    const double* gv = geometric_.data() + std::size_t(v) * kGeometric;
    for (int i = 0; i < kSummed; ++i) q.g[i] = gv[i];
    static const std::vector<float> zeros(4 * 3 * kMaxCoefficientsPerChannel, 0.0f);
    static const double noLocal[10] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    q.grad0 = zeros.data();
    q.grad1 = gradients_.data() + std::size_t(v) * 4 * m_;
    q.reference0 = q.reference1 = attributes_.data() + std::size_t(v) * m_;
    q.local0 = noLocal;
    q.local1 = gv + kLocal;
    for (double& w : q.weight0) w = 0.0;
    q.origin = origin(v);
    q.shift = Eigen::Vector3d::Zero();
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
    lastPlacement() = {this, collapses_.load(std::memory_order_relaxed), v0, v1, position, bestCost};
    return true;
}

// The engine prices an edge right after placing it, at that place: the cost placing found is reused.
RadianceQuadricMetric::Placement& RadianceQuadricMetric::lastPlacement() {
    thread_local Placement last;
    return last;
}

double RadianceQuadricMetric::priceEdge(const CollapseMesh& mesh, const EdgeQuery& query) const {
    const Placement& last = lastPlacement();
    if (last.metric == this && last.collapses == collapses_.load(std::memory_order_relaxed) && last.v0 == query.v0 && last.v1 == query.v1 &&
        last.position == query.position)
        return last.cost;
    Sum q;
    sumOf(query.v0, query.v1, q);
    double reduced[10];
    reduce(q, reduced);
    return evaluateOptimal(reduced, normalise(query.position));
}

void RadianceQuadricMetric::onCollapse(const CollapseMesh& mesh, const EdgeQuery& query) {
    collapses_.fetch_add(1, std::memory_order_relaxed);
    const std::uint32_t v0 = query.v0, v1 = query.v1;
    double* q0 = geometric_.data() + std::size_t(v0) * kGeometric;
    double* q1 = geometric_.data() + std::size_t(v1) * kGeometric;
    // The ends' planes at the survivor's place p (its origin from now on), in doubles: their values
    // there, sum_f w a_f(p) = E_j + G_j.t + W_c r_j per end, give s* over the weight. The survivor's
    // reference becomes s*, about which its planes sum to 0 (up to s*'s rounding to float).
    const Eigen::Vector3d p = query.halfEdge ? origin(v1) : normalise(query.position);
    const Eigen::Vector3d t0 = p - origin(v0), t1 = p - origin(v1);
    const GradientBlock a = gradientBlock(gradients_.data() + std::size_t(v0) * 4 * m_);
    float* g1 = gradients_.data() + std::size_t(v1) * 4 * m_;
    float* r1 = attributes_.data() + std::size_t(v1) * m_;
    const float* r0 = attributes_.data() + std::size_t(v0) * m_;
    // The values there and the survivor's reference (s*, as stored in floats; without weight, the
    // edge interpolation; half-edge: v1's own).
    thread_local std::vector<double> value;
    thread_local std::vector<float> reference;
    value.resize(m_);
    reference.resize(m_);
    for (int c = 0; c < kColorChannels; ++c) {
        const double w0 = q0[kW + c], w1 = q1[kW + c], w = w0 + w1, inverse = w > 0.0 ? 1.0 / w : 0.0;
        for (int j = c * kSh_; j < (c + 1) * kSh_; ++j) {
            value[j] = double(a.e[j]) + a.x[j] * t0.x() + a.y[j] * t0.y() + a.z[j] * t0.z() + w0 * r0[j] +
                       double(g1[3 * m_ + j]) + g1[j] * t1.x() + g1[m_ + j] * t1.y() + g1[2 * m_ + j] * t1.z() +
                       w1 * r1[j];
            reference[j] = query.halfEdge ? r1[j]
                           : static_cast<float>(w > 0.0 ? value[j] * inverse : (1.0 - query.s) * r0[j] + query.s * r1[j]);
        }
    }
    // Both local blocks moved to p and the new reference, then summed; the planes likewise.
    double moved0[10], moved1[10];
    moveLocalBlock(q0 + kLocal, t0, referenceShift(a.x, r0, reference.data(), q0 + kW, t0), moved0);
    moveLocalBlock(q1 + kLocal, t1, referenceShift(g1, r1, reference.data(), q1 + kW, t1), moved1);
    for (int c = 0; c < kColorChannels; ++c) {
        const double w = q0[kW + c] + q1[kW + c];
        for (int j = c * kSh_; j < (c + 1) * kSh_; ++j) {
            g1[j] = static_cast<float>(double(a.x[j]) + g1[j]);
            g1[m_ + j] = static_cast<float>(double(a.y[j]) + g1[m_ + j]);
            g1[2 * m_ + j] = static_cast<float>(double(a.z[j]) + g1[2 * m_ + j]);
            g1[3 * m_ + j] = static_cast<float>(value[j] - w * reference[j]);
        }
    }
    for (int i = 0; i < 10; ++i) q1[kLocal + i] = moved0[i] + moved1[i];
    for (int i = 0; i < kSummed; ++i) q1[i] += q0[i];
    for (int i = 0; i < 3; ++i) origins_[3 * std::size_t(v1) + i] = p[i];
    std::copy(reference.begin(), reference.end(), r1);
    if (query.halfEdge) return;

    thread_local std::vector<double> optimal;
    optimal.assign(reference.begin(), reference.end());
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
