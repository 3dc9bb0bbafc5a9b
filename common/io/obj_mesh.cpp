#include "io/obj_mesh.h"

#include "io/atomic_file.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <string_view>

namespace rad {
namespace {

std::string folderOf(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

std::string quoted(std::string_view t) {
    std::string s(t.substr(0, 40));
    if (t.size() > 40) s += "...";
    return "'" + s + "'";
}

void splitTokens(std::string_view line, std::vector<std::string_view>& tok) {
    tok.clear();
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
        const std::size_t start = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
        if (i > start) tok.push_back(line.substr(start, i - start));
    }
}

bool parseFloat(std::string_view t, float& out) {
    if (t.size() > 1 && t[0] == '+' && t[1] != '+' && t[1] != '-') t.remove_prefix(1);
    double d = 0.0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), d);
    if (r.ec != std::errc() || r.ptr != t.data() + t.size() || !std::isfinite(d)) return false;
    if (std::fabs(d) > double(std::numeric_limits<float>::max())) return false;
    out = float(d);
    return true;
}

bool parseInt(std::string_view t, long long& out) {
    if (t.size() > 1 && t[0] == '+') t.remove_prefix(1);
    const auto r = std::from_chars(t.data(), t.data() + t.size(), out);
    return r.ec == std::errc() && r.ptr == t.data() + t.size();
}

// Reads logical lines: comments stripped, '\' continuations joined, 1-based line numbers of the
// first physical line.
class Lines {
public:
    Lines(std::istream& in) : in_(in) {}
    bool next(std::string& line, long long& number) {
        line.clear();
        std::string physical;
        bool any = false;
        while (std::getline(in_, physical)) {
            ++count_;
            if (!any) number = count_;
            any = true;
            if (!physical.empty() && physical.back() == '\r') physical.pop_back();
            const std::size_t hash = physical.find('#');
            if (hash != std::string::npos) physical.resize(hash);
            if (!physical.empty() && physical.back() == '\\') {
                physical.pop_back();
                line += physical + " ";
                continue;
            }
            line += physical;
            return true;
        }
        return any;
    }

private:
    std::istream& in_;
    long long count_ = 0;
};

// The map_Kd of the material used first (or the first one) of an .mtl file; "" when none.
std::string textureOfMtl(const std::string& mtlPath, const std::vector<std::string>& usedMaterials,
                         std::vector<std::string>& warnings) {
    std::ifstream in(mtlPath);
    if (!in) {
        warnings.push_back("cannot read the material library '" + mtlPath + "': no texture taken from it");
        return "";
    }
    Lines lines(in);
    std::string line, material, firstTexture;
    long long number = 0;
    std::vector<std::pair<std::string, std::string>> textures;  // material -> map_Kd
    std::vector<std::string_view> tok;
    while (lines.next(line, number)) {
        splitTokens(line, tok);
        if (tok.empty()) continue;
        if (tok[0] == "newmtl" && tok.size() >= 2) material = std::string(tok[1]);
        else if (tok[0] == "map_Kd" && tok.size() >= 2) {
            // The file name is the last token (options such as -s u v w may precede it); names with
            // spaces are taken whole when no option is given.
            std::string name = tok[1][0] == '-' ? std::string(tok.back())
                                                : std::string(line.substr(line.find(tok[1])));
            while (!name.empty() && (name.back() == ' ' || name.back() == '\t')) name.pop_back();
            textures.emplace_back(material, name);
        }
    }
    for (const std::string& used : usedMaterials)
        for (const auto& t : textures)
            if (t.first == used) return t.second;
    return textures.empty() ? std::string() : textures.front().second;
}

void writeShortest(std::string& out, float v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, r.ptr);
}

}  // namespace

