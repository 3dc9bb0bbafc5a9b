// MeshLab's decorate plugin of the project: the decorations "Radiance Field"
// (radiance_field_decoration.h), "Baked Normal Map" (normal_map_decoration.h) and "Irradiance Vector
// Grid" (irradiance_grid_decoration.h). A thin adapter over the Decoration interface (decoration.h):
// it owns one of each, indexed by the decoration id, and forwards each of MeshLab's calls to the one
// whose id the action has.
#pragma once

#include "decoration.h"

#include <QObject>
#include <common/interfaces.h>

#include <array>
#include <memory>

class DecorateRadiancePlugin : public QObject, public MeshDecorateInterface {
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(MESH_DECORATE_INTERFACE_IID)
    Q_INTERFACES(MeshDecorateInterface)

public:
    enum { DP_RADIANCE_FIELD, DP_NORMAL_MAP, DP_IRRADIANCE_GRID, DP_COUNT };

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

private:
    // The decoration of an id; null for an id that is not one of ours.
    raddecorate::Decoration* decoration(FilterIDType id) const;
    raddecorate::Decoration& decoration(QAction* action) const { return *decoration(ID(action)); }

    std::array<std::unique_ptr<raddecorate::Decoration>, DP_COUNT> decorations_;
};
