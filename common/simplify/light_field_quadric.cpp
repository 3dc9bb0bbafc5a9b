#include "simplify/light_field_quadric.h"

#include "radiance/basis.h"
#include "radiance/radiance_distance.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rad {

namespace {
constexpr double kPi = 3.14159265358979323846;

// 1D Gauss-Legendre rules of the lune quadrature: theta on [0, pi] with the sin(theta) of dh folded
// into the weights, and phi on [0, 1] (scaled to the lune's [alpha - pi/2, pi/2] per pair).
struct LuneNodes {
    std::vector<double> cosTheta, sinTheta, thetaWeight;  // thetaWeight includes sin(theta)
    std::vector<double> unit, unitWeight;

    LuneNodes(int thetaNodes, int phiNodes) {
        std::vector<double> theta, w;
        gaussLegendre(thetaNodes, 0.0, kPi, theta, w);
        for (int i = 0; i < thetaNodes; ++i) {
            cosTheta.push_back(std::cos(theta[i]));
            sinTheta.push_back(std::sin(theta[i]));
            thetaWeight.push_back(w[i] * sinTheta.back());
        }
        gaussLegendre(phiNodes, 0.0, 1.0, unit, unitWeight);
    }
    std::size_t size() const { return cosTheta.size() * unit.size(); }
};

// Any unit vector orthogonal to unit n (the lune's axis when the normals are parallel).
Eigen::Vector3d orthogonalUnit(const Eigen::Vector3d& n) { return frameFromNormal(n).t; }

// The lune H(n1) cap H(n2) of the header's file comment, into `directions` / `weights`.
void luneRule(const LuneNodes& nodes, const Eigen::Vector3d& n1, const Eigen::Vector3d& n2,
              std::vector<Eigen::Vector3d>& directions, std::vector<double>& weights) {
    const Eigen::Vector3d cross = n1.cross(n2);
    const double sine = cross.norm();
    const double alpha = std::atan2(sine, n1.dot(n2));
    // Below this |n1 x n2| the axis direction is rounding noise; any axis orthogonal to n1 then
    // describes the (full or empty) lune, since phi only spans [alpha - pi/2, pi/2] with alpha 0 or pi.
    const Eigen::Vector3d e = sine > 1e-12 ? Eigen::Vector3d(cross / sine) : orthogonalUnit(n1);
    const Eigen::Vector3d u = n1, v = e.cross(n1);  // n2 = cos(alpha) u + sin(alpha) v
    const double phi0 = alpha - 0.5 * kPi, length = kPi - alpha;
    directions.clear();
    weights.clear();
    for (std::size_t j = 0; j < nodes.unit.size(); ++j) {
        const double phi = phi0 + length * nodes.unit[j];
        const Eigen::Vector3d ring = std::cos(phi) * u + std::sin(phi) * v;
        const double wPhi = length * nodes.unitWeight[j];
        for (std::size_t i = 0; i < nodes.cosTheta.size(); ++i) {
            directions.push_back(nodes.cosTheta[i] * e + nodes.sinTheta[i] * ring);
            weights.push_back(wPhi * nodes.thetaWeight[i]);
        }
    }
}

int defaultNodes(const BasisSpec& basis) { return 2 * basis.degree + 8; }

// E_L of eq. 3 (channels summed) between two vertex RF over their lune.
template <typename ScalarA, typename ScalarB>
double lightFieldErrorWith(const LuneNodes& nodes, const VertexRadianceT<ScalarA>& a,
                           const VertexRadianceT<ScalarB>& b, bool compareReflected) {
    thread_local std::vector<Eigen::Vector3d> directions;
    thread_local std::vector<double> weights;
    luneRule(nodes, a.frame.n, b.frame.n, directions, weights);
    double scratch[kMaxCoefficientsPerChannel];
    double sum = 0.0;
    for (std::size_t i = 0; i < directions.size(); ++i) {
        const Eigen::Vector3d& w = directions[i];
        const Eigen::Vector3d la = compareReflected ? evaluateReflectedRadiance(a, w, scratch) : evaluateRadiance(a, w, scratch);
        const Eigen::Vector3d lb = compareReflected ? evaluateReflectedRadiance(b, w, scratch) : evaluateRadiance(b, w, scratch);
        sum += weights[i] * (la - lb).squaredNorm();
    }
    return sum;
}

bool isHalfEdge(const EdgeQuery& query) { return query.halfEdge; }
}  // namespace

