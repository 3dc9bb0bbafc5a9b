#include "io/meshlab_project.h"

#include <Eigen/LU>

#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

namespace rad {

namespace {

// ---- A small strict XML reader -------------------------------------------------------------
// Enough XML for MeshLab projects (QDom writes them): prolog (<?xml?>, <!DOCTYPE>), elements with
// quoted attributes, text, comments, CDATA, the five predefined entities and numeric character
// references. Whitespace-only text is dropped and comments are kept as nodes, as QDom does by
// default, so "first child" means what it means to MeshLab.

struct XmlNode {
    enum class Kind { Element, Text, Comment } kind = Kind::Element;
    std::string name;  // element name
    std::vector<std::pair<std::string, std::string>> attributes;
    std::string text;  // Text / Comment content
    int line = 0;
    std::vector<std::unique_ptr<XmlNode>> children;

    const std::string* attribute(const std::string& key) const {
        for (const auto& a : attributes)
            if (a.first == key) return &a.second;
        return nullptr;
    }
    // Concatenated text of the direct text children.
    std::string innerText() const {
        std::string s;
        for (const auto& c : children)
            if (c->kind == Kind::Text) s += c->text;
        return s;
    }
};

class XmlParser {
public:
    XmlParser(const std::string& text, const std::string& source) : s_(text), source_(source) {}

    std::unique_ptr<XmlNode> parseDocument() {
        if (s_.compare(0, 3, "\xEF\xBB\xBF") == 0) pos_ = 3;  // UTF-8 byte-order mark
        skipMisc(true);
        if (pos_ >= s_.size() || s_[pos_] != '<') fail("no root element");
        auto root = parseElement();
        skipMisc(false);
        if (pos_ < s_.size()) fail("unexpected content after the root element");
        return root;
    }

private:
    const std::string& s_;
    const std::string& source_;
    std::size_t pos_ = 0;
    int line_ = 1;

