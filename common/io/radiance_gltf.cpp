// Radiance functions in glTF 2.0 (radiance_gltf.h). Binary chunk: POSITION, NORMAL, TANGENT (PB),
// COLOR_0, one view per coefficient attribute, the indices.
#include "io/radiance_gltf.h"

#include "io/glb_container.h"
#include "io/gltf_writer.h"
#include "radiance/material_radiance.h"
#include "radiance/radiance_frame.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace rad {

namespace {

void checkInput(const RadianceMesh& mesh) {
    const std::size_t n = mesh.vertexCount();
    if (!mesh.radiance)
        throw GltfInputError("The mesh has no radiance functions: fit them (Fit Radiance Functions from Rasters) or "
                             "create them (Create Radiance Data from Analytic Material) before exporting.");
    if (n == 0 || mesh.faceCount() == 0)
        throw GltfInputError("The mesh has no faces: the glTF export writes triangles; reconstruct a surface "
                             "(e.g. Screened Poisson) and fit or transfer the radiance onto it first.");
    const std::string why = mesh.radiance->validate();
    if (!why.empty()) throw GltfInputError(why);
    if (mesh.radiance->vertexCount() != n)
        throw GltfInputError("The radiance data has " + std::to_string(mesh.radiance->vertexCount()) +
                             " vertices but the mesh " + std::to_string(n) +
                             ": recompute the radiance on this mesh before exporting.");
    for (std::size_t i = 0; i < mesh.faces.size(); ++i)
        if (mesh.faces[i] >= n)
            throw GltfInputError("Face " + std::to_string(i / 3) + " refers to vertex " + std::to_string(mesh.faces[i]) +
                                 ", beyond the " + std::to_string(n) + " vertices.");
    for (std::size_t i = 0; i < mesh.positions.size(); ++i)
        if (!std::isfinite(mesh.positions[i]))
            throw GltfInputError("Vertex " + std::to_string(i / 3) +
                                 " has a coordinate that is not a finite number; glTF forbids them: remove it first.");
}

struct VertexStreams {
    std::vector<float> normal, tangent, color;
    std::vector<std::vector<float>> coefficients;  // per basis function: 3 floats per vertex
};

// The frame (normal, tangent), the mean colour and the coefficients regrouped per basis function,
// SH signs converted to the 3DGS convention.
VertexStreams vertexStreams(const RadianceField& field) {
    const std::size_t n = field.vertexCount();
    const int k = field.coefficientsPerChannel();
    VertexStreams s;
    s.normal.resize(3 * n);
    if (field.basis.usesLocalFrame()) s.tangent.resize(4 * n);
    s.color.resize(3 * n);
    meanHemisphereColors(field, s.color.data());
    for (float& c : s.color) c = std::clamp(c, 0.0f, 1.0f);
    std::vector<float> sign(k, 1.0f);
    if (!field.basis.usesLocalFrame())
        for (int l = 0; l <= field.basis.degree; ++l)
            for (int m = -l; m <= l; ++m) sign[harmonicIndex(l, m)] = gaussianSplattingShSign(l, m);
    s.coefficients.assign(k, std::vector<float>(3 * n));
    for (std::size_t v = 0; v < n; ++v) {
        const Frame frame = frameFromStored(field.frame(v));
        for (int a = 0; a < 3; ++a) s.normal[3 * v + a] = float(frame.n[a]);
        if (!s.tangent.empty()) {
            for (int a = 0; a < 3; ++a) s.tangent[4 * v + a] = float(frame.t[a]);
            s.tangent[4 * v + 3] = 1.0f;  // frames are right-handed: b = n x t
        }
        for (int c = 0; c < 3; ++c) {
            const float* coefficients = field.channelCoefficients(v, c);
            for (int j = 0; j < k; ++j) s.coefficients[j][3 * v + c] = sign[j] * coefficients[j];
        }
    }
    return s;
}

std::string accessor(std::size_t view, std::size_t count, const char* type, int componentType = 5126) {
    std::ostringstream j;
    j << "{\"bufferView\":" << view << ",\"componentType\":" << componentType << ",\"count\":" << count
      << ",\"type\":\"" << type << "\"";
    return j.str();
}

// The description of the functions, the same in the extension and in extras.
std::string description(const RadianceField& field, const std::vector<std::string>& names) {
    std::ostringstream j;
    j << "{\"basis\":\"" << (field.basis.usesLocalFrame() ? "PB" : "SH") << "\",\"degree\":" << field.basis.degree
      << ",\"coefficientsPerChannel\":" << field.coefficientsPerChannel()
      << ",\"reflected\":" << (field.reflected ? "true" : "false") << ",\"colorSpace\":\"srgb-linear\"";
    if (field.basis.usesLocalFrame())
        j << ",\"frame\":\"local: x = TANGENT.xyz, y = cross(NORMAL, TANGENT.xyz), z = NORMAL\"";
    else
        j << ",\"frame\":\"global\",\"shConvention\":\"3dgs\"";
    j << ",\"hemisphere\":\"NORMAL\",\"borderExtension\":true,\"meanColor\":\"COLOR_0\",\"attributes\":[";
    for (std::size_t i = 0; i < names.size(); ++i) j << (i ? "," : "") << jsonString(names[i]);
    j << "]}";
    return j.str();
}

}  // namespace

