#include "bake/bake_description.h"

#include "bake/map_filling.h"
#include "image/image_io.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rad {

namespace {
std::string trimmed(const std::string& s) {
    const auto first = s.find_first_not_of(" \t\r");
    if (first == std::string::npos) return {};
    const auto last = s.find_last_not_of(" \t\r");
    return s.substr(first, last - first + 1);
}

bool endsWith(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}
}  // namespace

void writeBakeDescription(const std::string& path, const std::vector<std::pair<std::string, std::string>>& lines) {
    std::ofstream out(path);
    out << "# Normal-map bake (docs/normal-map-baking.md)\n";
    for (const auto& [key, value] : lines) out << key << " = " << value << '\n';
    out.close();
    if (!out) throw std::runtime_error("cannot write " + path);
}

BakeDescription readBakeDescription(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot read the bake description " + path);
    BakeDescription d;
    std::string line;
    while (std::getline(in, line)) {
        line = trimmed(line);
        if (line.empty() || line[0] == '#') continue;
        const auto equal = line.find('=');
        if (equal == std::string::npos) continue;
        d.values[trimmed(line.substr(0, equal))] = trimmed(line.substr(equal + 1));
    }
    const auto value = [&](const char* key) {
        const auto it = d.values.find(key);
        return it == d.values.end() ? std::string() : it->second;
    };
    const std::string space = value("space");
    if (space != "object" && space != "tangent")
        throw std::runtime_error(path + ": 'space' must be object or tangent (is it a bake description?)");
    d.space = space == "object" ? NormalSpace::Object : NormalSpace::Tangent;
    const std::string frame = value("tangent_frame");
    if (frame == "mikktspace") d.tangentFrame = TangentFrame::MikkTSpace;
    else if (frame.empty() || frame == "per-face-dpdu") d.tangentFrame = TangentFrame::PerFaceUvDerivative;
    else throw std::runtime_error(path + ": 'tangent_frame' must be mikktspace or per-face-dpdu, not '" + frame + "'");
    d.normalMap = value("normal_map");
    if (d.normalMap.empty()) throw std::runtime_error(path + ": no normal_map line");
    d.diffuseMap = value("diffuse_map");
    d.leanMoments = value("lean_moments");
    try {
        d.size = std::stoi(value("size"));
        d.bits = std::stoi(value("bits"));
    } catch (const std::exception&) {
        throw std::runtime_error(path + ": 'size' and 'bits' must be integers");
    }
    return d;
}

std::string bakeDescriptionPathFor(const std::string& mapPath) {
    for (const char* suffix : {"_normal.png", "_diffuse.png"})
        if (endsWith(mapPath, suffix)) return mapPath.substr(0, mapPath.size() - std::string(suffix).size()) + "_bake.txt";
    return {};
}

std::vector<float> readNormalMap(const std::string& path, int& width, int& height) {
    int channels = 0;
    const std::vector<std::uint16_t> codes = readPng16(path, width, height, channels);
    if (channels < 3) throw std::runtime_error(path + ": a normal map needs RGB channels");
    std::vector<float> normals(std::size_t(width) * height * 3);
    for (std::size_t t = 0; t < std::size_t(width) * height; ++t)
        for (int k = 0; k < 3; ++k) normals[3 * t + k] = decodeNormal16(codes[t * channels + k]);
    normalizeTexelVectors(normals.data(), normals.size() / 3);
    return normals;
}

}  // namespace rad
