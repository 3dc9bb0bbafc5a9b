// Lebedev-Laikov quadrature rules on the unit sphere (Lebedev and Laikov 1999), and the hemisphere
// rules derived from them. A rule of precision p integrates every polynomial in (x, y, z) of total
// degree <= p exactly over the sphere (every product of spherical harmonics of bands l + l' <= p),
// with roughly 3x fewer points than a product Gauss rule of the same precision. Our weights sum to
// 4 pi (the published ones to 1). Rules are built once and shared read-only (thread-safe).
// Details: docs/architecture.md, "`common/radiance/lebedev_quadrature.h`: how it works".
#pragma once

#include <cstddef>
#include <vector>

namespace rad {

// A quadrature rule on the unit sphere: integral_S2 f ~= sum_i w[i] f(x[i], y[i], z[i]).
struct SphereQuadrature {
    std::vector<double> x, y, z, w;  // unit points, weights summing to 4 pi
    int precision = 0;               // every polynomial of total degree <= precision is integrated exactly

    std::size_t size() const { return w.size(); }
};

// The Lebedev-Laikov rule with that many points (see availableLebedevRules()). Built once, on first
// use, for all rules at once (thread-safe: C++11 function-local static), then shared read-only.
// Throws std::invalid_argument for a point count that is not an available rule.
const SphereQuadrature& lebedevRule(int pointCount);

// Point counts of the available rules, increasing:
// 6, 14, 26, 38, 50, 74, 86, 110, 146, 170, 194, 230, 266, 302, 350, 434, 590, 770, 974, 1202
// with precisions 3, 5, 7, ..., 31 (every odd degree up to 31), 35, 41, 47, 53, 59.
std::vector<int> availableLebedevRules();

// Precision of the rule with that many points; throws std::invalid_argument if none.
int lebedevPrecision(int pointCount);

// The smallest available rule that integrates every polynomial of total degree <= degree exactly
// (degree <= 0 gives the 6-point rule). Throws std::out_of_range above the largest precision (59).
// Example: projecting a band-L function onto band-L SH needs degree 2L (products Y Y'), so
// lebedevPointCountForPrecision(2 * L).
int lebedevPointCountForPrecision(int degree);

// The upper hemisphere z >= 0 (local frame: z = the hemisphere's axis, e.g. the normal) cut out of
// a Lebedev rule: the points with z > 0 keep their weight, the points with z == 0 (the rules contain
// points exactly on the equator) get half their weight, the points with z < 0 are dropped.
//
// Property (why half weights): every Lebedev rule is symmetric under z -> -z, so for a function f
// that is EVEN in z, sum over z > 0 plus half of the sum over z == 0 is exactly half the sphere rule
// applied to f, and integral_{z>=0} f = (1/2) integral_S2 f. Hence the hemisphere rule integrates
// exactly every polynomial of total degree <= precision that is even in z (e.g. the PB basis of
// basis.h and its products, which depend on (x, y) only). The total weight is 2 pi. It is NOT
// exact for polynomials odd in z (e.g. z itself: true integral pi): use it for z-even integrands,
// or accept the quadrature error.
struct HemisphereQuadrature {
    std::vector<double> x, y, z, w;  // unit points with z >= 0, weights summing to 2 pi
    int precision = 0;               // exact for z-even polynomials of total degree <= precision

    std::size_t size() const { return w.size(); }
};

// Throws std::invalid_argument for a point count that is not an available rule. pointCount is the
// size of the SPHERE rule the hemisphere rule is cut from (the result has about half the points).
HemisphereQuadrature hemisphereRule(int pointCount);

}  // namespace rad
