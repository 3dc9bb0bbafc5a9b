#include "io/off_reader.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string_view>
#include <vector>

namespace rad {

namespace {

// Splits the stream into non-empty lines of whitespace-separated tokens, comments removed, and
// remembers the line number of each for the error messages.
class LineTokenizer {
public:
    LineTokenizer(std::istream& in, const std::string& source) : in_(in), source_(source) {}

    // Next line with at least one token; false at the end of the stream.
    bool next(std::vector<std::string_view>& tokens) {
        tokens.clear();
        while (std::getline(in_, line_)) {
            ++lineNumber_;
            const std::size_t hash = line_.find('#');
            if (hash != std::string::npos) line_.erase(hash);
            std::size_t i = 0;
            const std::size_t n = line_.size();
            auto isSpace = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; };
            while (i < n) {
                while (i < n && isSpace(line_[i])) ++i;
                const std::size_t start = i;
                while (i < n && !isSpace(line_[i])) ++i;
                if (i > start) tokens.emplace_back(line_.data() + start, i - start);
            }
            if (!tokens.empty()) return true;
        }
        if (in_.bad()) fail("read error");
        return false;
    }

    [[noreturn]] void fail(const std::string& what) const {
        std::ostringstream msg;
        msg << source_ << ":" << lineNumber_ << ": " << what;
        throw OffReadError(msg.str());
    }

    [[noreturn]] void failAtEnd(const std::string& what) const {
        throw OffReadError(source_ + ": " + what);
    }

private:
    std::istream& in_;
    const std::string& source_;
    std::string line_;
    long long lineNumber_ = 0;
};

bool parseFloat(std::string_view t, float& out) {
    // from_chars refuses the explicit '+' that printf("%+g") and some exporters write.
    if (t.size() > 1 && t[0] == '+' && t[1] != '+' && t[1] != '-') t.remove_prefix(1);
    double d = 0.0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), d);
    if (r.ec != std::errc() || r.ptr != t.data() + t.size() || !std::isfinite(d)) return false;
    if (std::fabs(d) > static_cast<double>(std::numeric_limits<float>::max())) return false;
    out = static_cast<float>(d);
    return true;
}

bool parseCount(std::string_view t, unsigned long long& out) {
    if (t.size() > 1 && t[0] == '+' && t[1] != '+' && t[1] != '-') t.remove_prefix(1);
    const auto r = std::from_chars(t.data(), t.data() + t.size(), out);
    return r.ec == std::errc() && r.ptr == t.data() + t.size();
}

std::string quoted(std::string_view t) {
    std::string s(t.substr(0, 40));
    if (t.size() > 40) s += "...";
    return "'" + s + "'";
}

}  // namespace

