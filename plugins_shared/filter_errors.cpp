#include "filter_errors.h"

#include "progress/progress_callback.h"

#include <new>

namespace radml {

std::string runFilter(const Filter* filter, MeshDocument& md, const RichParameterList& par, vcg::CallBackPos* cb,
                      const std::function<void(const std::string&)>& log,
                      const std::function<void(const std::string&)>& warning) {
    if (filter == nullptr) return "Unknown filter.";
    MeshModel* current = md.mm();
    if (current == nullptr) return "There is no current mesh: open or select a layer first.";
    FilterProgress progress(cb);
    FilterContext context{md, *current, par, progress, log, warning};
    try {
        filter->apply(context);
        return {};
    } catch (const Refusal& e) {
        return e.what();
    } catch (const rad::OperationCancelled&) {
        return "Cancelled on request: the layers are unchanged and no file was written.";
    } catch (const std::invalid_argument& e) {
        return e.what();
    } catch (const std::bad_alloc&) {
        return "Out of memory: the data of this filter does not fit in memory; lower the degree, the "
               "resolution or the mesh size.";
    } catch (const std::exception& e) {
        return std::string("Internal error (please report it): ") + e.what();
    }
}

}  // namespace radml
