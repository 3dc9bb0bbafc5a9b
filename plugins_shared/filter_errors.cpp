#include "filter_errors.h"

#include "host_operations.h"

#include "errors/error_categories.h"
#include "progress/progress_callback.h"

#include <algorithm>
#include <cctype>
#include <new>
#include <vector>

namespace radml {

namespace {

// The checks every filter shares, so that the same mistake in a script gets the same answer from
// every filter: an enum index outside its choices (it used to be read as another choice), and a
// number that is not finite (NaN, infinity).
std::string parameterProblem(const RichParameterList& par) {
    for (const RichParameter& p : par) {
        int index = 0;
        QStringList choices;
        if (enumChoice(p, index, choices) && (index < 0 || index >= choices.size())) {
            QString list;
            for (int i = 0; i < choices.size(); ++i) list += QString("%1%2 = %3").arg(i > 0 ? ", " : "").arg(i).arg(choices[i]);
            return QString("The parameter '%1' is %2, which is none of its choices: %3.")
                .arg(p.name()).arg(index).arg(list).toStdString();
        }
        if (!parameterValueIsFinite(p))
            return QString("The parameter '%1' is not a finite number (NaN or infinity): give a finite value.")
                .arg(p.name()).toStdString();
    }
    return {};
}

// A core's refusal as the user reads it: the core's own words (what is wrong, how to fix it; the
// cores write them as sentences), then what the wrapper guarantees.
std::string withLayersUnchanged(std::string message) {
    while (!message.empty() && std::isspace(static_cast<unsigned char>(message.back()))) message.pop_back();
    static const std::string guarantee = "The layers are unchanged.";
    // A message that already ends with the guarantee (one passed through twice) does not repeat it;
    // any other mention of "unchanged" is the core's own sentence, followed by the guarantee.
    if (message.size() >= guarantee.size() &&
        message.compare(message.size() - guarantee.size(), guarantee.size(), guarantee) == 0)
        return message;
    if (!message.empty() && std::string(".!?").find(message.back()) == std::string::npos) message += '.';
    return message + " " + guarantee;
}

std::string outOfMemoryMessage(const Filter& filter) {
    const std::string advice = filter.outOfMemoryAdvice();
    return "Out of memory: '" + filter.name().toStdString() + "' needs more memory than is available here; " +
           (advice.empty() ? std::string("close other programs or layers, or run it on a smaller input (fewer faces, "
                                         "or fewer outputs such as levels or layers)")
                           : advice + ", or close other programs or layers") +
           ". The layers are unchanged.";
}

}  // namespace

std::string runFilter(const Filter* filter, MeshDocument& md, const RichParameterList& par, vcg::CallBackPos* cb,
                      const std::function<void(const std::string&)>& log,
                      const std::function<void(const std::string&)>& warning) {
    if (filter == nullptr) return "Unknown filter.";
    MeshModel* current = md.mm();
    if (current == nullptr && filter->needsCurrentLayer()) return "There is no current mesh: open or select a layer first.";
    if (const std::string problem = parameterProblem(par); !problem.empty()) return problem;
    FilterProgress progress(cb);
    // Every line the user reads names the host's operations its own way (host_operations.h).
    const auto hostLog = [&log](const std::string& line) { log(forThisHost(line)); };
    const auto hostWarning = [&warning](const std::string& line) { warning(forThisHost(line)); };
    FilterContext context{md, current, par, progress, hostLog, hostWarning};
    // Layers a filter added before it failed (a POP buffer's levels, LOD layers, when memory ran out
    // on the last one) are removed: a refusal leaves the document's layers as they were.
    const std::vector<MeshModel*> before = documentMeshes(md);
    const auto removeAddedLayers = [&] {
        for (MeshModel* m : documentMeshes(md))
            if (std::find(before.begin(), before.end(), m) == before.end()) removeLayer(md, m);
        if (current != nullptr && md.mm() != current) makeCurrentLayer(md, current);
    };
    std::string refusal;
    try {
        filter->apply(context);
        return {};
    } catch (const Refusal& e) {
        refusal = e.what();
    } catch (const rad::OperationCancelled&) {
        refusal = "Cancelled on request: the layers are unchanged and no file was written.";
    } catch (const std::invalid_argument& e) {  // rad::InputError and the cores' plain argument checks
        refusal = withLayersUnchanged(e.what());
    } catch (const rad::FileError& e) {
        refusal = withLayersUnchanged(e.what());
    } catch (const rad::ResourceError& e) {
        refusal = withLayersUnchanged(std::string(e.what()) + "; retry with a smaller input or on another machine");
    } catch (const std::bad_alloc&) {
        refusal = outOfMemoryMessage(*filter);
    } catch (const std::exception& e) {  // rad::InternalError and anything unforeseen
        refusal = std::string("Internal error (please report it): ") + e.what();
    }
    removeAddedLayers();
    return forThisHost(refusal);
}

}  // namespace radml
