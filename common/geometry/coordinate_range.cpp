#include "geometry/coordinate_range.h"

#include <cmath>
#include <sstream>

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
                << " that single-precision geometry can be computed with: scale the mesh down (Filters > Normals, "
                << "Curvatures and Orientation > Transform: Scale, Normalize) or remove the stray vertices.";
        }
        return why.str();
    }
    return {};
}

}  // namespace rad
