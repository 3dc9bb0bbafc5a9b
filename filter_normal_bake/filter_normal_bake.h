// Filter plugin "Bake Normal Map": the full scan's normals (and colours) baked into a texture of
// the simplified mesh (paper 004, Granier et al.), with LEAN covariance maps for filtered
// specular highlights (paper 002, Weber & Stamminger). A thin adapter: parameters in, a call into
// common/bake (normal_map_bake.h), the texture coordinates and the texture attached to the layer,
// log out.
#pragma once

#include <QObject>
#include <common/interfaces.h>

class NormalBakeFilterPlugin : public QObject, public MeshFilterInterface {
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID)
    Q_INTERFACES(MeshFilterInterface)

public:
    enum { FP_BAKE_NORMAL_MAP };

    NormalBakeFilterPlugin();
    QString pluginName() const override { return "FilterNormalBake"; }
    QString filterName(FilterIDType filter) const override;
    QString filterInfo(FilterIDType filter) const override;
    FilterClass getClass(QAction* action) override;
    int getPreConditions(QAction* action) const override;
    int postCondition(QAction* action) const override;
    FILTER_ARITY filterArity(QAction*) const override { return FIXED; }
    void initParameterSet(QAction* action, MeshDocument& md, RichParameterList& par) override;
    bool applyFilter(QAction* action, MeshDocument& md, const RichParameterList& par, vcg::CallBackPos* cb) override;

private:
    bool bake(MeshDocument& md, const RichParameterList& par, vcg::CallBackPos* cb);
};
