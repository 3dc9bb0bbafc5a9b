#include "progress/progress_callback.h"

#include <algorithm>
#include <cmath>

namespace rad {

void reportProgress(const ProgressCallback& progress, double fraction, const char* stage) {
    if (progress && !progress(fraction, stage != nullptr ? stage : "")) throw OperationCancelled();
}

ProgressCallback progressRange(const ProgressCallback& outer, double from, double to) {
    if (!outer) return {};
    return [outer, from, to](double fraction, const char* stage) {
        const double f = std::isfinite(fraction) ? std::clamp(fraction, 0.0, 1.0) : 0.0;
        return outer(from + (to - from) * f, stage != nullptr ? stage : "");
    };
}

LoopProgress::LoopProgress(const ProgressCallback& progress, const char* stage, std::size_t total)
    : progress_(progress), stage_(stage != nullptr ? stage : ""), total_(total) {}

void LoopProgress::itemDone(bool callingThread) {
    const std::size_t done = done_.fetch_add(1, std::memory_order_relaxed) + 1;
    if (!callingThread || !progress_ || stopRequested() || total_ == 0) return;
    const long percent = static_cast<long>(100.0 * static_cast<double>(done) / static_cast<double>(total_));
    if (percent == reportedPercent_) return;
    reportedPercent_ = percent;
    if (!progress_(std::min(1.0, static_cast<double>(done) / static_cast<double>(total_)), stage_))
        stopped_.store(true, std::memory_order_relaxed);
}

void LoopProgress::finish() {
    if (stopRequested()) throw OperationCancelled();
    if (reportedPercent_ < 100) {
        reportedPercent_ = 100;
        reportProgress(progress_, 1.0, stage_);
    }
}

}  // namespace rad
