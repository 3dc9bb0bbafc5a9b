#include "filter.h"

#include <algorithm>
#include <cstdarg>
#include <cstdio>

namespace radml {

std::string asSentence(const std::string& message) {
    QString s = QString::fromStdString(message).trimmed();
    if (!s.isEmpty()) s[0] = s[0].toUpper();
    if (!s.endsWith('.')) s += '.';
    return s.toStdString();
}

std::string formatLine(const char* format, ...) {
    char buffer[1024];
    va_list args;
    va_start(args, format);
    std::vsnprintf(buffer, sizeof buffer, format, args);
    va_end(args);
    return buffer;
}

bool FilterProgress::operator()(int percent, const char* what) {
    if (callback_ == nullptr) return true;
    percent = std::clamp(percent, 0, 100);
    const int overall = begin_ + (end_ - begin_) * percent / 100;
    const auto now = std::chrono::steady_clock::now();
    if (overall == last_ || (overall < 100 && now - lastTime_ < std::chrono::milliseconds(50))) return true;
    last_ = overall;
    lastTime_ = now;
    return callback_(overall, what != nullptr ? what : phase_.c_str());
}

rad::ProgressCallback FilterProgress::forCore() {
    return [this](double fraction, const char* stage) {
        return (*this)(static_cast<int>(100.0 * std::clamp(fraction, 0.0, 1.0)), stage);
    };
}

void FilterProgress::setPhase(int begin, int end, const char* what) {
    begin_ = std::clamp(begin, 0, 100);
    end_ = std::clamp(end, begin_, 100);
    if (what != nullptr) phase_ = what;
    last_ = -1;
    lastTime_ = {};
    (*this)(0);
}

}  // namespace radml