    [[noreturn]] void fail(const std::string& why) const {
        throw MeshLabProjectError(source_ + ":" + std::to_string(line_) + ": malformed XML: " + why);
    }
    bool startsWith(const char* t) const { return s_.compare(pos_, std::strlen(t), t) == 0; }
    void advance(std::size_t n) {
        for (std::size_t i = 0; i < n && pos_ < s_.size(); ++i)
            if (s_[pos_++] == '\n') ++line_;
    }
    void skipSpace() {
        while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) advance(1);
    }
    // Skips up to and including `end`; fails when it never comes.
    std::string until(const char* end, const char* what) {
        const std::size_t stop = s_.find(end, pos_);
        if (stop == std::string::npos) fail(std::string("unterminated ") + what);
        std::string content = s_.substr(pos_, stop - pos_);
        advance(stop - pos_ + std::strlen(end));
        return content;
    }
    // Whitespace, comments, processing instructions and (in the prolog) one DOCTYPE.
    void skipMisc(bool prolog) {
        for (;;) {
            skipSpace();
            if (startsWith("<!--")) {
                advance(4);
                until("-->", "comment");
            } else if (startsWith("<?")) {
                advance(2);
                until("?>", "processing instruction");
            } else if (prolog && startsWith("<!DOCTYPE")) {
                advance(9);
                // No internal subset in MeshLab projects: refuse one instead of misreading it.
                const std::string decl = until(">", "DOCTYPE");
                if (decl.find('[') != std::string::npos) fail("DOCTYPE with an internal subset is not supported");
            } else {
                return;
            }
        }
    }
    static bool nameChar(char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' || c == ':' ||
               (static_cast<unsigned char>(c) >= 0x80);
    }
    std::string parseName() {
        const std::size_t start = pos_;
        while (pos_ < s_.size() && nameChar(s_[pos_])) ++pos_;
        if (pos_ == start) fail("expected a name");
        return s_.substr(start, pos_ - start);
    }
    static void appendUtf8(std::string& out, std::uint32_t cp) {
        if (cp < 0x80) {
            out += static_cast<char>(cp);
        } else if (cp < 0x800) {
            out += static_cast<char>(0xC0 | (cp >> 6));
            out += static_cast<char>(0x80 | (cp & 0x3F));
        } else if (cp < 0x10000) {
            out += static_cast<char>(0xE0 | (cp >> 12));
            out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (cp & 0x3F));
        } else {
            out += static_cast<char>(0xF0 | (cp >> 18));
            out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
            out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (cp & 0x3F));
        }
    }
    // Decodes entity and character references of raw text.
    std::string decode(const std::string& raw) const {
        std::string out;
        for (std::size_t i = 0; i < raw.size(); ++i) {
            if (raw[i] != '&') {
                out += raw[i];
                continue;
            }
            const std::size_t semi = raw.find(';', i);
            if (semi == std::string::npos) fail("'&' without ';'");
            const std::string ent = raw.substr(i + 1, semi - i - 1);
            if (ent == "lt") out += '<';
            else if (ent == "gt") out += '>';
            else if (ent == "amp") out += '&';
            else if (ent == "quot") out += '"';
            else if (ent == "apos") out += '\'';
            else if (ent.size() > 1 && ent[0] == '#') {
                const bool hex = ent[1] == 'x' || ent[1] == 'X';
                const char* b = ent.data() + (hex ? 2 : 1);
                const char* e = ent.data() + ent.size();
                std::uint32_t cp = 0;
                const auto r = std::from_chars(b, e, cp, hex ? 16 : 10);
                if (r.ec != std::errc() || r.ptr != e || b == e || cp == 0 || cp > 0x10FFFF) fail("bad character reference &" + ent + ";");
                appendUtf8(out, cp);
            } else {
                fail("unknown entity &" + ent + ";");
            }
            i = semi;
        }
        return out;
    }
    std::unique_ptr<XmlNode> parseElement() {
        auto node = std::make_unique<XmlNode>();
        node->line = line_;
        advance(1);  // '<'
        node->name = parseName();
        for (;;) {
            skipSpace();
            if (pos_ >= s_.size()) fail("unterminated start tag <" + node->name + ">");
            if (startsWith("/>")) {
                advance(2);
                return node;
            }
            if (s_[pos_] == '>') {
                advance(1);
                break;
            }
            const std::string key = parseName();
            skipSpace();
            if (pos_ >= s_.size() || s_[pos_] != '=') fail("attribute '" + key + "' without '='");
            advance(1);
            skipSpace();
            if (pos_ >= s_.size() || (s_[pos_] != '"' && s_[pos_] != '\'')) fail("attribute '" + key + "' is not quoted");
            const char quote[2] = {s_[pos_], 0};
            advance(1);
            const std::string raw = until(quote, "attribute value");
            if (raw.find('<') != std::string::npos) fail("'<' inside attribute '" + key + "'");
            if (node->attribute(key)) fail("attribute '" + key + "' appears twice");
            node->attributes.emplace_back(key, decode(raw));
        }
        // Content.
        for (;;) {
            if (pos_ >= s_.size()) fail("element <" + node->name + "> is not closed");
            if (startsWith("</")) {
                advance(2);
                const std::string closing = parseName();
                if (closing != node->name) fail("</" + closing + "> closes <" + node->name + ">");
                skipSpace();
                if (pos_ >= s_.size() || s_[pos_] != '>') fail("malformed end tag </" + closing);
                advance(1);
                return node;
            }
            if (startsWith("<!--")) {
                auto c = std::make_unique<XmlNode>();
                c->kind = XmlNode::Kind::Comment;
                c->line = line_;
                advance(4);
                c->text = until("-->", "comment");
                node->children.push_back(std::move(c));
            } else if (startsWith("<![CDATA[")) {
                auto t = std::make_unique<XmlNode>();
                t->kind = XmlNode::Kind::Text;
                t->line = line_;
                advance(9);
                t->text = until("]]>", "CDATA section");
                node->children.push_back(std::move(t));
            } else if (startsWith("<?")) {
                advance(2);
                until("?>", "processing instruction");
            } else if (s_[pos_] == '<') {
                node->children.push_back(parseElement());
            } else {
                const int line = line_;
                const std::size_t stop = s_.find('<', pos_);
                const std::size_t end = stop == std::string::npos ? s_.size() : stop;
                const std::string raw = s_.substr(pos_, end - pos_);
                advance(end - pos_);
                bool blank = true;
                for (char ch : raw) blank = blank && std::isspace(static_cast<unsigned char>(ch));
                if (!blank) {
                    auto t = std::make_unique<XmlNode>();
                    t->kind = XmlNode::Kind::Text;
                    t->line = line;
                    t->text = decode(raw);
                    node->children.push_back(std::move(t));
                }
            }
        }
    }
};

