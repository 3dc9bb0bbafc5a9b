// Small helpers shared by the unit tests (not a core unit: no test file of its own).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <random>

namespace radtest {

// A uniformly distributed unit vector (normalised Gaussian triple, degenerate draws rejected).
inline Eigen::Vector3d randomUnit(std::mt19937& rng) {
    std::normal_distribution<double> g;
    Eigen::Vector3d v;
    do v = Eigen::Vector3d(g(rng), g(rng), g(rng));
    while (v.norm() < 1e-3);
    return v.normalized();
}

// Brute-force (1/2pi) integral of g over the hemisphere around unit n: midpoint rule in
// (theta, phi) with the sin(theta) weight, in a frame built here, independent of the quadrature
// rules and of radiance_frame under test.
template <typename G>
double bruteHemisphere(const Eigen::Vector3d& n, int thetaSteps, int phiSteps, G g) {
    const double pi = 3.14159265358979323846;
    const Eigen::Vector3d helper = std::fabs(n.x()) < 0.9 ? Eigen::Vector3d(1, 0, 0) : Eigen::Vector3d(0, 1, 0);
    const Eigen::Vector3d a = n.cross(helper).normalized(), b = n.cross(a);
    const double dt = 0.5 * pi / thetaSteps, dp = 2 * pi / phiSteps;
    double sum = 0;
    for (int i = 0; i < thetaSteps; ++i) {
        const double t = (i + 0.5) * dt, st = std::sin(t), ct = std::cos(t);
        double ring = 0;
        for (int j = 0; j < phiSteps; ++j) {
            const double p = (j + 0.5) * dp;
            ring += g(Eigen::Vector3d(st * std::cos(p) * a + st * std::sin(p) * b + ct * n));
        }
        sum += ring * st;
    }
    return sum * dt * dp / (2 * pi);
}

}  // namespace radtest
