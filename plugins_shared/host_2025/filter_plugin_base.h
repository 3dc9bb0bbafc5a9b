// MeshLab 2025.07's filter interface over a list of radml::Filter (filter.h). A plugin is a small
// class deriving from this one (Q_OBJECT and the plugin metadata must be in the final class) that
// registers its filters in its constructor.
#pragma once

#include "filter.h"

#include <QObject>

#include <memory>
#include <vector>

namespace radml {

class FilterPluginBase : public QObject, public FilterPlugin {
public:
    QString vendor() const override { return "radiance-tools"; }
    QString filterName(ActionIDType id) const override;
    QString filterInfo(ActionIDType id) const override;
    QString pythonFilterName(ActionIDType id) const override;
    FilterClass getClass(const QAction* action) const override;
    int getPreConditions(const QAction* action) const override;
    int postCondition(const QAction* action) const override;
    FilterArity filterArity(const QAction* action) const override;
    RichParameterList initParameterList(const QAction* action, const MeshModel& m) override;
    RichParameterList initParameterList(const QAction* action, const MeshDocument& md) override;
    std::map<std::string, QVariant> applyFilter(const QAction* action, const RichParameterList& par,
                                                MeshDocument& md, unsigned int& postConditionMask,
                                                vcg::CallBackPos* cb) override;

protected:
    void addFilter(std::unique_ptr<Filter> filter);

private:
    const Filter* filterOf(int id) const;
    std::vector<std::unique_ptr<Filter>> filters_;
};

}  // namespace radml
