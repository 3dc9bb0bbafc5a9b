// The "Irradiance Vector Grid" decoration: the layer lit by the indirect light of an irradiance
// vector grid (Granier et al. 2007), evaluated per fragment on the GPU (render_gl/irradiance_grid_*:
// the paper's 12 16-bit 3D textures, trilinear, squared-normal weights, L = rho / pi <I_n, n>), alone
// or added to one directional light that follows the camera (Lambert, no shadows). The grid is the
// layer's file with the extension .ivg (as the grid computation writes it) or a file named in the
// options; rho is the diffuse map of the layer's normal-map bake (B_diffuse.png) when there is one,
// else the layer's vertex colour (sRGB decoded) when it has colours, else the albedo option; when
// the layer carries a normal map baked by 'Bake Normal Map', the grid is evaluated with the mapped
// normal (the paper's simplified mesh + normal map + grid). A thin adapter: parameters,
// files, log; the drawing is render_gl/normal_map_gl_renderer.h.
#pragma once

#include "normal_map_gl_renderer.h"

#include <common/interfaces.h>

#include <memory>
#include <set>
#include <string>

namespace raddecorate {

struct IrradianceGridView {
    std::unique_ptr<radgl::NormalMapGlRenderer> renderer;
    std::string gridPath;        // the grid drawn
    std::string failedPath;      // a grid named in the options that could not be read (not retried every frame)
    bool normalMap = false;      // the layer's baked normal map is uploaded
    int vn = -1, fn = -1;        // what was uploaded (a filter that changes the layer stops the drawing)
    const void* vertices = nullptr;
    const void* faces = nullptr;
    std::set<std::string> reported;  // messages logged once
};

void addIrradianceGridParameters(RichParameterList& par);
QString irradianceGridInfo();

// Sets the layer up (mesh, albedo, normal map, grid). Returns null with `why` (no grid file, a bad
// file with the reader's reason, GL limits, no faces); else the view, with `startLine` for the log.
std::unique_ptr<IrradianceGridView> startIrradianceGrid(MeshModel& m, const RichParameterList& par, std::string& startLine,
                                                       std::string& why);

// Draws one frame (MeshLab's matrices current); problems are logged once each.
void drawIrradianceGrid(IrradianceGridView& view, MeshModel& m, const RichParameterList& par, GLLogStream& log);

}  // namespace raddecorate
