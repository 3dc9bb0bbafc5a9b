// Filter plugin for precomputed radiance transfer (paper 001, Krivanek, Pattanaik, Zara, and
// Sloan et al. 2002): per-vertex SH transfer vectors ray-cast with Embree, adaptive subdivision
// under a triangle budget (paper 001 Fig. 2-3, eq. 2-4), the uniform baseline, and relighting as
// vertex colours under an HDR environment map or a directional light.
// A thin adapter: parameters in, a call into common/prt, the result attached to the layer, log out.
#pragma once

#include <QObject>
#include <common/interfaces.h>

class PrtFilterPlugin : public QObject, public MeshFilterInterface {
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID)
    Q_INTERFACES(MeshFilterInterface)

public:
    enum { FP_COMPUTE_TRANSFER, FP_ADAPTIVE_SUBDIVISION, FP_UNIFORM_SUBDIVISION, FP_RELIGHT };

    PrtFilterPlugin();
    QString pluginName() const override { return "FilterPrtSubdivide"; }
    QString filterName(FilterIDType filter) const override;
    QString filterInfo(FilterIDType filter) const override;
    FilterClass getClass(QAction* action) override;
    int getPreConditions(QAction* action) const override;
    int postCondition(QAction* action) const override;
    FILTER_ARITY filterArity(QAction*) const override { return SINGLE_MESH; }
    void initParameterSet(QAction* action, MeshModel& m, RichParameterList& par) override;
    bool applyFilter(QAction* action, MeshDocument& md, const RichParameterList& par, vcg::CallBackPos* cb) override;

private:
    bool computeTransfer(MeshDocument& md, MeshModel& m, const RichParameterList& par, vcg::CallBackPos* cb);
    bool subdivide(MeshDocument& md, MeshModel& m, const RichParameterList& par, vcg::CallBackPos* cb, bool adaptive);
    bool relight(MeshModel& m, const RichParameterList& par, vcg::CallBackPos* cb);
};
