// Argument parsing shared by the command-line tools: strict numbers with messages naming the option.
#pragma once
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace radtools {

// A bad command line; main() prints what() and the usage.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The whole of `text` as a finite number, or UsageError naming `key`.
inline double toNumber(const std::string& key, const std::string& text) {
    std::size_t used = 0;
    double v = 0.0;
    try {
        v = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != text.size() || !std::isfinite(v)) throw UsageError(key + " needs a number, got '" + text + "'");
    return v;
}

inline int toInt(const std::string& key, const std::string& text) {
    const double v = toNumber(key, text);
    if (v != std::floor(v) || std::fabs(v) > 1e9) throw UsageError(key + " needs an integer, got '" + text + "'");
    return static_cast<int>(v);
}

// "a<sep>b<sep>c" -> numbers.
inline std::vector<double> numberList(const std::string& key, const std::string& text, char sep) {
    std::vector<double> out;
    std::istringstream in(text);
    std::string item;
    while (std::getline(in, item, sep)) out.push_back(toNumber(key, item));
    return out;
}

}  // namespace radtools
