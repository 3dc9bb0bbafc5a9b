// MeshLab 2020.09's filter interface over a list of radml::Filter (filter.h). A plugin is a small
// class deriving from this one (Q_OBJECT and the plugin metadata must be in the final class) that
// registers its filters in its constructor.
#pragma once

#include "filter.h"

#include <QObject>

#include <memory>
#include <vector>

namespace radml {

class FilterPluginBase : public QObject, public MeshFilterInterface {
public:
    QString filterName(FilterIDType id) const override;
    QString filterInfo(FilterIDType id) const override;
    FilterClass getClass(QAction* action) override;
    int getPreConditions(QAction* action) const override;
    int postCondition(QAction* action) const override;
    FILTER_ARITY filterArity(QAction* action) const override;
    using MeshFilterInterface::initParameterSet;
    void initParameterSet(QAction* action, MeshModel& m, RichParameterList& par) override;
    void initParameterSet(QAction* action, MeshDocument& md, RichParameterList& par) override;
    bool applyFilter(QAction* action, MeshDocument& md, const RichParameterList& par, vcg::CallBackPos* cb) override;

protected:
    void addFilter(std::unique_ptr<Filter> filter);

private:
    const Filter* filterOf(int id) const;
    std::vector<std::unique_ptr<Filter>> filters_;
};

}  // namespace radml
