// The "Radiance Field" decoration: draws the current mesh's radiance functions per vertex or per
// fragment (Vanhoey et al. 2015 sec. 5, eq. 8), or its PRT transfer relit by a light, over MeshLab's
// own rendering. A thin adapter: the drawing is render_gl/radiance_gl_renderer.h, the relighting
// prt/prt_lighting.h; this file reads parameters, gathers the layer's data, logs and writes the
// optional view file (docs/decorate-radiance.md).
#pragma once

#include "decoration.h"
#include "decoration_support.h"

namespace raddecorate {

class RadianceFieldDecoration : public Decoration {
public:
    RadianceFieldDecoration();
    ~RadianceFieldDecoration() override;
    QString name() const override;
    QString info() const override;
    ActionLook look() const override;
    bool isApplicable(const MeshModel& m, QString& message) const override;
    void addParameters(RichParameterList& par) const override;
    bool start(MeshModel& m, const RichParameterList& par, GLArea& gla, MeshLabInterface& pluginLog) override;
    void draw(MeshModel& m, const RichParameterList& par, GLArea* gla, GLLogStream& log,
              MeshLabInterface& pluginLog) override;
    void end(MeshModel& m, GLArea* gla) override;

    struct View;  // per (view, layer): the GL renderer and what it was built from

private:
    LayerViews<View> views_;
};

}  // namespace raddecorate
