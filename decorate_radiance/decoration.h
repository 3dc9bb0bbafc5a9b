// One MeshLab decoration of the plugin (MeshLab 2020.09's per-mesh decorations), described once:
// its name, help, action look, applicability, global parameters, and its start / draw / end on a
// layer of a view. The plugin class (decorate_radiance.h) owns one of each and forwards MeshLab's
// calls to the one whose action was used; each decoration keeps its own per-(view, layer) state.
#pragma once

#include <common/interfaces.h>

#include <QColor>
#include <QString>

class GLArea;

namespace raddecorate {

// How the decoration's action looks: its shortcut (Ctrl+Alt+key) and the colours of its toolbar icon.
struct ActionLook {
    Qt::Key shortcutKey;
    QColor iconMiddle;
    QColor iconEdge;
};

class Decoration {
public:
    virtual ~Decoration() = default;
    // The name of the action (menu Render, Decorator toolbar) and MeshLab's help text.
    virtual QString name() const = 0;
    virtual QString info() const = 0;
    virtual ActionLook look() const = 0;
    // False with `message` (what is missing and how to get it) when the layer cannot be decorated.
    virtual bool isApplicable(const MeshModel& m, QString& message) const = 0;
    // Its global parameters (Tools > Options > Decoration).
    virtual void addParameters(RichParameterList& par) const = 0;
    // Sets the layer up in the view's GL context; logs its start line, or why it refuses (false),
    // through the plugin's own log (`pluginLog`, which MeshLab may have unset).
    virtual bool start(MeshModel& m, const RichParameterList& par, GLArea& gla, MeshLabInterface& pluginLog) = 0;
    // Draws one frame over MeshLab's rendering of the layer (MeshLab's matrices current); per-frame
    // problems go to `log` once each.
    virtual void draw(MeshModel& m, const RichParameterList& par, GLArea* gla, GLLogStream& log,
                      MeshLabInterface& pluginLog) = 0;
    // Releases the layer's GL objects in the view's context.
    virtual void end(MeshModel& m, GLArea* gla) = 0;
};

}  // namespace raddecorate