// ---- Values ----------------------------------------------------------------------------------

// Rounded to float32, -0 made +0 (the writer writes "0"): what a project file holds, bit for bit.
double toFloat32(double v) { return static_cast<double>(static_cast<float>(v) + 0.0f); }

// The shortest decimal that reads back as the float32 nearest to v (locale-independent).
std::string formatFloat(double v) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, static_cast<float>(toFloat32(v)));
    return std::string(buf, r.ptr);
}

std::string escapeAttribute(const std::string& s) {
    std::string out;
    for (char c : s) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\n': out += "&#10;"; break;
            case '\r': out += "&#13;"; break;
            case '\t': out += "&#9;"; break;
            default: out += c;
        }
    }
    return out;
}

std::vector<std::string> splitWhitespace(const std::string& s) {
    std::vector<std::string> out;
    std::istringstream in(s);
    std::string token;
    while (in >> token) out.push_back(token);
    return out;
}

class ValueReader {
public:
    ValueReader(const std::string& source, const XmlNode& node) : source_(source), node_(node) {}

    [[noreturn]] void fail(const std::string& why) const {
        throw MeshLabProjectError(source_ + ":" + std::to_string(node_.line) + ": <" + node_.name + ">: " + why);
    }
    const std::string& required(const char* key) const {
        const std::string* v = node_.attribute(key);
        if (!v) fail(std::string("missing attribute ") + key);
        return *v;
    }
    // `count` numbers of a text attribute (extra values beyond `count` allowed only when
    // `allowExtra`), each rounded to float32 as MeshLab stores them.
    std::vector<double> floats(const char* key, std::size_t count, bool allowExtra = false) const {
        const std::vector<std::string> tokens = splitWhitespace(required(key));
        if (tokens.size() < count || (!allowExtra && tokens.size() != count))
            fail(std::string("attribute ") + key + " needs " + std::to_string(count) + " numbers, has " +
                 std::to_string(tokens.size()));
        std::vector<double> out;
        for (std::size_t i = 0; i < count; ++i) out.push_back(toFloat32(number(key, tokens[i])));
        return out;
    }
    std::vector<int> ints(const char* key, std::size_t count) const {
        const std::vector<std::string> tokens = splitWhitespace(required(key));
        if (tokens.size() != count)
            fail(std::string("attribute ") + key + " needs " + std::to_string(count) + " integers, has " +
                 std::to_string(tokens.size()));
        std::vector<int> out;
        for (const std::string& t : tokens) {
            int v = 0;
            const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
            if (r.ec != std::errc() || r.ptr != t.data() + t.size())
                fail(std::string("attribute ") + key + ": '" + t + "' is not an integer");
            out.push_back(v);
        }
        return out;
    }
    double number(const char* key, const std::string& t) const {
        double v = 0.0;
        const char* b = t.data();
        if (!t.empty() && *b == '+') ++b;
        const auto r = std::from_chars(b, t.data() + t.size(), v);
        if (r.ec != std::errc() || r.ptr != t.data() + t.size() || !std::isfinite(v) || !std::isfinite(float(v)))
            fail(std::string("attribute ") + key + ": '" + t + "' is not a finite float number");
        return v;
    }
    // Base64 (RFC 4648) bytes of a binary attribute, exactly `bytes` long.
    std::vector<unsigned char> binary(const char* key, std::size_t bytes) const {
        const std::string& text = required(key);
        std::vector<unsigned char> out;
        std::uint32_t acc = 0;
        int bits = 0;
        for (char c : text) {
            int v;
            if (c >= 'A' && c <= 'Z') v = c - 'A';
            else if (c >= 'a' && c <= 'z') v = c - 'a' + 26;
            else if (c >= '0' && c <= '9') v = c - '0' + 52;
            else if (c == '+') v = 62;
            else if (c == '/') v = 63;
            else if (c == '=' || std::isspace(static_cast<unsigned char>(c))) continue;
            else fail(std::string("attribute ") + key + " is not base64");
            acc = (acc << 6) | static_cast<std::uint32_t>(v);
            bits += 6;
            if (bits >= 8) {
                bits -= 8;
                out.push_back(static_cast<unsigned char>((acc >> bits) & 0xFF));
            }
        }
        if (out.size() < bytes) fail(std::string("binary attribute ") + key + " holds " + std::to_string(out.size()) +
                                     " bytes, needs " + std::to_string(bytes));
        out.resize(bytes);
        return out;
    }
    std::vector<double> binaryFloats(const char* key, std::size_t count) const {
        const std::vector<unsigned char> b = binary(key, 4 * count);
        std::vector<double> out;
        for (std::size_t i = 0; i < count; ++i) {
            const std::uint32_t bitsLe = std::uint32_t(b[4 * i]) | (std::uint32_t(b[4 * i + 1]) << 8) |
                                         (std::uint32_t(b[4 * i + 2]) << 16) | (std::uint32_t(b[4 * i + 3]) << 24);
            float f;
            std::memcpy(&f, &bitsLe, 4);
            if (!std::isfinite(f)) fail(std::string("binary attribute ") + key + " holds a non-finite value");
            out.push_back(f);
        }
        return out;
    }
    std::vector<int> binaryInts(const char* key, std::size_t count) const {
        const std::vector<unsigned char> b = binary(key, 4 * count);
        std::vector<int> out;
        for (std::size_t i = 0; i < count; ++i) {
            const std::uint32_t u = std::uint32_t(b[4 * i]) | (std::uint32_t(b[4 * i + 1]) << 8) |
                                    (std::uint32_t(b[4 * i + 2]) << 16) | (std::uint32_t(b[4 * i + 3]) << 24);
            std::int32_t v;
            std::memcpy(&v, &u, 4);
            out.push_back(v);
        }
        return out;
    }

private:
    const std::string& source_;
    const XmlNode& node_;
};

