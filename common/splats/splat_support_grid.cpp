#include "splats/splat_support_grid.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

namespace rad {

std::size_t SplatSupportGrid::CellHash::operator()(const CellKey& k) const {
    std::uint64_t h = static_cast<std::uint64_t>(k.level) * 0x9E3779B97F4A7C15ull;
    for (std::int64_t v : {k.x, k.y, k.z}) h = (h ^ static_cast<std::uint64_t>(v)) * 0xBF58476D1CE4E5B9ull + 0x94D049BB133111EBull;
    return static_cast<std::size_t>(h ^ (h >> 31));
}

std::int64_t SplatSupportGrid::cellIndex(double coordinate, int level) const {
    return static_cast<std::int64_t>(std::floor(coordinate / std::ldexp(baseCell_, level)));
}

SplatSupportGrid::SplatSupportGrid(const std::vector<SupportBox>& boxes) : boxes_(boxes) {
    // 1. Widths checked; the base cell is their median (a zero width counts as the smallest positive one).
    std::vector<double> widths(boxes_.size());
    for (std::size_t i = 0; i < boxes_.size(); ++i) {
        const SupportBox& b = boxes_[i];
        if (!b.lo.allFinite() || !b.hi.allFinite() || (b.hi - b.lo).minCoeff() < 0.0)
            throw std::invalid_argument("splat support box " + std::to_string(i) + " is not finite or inverted");
        widths[i] = (b.hi - b.lo).maxCoeff();
    }
    if (!widths.empty()) {
        std::vector<double> sorted(widths);
        std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
        baseCell_ = sorted[sorted.size() / 2];
        if (!(baseCell_ > 0.0)) {
            double smallest = 0.0;
            for (double w : widths)
                if (w > 0.0 && (smallest == 0.0 || w < smallest)) smallest = w;
            baseCell_ = smallest > 0.0 ? smallest : 1.0;
        }
    }
    // 2. Each box into the cell holding its centre, on the first level whose cells are as wide as it.
    std::set<int> used;
    for (std::size_t i = 0; i < boxes_.size(); ++i) {
        int level = 0;
        while (std::ldexp(baseCell_, level) < widths[i]) ++level;
        const Eigen::Vector3d centre = 0.5 * (boxes_[i].lo + boxes_[i].hi);
        cells_[CellKey{level, cellIndex(centre.x(), level), cellIndex(centre.y(), level), cellIndex(centre.z(), level)}]
            .push_back(static_cast<std::uint32_t>(i));
        used.insert(level);
    }
    levels_.assign(used.begin(), used.end());
}

void SplatSupportGrid::forEachContaining(const Eigen::Vector3d& p,
                                         const std::function<void(std::uint32_t)>& visit) const {
    for (int level : levels_) {
        const std::int64_t cx = cellIndex(p.x(), level), cy = cellIndex(p.y(), level), cz = cellIndex(p.z(), level);
        for (std::int64_t dx = -1; dx <= 1; ++dx)
            for (std::int64_t dy = -1; dy <= 1; ++dy)
                for (std::int64_t dz = -1; dz <= 1; ++dz) {
                    const auto it = cells_.find(CellKey{level, cx + dx, cy + dy, cz + dz});
                    if (it == cells_.end()) continue;
                    for (std::uint32_t i : it->second) {
                        const SupportBox& b = boxes_[i];
                        if ((p.array() >= b.lo.array()).all() && (p.array() <= b.hi.array()).all()) visit(i);
                    }
                }
    }
}

}  // namespace rad
