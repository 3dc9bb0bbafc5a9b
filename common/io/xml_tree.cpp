#include "io/xml_tree.h"

#include <expat.h>

#include <fstream>
#include <sstream>

namespace rad {

namespace {

struct Builder {
    XML_Parser parser = nullptr;
    XmlElement root;
    std::vector<XmlElement*> open;  // the path from the root to the element being read
    bool rootSeen = false;
};

void XMLCALL onStart(void* data, const XML_Char* name, const XML_Char** attributes) {
    Builder& b = *static_cast<Builder*>(data);
    XmlElement element;
    element.name = name;
    element.line = int(XML_GetCurrentLineNumber(b.parser));
    for (int i = 0; attributes[i] != nullptr; i += 2) element.attributes[attributes[i]] = attributes[i + 1];
    if (b.open.empty()) {
        b.root = std::move(element);
        b.rootSeen = true;
        b.open.push_back(&b.root);
    } else {
        // Appended to the innermost open element. The open elements' pointers stay valid: a vector
        // grows only while none of its elements is open (a sibling is added after the previous
        // one closed).
        b.open.back()->children.push_back(std::move(element));
        b.open.push_back(&b.open.back()->children.back());
    }
}

void XMLCALL onEnd(void* data, const XML_Char*) { static_cast<Builder*>(data)->open.pop_back(); }

void XMLCALL onText(void* data, const XML_Char* text, int length) {
    Builder& b = *static_cast<Builder*>(data);
    if (!b.open.empty()) b.open.back()->text.append(text, std::size_t(length));
}

}  // namespace

const XmlElement* XmlElement::child(const std::string& childName) const {
    for (const XmlElement& c : children)
        if (c.name == childName) return &c;
    return nullptr;
}

std::vector<const XmlElement*> XmlElement::childrenNamed(const std::string& childName) const {
    std::vector<const XmlElement*> out;
    for (const XmlElement& c : children)
        if (c.name == childName) out.push_back(&c);
    return out;
}

std::string XmlElement::attribute(const std::string& key, const std::string& fallback) const {
    const auto found = attributes.find(key);
    return found == attributes.end() ? fallback : found->second;
}

XmlElement parseXml(const std::string& text, const std::string& what) {
    Builder b;
    b.parser = XML_ParserCreate(nullptr);
    if (b.parser == nullptr) throw XmlError("cannot create an XML parser (out of memory)");
    XML_SetUserData(b.parser, &b);
    XML_SetElementHandler(b.parser, onStart, onEnd);
    XML_SetCharacterDataHandler(b.parser, onText);
    const bool ok = XML_Parse(b.parser, text.data(), int(text.size()), 1) == XML_STATUS_OK;
    std::string problem;
    if (!ok)
        problem = "'" + what + "' is not well-formed XML (line " + std::to_string(XML_GetCurrentLineNumber(b.parser)) +
                  ": " + XML_ErrorString(XML_GetErrorCode(b.parser)) + ")";
    XML_ParserFree(b.parser);
    if (!problem.empty()) throw XmlError(problem);
    if (!b.rootSeen) throw XmlError("'" + what + "' holds no XML element");
    return std::move(b.root);
}

XmlElement readXmlFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw XmlError("cannot open '" + path + "': check that it exists and is readable");
    std::ostringstream text;
    text << in.rdbuf();
    return parseXml(text.str(), path);
}

}  // namespace rad