VcgCamera readVcgCamera(const XmlNode& node, const std::string& source) {
    const ValueReader r(source, node);
    VcgCamera cam;
    bool binary = false;
    if (const std::string* b = node.attribute("BinaryData")) {
        const std::vector<int> v = r.ints("BinaryData", 1);
        if (v[0] != 0 && v[0] != 1) r.fail("BinaryData must be 0 or 1");
        binary = v[0] == 1;
        (void)b;
    }
    if (node.attribute("CameraType")) cam.cameraType = r.ints("CameraType", 1)[0];
    std::vector<double> rot, tra, focal, pixel, center, lens;
    std::vector<int> viewport;
    if (binary) {
        rot = r.binaryFloats("RotationMatrix", 16);
        tra = r.binaryFloats("TranslationVector", 3);
        focal = r.binaryFloats("FocalMm", 1);
        pixel = r.binaryFloats("PixelSizeMm", 2);
        center = r.binaryFloats("CenterPx", 2);
        lens = r.binaryFloats("LensDistortion", 2);
        viewport = r.binaryInts("ViewportPx", 2);
    } else {
        rot = r.floats("RotationMatrix", 16);
        tra = r.floats("TranslationVector", 3, true);  // MeshLab writes "x y z 1" and reads three
        focal = r.floats("FocalMm", 1);
        pixel = r.floats("PixelSizeMm", 2);
        center = r.floats("CenterPx", 2);
        lens = r.floats("LensDistortion", 2);
        viewport = r.ints("ViewportPx", 2);
    }
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) cam.rotation(i, j) = rot[4 * i + j];
    // The 4th row and column of a rotation are (0 0 0 1); anything else is not a camera MeshLab wrote.
    if (rot[3] != 0.0 || rot[7] != 0.0 || rot[11] != 0.0 || rot[12] != 0.0 || rot[13] != 0.0 || rot[14] != 0.0 ||
        rot[15] != 1.0)
        r.fail("RotationMatrix is not a rotation (its last row and column must be 0 0 0 1)");
    if ((cam.rotation * cam.rotation.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-4 ||
        cam.rotation.determinant() < 0.0)
        r.fail("RotationMatrix is not a proper orthonormal rotation");
    cam.translation = Eigen::Vector3d(tra[0], tra[1], tra[2]);
    cam.focalMm = focal[0];
    cam.pixelSizeMm = Eigen::Vector2d(pixel[0], pixel[1]);
    cam.centerPx = Eigen::Vector2d(center[0], center[1]);
    cam.lensDistortion = Eigen::Vector2d(lens[0], lens[1]);
    cam.viewportWidth = viewport[0];
    cam.viewportHeight = viewport[1];
    if (cam.viewportWidth <= 0 || cam.viewportHeight <= 0) r.fail("ViewportPx must be positive");
    if (!(cam.focalMm > 0.0)) r.fail("FocalMm must be positive");
    if (!(cam.pixelSizeMm.x() > 0.0) || !(cam.pixelSizeMm.y() > 0.0)) r.fail("PixelSizeMm must be positive");
    return cam;
}

