#include "progress/progress_callback.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace rad {

void reportProgress(const ProgressCallback& progress, double fraction, const char* stage) {
    if (progress && !progress(fraction, stage != nullptr ? stage : "")) throw OperationCancelled();
}

ProgressCallback progressRange(const ProgressCallback& outer, double from, double to) {
    if (!outer) return {};
    return [outer, from, to](double fraction, const char* stage) {
        const double f = std::isfinite(fraction) ? std::clamp(fraction, 0.0, 1.0) : 0.0;
        // Rounding could take from + (to - from) * 1 a bit past `to`, the start of the next step:
        // clamped, consecutive steps stay non-decreasing.
        const double mapped = from + (to - from) * f;
        return outer(from <= to ? std::clamp(mapped, from, to) : mapped, stage != nullptr ? stage : "");
    };
}

LoopProgress::LoopProgress(const ProgressCallback& progress, const char* stage, std::size_t total, int reports)
    : progress_(progress), stage_(stage != nullptr ? stage : ""), total_(total), reports_(std::max(1, reports)) {}

void LoopProgress::itemDone(bool callingThread, std::size_t items) {
    const std::size_t done = done_.fetch_add(items, std::memory_order_relaxed) + items;
    if (!callingThread || !progress_ || stopRequested() || total_ == 0) return;
    const long step = static_cast<long>(static_cast<double>(reports_) * static_cast<double>(done) /
                                        static_cast<double>(total_));
    if (step == reportedStep_) return;
    reportedStep_ = step;
    // Called inside the caller's parallel region: what the callback throws is captured like an item's.
    bool keepGoing = true;
    try {
        keepGoing = progress_(std::min(1.0, static_cast<double>(done) / static_cast<double>(total_)), stage_);
    } catch (...) {
        captureException(std::current_exception());
        return;
    }
    if (!keepGoing) stopped_.store(true, std::memory_order_relaxed);
}

void LoopProgress::captureException(std::exception_ptr error) {
    {
        const std::lock_guard<std::mutex> lock(failureMutex_);
        if (!failure_) failure_ = std::move(error);
    }
    stopped_.store(true, std::memory_order_relaxed);
}

void LoopProgress::finish() {
    std::exception_ptr failure;
    {
        const std::lock_guard<std::mutex> lock(failureMutex_);
        failure = failure_;
    }
    if (failure) std::rethrow_exception(failure);
    if (stopRequested()) throw OperationCancelled();
    if (reportedStep_ < reports_) {
        reportedStep_ = reports_;
        reportProgress(progress_, 1.0, stage_);
    }
}

}  // namespace rad
