#include "radiance/radiance_distance.h"

#include "radiance/lebedev_quadrature.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rad {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

void gaussLegendre(int n, double a, double b, std::vector<double>& nodes, std::vector<double>& weights) {
    if (n < 1) throw std::invalid_argument("gaussLegendre: need at least one node");
    nodes.assign(n, 0.0);
    weights.assign(n, 0.0);
    const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
    // Newton on P_n from the Tricomi initial guess; roots symmetric about 0
    // (W. H. Press et al., Numerical Recipes 3rd ed., sec. 4.6.1, routine gauleg).
    for (int i = 0; i < (n + 1) / 2; ++i) {
        double x = std::cos(kPi * (i + 0.75) / (n + 0.5));
        double dp = 1.0;
        for (int iter = 0; iter < 100; ++iter) {
            double p0 = 1.0, p1 = 0.0;
            for (int j = 1; j <= n; ++j) {  // P_j by the three-term recurrence
                const double p2 = p1;
                p1 = p0;
                p0 = ((2.0 * j - 1.0) * x * p1 - (j - 1.0) * p2) / j;
            }
            dp = n * (x * p0 - p1) / (x * x - 1.0);
            const double dx = p0 / dp;
            x -= dx;
            if (std::fabs(dx) < 1e-16) break;
        }
        // recompute derivative at the converged root
        double p0 = 1.0, p1 = 0.0;
        for (int j = 1; j <= n; ++j) {
            const double p2 = p1;
            p1 = p0;
            p0 = ((2.0 * j - 1.0) * x * p1 - (j - 1.0) * p2) / j;
        }
        dp = n * (x * p0 - p1) / (x * x - 1.0);
        const double w = 2.0 / ((1.0 - x * x) * dp * dp);
        nodes[i] = mid - half * x;
        nodes[n - 1 - i] = mid + half * x;
        weights[i] = weights[n - 1 - i] = half * w;
    }
}

HemisphereIntegrator::HemisphereIntegrator()
    : HemisphereIntegrator(gaussProduct(kDefaultDistanceZNodes, kDefaultDistancePhiNodes)) {}

HemisphereIntegrator HemisphereIntegrator::gaussProduct(int zNodes, int phiNodes) {
    if (zNodes < 1 || phiNodes < 1) throw std::invalid_argument("HemisphereIntegrator: need positive node counts");
    std::vector<double> z, wz;
    gaussLegendre(zNodes, 0.0, 1.0, z, wz);
    std::vector<Eigen::Vector3d> points;
    std::vector<double> weights;
    // (1/2pi) int_0^2pi int_0^1 g dz dphi: phi weights 2pi/q, divided by 2pi -> 1/q.
    for (int i = 0; i < zNodes; ++i) {
        const double s = std::sqrt(std::max(0.0, 1.0 - z[i] * z[i]));
        for (int j = 0; j < phiNodes; ++j) {
            // Half-step offset in phi per ring avoids aligning every ring on the tangent.
            const double phi = 2.0 * kPi * (j + 0.5 * (i % 2)) / phiNodes;
            points.emplace_back(s * std::cos(phi), s * std::sin(phi), z[i]);
            weights.push_back(wz[i] / phiNodes);
        }
    }
    return HemisphereIntegrator(std::move(points), std::move(weights));
}

HemisphereIntegrator HemisphereIntegrator::lebedev(int spherePointCount) {
    const HemisphereQuadrature q = hemisphereRule(spherePointCount);
    std::vector<Eigen::Vector3d> points;
    std::vector<double> weights;
    for (std::size_t i = 0; i < q.size(); ++i) {
        points.emplace_back(q.x[i], q.y[i], q.z[i]);
        weights.push_back(q.w[i] / (2.0 * kPi));
    }
    return HemisphereIntegrator(std::move(points), std::move(weights));
}

void HemisphereIntegrator::directions(const Eigen::Vector3d& n0, std::vector<Eigen::Vector3d>& out) const {
    const Frame frame = frameFromNormal(n0);
    out.resize(points_.size());
    for (std::size_t i = 0; i < points_.size(); ++i) out[i] = frame.toWorld(points_[i]);
}

double HemisphereIntegrator::integrate(const Eigen::Vector3d& n0,
                                       const std::function<double(const Eigen::Vector3d&)>& g) const {
    const Frame frame = frameFromNormal(n0);
    double sum = 0.0;
    for (std::size_t i = 0; i < points_.size(); ++i) sum += weights_[i] * g(frame.toWorld(points_[i]));
    return sum;
}

