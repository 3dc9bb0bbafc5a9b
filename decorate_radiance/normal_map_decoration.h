// The "Baked Normal Map" decoration: draws a layer with the normal map of the "Bake Normal Map"
// filter, with Blinn-Phong or with the LEAN Gaussian lobe (Weber and Stamminger, Alg. 3-4;
// render_gl/normal_map_gl_renderer.h), so that the highlight's behaviour at a distance can be
// compared (docs/normal-map-baking.md), optionally as a POP buffer level of detail (Limper et al. 2013).
#pragma once

#include "decoration.h"
#include "decoration_support.h"

namespace raddecorate {

class NormalMapDecoration : public Decoration {
public:
    NormalMapDecoration();
    ~NormalMapDecoration() override;
    QString name() const override;
    QString info() const override;
    ActionLook look() const override;
    bool isApplicable(const MeshModel& m, QString& message) const override;
    void addParameters(RichParameterList& par) const override;
    bool start(MeshModel& m, const RichParameterList& par, GLArea& gla, MeshLabInterface& pluginLog) override;
    void draw(MeshModel& m, const RichParameterList& par, GLArea* gla, GLLogStream& log,
              MeshLabInterface& pluginLog) override;
    void end(MeshModel& m, GLArea* gla) override;

    struct View;  // per (view, layer): the normal-map renderer

private:
    LayerViews<View> views_;
};

}  // namespace raddecorate
