// A whole XML file as a tree of elements (name, attributes, text, children), parsed by expat
// (Debian's libexpat1-dev): camera files (Metashape's XML) are small, and a tree is the simplest
// thing to read them from. Namespaces, DTDs and processing instructions are not interpreted.
#pragma once

#include "errors/error_categories.h"

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace rad {

struct XmlError : FileError {
    using FileError::FileError;
};

struct XmlElement {
    std::string name;
    std::map<std::string, std::string> attributes;
    std::string text;  // the character data directly inside the element, concatenated
    std::vector<XmlElement> children;
    int line = 0;      // where the element starts (for messages)

    // The first child named `childName`, or null.
    const XmlElement* child(const std::string& childName) const;
    // Every child named `childName`, in document order.
    std::vector<const XmlElement*> childrenNamed(const std::string& childName) const;
    // The attribute's value, or `fallback` when absent.
    std::string attribute(const std::string& key, const std::string& fallback = "") const;
};

// Parses `path`; throws XmlError naming the file, the line and expat's reason for a missing file or
// text that is not well-formed XML.
XmlElement readXmlFile(const std::string& path);
// The same for text in memory (`what` names it in messages).
XmlElement parseXml(const std::string& text, const std::string& what);

}  // namespace rad
