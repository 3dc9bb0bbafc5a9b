// One MeshLab filter, described once for both hosts (MeshLab 2020.09 and 2025.07): its name, help,
// class, conditions, parameters and body. The host plugin classes (host_20xx/filter_plugin_base.h)
// turn a list of these into MeshLab's interface; a filter body never sees which host runs it.
//
// The contract of a body (`apply`): read the parameters, call a core, change the layers only once
// the core succeeded. To refuse, throw radml::Refusal with what is wrong and how to fix it; the host
// shows it in MeshLab's log and dialog (2020.09) or raises it as pymeshlab's exception (2025.07),
// and the layers are left as they were. std::invalid_argument from a core's validation is shown the
// same way; std::bad_alloc becomes an out-of-memory refusal.
#pragma once

#include "meshlab_host.h"

#include <QString>

#include "progress/progress_callback.h"

#include <chrono>
#include <functional>
#include <stdexcept>
#include <string>

namespace radml {

// A refusal the user can act on: "what is wrong; how to fix it".
class Refusal : public std::runtime_error {
public:
    explicit Refusal(const std::string& message) : std::runtime_error(message) {}
    explicit Refusal(const char* message) : std::runtime_error(message) {}
    explicit Refusal(const QString& message) : std::runtime_error(message.toStdString()) {}
};

// A core's message as a sentence of the log or of a refusal: capital first letter, full stop at the end.
std::string asSentence(const std::string& message);

// printf-style formatting of a log line.
std::string formatLine(const char* format, ...) __attribute__((format(printf, 1, 2)));

// Progress toward MeshLab's callback, throttled to whole percents and at most ~20 updates a second
// (the GUI repaints on each), mapped into [begin, end] of the whole filter.
class FilterProgress {
public:
    explicit FilterProgress(vcg::CallBackPos* callback) : callback_(callback) {}
    // Reports `percent` (0..100) of the current phase; returns false when the host asked to stop.
    bool operator()(int percent, const char* what = nullptr);
    // Subsequent reports are mapped into [begin, end] percent of the whole filter.
    void setPhase(int begin, int end, const char* what);
    // The cores' progress contract (progress/progress_callback.h) over the current phase: the core's
    // fraction maps onto the phase, its stage name is shown, and a stop request of the host becomes
    // the core's OperationCancelled (mapped to one message by runFilter). Valid while *this lives.
    rad::ProgressCallback forCore();
    vcg::CallBackPos* callback() const { return callback_; }

private:
    vcg::CallBackPos* callback_;
    int begin_ = 0, end_ = 100;
    int last_ = -1;
    std::string phase_ = "Working";
    std::chrono::steady_clock::time_point lastTime_{};
};

// Everything a filter body may use.
struct FilterContext {
    MeshDocument& document;
    MeshModel* current;  // the current layer; null only for filters that need none (Filter::needsCurrentLayer)
    const RichParameterList& parameters;
    FilterProgress& progress;
    std::function<void(const std::string&)> log;      // an information line in MeshLab's log
    std::function<void(const std::string&)> warning;  // a warning line
    // The current layer (runFilter has checked that there is one for the filters that need it).
    MeshModel& mesh() const { return *current; }
};

class Filter {
public:
    virtual ~Filter() = default;
    // The name shown in the menus and used by scripts (pymeshlab derives its Python name from it).
    virtual QString name() const = 0;
    // The Python name pymeshlab calls it by: an interface scripts depend on, so every filter declares
    // it rather than letting MeshLab derive it from the menu label (tests/python pins each one).
    virtual QString pythonName() const = 0;
    // Help text (HTML), citing the paper the filter implements by authors and year.
    virtual QString description() const = 0;
    // MeshLab's FilterClass bits (same values in both hosts).
    virtual int filterClass() const = 0;
    virtual int preconditions() const { return 0; }
    // True when the filter reads layers besides the current one (MeshLab's FIXED arity).
    virtual bool readsOtherLayers() const { return false; }
    virtual int postconditions() const = 0;
    virtual RichParameterList parameters(const MeshDocument& document, const MeshModel& current) const = 0;
    // False for a filter that reads its input from a file and adds a layer (MeshLab's "Create New
    // Mesh Layer" class): it runs in an empty document too (the GUI offers it there, pymeshlab on an
    // empty MeshSet), where its parameters come from parametersWithoutLayer and context.current is
    // null.
    virtual bool needsCurrentLayer() const { return true; }
    virtual RichParameterList parametersWithoutLayer(const MeshDocument&) const { return {}; }
    // What to change when the filter runs out of memory (the parameter that drives its memory), as a
    // clause: "choose a smaller texture size". Empty: runFilter's generic advice.
    virtual std::string outOfMemoryAdvice() const { return {}; }
    // Runs the filter. Throw Refusal for what the filter itself checks; anything a core throws is
    // mapped to the user's message once, by its category (runFilter, plugins_shared/filter_errors.cpp).
    virtual void apply(FilterContext& context) const = 0;
};

}  // namespace radml