void hemisphereIntersectionRule(const Eigen::Vector3d& n1, const Eigen::Vector3d& n2, int thetaNodes, int phiNodes,
                                std::vector<Eigen::Vector3d>& directions, std::vector<double>& weights) {
    if (thetaNodes < 1 || phiNodes < 1)
        throw std::invalid_argument("hemisphereIntersectionRule: need positive node counts");
    luneRule(LuneNodes(thetaNodes, phiNodes), n1, n2, directions, weights);
}

double normalAngle(const Eigen::Vector3d& n1, const Eigen::Vector3d& n2) {
    return std::atan2(n1.cross(n2).norm(), n1.dot(n2));
}

double orientationError(const Eigen::Vector3d& n1, const Eigen::Vector3d& n2, double channelMaxDifference) {
    return 2.0 * normalAngle(n1, n2) * kColorChannels * channelMaxDifference * channelMaxDifference;
}

template <typename ScalarA, typename ScalarB>
double lightFieldError(const VertexRadianceT<ScalarA>& a, const VertexRadianceT<ScalarB>& b, int thetaNodes,
                       int phiNodes, bool compareReflected) {
    if (thetaNodes < 1 || phiNodes < 1) throw std::invalid_argument("lightFieldError: need positive node counts");
    return lightFieldErrorWith(LuneNodes(thetaNodes, phiNodes), a, b, compareReflected);
}

LightFieldQuadricMetric::LightFieldQuadricMetric(const CollapseMesh& mesh, RadianceField& field,
                                                 LightFieldQuadricOptions options)
    : field_(field), options_(options) {
    const std::string why = field.validate();
    if (!why.empty()) throw std::invalid_argument("light-field quadric: " + why);
    if (field.vertexCount() != mesh.vertexCount())
        throw std::invalid_argument("light-field quadric: the radiance field has " + std::to_string(field.vertexCount()) +
                                    " vertices, the mesh " + std::to_string(mesh.vertexCount()));
    if (options_.thetaNodes < 0 || options_.phiNodes < 0)
        throw std::invalid_argument("light-field quadric: node counts must be >= 0 (0: automatic)");
    if (!(options_.channelMaxDifference >= 0.0) || !std::isfinite(options_.channelMaxDifference))
        throw std::invalid_argument("light-field quadric: E_max must be finite and >= 0");
    if (!(options_.ridge >= 0.0) || !std::isfinite(options_.ridge))
        throw std::invalid_argument("light-field quadric: ridge must be finite and >= 0");
    if (options_.thetaNodes == 0) options_.thetaNodes = defaultNodes(field.basis);
    if (options_.phiNodes == 0) options_.phiNodes = defaultNodes(field.basis);
}

namespace {
// One LuneNodes per thread and node-count pair (metrics of one run share their options, so this is
// built once per thread).
const LuneNodes& threadNodes(int thetaNodes, int phiNodes) {
    thread_local int cachedTheta = -1, cachedPhi = -1;
    thread_local LuneNodes nodes(1, 1);
    if (cachedTheta != thetaNodes || cachedPhi != phiNodes) {
        nodes = LuneNodes(thetaNodes, phiNodes);
        cachedTheta = thetaNodes;
        cachedPhi = phiNodes;
    }
    return nodes;
}
}  // namespace

