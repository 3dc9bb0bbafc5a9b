#include "filter_plugin_base.h"

#include "filter_errors.h"

namespace radml {

void FilterPluginBase::addFilter(std::unique_ptr<Filter> filter) {
    const int id = int(filters_.size());
    filters_.push_back(std::move(filter));
    typeList << id;
    actionList << new QAction(filters_.back()->name(), this);
}

const Filter* FilterPluginBase::filterOf(int id) const {
    return id >= 0 && id < int(filters_.size()) ? filters_[std::size_t(id)].get() : nullptr;
}

QString FilterPluginBase::filterName(FilterIDType id) const {
    const Filter* f = filterOf(id);
    return f ? f->name() : QString();
}

QString FilterPluginBase::filterInfo(FilterIDType id) const {
    const Filter* f = filterOf(id);
    return f ? f->description() : QString();
}

MeshFilterInterface::FilterClass FilterPluginBase::getClass(QAction* action) {
    const Filter* f = filterOf(ID(action));
    return f ? FilterClass(f->filterClass()) : MeshFilterInterface::Generic;
}

int FilterPluginBase::getPreConditions(QAction* action) const {
    const Filter* f = filterOf(ID(action));
    return f ? f->preconditions() : int(MeshModel::MM_NONE);
}

MeshFilterInterface::FILTER_ARITY FilterPluginBase::filterArity(QAction* action) const {
    const Filter* f = filterOf(ID(action));
    if (f && !f->needsCurrentLayer()) return NONE;
    return f && f->readsOtherLayers() ? FIXED : SINGLE_MESH;
}

int FilterPluginBase::postCondition(QAction* action) const {
    const Filter* f = filterOf(ID(action));
    return f ? f->postconditions() : int(MeshModel::MM_NONE);
}

void FilterPluginBase::initParameterSet(QAction* action, MeshModel& m, RichParameterList& par) {
    // Only reached by callers without a document; our filters take the document overload.
    MeshDocument* md = m.parent;
    if (md != nullptr) initParameterSet(action, *md, par);
}

void FilterPluginBase::initParameterSet(QAction* action, MeshDocument& md, RichParameterList& par) {
    const Filter* f = filterOf(ID(action));
    if (f == nullptr) return;
    if (md.mm() != nullptr) par.join(f->parameters(md, *md.mm()));
    else if (!f->needsCurrentLayer()) par.join(f->parametersWithoutLayer(md));
}

bool FilterPluginBase::applyFilter(QAction* action, MeshDocument& md, const RichParameterList& par,
                                   vcg::CallBackPos* cb) {
    errorMessage.clear();
    const Filter* f = filterOf(ID(action));
    const QString name = f ? f->name() : QString("unknown filter");
    const std::string failure = runFilter(f, md, par, cb, [this](const std::string& line) {
        Log(GLLogStream::FILTER, line);
    }, [this](const std::string& line) { Log(GLLogStream::WARNING, line); });
    if (failure.empty()) return true;
    errorMessage = QString::fromStdString(failure);
    // The GUI shows errorMessage in a dialog; meshlabserver only prints the log, so log it too.
    Log(GLLogStream::WARNING, qUtf8Printable(name + ": " + errorMessage));
    return false;
}

}  // namespace radml
