#include "io/ply_header.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>

namespace {

using rad::PlyHeaderFaultKind;
using rad::PlyHeaderParse;
using rad::PlyHeaderRules;
using rad::PlyType;

PlyHeaderRules strictRules() { return PlyHeaderRules{}; }
PlyHeaderRules lenientRules() {
    PlyHeaderRules rules;
    rules.strict = false;
    return rules;
}

PlyHeaderParse parse(const std::string& text, const PlyHeaderRules& rules = strictRules()) {
    return rad::parsePlyHeader(text.data(), text.size(), rules);
}

// The fault kind of a refused header (fails the test when the header is accepted).
PlyHeaderFaultKind faultOf(const std::string& text, const PlyHeaderRules& rules = strictRules()) {
    const PlyHeaderParse p = parse(text, rules);
    EXPECT_TRUE(p.fault.has_value()) << "accepted: " << text;
    return p.fault ? p.fault->kind : PlyHeaderFaultKind::EmptyFile;
}

const std::string kStart = "ply\nformat binary_little_endian 1.0\n";

// ---------------------------------------------------------------------------------------------------
// Scalar types

TEST(PlyHeader, TypeNamesInBothSpellingsWithTheirSizes) {
    const struct {
        const char* classic;
        const char* sized;
        PlyType type;
        std::size_t bytes;
        bool integer;
    } cases[] = {{"char", "int8", PlyType::Int8, 1, true},        {"uchar", "uint8", PlyType::UInt8, 1, true},
                 {"short", "int16", PlyType::Int16, 2, true},     {"ushort", "uint16", PlyType::UInt16, 2, true},
                 {"int", "int32", PlyType::Int32, 4, true},       {"uint", "uint32", PlyType::UInt32, 4, true},
                 {"float", "float32", PlyType::Float32, 4, false}, {"double", "float64", PlyType::Float64, 8, false}};
    for (const auto& c : cases) {
        ASSERT_EQ(rad::parsePlyType(c.classic), c.type) << c.classic;
        ASSERT_EQ(rad::parsePlyType(c.sized), c.type) << c.sized;
        EXPECT_EQ(rad::plyTypeSize(c.type), c.bytes) << c.classic;
        EXPECT_STREQ(rad::plyTypeName(c.type), c.classic);
        EXPECT_EQ(rad::isPlyIntegerType(c.type), c.integer) << c.classic;
    }
    EXPECT_FALSE(rad::parsePlyType("list"));
    EXPECT_FALSE(rad::parsePlyType("int64"));
    EXPECT_FALSE(rad::parsePlyType("Float"));
    EXPECT_FALSE(rad::parsePlyType(""));
}

TEST(PlyHeader, BinaryValuesInBothByteOrders) {
    // 1.5f is 0x3FC00000; -2 as int16 is 0xFFFE; 0x01020304 as uint32; 0.25 as double is 0x3FD0000000000000.
    const unsigned char floatLittle[] = {0x00, 0x00, 0xC0, 0x3F}, floatBig[] = {0x3F, 0xC0, 0x00, 0x00};
    EXPECT_EQ(rad::readPlyNumber(floatLittle, PlyType::Float32, false), 1.5);
    EXPECT_EQ(rad::readPlyNumber(floatBig, PlyType::Float32, true), 1.5);
    const unsigned char shortLittle[] = {0xFE, 0xFF}, shortBig[] = {0xFF, 0xFE};
    EXPECT_EQ(rad::readPlyInteger(shortLittle, PlyType::Int16, false), -2);
    EXPECT_EQ(rad::readPlyInteger(shortBig, PlyType::Int16, true), -2);
    EXPECT_EQ(rad::readPlyInteger(shortLittle, PlyType::UInt16, false), 65534);
    const unsigned char wordLittle[] = {0x04, 0x03, 0x02, 0x01}, wordBig[] = {0x01, 0x02, 0x03, 0x04};
    EXPECT_EQ(rad::readPlyInteger(wordLittle, PlyType::UInt32, false), 0x01020304);
    EXPECT_EQ(rad::readPlyInteger(wordBig, PlyType::UInt32, true), 0x01020304);
    EXPECT_EQ(rad::readPlyNumber(wordBig, PlyType::Int32, true), double(0x01020304));
    const unsigned char doubleBig[] = {0x3F, 0xD0, 0, 0, 0, 0, 0, 0}, doubleLittle[] = {0, 0, 0, 0, 0, 0, 0xD0, 0x3F};
    EXPECT_EQ(rad::readPlyNumber(doubleBig, PlyType::Float64, true), 0.25);
    EXPECT_EQ(rad::readPlyNumber(doubleLittle, PlyType::Float64, false), 0.25);
    const unsigned char byte[] = {0xFF};
    EXPECT_EQ(rad::readPlyInteger(byte, PlyType::Int8, true), -1);
    EXPECT_EQ(rad::readPlyInteger(byte, PlyType::UInt8, false), 255);
    EXPECT_EQ(rad::readPlyNumber(byte, PlyType::Int8, false), -1.0);
    // Float types are not integers: a list length or index of that type reads as 0.
    EXPECT_EQ(rad::readPlyInteger(floatLittle, PlyType::Float32, false), 0);
}

TEST(PlyHeader, AsciiValues) {
    EXPECT_EQ(rad::parsePlyAsciiNumber("42", 2, PlyType::UInt8), 42.0);
    EXPECT_EQ(rad::parsePlyAsciiNumber("-7", 2, PlyType::Int32), -7.0);
    EXPECT_EQ(rad::parsePlyAsciiNumber("1.5", 3, PlyType::Float32), 1.5);
    EXPECT_EQ(rad::parsePlyAsciiNumber("-2.5e2", 6, PlyType::Float64), -250.0);
    // Only the given length is read: "12" of "123".
    EXPECT_EQ(rad::parsePlyAsciiNumber("123", 2, PlyType::Int32), 12.0);
    for (const char* nan : {"nan", "-nan", "NaN"}) {
        const auto v = rad::parsePlyAsciiNumber(nan, std::strlen(nan), PlyType::Float32);
        ASSERT_TRUE(v) << nan;
        EXPECT_TRUE(std::isnan(*v)) << nan;
    }
    EXPECT_EQ(rad::parsePlyAsciiNumber("inf", 3, PlyType::Float32), std::numeric_limits<double>::infinity());
    EXPECT_EQ(rad::parsePlyAsciiNumber("Inf", 3, PlyType::Float64), std::numeric_limits<double>::infinity());
    EXPECT_EQ(rad::parsePlyAsciiNumber("-inf", 4, PlyType::Float32), -std::numeric_limits<double>::infinity());
    EXPECT_EQ(rad::parsePlyAsciiNumber("-Inf", 4, PlyType::Float32), -std::numeric_limits<double>::infinity());
    EXPECT_FALSE(rad::parsePlyAsciiNumber("1.5", 3, PlyType::Int32));  // not an integer
    EXPECT_FALSE(rad::parsePlyAsciiNumber("nan", 3, PlyType::Int32));
    EXPECT_FALSE(rad::parsePlyAsciiNumber("abc", 3, PlyType::Float32));
    EXPECT_FALSE(rad::parsePlyAsciiNumber("1,5", 3, PlyType::Float32));  // no locale decimal comma
    EXPECT_FALSE(rad::parsePlyAsciiNumber("", 0, PlyType::Float32));
}

TEST(PlyHeader, UnsignedDecimal) {
    EXPECT_EQ(rad::parsePlyUnsigned("0"), 0u);
    EXPECT_EQ(rad::parsePlyUnsigned("007"), 7u);
    EXPECT_EQ(rad::parsePlyUnsigned("18446744073709551615"), std::numeric_limits<std::uint64_t>::max());
    EXPECT_FALSE(rad::parsePlyUnsigned("18446744073709551616"));  // overflow
    for (const char* bad : {"", "-1", "+1", "1a", " 1", "0x10"}) EXPECT_FALSE(rad::parsePlyUnsigned(bad)) << bad;
}

TEST(PlyHeader, NextTokenSplitsOnBlanksOnly) {
    const std::string line = "comment  block_meta\tb key value with  spaces";
    std::size_t pos = 0;
    EXPECT_EQ(rad::nextPlyToken(line, pos), "comment");
    EXPECT_EQ(rad::nextPlyToken(line, pos), "block_meta");
    EXPECT_EQ(rad::nextPlyToken(line, pos), "b");
    EXPECT_EQ(rad::nextPlyToken(line, pos), "key");
    EXPECT_EQ(line.substr(pos + 1), "value with  spaces");
    std::size_t end = line.size();
    EXPECT_EQ(rad::nextPlyToken(line, end), "");
}

// ---------------------------------------------------------------------------------------------------
// Header

TEST(PlyHeader, ParsesElementsPropertiesOffsetsAndComments) {
    const std::string text = "ply\r\nformat binary_big_endian 1.0\r\ncomment made by hand\r\n"
                             "element vertex 3\nproperty float x\nproperty double y\nproperty uchar red\n"
                             "obj_info ignored\n"
                             "element face 2\nproperty uchar flags\nproperty list uchar int vertex_indices\n"
                             "property short after\n"
                             "end_header\nDATA";
    const PlyHeaderParse p = parse(text);
    ASSERT_FALSE(p.fault);
    EXPECT_EQ(p.header.encoding, rad::PlyEncoding::BinaryBigEndian);
    EXPECT_EQ(p.header.dataOffset, text.size() - 4);
    ASSERT_EQ(p.header.comments.size(), 1u);
    EXPECT_EQ(p.header.comments[0].lineNumber, 3u);
    EXPECT_EQ(p.header.comments[0].line, "comment made by hand");  // CR removed
    EXPECT_EQ(p.header.comments[0].tokens, (std::vector<std::string>{"comment", "made", "by", "hand"}));
    ASSERT_EQ(p.header.elements.size(), 2u);
    const rad::PlyElement& v = p.header.elements[0];
    EXPECT_EQ(v.name, "vertex");
    EXPECT_EQ(v.count, 3u);
    EXPECT_FALSE(v.hasList);
    EXPECT_EQ(v.scalarBytes, 4u + 8u + 1u);
    ASSERT_EQ(v.properties.size(), 3u);
    EXPECT_EQ(v.find("y")->offset, 4u);
    EXPECT_EQ(v.find("y")->type, PlyType::Float64);
    EXPECT_EQ(v.find("red")->offset, 12u);
    EXPECT_EQ(v.indexOf("red"), 2);
    EXPECT_EQ(v.indexOf("z"), -1);
    EXPECT_EQ(v.find("z"), nullptr);
    const rad::PlyElement& f = *p.header.find("face");
    EXPECT_TRUE(f.hasList);
    const rad::PlyProperty& list = f.properties[1];
    EXPECT_TRUE(list.isList);
    EXPECT_EQ(list.countType, PlyType::UInt8);
    EXPECT_EQ(list.type, PlyType::Int32);
    EXPECT_EQ(p.header.find("edge"), nullptr);
    // Smallest record: flags (1) + length (1) + short (2), plus 3 ints when the list holds a triangle.
    EXPECT_EQ(rad::minimumPlyRecordBytes(f), 4u);
    EXPECT_EQ(rad::minimumPlyRecordBytes(f, 1), 16u);
    EXPECT_EQ(rad::minimumPlyRecordBytes(v), 13u);
}

TEST(PlyHeader, FaultsNameTheLineItsOffsetAndTheToken) {
    const std::string text = kStart + "element vertex 1\nproperty float x\nproperty float x\nend_header\n";
    const PlyHeaderParse p = parse(text);
    ASSERT_TRUE(p.fault);
    EXPECT_EQ(p.fault->kind, PlyHeaderFaultKind::DuplicateProperty);
    EXPECT_EQ(p.fault->lineNumber, 5u);
    EXPECT_EQ(p.fault->lineOffset, text.find("property float x\nend"));
    EXPECT_EQ(p.fault->token, "x");
    EXPECT_EQ(p.fault->detail, "vertex");

    const PlyHeaderParse count = parse(kStart + "element vertex 12b\nend_header\n");
    ASSERT_TRUE(count.fault);
    EXPECT_EQ(count.fault->kind, PlyHeaderFaultKind::InvalidElementCount);
    EXPECT_EQ(count.fault->token, "vertex");
    EXPECT_EQ(count.fault->detail, "12b");
    EXPECT_EQ(count.fault->lineNumber, 3u);
}

TEST(PlyHeader, RefusesWhatNoRulesAccept) {
    using K = PlyHeaderFaultKind;
    const struct {
        std::string text;
        PlyHeaderFaultKind kind;
    } cases[] = {
        {"", K::EmptyFile},
        {"plx\nformat ascii 1.0\nend_header\n", K::NoPlyLine},
        {"ply", K::NoPlyLine},
        {"ply \nformat ascii 1.0\nend_header\n", K::NoPlyLine},
        {kStart + "format binary_little_endian 1.0\nend_header\n", K::RepeatedFormat},
        {"ply\nformat binary_little_endian\nend_header\n", K::MalformedFormat},
        {"ply\nformat binary_middle_endian 1.0\nend_header\n", K::UnknownFormat},
        {"ply\nformat ascii 2.0\nend_header\n", K::UnsupportedVersion},
        {kStart + "element vertex\nend_header\n", K::MalformedElement},
        {kStart + "element vertex -1\nend_header\n", K::InvalidElementCount},
        {kStart + "element vertex 18446744073709551616\nend_header\n", K::InvalidElementCount},
        {kStart + "element v 1\nelement v 2\nend_header\n", K::DuplicateElement},
        {kStart + "property float x\nend_header\n", K::PropertyBeforeElement},
        {kStart + "element f 1\nproperty list uchar integer i\nend_header\n", K::UnknownListType},
        {kStart + "element f 1\nproperty list float int i\nend_header\n", K::NonIntegerListLength},
        {kStart + "element f 1\nproperty list i\nend_header\n", K::ScalarPropertyOfTypeList},
        {kStart + "element f 1\nproperty real x\nend_header\n", K::UnknownPropertyType},
        {kStart + "element f 1\nproperty float\nend_header\n", K::MalformedProperty},
        {kStart + "element f 1\nproperty list uchar int\nend_header\n", K::MalformedProperty},
        {kStart + "elements f 1\nend_header\n", K::UnknownKeyword},
        {kStart + "element f 1\n", K::NoEndHeader},
        {kStart + "element f 1\nend_header", K::NoEndHeader},  // no line break
        {"ply\nend_header\n", K::NoFormatLine},
    };
    for (const PlyHeaderRules& rules : {strictRules(), lenientRules()})
        for (const auto& c : cases) EXPECT_EQ(faultOf(c.text, rules), c.kind) << c.text << " strict " << rules.strict;
    const PlyHeaderParse noEnd = parse(kStart + "element f 1\n");
    ASSERT_TRUE(noEnd.fault);
    EXPECT_EQ(noEnd.fault->lineOffset, (kStart + "element f 1\n").size());  // where the bytes given end
}

TEST(PlyHeader, StrictAndLenientRulesDiffer) {
    using K = PlyHeaderFaultKind;
    // The "ply" line ends with CR alone.
    const std::string crOnly = "ply\rjunk\nformat ascii 1.0\nend_header\n";
    EXPECT_EQ(faultOf(crOnly), K::NoPlyLine);
    EXPECT_FALSE(parse(crOnly, lenientRules()).fault);
    // Tokens after end_header.
    const std::string endJunk = kStart + "end_header junk\n";
    EXPECT_EQ(faultOf(endJunk), K::MalformedEndHeader);
    EXPECT_FALSE(parse(endJunk, lenientRules()).fault);
    // Format line after an element, element before the format line.
    const std::string formatLate = "ply\nelement v 0\nformat ascii 1.0\nend_header\n";
    EXPECT_EQ(faultOf(formatLate), K::ElementBeforeFormat);
    EXPECT_FALSE(parse(formatLate, lenientRules()).fault);
    EXPECT_EQ(faultOf("ply\nelement v 0\nend_header\n", lenientRules()), K::NoFormatLine);
    const std::string twoThenFormat = "ply\ncomment x\nformat ascii 1.0\nelement v 0\nend_header\n";
    EXPECT_FALSE(parse(twoThenFormat).fault);
    // A count with more than 20 digits (zeros in front).
    const std::string longCount = kStart + "element v 000000000000000000007\nend_header\n";
    EXPECT_EQ(faultOf(longCount), K::InvalidElementCount);
    const PlyHeaderParse lenientCount = parse(longCount, lenientRules());
    ASSERT_FALSE(lenientCount.fault);
    EXPECT_EQ(lenientCount.header.elements[0].count, 7u);
    // Vertical tab between tokens: white space for the lenient rules, part of a token for the strict.
    const std::string verticalTab = kStart + "element\vv 1\nproperty float x\nend_header\n";
    EXPECT_EQ(faultOf(verticalTab), K::UnknownKeyword);
    const PlyHeaderParse lenientTab = parse(verticalTab, lenientRules());
    ASSERT_FALSE(lenientTab.fault);
    EXPECT_EQ(lenientTab.header.elements[0].name, "v");
}

TEST(PlyHeader, EncodingsTheRulesRefuse) {
    PlyHeaderRules littleOnly;
    littleOnly.acceptAscii = false;
    littleOnly.acceptBigEndian = false;
    const PlyHeaderParse ascii = parse("ply\nformat ascii 1.0\nend_header\n", littleOnly);
    ASSERT_TRUE(ascii.fault);
    EXPECT_EQ(ascii.fault->kind, PlyHeaderFaultKind::EncodingNotAccepted);
    EXPECT_EQ(ascii.fault->token, "ascii");
    const PlyHeaderParse big = parse("ply\nformat binary_big_endian 1.0\nend_header\n", littleOnly);
    ASSERT_TRUE(big.fault);
    EXPECT_EQ(big.fault->token, "binary_big_endian");
    // The encoding is refused before the version is looked at.
    EXPECT_EQ(faultOf("ply\nformat ascii 2.0\nend_header\n", littleOnly), PlyHeaderFaultKind::EncodingNotAccepted);
    const PlyHeaderParse accepted = parse("ply\nformat ascii 1.0\nelement v 0\nend_header\n", lenientRules());
    ASSERT_FALSE(accepted.fault);
    EXPECT_EQ(accepted.header.encoding, rad::PlyEncoding::Ascii);
}

}  // namespace