ObjMesh readObj(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw ObjReadError(path + ": cannot open the file");
    ObjMesh result;
    TriangleMesh& mesh = result.mesh;
    std::vector<float> uvs, normals;
    struct Corner {
        long long v, vt, vn;
    };
    std::vector<Corner> corners;           // 3 per triangle, resolved 0-based (-1: absent)
    int uvState = -1, normalState = -1;    // -1 unknown, 0 absent, 1 present
    bool normalsMixed = false;
    std::string mtllib;
    std::vector<std::string> usedMaterials;

    Lines lines(in);
    std::string line;
    long long number = 0;
    std::vector<std::string_view> tok;
    std::vector<Corner> polygon;
    auto fail = [&](const std::string& what) -> void {
        std::ostringstream msg;
        msg << path << ":" << number << ": " << what;
        throw ObjReadError(msg.str());
    };
    auto resolve = [&](std::string_view t, std::size_t count, const char* what) -> long long {
        long long i = 0;
        if (!parseInt(t, i)) fail(std::string("malformed ") + what + " index " + quoted(t));
        if (i == 0) fail(std::string(what) + " index 0 (OBJ indices start at 1)");
        const long long resolved = i > 0 ? i - 1 : (long long)count + i;
        if (resolved < 0 || resolved >= (long long)count) {
            std::ostringstream msg;
            msg << what << " index " << i << " out of range: " << count << " " << what << (count == 1 ? "" : "s")
                << " read so far";
            fail(msg.str());
        }
        return resolved;
    };

    while (lines.next(line, number)) {
        splitTokens(line, tok);
        if (tok.empty()) continue;
        const std::string_view key = tok[0];
        if (key == "v") {
            if (tok.size() != 4 && tok.size() != 5 && tok.size() != 7 && tok.size() != 8)
                fail("a vertex needs x y z (optionally w or r g b), got " + std::to_string(tok.size() - 1) + " values");
            float x[3];
            for (int k = 0; k < 3; ++k)
                if (!parseFloat(tok[std::size_t(k) + 1], x[k])) fail("malformed vertex coordinate " + quoted(tok[std::size_t(k) + 1]));
            for (std::size_t k = 4; k < tok.size(); ++k) {
                float ignored;
                if (!parseFloat(tok[k], ignored)) fail("malformed vertex value " + quoted(tok[k]));
            }
            mesh.positions.insert(mesh.positions.end(), x, x + 3);
        } else if (key == "vt") {
            if (tok.size() < 2 || tok.size() > 4)
                fail("a texture coordinate needs u v [w], got " + std::to_string(tok.size() - 1) + " values");
            float u = 0, v = 0, w = 0;
            if (!parseFloat(tok[1], u) || (tok.size() > 2 && !parseFloat(tok[2], v)) || (tok.size() > 3 && !parseFloat(tok[3], w)))
                fail("malformed texture coordinate in " + quoted(line));
            uvs.push_back(u);
            uvs.push_back(v);
        } else if (key == "vn") {
            if (tok.size() != 4) fail("a normal needs x y z, got " + std::to_string(tok.size() - 1) + " values");
            float n[3];
            for (int k = 0; k < 3; ++k)
                if (!parseFloat(tok[std::size_t(k) + 1], n[k])) fail("malformed normal component " + quoted(tok[std::size_t(k) + 1]));
            normals.insert(normals.end(), n, n + 3);
        } else if (key == "f") {
            if (tok.size() < 4) fail("a face needs at least 3 corners, got " + std::to_string(tok.size() - 1));
            polygon.clear();
            for (std::size_t k = 1; k < tok.size(); ++k) {
                const std::string_view c = tok[k];
                const std::size_t s1 = c.find('/');
                const std::size_t s2 = s1 == std::string_view::npos ? s1 : c.find('/', s1 + 1);
                if (s2 != std::string_view::npos && c.find('/', s2 + 1) != std::string_view::npos)
                    fail("malformed face corner " + quoted(c));
                Corner corner{resolve(c.substr(0, s1), mesh.vertexCount(), "vertex"), -1, -1};
                if (s1 != std::string_view::npos) {
                    const std::string_view t = c.substr(s1 + 1, s2 == std::string_view::npos ? std::string_view::npos : s2 - s1 - 1);
                    if (!t.empty()) corner.vt = resolve(t, uvs.size() / 2, "texture coordinate");
                    else if (s2 == std::string_view::npos) fail("malformed face corner " + quoted(c));
                    if (s2 != std::string_view::npos) corner.vn = resolve(c.substr(s2 + 1), normals.size() / 3, "normal");
                }
                const int hasUv = corner.vt >= 0, hasNormal = corner.vn >= 0;
                if (uvState < 0) uvState = hasUv;
                else if (uvState != hasUv)
                    fail("face corner " + quoted(c) + (hasUv ? " has" : " has no") +
                         " texture coordinate, unlike the corners before it (all or none must have one)");
                if (normalState < 0) normalState = hasNormal;
                else if (normalState != hasNormal) normalsMixed = true;
                polygon.push_back(corner);
            }
            for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
                const Corner tri[3] = {polygon[0], polygon[k], polygon[k + 1]};
                for (const Corner& t : tri) corners.push_back(t);
            }
        } else if (key == "mtllib") {
            if (tok.size() < 2) fail("mtllib without a file name");
            if (mtllib.empty()) mtllib = std::string(line.substr(line.find(tok[1])));
            while (!mtllib.empty() && (mtllib.back() == ' ' || mtllib.back() == '\t')) mtllib.pop_back();
        } else if (key == "usemtl") {
            if (tok.size() >= 2) usedMaterials.emplace_back(tok[1]);
        }
        // o, g, s, l, p, and anything else: ignored.
    }
    if (in.bad()) throw ObjReadError(path + ": read error");

    const std::size_t faceCount = corners.size() / 3;
    mesh.faces.resize(corners.size());
    for (std::size_t i = 0; i < corners.size(); ++i) mesh.faces[i] = std::uint32_t(corners[i].v);
    if (uvState == 1) {
        result.wedgeUv.resize(6 * faceCount);
        for (std::size_t i = 0; i < corners.size(); ++i) {
            result.wedgeUv[2 * i] = uvs[2 * std::size_t(corners[i].vt)];
            result.wedgeUv[2 * i + 1] = uvs[2 * std::size_t(corners[i].vt) + 1];
        }
    }
    if (normalState == 1 && !normalsMixed) {
        std::vector<double> sum(mesh.positions.size(), 0.0);
        for (const Corner& c : corners)
            for (int k = 0; k < 3; ++k) sum[3 * std::size_t(c.v) + k] += normals[3 * std::size_t(c.vn) + k];
        mesh.normals.assign(mesh.positions.size(), 0.0f);
        for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
            const double n = std::sqrt(sum[3 * v] * sum[3 * v] + sum[3 * v + 1] * sum[3 * v + 1] + sum[3 * v + 2] * sum[3 * v + 2]);
            if (n > 0)
                for (int k = 0; k < 3; ++k) mesh.normals[3 * v + k] = float(sum[3 * v + k] / n);
        }
    } else if (normalsMixed) {
        result.warnings.push_back("some face corners have normals and some do not: normals ignored");
    }
    if (!mtllib.empty()) {
        const std::string mtlPath = mtllib[0] == '/' ? mtllib : folderOf(path) + mtllib;
        result.textureName = textureOfMtl(mtlPath, usedMaterials, result.warnings);
        if (!result.textureName.empty())
            result.texturePath = result.textureName[0] == '/' ? result.textureName : folderOf(mtlPath) + result.textureName;
    }
    return result;
}