[[noreturn]] void failAt(const std::string& source, const XmlNode& n, const std::string& why) {
    throw MeshLabProjectError(source + ":" + std::to_string(n.line) + ": " + why);
}

std::string resolve(const std::string& base, const std::string& file) {
    const std::filesystem::path p(file);
    if (p.is_absolute() || base.empty()) return p.lexically_normal().string();
    return (std::filesystem::path(base) / p).lexically_normal().string();
}

}  // namespace

// ---- Cameras ---------------------------------------------------------------------------------

bool VcgCamera::project(const Eigen::Vector3d& X, double& px, double& py) const {
    Eigen::Vector3d cp = rotation * (X + translation);  // R (X - C), C = -translation
    cp.z() = -cp.z();
    if (!(cp.z() > 0.0)) return false;
    px = cp.x() * focalMm / cp.z() / pixelSizeMm.x() + centerPx.x();
    py = cp.y() * focalMm / cp.z() / pixelSizeMm.y() + centerPx.y();
    return true;
}

VcgCamera toVcgCamera(const PinholeCamera& camera, double pixelSizeMm) {
    VcgCamera v;
    v.rotation = camera.rotation;
    v.rotation.row(1) *= -1.0;  // down -> up
    v.rotation.row(2) *= -1.0;  // forward -> backwards
    v.translation = -camera.center;
    v.focalMm = camera.fx * pixelSizeMm;
    v.pixelSizeMm = Eigen::Vector2d(pixelSizeMm, v.focalMm / camera.fy);
    v.centerPx = Eigen::Vector2d(camera.cx, camera.height - camera.cy);
    v.viewportWidth = camera.width;
    v.viewportHeight = camera.height;
    v.lensDistortion.setZero();
    v.cameraType = 0;
    return v;
}

PinholeCamera fromVcgCamera(const VcgCamera& v) {
    if (v.cameraType != 0)
        throw MeshLabProjectError("the raster camera is not a perspective camera (CameraType " +
                                  std::to_string(v.cameraType) + "); only perspective cameras are supported");
    if (v.lensDistortion.x() != 0.0 || v.lensDistortion.y() != 0.0) {
        std::ostringstream why;
        why << "the raster camera has lens distortion (" << v.lensDistortion.x() << " " << v.lensDistortion.y()
            << "); undistort the images and set LensDistortion to 0 0";
        throw MeshLabProjectError(why.str());
    }
    if (v.viewportWidth <= 0 || v.viewportHeight <= 0 || !(v.focalMm > 0.0) || !(v.pixelSizeMm.x() > 0.0) ||
        !(v.pixelSizeMm.y() > 0.0))
        throw MeshLabProjectError("the raster camera has a non-positive image size, focal length or pixel size");
    PinholeCamera c;
    c.rotation = v.rotation;
    c.rotation.row(1) *= -1.0;
    c.rotation.row(2) *= -1.0;
    c.center = -v.translation;
    c.fx = v.focalMm / v.pixelSizeMm.x();
    c.fy = v.focalMm / v.pixelSizeMm.y();
    c.width = v.viewportWidth;
    c.height = v.viewportHeight;
    c.cx = v.centerPx.x();
    c.cy = v.viewportHeight - v.centerPx.y();
    return c;
}

VcgCamera roundedToFloat(const VcgCamera& v) {
    VcgCamera r = v;
    r.rotation = v.rotation.unaryExpr([](double x) { return toFloat32(x); });
    r.translation = v.translation.unaryExpr([](double x) { return toFloat32(x); });
    r.focalMm = toFloat32(v.focalMm);
    r.pixelSizeMm = v.pixelSizeMm.unaryExpr([](double x) { return toFloat32(x); });
    r.centerPx = v.centerPx.unaryExpr([](double x) { return toFloat32(x); });
    r.lensDistortion = v.lensDistortion.unaryExpr([](double x) { return toFloat32(x); });
    return r;
}