const HemisphereIntegrator& defaultHemisphereIntegrator() {
    static const HemisphereIntegrator rule;
    return rule;
}

double squaredRadianceDistance(const RgbFunction& f, const RgbFunction& g, const Eigen::Vector3d& n0,
                               const HemisphereIntegrator& rule) {
    return rule.integrate(n0, [&](const Eigen::Vector3d& w) { return (f(w) - g(w)).squaredNorm(); });
}

double radianceDistance(const RgbFunction& f, const RgbFunction& g, const Eigen::Vector3d& n0,
                        const HemisphereIntegrator& rule) {
    return std::sqrt(std::max(0.0, squaredRadianceDistance(f, g, n0, rule)));
}

double squaredRadianceNorm(const RgbFunction& f, const Eigen::Vector3d& n0, const HemisphereIntegrator& rule) {
    return rule.integrate(n0, [&](const Eigen::Vector3d& w) { return f(w).squaredNorm(); });
}

template <typename ScalarA, typename ScalarB>
double squaredRadianceDistance(const VertexRadianceT<ScalarA>& a, const VertexRadianceT<ScalarB>& b,
                               const Eigen::Vector3d& n0, const HemisphereIntegrator& rule) {
    const Frame frame = frameFromNormal(n0);
    double scratch[kMaxCoefficientsPerChannel];
    double sum = 0.0;
    const std::vector<Eigen::Vector3d>& points = rule.localPoints();
    const std::vector<double>& weights = rule.weights();
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Eigen::Vector3d w = frame.toWorld(points[i]);
        const Eigen::Vector3d diff = evaluateReflectedRadiance(a, w, scratch) - evaluateReflectedRadiance(b, w, scratch);
        sum += weights[i] * diff.squaredNorm();
    }
    return sum;
}

double squaredRadianceDistance(const RadianceField& fa, std::size_t va, const RadianceField& fb, std::size_t vb,
                               const Eigen::Vector3d& n0, const HemisphereIntegrator& rule) {
    return squaredRadianceDistance(vertexRadiance(fa, va), vertexRadiance(fb, vb), n0, rule);
}

double radianceDistance(const RadianceField& fa, std::size_t va, const RadianceField& fb, std::size_t vb,
                        const Eigen::Vector3d& n0, const HemisphereIntegrator& rule) {
    return std::sqrt(std::max(0.0, squaredRadianceDistance(fa, va, fb, vb, n0, rule)));
}

template <typename Scalar>
double squaredDistanceToCombination(const VertexRadianceT<Scalar>& target, const VertexRadianceT<Scalar>* sources,
                                    const double* weights, int sourceCount, const Eigen::Vector3d& n0,
                                    const HemisphereIntegrator& rule) {
    const Frame frame = frameFromNormal(n0);
    double scratch[kMaxCoefficientsPerChannel];
    double sum = 0.0;
    const std::vector<Eigen::Vector3d>& points = rule.localPoints();
    const std::vector<double>& ruleWeights = rule.weights();
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Eigen::Vector3d w = frame.toWorld(points[i]);
        Eigen::Vector3d diff = evaluateReflectedRadiance(target, w, scratch);
        for (int s = 0; s < sourceCount; ++s) diff -= weights[s] * evaluateReflectedRadiance(sources[s], w, scratch);
        sum += ruleWeights[i] * diff.squaredNorm();
    }
    return sum;
}

template double squaredDistanceToCombination<float>(const VertexRadianceT<float>&, const VertexRadianceT<float>*,
                                                     const double*, int, const Eigen::Vector3d&,
                                                     const HemisphereIntegrator&);
template double squaredDistanceToCombination<double>(const VertexRadianceT<double>&, const VertexRadianceT<double>*,
                                                      const double*, int, const Eigen::Vector3d&,
                                                      const HemisphereIntegrator&);
template double squaredRadianceDistance<float, float>(const VertexRadianceT<float>&, const VertexRadianceT<float>&,
                                                      const Eigen::Vector3d&, const HemisphereIntegrator&);
template double squaredRadianceDistance<float, double>(const VertexRadianceT<float>&, const VertexRadianceT<double>&,
                                                       const Eigen::Vector3d&, const HemisphereIntegrator&);
template double squaredRadianceDistance<double, float>(const VertexRadianceT<double>&, const VertexRadianceT<float>&,
                                                       const Eigen::Vector3d&, const HemisphereIntegrator&);
template double squaredRadianceDistance<double, double>(const VertexRadianceT<double>&,
                                                        const VertexRadianceT<double>&, const Eigen::Vector3d&,
                                                        const HemisphereIntegrator&);

}  // namespace rad
