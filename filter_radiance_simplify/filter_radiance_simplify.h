// Filter plugin for radiance data on meshes (paper 000, Vanhoey et al. 2015): fits radiance
// functions from calibrated photographs (raster layers), creates them from an analytic material,
// evaluates them toward a viewpoint as vertex colours, and simplifies meshes carrying them
// (radiance-aware edge collapse with levels of detail).
// A thin adapter: parameters in, a call into common/, the result attached to the layer, log out.
#pragma once

#include <QObject>
#include <common/interfaces.h>

class RadianceFilterPlugin : public QObject, public MeshFilterInterface {
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID)
    Q_INTERFACES(MeshFilterInterface)

public:
    enum { FP_CREATE_ANALYTIC_RADIANCE, FP_RADIANCE_TO_VERTEX_COLOR, FP_FIT_FROM_RASTERS, FP_RADIANCE_SIMPLIFICATION };

    RadianceFilterPlugin();
    QString pluginName() const override { return "FilterRadiance"; }
    QString filterName(FilterIDType filter) const override;
    QString filterInfo(FilterIDType filter) const override;
    FilterClass getClass(QAction* action) override;
    int getPreConditions(QAction* action) const override;
    int postCondition(QAction* action) const override;
    FILTER_ARITY filterArity(QAction*) const override { return SINGLE_MESH; }
    void initParameterSet(QAction* action, MeshModel& m, RichParameterList& par) override;
    bool applyFilter(QAction* action, MeshDocument& md, const RichParameterList& par, vcg::CallBackPos* cb) override;

private:
    bool createAnalyticRadiance(MeshModel& m, const RichParameterList& par, vcg::CallBackPos* cb);
    bool radianceToVertexColor(MeshModel& m, const RichParameterList& par, vcg::CallBackPos* cb);
    static void addFitParameters(MeshModel& m, RichParameterList& par);
    bool fitFromRasters(MeshDocument& md, MeshModel& m, const RichParameterList& par, vcg::CallBackPos* cb);
    static void addSimplifyParameters(MeshModel& m, RichParameterList& par);
    bool simplifyRadiance(MeshDocument& md, MeshModel& m, const RichParameterList& par, vcg::CallBackPos* cb);
};