namespace {

// Whole or not at all (io/atomic_file.h): a reader never sees half an OBJ or MTL.
void writeWholeFile(const std::string& path, const std::string& text, const char* what) {
    try {
        writeFileAtomically(path, {{text.data(), text.size()}});
    } catch (const AtomicFileError& e) {
        throw ObjWriteError(std::string("cannot write ") + what + ": " + e.what());
    }
}

}  // namespace

void writeObj(const std::string& path, const TriangleMesh& mesh, const std::vector<float>& wedgeUv,
              const std::string& textureName) {
    const std::string problem = mesh.validate();
    if (!problem.empty()) throw ObjWriteError("cannot write '" + path + "': " + problem);
    if (!wedgeUv.empty() && wedgeUv.size() != 6 * mesh.faceCount())
        throw ObjWriteError("cannot write '" + path + "': " + std::to_string(wedgeUv.size()) +
                            " wedge texture coordinates for " + std::to_string(mesh.faceCount()) + " faces (6 per face)");
    for (const float v : wedgeUv)
        if (!std::isfinite(v)) throw ObjWriteError("cannot write '" + path + "': a texture coordinate is not finite");
    if (textureName.find_first_of("\n\r") != std::string::npos)
        throw ObjWriteError("cannot write '" + path + "': the texture name holds a line break");

    std::string mtlName, mtlPath;
    if (!textureName.empty()) {
        const std::size_t slash = path.find_last_of('/');
        std::string base = path.substr(slash == std::string::npos ? 0 : slash + 1);
        if (base.size() > 4 && (base.compare(base.size() - 4, 4, ".obj") == 0 || base.compare(base.size() - 4, 4, ".OBJ") == 0))
            base.resize(base.size() - 4);
        mtlName = base + ".mtl";
        mtlPath = folderOf(path) + mtlName;
        const std::string mtl = "# written by radiance_tools\nnewmtl material_0\nKa 0.2 0.2 0.2\nKd 1 1 1\nKs 0 0 0\n"
                                "illum 1\nmap_Kd " + textureName + "\n";
        writeWholeFile(mtlPath, mtl, "the material library");
    }

    std::string out;
    out.reserve(mesh.positions.size() * 12 + wedgeUv.size() * 10 + mesh.faces.size() * 16 + 256);
    out += "# written by radiance_tools: " + std::to_string(mesh.vertexCount()) + " vertices, " +
           std::to_string(mesh.faceCount()) + " faces\n";
    if (!mtlName.empty()) out += "mtllib " + mtlName + "\n";
    const bool hasNormals = mesh.hasNormals();
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
        if (hasNormals) {
            out += "vn";
            for (int k = 0; k < 3; ++k) out += ' ', writeShortest(out, mesh.normals[3 * v + k]);
            out += '\n';
        }
        out += 'v';
        for (int k = 0; k < 3; ++k) out += ' ', writeShortest(out, mesh.positions[3 * v + k]);
        out += '\n';
    }
    for (std::size_t i = 0; i < wedgeUv.size(); i += 2) {
        out += "vt ";
        writeShortest(out, wedgeUv[i]);
        out += ' ';
        writeShortest(out, wedgeUv[i + 1]);
        out += '\n';
    }
    if (!mtlName.empty()) out += "usemtl material_0\n";
    for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
        out += 'f';
        for (int k = 0; k < 3; ++k) {
            const std::string v = std::to_string(mesh.faces[3 * f + k] + 1);
            out += ' ';
            out += v;
            if (!wedgeUv.empty()) out += '/' + std::to_string(3 * f + k + 1);
            if (hasNormals) out += (wedgeUv.empty() ? "//" : "/") + v;
        }
        out += '\n';
    }
    writeWholeFile(path, out, "the mesh");
}

}  // namespace rad