double LightFieldQuadricMetric::halfEdgeCost(std::uint32_t v0, std::uint32_t v1) const {
    const VertexRadiance l0 = vertexRadiance(field_, v0), l1 = vertexRadiance(field_, v1);
    const LuneNodes& nodes = threadNodes(options_.thetaNodes, options_.phiNodes);
    return lightFieldErrorWith(nodes, l1, l0, options_.compareReflected) +
           orientationError(l1.frame.n, l0.frame.n, options_.channelMaxDifference);
}

template <typename Scalar>
double LightFieldQuadricMetric::collapseCost(std::uint32_t v0, std::uint32_t v1,
                                             const VertexRadianceT<Scalar>& candidate) const {
    if (candidate.basis != field_.basis)
        throw std::invalid_argument("light-field quadric: candidate basis " + candidate.basis.name() +
                                    " differs from the field's " + field_.basis.name());
    const VertexRadiance l0 = vertexRadiance(field_, v0), l1 = vertexRadiance(field_, v1);
    const LuneNodes& nodes = threadNodes(options_.thetaNodes, options_.phiNodes);
    const double e = options_.channelMaxDifference;
    return lightFieldErrorWith(nodes, candidate, l0, options_.compareReflected) +
           lightFieldErrorWith(nodes, candidate, l1, options_.compareReflected) +
           orientationError(candidate.frame.n, l0.frame.n, e) + orientationError(candidate.frame.n, l1.frame.n, e);
}

double LightFieldQuadricMetric::solve(std::uint32_t v0, std::uint32_t v1, double s, Frame& frame,
                                      double* coefficients) const {
    const BasisSpec& basis = field_.basis;
    const int K = basis.coefficientCount();
    const VertexRadiance ends[2] = {vertexRadiance(field_, v0), vertexRadiance(field_, v1)};
    frame = frameFromNormal(slerpNormal(ends[0].frame.n, ends[1].frame.n, std::clamp(s, 0.0, 1.0)));
    // The function compared is L (or L~): evaluate the new stored coefficients where that function
    // is read (radiance_evaluation.h: basisDirection with the "reflect the argument" flag).
    const bool reflectArgument = field_.reflected != options_.compareReflected;

    // Least-squares form of eq. 5 summed over both lunes: rows sqrt(weight) B(w_i), right-hand
    // sides sqrt(weight) L_k(w_i), so that A = Bw^T Bw, -b = Bw^T Yw, c = |Yw|^2.
    const LuneNodes& nodes = threadNodes(options_.thetaNodes, options_.phiNodes);
    const Eigen::Index rows = Eigen::Index(2 * nodes.size());
    thread_local Eigen::MatrixXd Bw, Yw;
    thread_local std::vector<Eigen::Vector3d> directions;
    thread_local std::vector<double> weights;
    Bw.resize(rows, K);
    Yw.resize(rows, kColorChannels);
    double scratch[kMaxCoefficientsPerChannel];
    Eigen::Index row = 0;
    for (const VertexRadiance& end : ends) {
        luneRule(nodes, frame.n, end.frame.n, directions, weights);
        for (std::size_t i = 0; i < directions.size(); ++i, ++row) {
            const Eigen::Vector3d& w = directions[i];
            const double r = std::sqrt(weights[i]);
            const Eigen::Vector3d d = basisDirection(basis, frame, w, reflectArgument);
            evaluateBasis(basis, d.x(), d.y(), d.z(), scratch);
            for (int k = 0; k < K; ++k) Bw(row, k) = r * scratch[k];
            const Eigen::Vector3d l =
                options_.compareReflected ? evaluateReflectedRadiance(end, w, scratch) : evaluateRadiance(end, w, scratch);
            Yw.row(row) = r * l.transpose();
        }
    }

    // Thread-local so that the hot path allocates nothing once the sizes are known.
    thread_local Eigen::MatrixXd A, a, rhs, residual;
    thread_local Eigen::LLT<Eigen::MatrixXd, Eigen::Lower> llt;
    A.setZero(K, K);
    A.selfadjointView<Eigen::Lower>().rankUpdate(Bw.transpose());
    const double mu = options_.ridge * A.trace() / K;
    A.diagonal().array() += mu;
    rhs.noalias() = Bw.transpose() * Yw;  // -b, K x 3
    llt.compute(A);
    if (llt.info() == Eigen::Success) a = llt.solve(rhs);
    if (llt.info() != Eigen::Success || !a.allFinite()) {
        // Only reachable with ridge == 0 and a singular A (or non-finite data): least-squares
        // minimum-norm solution instead.
        a = Bw.completeOrthogonalDecomposition().solve(Yw);
    }
    for (int c = 0; c < kColorChannels; ++c)
        for (int k = 0; k < K; ++k) coefficients[c * K + k] = a(k, c);
    residual = Yw;
    residual.noalias() -= Bw * a;
    return residual.squaredNorm();
}