std::string radianceGltfAttributeName(const BasisSpec& basis, int index) {
    if (basis.usesLocalFrame()) return "_RF_PB_COEF_" + std::to_string(index);
    int l = 0;
    while ((l + 1) * (l + 1) <= index) ++l;
    return "_RF_SH_DEGREE_" + std::to_string(l) + "_COEF_" + std::to_string(index - l * l);
}

std::vector<unsigned char> buildRadianceGlb(const RadianceMesh& mesh, const RadianceGltfOptions& options) {
    checkInput(mesh);
    const RadianceField& field = *mesh.radiance;
    const std::size_t n = mesh.vertexCount();
    const VertexStreams streams = vertexStreams(field);
    float lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = std::numeric_limits<float>::max();
        hi[a] = -lo[a];
    }
    for (std::size_t v = 0; v < n; ++v)
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], mesh.positions[3 * v + a]);
            hi[a] = std::max(hi[a], mesh.positions[3 * v + a]);
        }

    GlbBinary bin;
    const int k = field.coefficientsPerChannel();
    std::vector<std::string> names(k);
    for (int j = 0; j < k; ++j) names[j] = radianceGltfAttributeName(field.basis, j);
    std::ostringstream attributes, accessors;
    const auto add = [&](const std::string& name, const std::vector<float>& data, const char* type,
                         const std::string& extra = "") {
        // One view per accessor: accessor i reads view i.
        const std::size_t index = bin.addView(data.data(), data.size() * 4, 34962);
        attributes << (index ? "," : "") << jsonString(name) << ":" << index;
        accessors << (index ? "," : "") << accessor(index, n, type) << extra << "}";
    };
    add("POSITION", mesh.positions, "VEC3",
        ",\"min\":[" + jsonNumber(lo[0]) + "," + jsonNumber(lo[1]) + "," + jsonNumber(lo[2]) + "],\"max\":[" +
            jsonNumber(hi[0]) + "," + jsonNumber(hi[1]) + "," + jsonNumber(hi[2]) + "]");
    add("NORMAL", streams.normal, "VEC3");
    if (!streams.tangent.empty()) add("TANGENT", streams.tangent, "VEC4");
    add("COLOR_0", streams.color, "VEC3");
    for (int j = 0; j < k; ++j) add(names[j], streams.coefficients[j], "VEC3");
    const std::size_t indexView = bin.addView(mesh.faces.data(), mesh.faces.size() * 4, 34963);

    const std::string about = description(field, names);
    std::ostringstream j;
    j << "{\"asset\":{\"version\":\"2.0\",\"generator\":" << jsonString(options.generator) << "},";
    j << "\"extensionsUsed\":[\"KHR_materials_unlit\",\"" << kRadianceGltfExtension << "\"],";
    j << "\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0,\"name\":" << jsonString(options.name) << "}],";
    j << "\"meshes\":[{\"name\":" << jsonString(options.name) << ",\"primitives\":[{\"attributes\":{" << attributes.str()
      << "},\"indices\":" << indexView << ",\"material\":0,\"mode\":4,\"extensions\":{\"" << kRadianceGltfExtension
      << "\":" << about << "},\"extras\":{\"radianceFunctions\":" << about << "}}]}],";
    j << "\"accessors\":[" << accessors.str() << "," << accessor(indexView, mesh.faces.size(), "SCALAR", 5125) << "}],";
    j << bin.viewsJson();
    // The RF is outgoing radiance, lighting included: unlit (KHR_materials_unlit), COLOR_0 times a white
    // base colour, so that viewers show the mean colour as it is instead of shading it a second time.
    j << ",\"materials\":[{\"name\":" << jsonString(options.name + " mean colour")
      << ",\"pbrMetallicRoughness\":{\"baseColorFactor\":[1,1,1,1],\"metallicFactor\":0,\"roughnessFactor\":1}"
      << ",\"extensions\":{\"KHR_materials_unlit\":{}}}]}";
    try {
        return assembleGlb(j.str(), bin.bytes(), "simplify the mesh or choose a lower degree before exporting.");
    } catch (const std::length_error& e) {
        throw GltfInputError(e.what());
    }
}

}  // namespace rad
