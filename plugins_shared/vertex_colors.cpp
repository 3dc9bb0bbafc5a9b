#include "vertex_colors.h"

#include "filter.h"

#include "radiance/view_colors.h"

#include <cmath>

namespace radml {

VertexArrays collectVertexArrays(const CMeshO& mesh) {
    VertexArrays out;
    out.positions.reserve(3 * std::size_t(mesh.vn));
    out.normals.reserve(3 * std::size_t(mesh.vn));
    std::vector<std::uint32_t> liveIndex(mesh.vert.size(), 0);
    std::uint32_t next = 0;
    for (std::size_t i = 0; i < mesh.vert.size(); ++i) {
        const CVertexO& v = mesh.vert[i];
        if (v.IsD()) continue;
        liveIndex[i] = next++;
        for (int k = 0; k < 3; ++k) {
            out.positions.push_back(float(v.cP()[k]));
            out.normals.push_back(float(v.cN()[k]));
        }
    }
    if (out.positions.empty()) throw Refusal("The current mesh has no vertices: select a layer that has some.");
    out.faces.reserve(3 * std::size_t(mesh.fn));
    for (const CFaceO& f : mesh.face) {
        if (f.IsD()) continue;
        for (int k = 0; k < 3; ++k) out.faces.push_back(liveIndex[vcg::tri::Index(mesh, f.cV(k))]);
    }
    return out;
}

void setVertexColorsFromLinear(MeshModel& m, const std::vector<float>& linearRgb) {
    std::size_t i = 0;
    for (CVertexO& v : m.cm.vert) {
        if (v.IsD()) continue;
        v.C() = vcg::Color4b(rad::encodeSrgb8(linearRgb[3 * i]), rad::encodeSrgb8(linearRgb[3 * i + 1]),
                             rad::encodeSrgb8(linearRgb[3 * i + 2]), 255);
        ++i;
    }
    m.updateDataMask(MeshModel::MM_VERTCOLOR);
}

void setVertexQuality(MeshModel& m, const std::vector<float>& values) {
    m.updateDataMask(MeshModel::MM_VERTQUALITY);
    std::size_t i = 0;
    for (CVertexO& v : m.cm.vert) {
        if (v.IsD()) continue;
        v.Q() = values[i++];
    }
}

std::array<float, 3> linearColorParameter(const RichParameterList& par, const QString& name) {
    const QColor c = par.getColor(name);
    auto decode = [](double s) {
        return float(s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4));
    };
    return {decode(c.redF()), decode(c.greenF()), decode(c.blueF())};
}

}  // namespace radml
