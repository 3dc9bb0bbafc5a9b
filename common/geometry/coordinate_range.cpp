#include "geometry/coordinate_range.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

namespace rad {

std::string coordinateRangeProblem(const float* positions, std::size_t vertexCount) {
    for (std::size_t i = 0; i < 3 * vertexCount; ++i) {
        const float x = positions[i];
        if (std::isfinite(x) && std::fabs(x) <= kMaxCoordinateMagnitude) continue;
        std::ostringstream why;
        if (!std::isfinite(x)) {
            why << "Vertex " << i / 3 << " has a coordinate that is not a finite number (NaN or infinity): remove "
                << "such vertices or fix the file.";
        } else {
            why << "Vertex " << i / 3 << " has a coordinate of " << x << ", beyond the " << kMaxCoordinateMagnitude
                << " that single-precision geometry can be computed with: scale the mesh down "
                << "({{Transform: Scale, Normalize}}) or remove the stray vertices.";
        }
        return why.str();
    }
    return {};
}

bool referencedBox(const float* positions, std::size_t vertexCount, const std::uint32_t* faces, std::size_t faceCount,
                   double lo[3], double hi[3]) {
    for (int a = 0; a < 3; ++a) {
        lo[a] = std::numeric_limits<double>::infinity();
        hi[a] = -std::numeric_limits<double>::infinity();
    }
    bool any = false;
    const auto add = [&](std::size_t v) {
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], double(positions[3 * v + a]));
            hi[a] = std::max(hi[a], double(positions[3 * v + a]));
        }
        any = true;
    };
    if (!faces) {
        for (std::size_t v = 0; v < vertexCount; ++v) add(v);
    } else {
        for (std::size_t i = 0; i < 3 * faceCount; ++i)
            if (faces[i] < vertexCount) add(faces[i]);
    }
    return any;
}

std::string sceneScaleProblem(const float* positions, std::size_t vertexCount, const std::uint32_t* faces,
                              std::size_t faceCount, const std::string& what) {
    if (std::string range = coordinateRangeProblem(positions, vertexCount); !range.empty()) return range;
    double lo[3], hi[3];
    if (!referencedBox(positions, vertexCount, faces, faceCount, lo, hi)) return {};
    return boxScaleProblem(lo, hi, what);
}

std::string boxScaleProblem(const double lo[3], const double hi[3], const std::string& what) {
    double extent = 0.0, magnitude = 0.0;
    for (int a = 0; a < 3; ++a) {
        extent = std::max(extent, hi[a] - lo[a]);
        magnitude = std::max({magnitude, std::fabs(lo[a]), std::fabs(hi[a])});
    }
    std::ostringstream why;
    if (extent < kMinSceneExtent) {
        why << what << " is " << extent << " units across, below the " << kMinSceneExtent
            << " that single-precision geometry can be computed with (products of coordinates underflow to zero): "
            << "scale it up ({{Transform: Scale, Normalize}}, e.g. 'Scale to Unit bbox').";
    } else if (extent < kMinRelativeExtent * magnitude) {
        why << what << " is " << extent << " units across but lies " << magnitude
            << " units from the origin: single-precision coordinates there are too coarse for its size. Move it to "
            << "the origin first ({{Transform: Translate, Center, set Origin}}, with 'Center on BBox').";
    }
    return why.str();
}

}  // namespace rad
