// The XML tree: elements, attributes, text, nesting and siblings; errors with their line.
#include "io/xml_tree.h"

#include <gtest/gtest.h>

namespace {

TEST(XmlTree, ReadsElementsAttributesTextAndSiblings) {
    const rad::XmlElement root = rad::parseXml(
        "<?xml version=\"1.0\"?>\n<document version=\"1.5\">\n <a id=\"1\">x &amp; y</a>\n <a id=\"2\"><b>3</b><b>4</b></a>\n"
        " <!-- a comment -->\n <c/>\n</document>\n",
        "test");
    EXPECT_EQ(root.name, "document");
    EXPECT_EQ(root.attribute("version"), "1.5");
    EXPECT_EQ(root.attribute("missing", "none"), "none");
    ASSERT_EQ(root.childrenNamed("a").size(), 2u);
    EXPECT_EQ(root.child("a")->text, "x & y");
    EXPECT_EQ(root.child("a")->line, 3);
    const rad::XmlElement* second = root.childrenNamed("a")[1];
    EXPECT_EQ(second->attribute("id"), "2");
    ASSERT_EQ(second->childrenNamed("b").size(), 2u);
    EXPECT_EQ(second->childrenNamed("b")[1]->text, "4");
    EXPECT_NE(root.child("c"), nullptr);
    EXPECT_EQ(root.child("d"), nullptr);
}

TEST(XmlTree, MalformedTextIsRefusedWithItsLine) {
    try {
        rad::parseXml("<a>\n<b>\n</a>\n", "bad.xml");
        ADD_FAILURE() << "accepted";
    } catch (const rad::XmlError& e) {
        EXPECT_NE(std::string(e.what()).find("bad.xml"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("line 3"), std::string::npos) << e.what();
    }
    EXPECT_THROW(rad::readXmlFile("/nonexistent/file.xml"), rad::XmlError);
}

}  // namespace
