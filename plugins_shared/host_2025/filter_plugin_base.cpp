#include "filter_plugin_base.h"

#include "filter_errors.h"

namespace radml {

void FilterPluginBase::addFilter(std::unique_ptr<Filter> filter) {
    const int id = int(filters_.size());
    filters_.push_back(std::move(filter));
    typeList.push_back(id);
    actionList.push_back(new QAction(filters_.back()->name(), this));
}

const Filter* FilterPluginBase::filterOf(int id) const {
    return id >= 0 && id < int(filters_.size()) ? filters_[std::size_t(id)].get() : nullptr;
}

QString FilterPluginBase::filterName(ActionIDType id) const {
    const Filter* f = filterOf(id);
    return f ? f->name() : QString();
}

QString FilterPluginBase::filterInfo(ActionIDType id) const {
    const Filter* f = filterOf(id);
    return f ? f->description() : QString();
}

QString FilterPluginBase::pythonFilterName(ActionIDType id) const {
    const Filter* f = filterOf(id);
    if (f != nullptr && !f->pythonName().isEmpty()) return f->pythonName();
    return FilterPlugin::pythonFilterName(id);
}

FilterPlugin::FilterClass FilterPluginBase::getClass(const QAction* action) const {
    const Filter* f = filterOf(ID(action));
    return f ? FilterClass(f->filterClass()) : FilterPlugin::Generic;
}

int FilterPluginBase::getPreConditions(const QAction* action) const {
    const Filter* f = filterOf(ID(action));
    return f ? f->preconditions() : int(MeshModel::MM_NONE);
}

FilterPlugin::FilterArity FilterPluginBase::filterArity(const QAction* action) const {
    const Filter* f = filterOf(ID(action));
    if (f && !f->needsCurrentLayer()) return NONE;
    return f && f->readsOtherLayers() ? FIXED : SINGLE_MESH;
}

int FilterPluginBase::postCondition(const QAction* action) const {
    const Filter* f = filterOf(ID(action));
    return f ? f->postconditions() : int(MeshModel::MM_NONE);
}

RichParameterList FilterPluginBase::initParameterList(const QAction*, const MeshModel&) {
    // MeshLab 2025 and pymeshlab ask through the document overload; without a document there are no
    // layers to offer as defaults.
    return {};
}

RichParameterList FilterPluginBase::initParameterList(const QAction* action, const MeshDocument& md) {
    const Filter* f = filterOf(ID(action));
    if (f == nullptr) return {};
    if (md.mm() != nullptr) return f->parameters(md, *md.mm());
    return f->needsCurrentLayer() ? RichParameterList() : f->parametersWithoutLayer(md);
}

std::map<std::string, QVariant> FilterPluginBase::applyFilter(const QAction* action, const RichParameterList& par,
                                                              MeshDocument& md, unsigned int& postConditionMask,
                                                              vcg::CallBackPos* cb) {
    const Filter* f = filterOf(ID(action));
    const std::string failure = runFilter(f, md, par, cb, [this](const std::string& line) {
        log(GLLogStream::FILTER, line);
    }, [this](const std::string& line) { log(GLLogStream::WARNING, line); });
    // pymeshlab raises our message as its exception; MeshLab's GUI shows it in a dialog.
    if (!failure.empty()) throw MLException(QString::fromStdString(failure));
    if (f != nullptr) postConditionMask = unsigned(f->postconditions());
    return {};
}

}  // namespace radml
