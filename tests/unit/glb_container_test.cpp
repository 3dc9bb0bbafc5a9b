// io/glb_container.h: the binary glTF container byte by byte (glTF 2.0 sec. 4.4): header, chunk
// lengths and types, padding (JSON with spaces, binary with zeros), buffer views at 4-byte
// boundaries and their JSON, JSON string escaping and numbers that read back as the same float.
#include "io/glb_container.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

std::uint32_t u32(const std::vector<unsigned char>& b, std::size_t at) {
    return std::uint32_t(b[at]) | std::uint32_t(b[at + 1]) << 8 | std::uint32_t(b[at + 2]) << 16 |
           std::uint32_t(b[at + 3]) << 24;
}

TEST(GlbContainer, HeaderChunksAndPadding) {
    const std::vector<unsigned char> binary = {1, 2, 3, 4, 5};  // padded to 8 with zeros
    const std::vector<unsigned char> glb = rad::assembleGlb("{\"a\":1}", binary, "remedy");  // 7 -> 8 with a space
    ASSERT_EQ(glb.size(), 12u + 8 + 8 + 8 + 8);
    EXPECT_EQ(u32(glb, 0), 0x46546C67u);
    EXPECT_EQ(u32(glb, 4), 2u);
    EXPECT_EQ(u32(glb, 8), glb.size());
    EXPECT_EQ(u32(glb, 12), 8u);
    EXPECT_EQ(u32(glb, 16), 0x4E4F534Au);
    EXPECT_EQ(std::string(glb.begin() + 20, glb.begin() + 28), "{\"a\":1} ");
    EXPECT_EQ(u32(glb, 28), 8u);
    EXPECT_EQ(u32(glb, 32), 0x004E4942u);
    const std::vector<unsigned char> tail(glb.begin() + 36, glb.end());
    EXPECT_EQ(tail, (std::vector<unsigned char>{1, 2, 3, 4, 5, 0, 0, 0}));
}

TEST(GlbContainer, ViewsAreAlignedAndDescribed) {
    rad::GlbBinary bin;
    const unsigned char three[3] = {9, 9, 9};
    const float two[2] = {1.0f, 2.0f};
    EXPECT_EQ(bin.addView(three, 3, 0), 0u);
    EXPECT_EQ(bin.addView(two, 8, 34962), 1u);
    ASSERT_EQ(bin.views().size(), 2u);
    EXPECT_EQ(bin.views()[1].offset, 4u) << "4-byte boundary after 3 bytes";
    EXPECT_EQ(bin.viewsJson(),
              "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":3},"
              "{\"buffer\":0,\"byteOffset\":4,\"byteLength\":8,\"target\":34962}],"
              "\"buffers\":[{\"byteLength\":12}]");
    EXPECT_EQ(bin.bytes().size(), 12u);
    EXPECT_EQ(bin.bytes()[3], 0) << "padding is zero";
}

TEST(GlbContainer, JsonStringsAndNumbers) {
    EXPECT_EQ(rad::jsonString("a\"b\\c\n"), "\"a\\\"b\\\\c\\u000a\"");
    for (float v : {0.1f, -1.0f / 3.0f, 3.4028235e38f, 1e-30f}) {
        const std::string text = rad::jsonNumber(v);
        EXPECT_EQ(std::strtof(text.c_str(), nullptr), v) << text;
    }
}

}  // namespace
