// The mesh the GL frame benchmarks draw: an OFF file, optionally midpoint-subdivided, with
// area-weighted normals, centred on the origin and scaled so its longest side is 2 (so one camera
// orbit frames any mesh).
#pragma once

#include "geometry/mesh_normals.h"
#include "geometry/midpoint_subdivision.h"
#include "io/off_reader.h"

#include <Eigen/Core>

#include <algorithm>
#include <string>

namespace radbench {

inline rad::TriangleMesh loadBenchMesh(const std::string& path, int subdivisionLevels) {
    rad::TriangleMesh mesh = rad::readOff(path);
    if (subdivisionLevels > 0) mesh = rad::subdivideMidpoint(mesh, subdivisionLevels);
    rad::computeAreaWeightedNormals(mesh);
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e30), hi = -lo;
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], double(mesh.positions[3 * v + a]));
            hi[a] = std::max(hi[a], double(mesh.positions[3 * v + a]));
        }
    const Eigen::Vector3d centre = 0.5 * (lo + hi);
    const double scale = 2.0 / (hi - lo).maxCoeff();
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
        for (int a = 0; a < 3; ++a) mesh.positions[3 * v + a] = float((mesh.positions[3 * v + a] - centre[a]) * scale);
    return mesh;
}

}  // namespace radbench
