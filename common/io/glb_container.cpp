// Binary glTF container (glb_container.h).
#include "io/glb_container.h"

#include <cstdint>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace rad {

namespace {

void appendLittleEndian32(std::vector<unsigned char>& out, std::uint32_t v) {
    for (int k = 0; k < 4; ++k) out.push_back(static_cast<unsigned char>((v >> (8 * k)) & 0xffu));
}

void padTo4(std::vector<unsigned char>& data) {
    while (data.size() % 4) data.push_back(0);
}

}  // namespace

std::size_t GlbBinary::addView(const void* bytes, std::size_t size, int target) {
    padTo4(data_);
    views_.push_back({data_.size(), size, target});
    data_.insert(data_.end(), static_cast<const unsigned char*>(bytes), static_cast<const unsigned char*>(bytes) + size);
    return views_.size() - 1;
}

std::string GlbBinary::viewsJson() const {
    std::ostringstream j;
    j << "\"bufferViews\":[";
    for (std::size_t i = 0; i < views_.size(); ++i) {
        j << (i ? "," : "") << "{\"buffer\":0,\"byteOffset\":" << views_[i].offset << ",\"byteLength\":" << views_[i].length;
        if (views_[i].target) j << ",\"target\":" << views_[i].target;
        j << "}";
    }
    std::size_t padded = data_.size();
    while (padded % 4) ++padded;
    j << "],\"buffers\":[{\"byteLength\":" << padded << "}]";
    return j.str();
}

const std::vector<unsigned char>& GlbBinary::bytes() {
    padTo4(data_);
    return data_;
}

std::string jsonNumber(double v) {
    char text[40];
    std::snprintf(text, sizeof text, "%.9g", v);
    return text;
}

std::string jsonString(const std::string& s) {
    std::string out = "\"";
    for (unsigned char ch : s) {
        if (ch == '"' || ch == '\\') {
            out += '\\';
            out += char(ch);
        } else if (ch < 0x20) {
            char escaped[8];
            std::snprintf(escaped, sizeof escaped, "\\u%04x", ch);
            out += escaped;
        } else {
            out += char(ch);
        }
    }
    return out + "\"";
}

std::vector<unsigned char> assembleGlb(std::string json, const std::vector<unsigned char>& binary,
                                       const std::string& remedy) {
    while (json.size() % 4) json += ' ';  // JSON chunk padding: spaces (sec. 4.4.3.2)
    std::size_t binaryLength = binary.size();
    while (binaryLength % 4) ++binaryLength;
    const std::uint64_t total = 12 + 8 + json.size() + 8 + binaryLength;
    if (total > 0xffffffffull)
        throw std::length_error("The glTF file would be " + std::to_string(total >> 20) +
                                " MiB, beyond the format's 4 GiB: " + remedy);
    std::vector<unsigned char> out;
    out.reserve(std::size_t(total));
    appendLittleEndian32(out, 0x46546C67u);  // "glTF"
    appendLittleEndian32(out, 2);
    appendLittleEndian32(out, std::uint32_t(total));
    appendLittleEndian32(out, std::uint32_t(json.size()));
    appendLittleEndian32(out, 0x4E4F534Au);  // "JSON"
    out.insert(out.end(), json.begin(), json.end());
    appendLittleEndian32(out, std::uint32_t(binaryLength));
    appendLittleEndian32(out, 0x004E4942u);  // "BIN\0"
    out.insert(out.end(), binary.begin(), binary.end());
    padTo4(out);
    return out;
}

}  // namespace rad
