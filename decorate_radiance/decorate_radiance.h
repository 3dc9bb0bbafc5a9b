// MeshLab decorations "Radiance Field" and "Baked Normal Map".
// "Radiance Field" draws the current mesh's radiance functions per vertex or per
// fragment (Vanhoey et al. 2015 sec. 5, eq. 8), or its PRT transfer relit by a light, over MeshLab's own
// rendering. A thin adapter: the drawing is render_gl/radiance_gl_renderer.h, the relighting
// prt/prt_lighting.h; this file reads parameters, gathers the layer's data, logs and writes the
// optional view file (docs/decorate-radiance.md).
// "Baked Normal Map" draws a layer with the normal map of the "Bake Normal Map" filter, with
// Blinn-Phong or with the LEAN Gaussian lobe (Weber and Stamminger, Alg. 3-4; render_gl/normal_map_gl_renderer.h),
// so that the highlight's behaviour at a distance can be compared (docs/normal-map-baking.md).
// "Irradiance Vector Grid" draws a layer lit by the indirect light of an irradiance vector grid
// (Granier et al. 2007; irradiance_grid_decoration.h).
#pragma once

#include <QObject>
#include <common/interfaces.h>

#include <map>
#include <memory>

namespace raddecorate {
struct IrradianceGridView;
}
#include <utility>

class DecorateRadiancePlugin : public QObject, public MeshDecorateInterface {
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(MESH_DECORATE_INTERFACE_IID)
    Q_INTERFACES(MeshDecorateInterface)

public:
    enum { DP_RADIANCE_FIELD, DP_NORMAL_MAP, DP_IRRADIANCE_GRID };

    DecorateRadiancePlugin();
    ~DecorateRadiancePlugin() override;
    QString pluginName() const override { return "DecorateRadiance"; }
    QString decorationName(FilterIDType id) const override;
    QString decorationInfo(FilterIDType id) const override;
    int getDecorationClass(QAction*) const override { return MeshDecorateInterface::PerMesh; }
    bool isDecorationApplicable(QAction* action, const MeshModel& m, QString& message) const override;
    void initGlobalParameterSet(QAction* action, RichParameterList& parset) override;
    bool startDecorate(QAction* action, MeshModel& m, const RichParameterList* par, GLArea* gla) override;
    void decorateMesh(QAction* action, MeshModel& m, const RichParameterList* par, GLArea* gla, QPainter* painter,
                      GLLogStream& log) override;
    void decorateDoc(QAction*, MeshDocument&, const RichParameterList*, GLArea*, QPainter*, GLLogStream&) override {}
    void endDecorate(QAction* action, MeshModel& m, const RichParameterList* par, GLArea* gla) override;

    struct MeshView;       // per (view, layer): the GL renderer and what it was built from
    struct NormalMapView;  // per (view, layer): the normal-map renderer

private:
    bool startNormalMap(MeshModel& m, const RichParameterList* par, GLArea* gla);
    void decorateNormalMap(MeshModel& m, const RichParameterList* par, GLArea* gla, GLLogStream& log);

    using Key = std::pair<const GLArea*, int>;
    std::map<Key, std::unique_ptr<MeshView>> views_;
    std::map<Key, std::unique_ptr<NormalMapView>> normalViews_;
    std::map<Key, std::unique_ptr<raddecorate::IrradianceGridView>> gridViews_;
};
