// The JSON reader: every kind of value, nesting, escapes, Python's NaN, and errors with their line.
#include "io/json_value.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

TEST(JsonValue, ReadsEveryKindOfValue) {
    const rad::JsonValue v = rad::parseJson(
        "{\"a\": 1.5e2, \"b\": [true, false, null, -3], \"c\": {\"d\": \"x\\\"y\\u00e9\"}, \"e\": NaN, \"f\": []}", "t");
    ASSERT_EQ(v.type, rad::JsonValue::Type::Object);
    EXPECT_EQ(v.find("a")->number, 150.0);
    const rad::JsonValue& b = *v.find("b");
    ASSERT_EQ(b.array.size(), 4u);
    EXPECT_TRUE(b.array[0].boolean);
    EXPECT_EQ(b.array[1].type, rad::JsonValue::Type::Bool);
    EXPECT_FALSE(b.array[1].boolean);
    EXPECT_EQ(b.array[2].type, rad::JsonValue::Type::Null);
    EXPECT_EQ(b.array[3].number, -3.0);
    EXPECT_EQ(v.find("c")->find("d")->string, "x\"y\xC3\xA9");
    EXPECT_TRUE(std::isnan(v.find("e")->number));
    EXPECT_TRUE(v.find("f")->array.empty());
    EXPECT_EQ(v.find("missing"), nullptr);
}

TEST(JsonValue, InvalidTextIsRefusedWithItsLine) {
    for (const char* bad : {"{\"a\": 1,\n\n}", "{\"a\" 1}", "[1, 2", "{\"a\": tru}", "{} x"}) {
        try {
            rad::parseJson(bad, "bad.json");
            ADD_FAILURE() << bad << " accepted";
        } catch (const rad::JsonError& e) {
            EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
        }
    }
    try {
        rad::parseJson("{\"a\": 1,\n\n}", "bad.json");
    } catch (const rad::JsonError& e) {
        EXPECT_NE(std::string(e.what()).find("line 3"), std::string::npos) << e.what();
    }
}

}  // namespace