TriangleMesh parseOff(std::istream& in, const std::string& sourceName) {
    LineTokenizer lines(in, sourceName);
    std::vector<std::string_view> tok;

    // Header.
    if (!lines.next(tok)) lines.failAtEnd("empty file, expected the OFF header");
    std::string_view header = tok[0];
    if (header.size() >= 3 && static_cast<unsigned char>(header[0]) == 0xEF &&
        static_cast<unsigned char>(header[1]) == 0xBB && static_cast<unsigned char>(header[2]) == 0xBF)
        header.remove_prefix(3);  // UTF-8 byte order mark
    bool hasColors = false, hasNormals = false;
    if (header == "OFF") {
    } else if (header == "COFF") {
        hasColors = true;
    } else if (header == "NOFF") {
        hasNormals = true;
    } else if (header == "CNOFF") {
        hasColors = hasNormals = true;
    } else if (header.size() > 3 && header.substr(header.size() - 3) == "OFF") {
        lines.fail("unsupported OFF variant " + quoted(header) + " (only OFF, COFF, NOFF, CNOFF)");
    } else {
        lines.fail("not an OFF file: expected the header 'OFF', found " + quoted(header));
    }
    std::size_t next = 1;
    if (tok.size() > 1 && tok[1] == "BINARY") lines.fail("binary OFF is not supported");
    if (tok.size() == 1) {
        if (!lines.next(tok)) lines.failAtEnd("file ends before the vertex and face counts");
        next = 0;
    }

    // Counts.
    const std::size_t countTokens = tok.size() - next;
    if (countTokens < 2 || countTokens > 3)
        lines.fail("expected 'nVertices nFaces nEdges', found " + std::to_string(countTokens) + " values");
    unsigned long long nv = 0, nf = 0, ne = 0;
    if (!parseCount(tok[next], nv)) lines.fail("bad vertex count " + quoted(tok[next]));
    if (!parseCount(tok[next + 1], nf)) lines.fail("bad face count " + quoted(tok[next + 1]));
    if (countTokens == 3 && !parseCount(tok[next + 2], ne)) lines.fail("bad edge count " + quoted(tok[next + 2]));
    if (nv > std::numeric_limits<std::uint32_t>::max()) lines.fail("too many vertices for 32-bit indices");

    TriangleMesh mesh;
    constexpr unsigned long long kReserveCap = 1ull << 24;  // a bogus header must not allocate gigabytes
    mesh.positions.reserve(3 * std::min(nv, kReserveCap));
    if (hasNormals) mesh.normals.reserve(3 * std::min(nv, kReserveCap));
    mesh.faces.reserve(3 * std::min(nf, kReserveCap));

    // Vertices.
    const std::size_t base = hasNormals ? 6 : 3;
    for (unsigned long long v = 0; v < nv; ++v) {
        if (!lines.next(tok))
            lines.failAtEnd("file ends after " + std::to_string(v) + " of " + std::to_string(nv) + " vertices");
        const bool sizeOk = hasColors ? (tok.size() == base + 3 || tok.size() == base + 4) : tok.size() == base;
        if (!sizeOk) {
            std::string expected = std::to_string(base);
            if (hasColors) expected = std::to_string(base + 3) + " or " + std::to_string(base + 4);
            lines.fail("vertex " + std::to_string(v) + " has " + std::to_string(tok.size()) + " values, expected " +
                       expected);
        }
        float value[6];
        for (std::size_t k = 0; k < tok.size(); ++k) {
            float x = 0.0f;
            if (!parseFloat(tok[k], x))
                lines.fail("vertex " + std::to_string(v) + ": bad number " + quoted(tok[k]));
            if (k < base) value[k] = x;
        }
        mesh.positions.insert(mesh.positions.end(), value, value + 3);
        if (hasNormals) mesh.normals.insert(mesh.normals.end(), value + 3, value + 6);
    }

    // Faces.
    std::vector<std::uint32_t> polygon;
    for (unsigned long long f = 0; f < nf; ++f) {
        if (!lines.next(tok))
            lines.failAtEnd("file ends after " + std::to_string(f) + " of " + std::to_string(nf) + " faces");
        unsigned long long k = 0;
        if (!parseCount(tok[0], k)) lines.fail("face " + std::to_string(f) + ": bad vertex count " + quoted(tok[0]));
        if (k < 3) lines.fail("face " + std::to_string(f) + " has " + std::to_string(k) + " vertices, at least 3 needed");
        if (tok.size() < k + 1)
            lines.fail("face " + std::to_string(f) + " announces " + std::to_string(k) + " vertices but lists " +
                       std::to_string(tok.size() - 1));
        if (tok.size() > k + 1 + 4)
            lines.fail("face " + std::to_string(f) + " has " + std::to_string(tok.size() - 1 - k) +
                       " values after its indices (at most 4 colour values)");
        polygon.clear();
        for (std::size_t i = 1; i <= k; ++i) {
            unsigned long long index = 0;
            if (!parseCount(tok[i], index))
                lines.fail("face " + std::to_string(f) + ": bad vertex index " + quoted(tok[i]));
            if (index >= nv)
                lines.fail("face " + std::to_string(f) + " refers to vertex " + std::to_string(index) + " but the file has " +
                           std::to_string(nv) + " vertices");
            const auto idx = static_cast<std::uint32_t>(index);
            if (std::find(polygon.begin(), polygon.end(), idx) != polygon.end())
                lines.fail("face " + std::to_string(f) + " uses vertex " + std::to_string(index) + " twice");
            polygon.push_back(idx);
        }
        for (std::size_t i = k + 1; i < tok.size(); ++i) {
            float c = 0.0f;
            if (!parseFloat(tok[i], c)) lines.fail("face " + std::to_string(f) + ": bad colour value " + quoted(tok[i]));
        }
        for (std::size_t i = 1; i + 1 < polygon.size(); ++i)
            mesh.faces.insert(mesh.faces.end(), {polygon[0], polygon[i], polygon[i + 1]});
    }

    if (lines.next(tok)) lines.fail("unexpected data after the last face: " + quoted(tok[0]));
    return mesh;
}

TriangleMesh readOff(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw OffReadError(path + ": cannot open the file");
    return parseOff(in, path);
}

}  // namespace rad
