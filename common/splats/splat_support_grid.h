// Which splats can reach a point: a hierarchy of uniform grids over axis-aligned boxes (one per splat,
// its support), answering "every box that contains p" in time independent of the splat count.
//
// Splat sizes span orders of magnitude in a trained scene, which defeats a single grid (a big splat
// would fill thousands of cells, a coarse cell would hold thousands of small splats). Each box goes
// to the level whose cell size c0 2^L is the first at least as wide as the box, into the one cell that
// holds its centre; a box containing p then has its centre within half a cell of p along each axis,
// so a query looks at the 3 x 3 x 3 cells around p on every level in use. c0 is the median box width.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <unordered_map>
#include <vector>

namespace rad {

struct SupportBox {
    Eigen::Vector3d lo, hi;  // finite, lo <= hi
};

class SplatSupportGrid {
public:
    // Indexes boxes[i] as item i. Throws std::invalid_argument on a box that is not finite or inverted.
    explicit SplatSupportGrid(const std::vector<SupportBox>& boxes);

    // Calls visit(i) once for every box i that contains p (boundary included).
    void forEachContaining(const Eigen::Vector3d& p, const std::function<void(std::uint32_t)>& visit) const;

    int levelCount() const { return static_cast<int>(levels_.size()); }
    double baseCellSize() const { return baseCell_; }

private:
    struct CellKey {
        int level;
        std::int64_t x, y, z;
        bool operator==(const CellKey& o) const { return level == o.level && x == o.x && y == o.y && z == o.z; }
    };
    struct CellHash {
        std::size_t operator()(const CellKey& k) const;
    };
    std::int64_t cellIndex(double coordinate, int level) const;

    std::vector<SupportBox> boxes_;
    double baseCell_ = 1.0;
    std::vector<int> levels_;  // levels holding at least one box
    std::unordered_map<CellKey, std::vector<std::uint32_t>, CellHash> cells_;
};

}  // namespace rad
