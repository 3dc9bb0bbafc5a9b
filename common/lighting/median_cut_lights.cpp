#include "lighting/median_cut_lights.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rad {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Summed-area table of the weighted luminance: at(r, c) = sum over rows < r, columns < c.
class SummedArea {
public:
    explicit SummedArea(const EnvironmentMap& map) : width_(map.width()), table_((map.width() + 1) * std::size_t(map.height() + 1), 0.0) {
        for (int r = 0; r < map.height(); ++r) {
            const double solidAngle = map.texelSolidAngle(r);
            double rowSum = 0.0;
            for (int c = 0; c < map.width(); ++c) {
                const float* t = map.texel(c, r);
                rowSum += luminanceRec709(t[0], t[1], t[2]) * solidAngle;
                at(r + 1, c + 1) = at(r, c + 1) + rowSum;
            }
        }
    }
    double energy(int c0, int c1, int r0, int r1) const { return at(r1, c1) - at(r0, c1) - at(r1, c0) + at(r0, c0); }

private:
    double& at(int r, int c) { return table_[std::size_t(r) * (width_ + 1) + c]; }
    double at(int r, int c) const { return table_[std::size_t(r) * (width_ + 1) + c]; }
    int width_;
    std::vector<double> table_;
};

// The cut position in (lo, hi) whose first part [lo, cut) holds the energy closest to half of
// [lo, hi). firstPart(cut) is non-decreasing in cut: binary search for the first cut reaching
// half, then compare with its predecessor. A black region is cut in the middle.
template <typename FirstPart>
int medianCut(int lo, int hi, double total, FirstPart firstPart) {
    if (!(total > 0.0)) return lo + (hi - lo) / 2;
    int a = lo + 1, b = hi - 1;  // search range of valid cuts
    while (a < b) {
        const int mid = a + (b - a) / 2;
        if (2.0 * firstPart(mid) >= total) b = mid;
        else a = mid + 1;
    }
    if (a > lo + 1 && std::fabs(2.0 * firstPart(a - 1) - total) <= std::fabs(2.0 * firstPart(a) - total)) return a - 1;
    return a;
}

}  // namespace

std::vector<MedianCutRegion> medianCutRegions(const EnvironmentMap& map, int levels) {
    if (levels < 0 || levels > 24)
        throw std::invalid_argument("medianCutRegions: levels " + std::to_string(levels) + " outside [0, 24]");
    std::vector<MedianCutRegion> regions;
    if (map.empty()) return regions;
    const int W = map.width(), H = map.height();
    const SummedArea sat(map);
    const double dPhi = 2.0 * kPi / W, dTheta = kPi / H;

    MedianCutRegion whole;
    whole.column1 = W;
    whole.row1 = H;
    regions.push_back(whole);
    for (int level = 0; level < levels; ++level) {
        std::vector<MedianCutRegion> next;
        next.reserve(regions.size() * 2);
        for (const MedianCutRegion& region : regions) {
            const int columns = region.column1 - region.column0, rows = region.row1 - region.row0;
            if (columns == 1 && rows == 1) {
                next.push_back(region);
                continue;
            }
            // Angular side lengths (Debevec's cos(latitude) scaling of the width).
            const double middleTheta = 0.5 * (region.row0 + region.row1) * dTheta;
            const double angularWidth = columns * dPhi * std::sin(middleTheta);
            const double angularHeight = rows * dTheta;
            const bool cutColumns = rows == 1 || (columns > 1 && angularWidth >= angularHeight);
            const double total = sat.energy(region.column0, region.column1, region.row0, region.row1);
            MedianCutRegion first = region, second = region;
            if (cutColumns) {
                const int cut = medianCut(region.column0, region.column1, total, [&](int c) {
                    return sat.energy(region.column0, c, region.row0, region.row1);
                });
                first.column1 = second.column0 = cut;
            } else {
                const int cut = medianCut(region.row0, region.row1, total, [&](int r) {
                    return sat.energy(region.column0, region.column1, region.row0, r);
                });
                first.row1 = second.row0 = cut;
            }
            next.push_back(first);
            next.push_back(second);
        }
        regions.swap(next);
        if (static_cast<long long>(regions.size()) >= static_cast<long long>(W) * H) break;  // all single texels
    }

    // Per-texel geometry, in the map frame; rotated at the end.
    std::vector<double> cosPhi(W), sinPhi(W), sinTheta(H), cosTheta(H), solidAngle(H);
    for (int c = 0; c < W; ++c) {
        const Eigen::Vector3d d = EnvironmentMap::mapDirection((c + 0.5) / W, 0.5);  // on the equator: (cos phi, sin phi, 0)
        cosPhi[c] = d.x();
        sinPhi[c] = d.y();
    }
    for (int r = 0; r < H; ++r) {
        const double theta = (r + 0.5) * dTheta;
        sinTheta[r] = std::sin(theta);
        cosTheta[r] = std::cos(theta);
        solidAngle[r] = map.texelSolidAngle(r);
    }
    const Eigen::Matrix3d& R = map.rotation();
#pragma omp parallel for schedule(dynamic, 1)
    for (long long i = 0; i < static_cast<long long>(regions.size()); ++i) {
        MedianCutRegion& region = regions[i];
        Eigen::Vector3d power = Eigen::Vector3d::Zero(), centroid = Eigen::Vector3d::Zero();
        double luminance = 0.0;
        for (int r = region.row0; r < region.row1; ++r) {
            Eigen::Vector3d rowPower = Eigen::Vector3d::Zero();
            double rowCos = 0.0, rowSin = 0.0, rowLuminance = 0.0;
            for (int c = region.column0; c < region.column1; ++c) {
                const float* t = map.texel(c, r);
                const double y = luminanceRec709(t[0], t[1], t[2]);
                rowPower += Eigen::Vector3d(t[0], t[1], t[2]);
                rowLuminance += y;
                rowCos += y * cosPhi[c];
                rowSin += y * sinPhi[c];
            }
            power += rowPower * solidAngle[r];
            luminance += rowLuminance * solidAngle[r];
            centroid += solidAngle[r] * Eigen::Vector3d(sinTheta[r] * rowCos, sinTheta[r] * rowSin, cosTheta[r] * rowLuminance);
        }
        Eigen::Vector3d direction;
        if (luminance > 0.0 && centroid.norm() > 1e-9 * luminance)
            direction = centroid.normalized();
        else  // black region, or luminance spread so evenly that its mean direction vanishes
            direction = EnvironmentMap::mapDirection(0.5 * (region.column0 + region.column1) / W,
                                                     0.5 * (region.row0 + region.row1) / H);
        region.light.direction = R * direction;
        region.light.irradiance = power;
    }
    return regions;
}

std::vector<DirectionalLight> medianCutLights(const EnvironmentMap& map, int levels) {
    const std::vector<MedianCutRegion> regions = medianCutRegions(map, levels);
    std::vector<DirectionalLight> lights;
    lights.reserve(regions.size());
    for (const MedianCutRegion& region : regions)
        if (region.light.irradiance.maxCoeff() > 0.0) lights.push_back(region.light);
    std::stable_sort(lights.begin(), lights.end(), [](const DirectionalLight& a, const DirectionalLight& b) {
        return luminanceRec709(a.irradiance[0], a.irradiance[1], a.irradiance[2]) >
               luminanceRec709(b.irradiance[0], b.irradiance[1], b.irradiance[2]);
    });
    return lights;
}

}  // namespace rad
