// The description file of a normal-map bake (<base>_bake.txt, docs/normal-map-baking.md): what
// was baked and where the files are, so that a renderer (the MeshLab decoration) can find the
// LEAN moments and the normal space of a map assigned as a layer's texture. Plus the decoding of
// the normal map itself, shared by the renderer and the tools.
#pragma once
#include "bake/normal_baker.h"

#include <map>
#include <string>
#include <vector>

namespace rad {

struct BakeDescription {
    NormalSpace space = NormalSpace::Object;
    // Tangent-space maps: the frame they were baked in ("tangent_frame"); files without the key
    // predate MikkTSpace and used the per-face frame.
    TangentFrame tangentFrame = TangentFrame::PerFaceUvDerivative;
    int size = 0, bits = 16;
    std::string normalMap, diffuseMap, leanMoments;  // file names, relative to the description's folder
    std::map<std::string, std::string> values;       // every key = value line, as read
};

// Writes `key = value` lines (values in insertion order of `lines`); throws std::runtime_error
// naming the file when it cannot be written.
void writeBakeDescription(const std::string& path, const std::vector<std::pair<std::string, std::string>>& lines);
// Throws std::runtime_error naming the file when it is missing or has no valid space / normal_map.
BakeDescription readBakeDescription(const std::string& path);

// "<dir>/<base>_normal.png" or "_diffuse.png" -> "<dir>/<base>_bake.txt"; empty when the name has
// neither suffix.
std::string bakeDescriptionPathFor(const std::string& mapPath);

// Reads an 8- or 16-bit RGB normal map and decodes it to unit vectors (3 floats per texel, rows
// top to bottom). Throws ImageFileError / std::runtime_error naming the file.
std::vector<float> readNormalMap(const std::string& path, int& width, int& height);

}  // namespace rad
