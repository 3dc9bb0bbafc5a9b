#include "errors/host_operations.h"

namespace rad {

std::string expandHostOperations(const std::string& message, const std::function<std::string(const std::string&)>& name) {
    std::string out;
    out.reserve(message.size());
    std::size_t at = 0;
    while (at < message.size()) {
        const std::size_t open = message.find("{{", at);
        const std::size_t close = open == std::string::npos ? std::string::npos : message.find("}}", open + 2);
        if (close == std::string::npos) {
            out.append(message, at, std::string::npos);
            break;
        }
        out.append(message, at, open - at);
        out += name(message.substr(open + 2, close - open - 2));
        at = close + 2;
    }
    return out;
}

std::string plainHostOperations(const std::string& message) {
    return expandHostOperations(message, [](const std::string& operation) { return "MeshLab's " + operation; });
}

}  // namespace rad
