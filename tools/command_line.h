// Argument parsing shared by the command-line tools: strict numbers with messages naming the option.
#pragma once

#include "errors/error_categories.h"
#include "errors/host_operations.h"

#include <cmath>
#include <exception>
#include <iostream>
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

// A tool's main(): run(argc, argv); a UsageError prints the message and the usage (exit 2), any
// other exception its message (exit 1), each prefixed with the tool's name. Tools whose generators
// refuse parameters with std::invalid_argument pass invalidArgumentIsUsage: exit 2, no usage (a
// rad::InputError, a core refusing the mesh or scene, stays exit 1).
template <typename Run, typename Usage>
int runTool(const char* name, int argc, char** argv, Run run, Usage usage, bool invalidArgumentIsUsage = false) {
    try {
        return run(argc, argv);
    } catch (const UsageError& e) {
        std::cerr << name << ": " << rad::plainHostOperations(e.what()) << "\n";
        usage(std::cerr);
        return 2;
    } catch (const rad::InputError& e) {  // a core's refusal of the mesh or scene, never a usage error
        std::cerr << name << ": " << rad::plainHostOperations(e.what()) << "\n";
        return 1;
    } catch (const std::invalid_argument& e) {
        std::cerr << name << ": " << rad::plainHostOperations(e.what()) << "\n";
        return invalidArgumentIsUsage ? 2 : 1;
    } catch (const std::exception& e) {
        std::cerr << name << ": " << rad::plainHostOperations(e.what()) << "\n";
        return 1;
    }
}

}  // namespace radtools