PinholeCamera storedCamera(const PinholeCamera& camera, double pixelSizeMm) {
    return fromVcgCamera(roundedToFloat(toVcgCamera(camera, pixelSizeMm)));
}

// ---- Writing ---------------------------------------------------------------------------------

std::string formatMeshLabProject(const MeshLabProject& project) {
    auto checkFinite = [](bool ok, const std::string& what) {
        if (!ok) throw MeshLabProjectError("cannot write the project: " + what + " has a non-finite value");
    };
    std::ostringstream out;
    out << "<!DOCTYPE MeshLabDocument>\n<MeshLabProject>\n";
    if (project.meshes.empty()) {
        out << " <MeshGroup/>\n";
    } else {
        out << " <MeshGroup>\n";
        for (const ProjectMesh& m : project.meshes) {
            checkFinite(m.transform.allFinite(), "the transform of mesh '" + m.label + "'");
            out << "  <MLMesh label=\"" << escapeAttribute(m.label) << "\" filename=\"" << escapeAttribute(m.fileName)
                << "\" visible=\"" << (m.visible ? 1 : 0) << "\">\n   <MLMatrix44>\n";
            for (int i = 0; i < 4; ++i) {
                for (int j = 0; j < 4; ++j) out << formatFloat(m.transform(i, j)) << ' ';
                out << '\n';
            }
            out << "</MLMatrix44>\n  </MLMesh>\n";
        }
        out << " </MeshGroup>\n";
    }
    out << " <RasterGroup>\n";
    for (const ProjectRaster& r : project.rasters) {
        const VcgCamera& c = r.camera;
        checkFinite(c.rotation.allFinite() && c.translation.allFinite() && std::isfinite(c.focalMm) &&
                        c.pixelSizeMm.allFinite() && c.centerPx.allFinite() && c.lensDistortion.allFinite(),
                    "the camera of raster '" + r.label + "'");
        out << "  <MLRaster label=\"" << escapeAttribute(r.label) << "\">\n   <VCGCamera";
        out << " TranslationVector=\"" << formatFloat(c.translation.x()) << ' ' << formatFloat(c.translation.y()) << ' '
            << formatFloat(c.translation.z()) << " 1\"";
        out << " LensDistortion=\"" << formatFloat(c.lensDistortion.x()) << ' ' << formatFloat(c.lensDistortion.y()) << "\"";
        out << " ViewportPx=\"" << c.viewportWidth << ' ' << c.viewportHeight << "\"";
        out << " PixelSizeMm=\"" << formatFloat(c.pixelSizeMm.x()) << ' ' << formatFloat(c.pixelSizeMm.y()) << "\"";
        out << " CenterPx=\"" << formatFloat(c.centerPx.x()) << ' ' << formatFloat(c.centerPx.y()) << "\"";
        out << " FocalMm=\"" << formatFloat(c.focalMm) << "\"";
        // MeshLab writes 16 values each followed by a space; its reader splits on spaces.
        out << " RotationMatrix=\"";
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j)
                out << (i < 3 && j < 3 ? formatFloat(c.rotation(i, j)) : std::string(i == j ? "1" : "0")) << ' ';
        out << "\" CameraType=\"" << c.cameraType << "\" BinaryData=\"0\"/>\n";
        out << "   <Plane semantic=\"1\" fileName=\"" << escapeAttribute(r.imageFile) << "\"/>\n  </MLRaster>\n";
    }
    out << " </RasterGroup>\n</MeshLabProject>\n";
    return out.str();
}

void writeMeshLabProject(const std::string& path, const MeshLabProject& project) {
    const std::string text = formatMeshLabProject(project);
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) throw MeshLabProjectError("cannot open " + path + " for writing: " + std::strerror(errno));
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.flush();
    if (!out) throw MeshLabProjectError("error while writing " + path);
}

// ---- Reading ---------------------------------------------------------------------------------

