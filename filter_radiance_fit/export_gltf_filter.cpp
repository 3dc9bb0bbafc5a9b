// "Radiance: Export Radiance Functions as glTF (.glb)": the current layer's radiance functions in a
// glTF 2.0 binary file (io/radiance_gltf.h, docs/gltf-radiance.md). The layers are not changed.
#include "radiance_fit_plugin.h"

#include "citations.h"
#include "mesh_conversion.h"
#include "radiance_attribute.h"

#include "io/atomic_file.h"
#include "io/gltf_writer.h"
#include "io/radiance_gltf.h"

#include <QFileInfo>

namespace radml {
namespace {

class ExportGltfFilter : public Filter {
public:
    QString name() const override { return "Radiance: Export Radiance Functions as glTF (.glb)"; }
    QString pythonName() const override { return "radiance_export_gltf"; }
    QString description() const override {
        return QString(
                   "Writes the current mesh with its radiance functions as a glTF 2.0 binary file (.glb): positions, "
                   "the radiance frame as NORMAL (and TANGENT for the polynomial basis), COLOR_0 = each function's mean "
                   "colour over its hemisphere (what every glTF viewer shows), and the coefficients as the attributes "
                   "_RF_SH_DEGREE_l_COEF_n (spherical harmonics, in the sign convention of 3D Gaussian Splatting) or "
                   "_RF_PB_COEF_k (polynomials), described by the extension RADIANCE_vertex_radiance_functions "
                   "(docs/gltf-radiance.md). View it with <i>python -m pymeshlab_radiance.view FILE.glb</i>. The "
                   "layers are not changed.") +
               kCiteVanhoey2015;
    }
    // Layer ("layers, attributes"): both hosts know it, and pymeshlab refuses Generic.
    int filterClass() const override { return 0x00200; /* Layer */ }
    int postconditions() const override { return MeshModel::MM_NONE; }

    RichParameterList parameters(const MeshDocument&, const MeshModel&) const override {
        RichParameterList par;
        par.addParam(RichString("outputFile", "", "Output file (.glb)",
                                "Path of the glTF binary file to write; its folder must exist. An existing file is "
                                "replaced only once the new one is complete."));
        return par;
    }

    void apply(FilterContext& ctx) const override {
        const std::string path = ctx.parameters.getString("outputFile").trimmed().toStdString();
        checkOutputPath(path);
        rad::RadianceMesh plain = radianceMesh(ctx.mesh().cm);
        ctx.progress(20, "Writing glTF");
        rad::RadianceGltfOptions options;
        options.name = ctx.mesh().label().toStdString();
        // A refusal of either step (GltfInputError, AtomicFileError) reaches the user through runFilter.
        const std::vector<unsigned char> glb = rad::buildRadianceGlb(plain, options);
        rad::writeFileAtomically(path, {{glb.data(), glb.size()}});
        ctx.progress(100, "Done");
        ctx.log(formatLine("Wrote %s radiance of %zu vertices, %zu faces to %s (%.1f MiB)",
                           plain.radiance->basis.name().c_str(), plain.vertexCount(), plain.faceCount(), path.c_str(),
                           double(glb.size()) / (1024.0 * 1024.0)));
    }

private:
    static void checkOutputPath(const std::string& path) {
        if (path.empty()) throw Refusal("Output file: none given; give the path of the .glb file to write.");
        if (QFileInfo(QString::fromStdString(path)).suffix().toLower() != "glb")
            throw Refusal("Output file '" + path + "' does not end in .glb; name the file FILE.glb (a binary glTF).");
        const std::string problem = rad::outputPathProblem(path);
        if (!problem.empty()) throw Refusal(problem);
    }

    // Positions, faces and radiance of the live elements.
    static rad::RadianceMesh radianceMesh(CMeshO& mesh) {
        ExportChoice choice;
        choice.normals = choice.colors = choice.quality = choice.transfer = false;
        rad::RadianceMesh plain;
        std::string why;
        if (!hasRadiance(mesh)) throw Refusal(missingRadianceAdvice());
        if (!exportPlainMesh(mesh, choice, plain, why)) throw Refusal(why);
        if (!plain.radiance) throw Refusal(missingRadianceAdvice());
        return plain;
    }
};

}  // namespace

std::unique_ptr<Filter> makeExportGltfFilter() { return std::make_unique<ExportGltfFilter>(); }

}  // namespace radml
