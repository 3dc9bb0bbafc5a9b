// The one progress and cancellation contract of every core (fit, material projection, simplification,
// PRT transfer and subdivision, normal-map bake, acquisition):
//
//   - a long call takes a `const ProgressCallback&` (may be empty);
//   - it calls it with the fraction done in [0, 1], non-decreasing, and a short English phrase naming
//     the stage (never null), from one thread at a time (the calling thread unless stated);
//   - the callback returns false to ask the core to stop; the core then throws OperationCancelled,
//     after releasing what it holds and before writing any output (no partial file, the caller's data
//     untouched).
//
// The MeshLab adapters map that exception once, in plugins_shared/filter_errors, to the same message
// for every filter; tools and benchmarks pass an empty callback or print the fraction.
#pragma once

#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <stdexcept>

namespace rad {

using ProgressCallback = std::function<bool(double fraction, const char* stage)>;

struct OperationCancelled : std::runtime_error {
    OperationCancelled() : std::runtime_error("cancelled") {}
};

// Calls `progress` (if any) and throws OperationCancelled when it asks to stop.
void reportProgress(const ProgressCallback& progress, double fraction, const char* stage);

// A callback for a step of a longer call: the step's fraction in [0, 1] is mapped onto [from, to] of
// `outer` (clamped). Empty when `outer` is empty, so a step can test `if (progress)` cheaply.
ProgressCallback progressRange(const ProgressCallback& outer, double from, double to);

// The contract for a parallel loop of `total` items (an exception cannot leave an OpenMP region):
// every thread calls itemDone() after an item, passing whether it is the calling thread (e.g.
// omp_get_thread_num() == 0); only that thread calls the callback, at most `reports` times (once per
// percent by default; a long loop may ask for finer steps, so that a stop request is seen sooner). A
// loop over chunks of items passes each chunk's item count to itemDone(), so that the fraction counts
// items. A stop request is final: the loop skips its remaining items when stopRequested(), and the
// calling thread calls finish() after the loop (throws OperationCancelled after a stop, else reports 1).
//
// An exception thrown by an item is handed to captureException() (or the item is run through
// runItem(), which does it): the first one is kept, later ones are dropped, the loop skips its
// remaining items as for a stop request, and finish() rethrows it on the calling thread. An exception
// the callback itself throws is captured the same way.
class LoopProgress {
public:
    LoopProgress(const ProgressCallback& progress, const char* stage, std::size_t total, int reports = 100);
    // `items` of the total are done (1, or a chunk's item count).
    void itemDone(bool callingThread, std::size_t items = 1);
    bool stopRequested() const { return stopped_.load(std::memory_order_relaxed); }
    // Thread-safe; call it from a catch block with std::current_exception().
    void captureException(std::exception_ptr error);
    // Skips the item after a stop or a captured exception; otherwise runs item(), captures what it
    // throws and counts it done (as `items` of the total: a chunk's item count). A template, so the
    // per-item call costs no std::function.
    template <class Item>
    void runItem(bool callingThread, Item&& item, std::size_t items = 1) {
        if (stopRequested()) return;
        try {
            item();
        } catch (...) {
            captureException(std::current_exception());
            return;
        }
        itemDone(callingThread, items);
    }
    void finish();

private:
    const ProgressCallback progress_;  // a copy: a caller may pass a temporary (an empty {})
    const char* stage_;
    std::size_t total_;
    long reports_;  // steps of the fraction reported, at least 1
    std::atomic<std::size_t> done_{0};
    std::atomic<bool> stopped_{false};
    long reportedStep_ = -1;   // touched by the calling thread only
    std::mutex failureMutex_;  // taken only when an item throws
    std::exception_ptr failure_;
};

}  // namespace rad