MeshLabProject parseMeshLabProject(const std::string& text, const std::string& baseDirectory,
                                   const std::string& sourceName) {
    XmlParser parser(text, sourceName);
    const std::unique_ptr<XmlNode> root = parser.parseDocument();
    auto fail = [&](const XmlNode& n, const std::string& why) { failAt(sourceName, n, why); };
    if (root->name != "MeshLabProject")
        fail(*root, "the root element is <" + root->name + ">, not <MeshLabProject>: not a MeshLab project");
    MeshLabProject project;
    for (const auto& group : root->children) {
        if (group->kind != XmlNode::Kind::Element) continue;
        if (group->name == "MeshGroup") {
            for (const auto& m : group->children) {
                if (m->kind == XmlNode::Kind::Comment)
                    fail(*m, "a comment inside <MeshGroup>: MeshLab reads every child of MeshGroup as a mesh; remove it");
                if (m->kind == XmlNode::Kind::Text) fail(*m, "text inside <MeshGroup>");
                if (m->name != "MLMesh") fail(*m, "<" + m->name + "> inside <MeshGroup>, expected <MLMesh>");
                ProjectMesh mesh;
                const std::string* file = m->attribute("filename");
                if (!file || file->empty()) fail(*m, "<MLMesh> without a filename attribute");
                mesh.fileName = *file;
                mesh.path = resolve(baseDirectory, *file);
                if (const std::string* l = m->attribute("label")) mesh.label = *l;
                if (const std::string* vis = m->attribute("visible")) mesh.visible = *vis == "1";
                for (const auto& c : m->children) {
                    if (c->kind != XmlNode::Kind::Element || c->name != "MLMatrix44") continue;
                    const std::vector<std::string> tokens = splitWhitespace(c->innerText());
                    if (tokens.size() != 16) fail(*c, "<MLMatrix44> needs 16 numbers (binary .mlb matrices are not supported)");
                    XmlNode holder;  // reuse the number parser's checks and messages
                    holder.name = "MLMatrix44";
                    holder.line = c->line;
                    const ValueReader r(sourceName, holder);
                    for (int i = 0; i < 16; ++i) mesh.transform(i / 4, i % 4) = toFloat32(r.number("MLMatrix44", tokens[i]));
                    break;
                }
                project.meshes.push_back(std::move(mesh));
            }
        } else if (group->name == "RasterGroup") {
            for (const auto& rnode : group->children) {
                if (rnode->kind == XmlNode::Kind::Comment)
                    fail(*rnode, "a comment inside <RasterGroup>: MeshLab reads every child of RasterGroup as a raster; remove it");
                if (rnode->kind == XmlNode::Kind::Text) fail(*rnode, "text inside <RasterGroup>");
                if (rnode->name != "MLRaster") fail(*rnode, "<" + rnode->name + "> inside <RasterGroup>, expected <MLRaster>");
                ProjectRaster raster;
                if (const std::string* l = rnode->attribute("label")) raster.label = *l;
                if (rnode->children.empty() || rnode->children.front()->kind != XmlNode::Kind::Element ||
                    rnode->children.front()->name != "VCGCamera")
                    fail(*rnode, "raster '" + raster.label +
                                     "': its first child must be <VCGCamera> (MeshLab reads the camera only there)");
                raster.camera = readVcgCamera(*rnode->children.front(), sourceName);
                const XmlNode* plane = nullptr;
                for (const auto& c : rnode->children)
                    if (c->kind == XmlNode::Kind::Element && c->name == "Plane") {
                        plane = c.get();
                        break;
                    }
                if (!plane) fail(*rnode, "raster '" + raster.label + "' has no <Plane> (no image file)");
                const std::string* file = plane->attribute("fileName");
                if (!file || file->empty()) fail(*plane, "<Plane> without a fileName attribute");
                raster.imageFile = *file;
                raster.imagePath = resolve(baseDirectory, *file);
                project.rasters.push_back(std::move(raster));
            }
        }
    }
    return project;
}

MeshLabProject readMeshLabProject(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw MeshLabProjectError("cannot open the MeshLab project " + path + ": " + std::strerror(errno));
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (in.bad()) throw MeshLabProjectError("error while reading " + path);
    const std::string base = std::filesystem::path(path).parent_path().string();
    return parseMeshLabProject(buffer.str(), base, path);
}

}  // namespace rad
