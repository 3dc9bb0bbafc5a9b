// The "Radiance Field" decoration: draws the current mesh's radiance functions per vertex or per
// fragment (Vanhoey et al. 2015 sec. 5, eq. 8), or its PRT transfer relit by a light, over MeshLab's
// own rendering. A thin adapter: the drawing is render_gl/radiance_gl_renderer.h, the relighting
// prt/prt_lighting.h; this file reads parameters, gathers the layer's data, logs and writes the
// optional view file (docs/decorate-radiance.md).
#pragma once

#include "decoration.h"

#include <memory>

namespace raddecorate {

std::unique_ptr<Decoration> makeRadianceFieldDecoration();

}  // namespace raddecorate
