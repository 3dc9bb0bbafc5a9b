#include "decorate_radiance.h"

#include "irradiance_grid_decoration.h"
#include "normal_map_decoration.h"
#include "radiance_field_decoration.h"

#include <QPainter>

namespace {

// MeshLab lists a decoration on its toolbar only when it has an icon: a small drawn one.
QIcon drawnIcon(const raddecorate::ActionLook& look) {
    QPixmap pixmap(32, 32);
    pixmap.fill(Qt::transparent);
    QPainter painter(&pixmap);
    painter.setRenderHint(QPainter::Antialiasing);
    QRadialGradient gradient(QPointF(12, 11), 16);
    gradient.setColorAt(0.0, QColor(255, 255, 240));
    gradient.setColorAt(0.35, look.iconMiddle);
    gradient.setColorAt(1.0, look.iconEdge);
    painter.setBrush(gradient);
    painter.setPen(Qt::NoPen);
    painter.drawEllipse(QRectF(3, 3, 26, 26));
    painter.end();
    return QIcon(pixmap);
}

}  // namespace

DecorateRadiancePlugin::DecorateRadiancePlugin() {
    decorations_[DP_RADIANCE_FIELD] = raddecorate::makeRadianceFieldDecoration();
    decorations_[DP_NORMAL_MAP] = raddecorate::makeNormalMapDecoration();
    decorations_[DP_IRRADIANCE_GRID] = raddecorate::makeIrradianceGridDecoration();
    typeList << DP_RADIANCE_FIELD << DP_NORMAL_MAP << DP_IRRADIANCE_GRID;
    for (FilterIDType tt : types()) {
        const raddecorate::ActionLook look = decoration(tt)->look();
        QAction* action = new QAction(decorationName(tt), this);
        action->setCheckable(true);
        action->setShortcut(QKeySequence(Qt::CTRL + Qt::ALT + look.shortcutKey));
        action->setIcon(drawnIcon(look));
        actionList << action;
    }
}

// The decorations release what is left of their GL objects without a context (LayerViews).
DecorateRadiancePlugin::~DecorateRadiancePlugin() = default;

raddecorate::Decoration* DecorateRadiancePlugin::decoration(FilterIDType id) const {
    return id >= 0 && id < DP_COUNT ? decorations_[id].get() : nullptr;
}

QString DecorateRadiancePlugin::decorationName(FilterIDType id) const {
    const raddecorate::Decoration* d = decoration(id);
    return d ? d->name() : QString();
}

QString DecorateRadiancePlugin::decorationInfo(FilterIDType id) const {
    const raddecorate::Decoration* d = decoration(id);
    return d ? d->info() : QString();
}

bool DecorateRadiancePlugin::isDecorationApplicable(QAction* action, const MeshModel& m, QString& message) const {
    return decoration(action).isApplicable(m, message);
}

void DecorateRadiancePlugin::initGlobalParameterSet(QAction* action, RichParameterList& par) {
    decoration(action).addParameters(par);
}

bool DecorateRadiancePlugin::startDecorate(QAction* action, MeshModel& m, const RichParameterList* par, GLArea* gla) {
    if (!gla || !par) return false;
    return decoration(action).start(m, *par, *gla, *this);
}

void DecorateRadiancePlugin::endDecorate(QAction* action, MeshModel& m, const RichParameterList*, GLArea* gla) {
    decoration(action).end(m, gla);
}

void DecorateRadiancePlugin::decorateMesh(QAction* action, MeshModel& m, const RichParameterList* par, GLArea* gla,
                                          QPainter*, GLLogStream& log) {
    if (!par) return;
    decoration(action).draw(m, *par, gla, log, *this);
}

MESHLAB_PLUGIN_NAME_EXPORTER(DecorateRadiancePlugin)
