// Mesh loading and sample-scene setup shared by the tools that build synthetic radiance data
// (virtual_acquisition, make_radiance_mesh).
#pragma once

#include "geometry/triangle_mesh.h"
#include "io/off_reader.h"
#include "io/radiance_ply.h"
#include "radiance/material_radiance.h"
#include "radiance/view_colors.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "command_line.h"

namespace radtools {

inline Eigen::Vector3d parseAxis(const std::string& text) {
    static const std::pair<const char*, Eigen::Vector3d> axes[] = {
        {"x", Eigen::Vector3d::UnitX()},  {"y", Eigen::Vector3d::UnitY()},  {"z", Eigen::Vector3d::UnitZ()},
        {"-x", -Eigen::Vector3d::UnitX()}, {"-y", -Eigen::Vector3d::UnitY()}, {"-z", -Eigen::Vector3d::UnitZ()}};
    for (const auto& a : axes)
        if (text == a.first) return a.second;
    throw UsageError("--up needs x, y, z, -x, -y or -z, got '" + text + "'");
}

inline std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

// An .off, or a binary little-endian .ply / .rply (radiance, if any, dropped).
inline rad::TriangleMesh loadMesh(const std::string& path) {
    const std::string ext = lower(std::filesystem::path(path).extension().string());
    rad::TriangleMesh mesh;
    if (ext == ".off") {
        mesh = rad::readOff(path);
    } else if (ext == ".ply" || ext == ".rply") {
        rad::RadianceMesh rm = rad::readRadiancePly(path);
        mesh.positions = std::move(rm.positions);
        mesh.normals = std::move(rm.normals);
        mesh.faces = std::move(rm.faces);
    } else {
        throw UsageError("the mesh must be an .off or a binary little-endian .ply file: " + path);
    }
    return mesh;
}

// Bounding box and the radius of the bounding sphere around its centre.
// Vertex colour := the RF's mean colour in 8-bit sRGB, opaque, as the fitting filter sets it (so any
// PLY viewer shows the diffuse look). Precondition: out.radiance is set.
inline void setMeanColors(rad::RadianceMesh& out) {
    std::vector<float> mean(3 * out.vertexCount());
    rad::meanHemisphereColors(*out.radiance, mean.data());
    out.colors.resize(4 * out.vertexCount());
    for (std::size_t v = 0; v < out.vertexCount(); ++v) {
        for (int c = 0; c < 3; ++c) out.colors[4 * v + c] = rad::encodeSrgb8(mean[3 * v + c]);
        out.colors[4 * v + 3] = 255;
    }
}

}  // namespace radtools
