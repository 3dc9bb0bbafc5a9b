// The binary glTF container (.glb, Khronos glTF 2.0 specification sec. 4.4 "GLB File Format
// Specification"): a 12-byte header, a JSON chunk padded with spaces and a binary chunk padded with
// zeros, each 4-byte aligned. Shared by the writers of glTF files (gltf_writer.h for baked maps,
// radiance_gltf.h for radiance functions), which build their JSON as text: a fixed structure of
// numbers and our own names, for which no JSON library is needed.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace rad {

// The binary chunk being assembled: byte ranges appended at 4-byte boundaries (accessors of 4-byte
// components need them), each becoming a bufferView.
class GlbBinary {
public:
    struct View {
        std::size_t offset, length;
        int target;  // 34962 ARRAY_BUFFER, 34963 ELEMENT_ARRAY_BUFFER, 0 none (images)
    };
    // Appends `bytes` as a new bufferView; returns its index.
    std::size_t addView(const void* bytes, std::size_t size, int target);
    const std::vector<View>& views() const { return views_; }
    // The "bufferViews" and "buffers" members (without the surrounding braces), for the JSON.
    std::string viewsJson() const;
    // The chunk, padded to 4 bytes.
    const std::vector<unsigned char>& bytes();

private:
    std::vector<unsigned char> data_;
    std::vector<View> views_;
};

// A JSON number: finite, shortest text that reads back as the same float (9 significant digits).
std::string jsonNumber(double v);
// A JSON string literal with quotes, escaping quotes, backslashes and control characters.
std::string jsonString(const std::string& s);

// The whole .glb file. Throws std::length_error naming the size and `remedy` beyond the format's
// 4 GiB limit.
std::vector<unsigned char> assembleGlb(std::string json, const std::vector<unsigned char>& binary,
                                       const std::string& remedy);

}  // namespace rad