LightFieldCollapse LightFieldQuadricMetric::optimalCollapse(std::uint32_t v0, std::uint32_t v1, double s) const {
    LightFieldCollapse out;
    out.coefficients.resize(field_.coefficientsPerVertex());
    out.lightError = solve(v0, v1, s, out.frame, out.coefficients.data());
    const double e = options_.channelMaxDifference;
    const Frame f0 = frameFromStored(field_.frame(v0)), f1 = frameFromStored(field_.frame(v1));
    out.orientationError = orientationError(out.frame.n, f0.n, e) + orientationError(out.frame.n, f1.n, e);
    return out;
}

void LightFieldQuadricMetric::priceHalfEdges(const CollapseMesh& mesh, const HalfEdgeQuery& query,
                                             double* costs) const {
    for (int i = 0; i < query.targetCount; ++i) costs[i] = halfEdgeCost(query.source, query.targets[i]);
}

double LightFieldQuadricMetric::priceEdge(const CollapseMesh& mesh, const EdgeQuery& query) const {
    if (isHalfEdge(query)) return halfEdgeCost(query.v0, query.v1);
    Frame frame;
    double coefficients[kColorChannels * kMaxCoefficientsPerChannel];
    const double light = solve(query.v0, query.v1, query.s, frame, coefficients);
    const double e = options_.channelMaxDifference;
    const Frame f0 = frameFromStored(field_.frame(query.v0)), f1 = frameFromStored(field_.frame(query.v1));
    return light + orientationError(frame.n, f0.n, e) + orientationError(frame.n, f1.n, e);
}

void LightFieldQuadricMetric::onCollapse(const CollapseMesh& mesh, const EdgeQuery& query) {
    if (isHalfEdge(query)) return;  // v1 keeps (F1, L1)
    Frame frame;
    double coefficients[kColorChannels * kMaxCoefficientsPerChannel];
    solve(query.v0, query.v1, query.s, frame, coefficients);
    float* out = field_.vertexCoefficients(query.v1);
    for (int k = 0; k < field_.coefficientsPerVertex(); ++k) out[k] = static_cast<float>(coefficients[k]);
    storeFrame(frame, field_.frame(query.v1));
}

template double lightFieldError<float, float>(const VertexRadianceT<float>&, const VertexRadianceT<float>&, int, int, bool);
template double lightFieldError<float, double>(const VertexRadianceT<float>&, const VertexRadianceT<double>&, int, int,
                                               bool);
template double lightFieldError<double, float>(const VertexRadianceT<double>&, const VertexRadianceT<float>&, int, int,
                                               bool);
template double lightFieldError<double, double>(const VertexRadianceT<double>&, const VertexRadianceT<double>&, int,
                                                int, bool);
template double LightFieldQuadricMetric::collapseCost<float>(std::uint32_t, std::uint32_t,
                                                             const VertexRadianceT<float>&) const;
template double LightFieldQuadricMetric::collapseCost<double>(std::uint32_t, std::uint32_t,
                                                              const VertexRadianceT<double>&) const;

}  // namespace rad
