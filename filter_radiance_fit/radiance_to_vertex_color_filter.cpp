// "Radiance: Evaluate Radiance toward a Viewpoint as Vertex Color": the per-vertex (Gouraud-like)
// evaluation of Vanhoey et al. 2015, sec. 5, with the hemisphere border extension of sec. 7.
#include "radiance_fit_plugin.h"

#include "citations.h"
#include "radiance_attribute.h"
#include "vertex_colors.h"

#include "radiance/view_colors.h"

namespace radml {
namespace {

class RadianceToVertexColorFilter : public Filter {
public:
    QString name() const override { return "Radiance: Evaluate Radiance toward a Viewpoint as Vertex Color"; }
    QString pythonName() const override { return "radiance_evaluate_radiance_toward_a_viewpoint_as_vertex_color"; }
    QString description() const override {
        return QString(
                   "Evaluates every vertex's radiance function toward a viewpoint, L(p, normalize(eye - p)), "
                   "and stores it as the vertex colour (sRGB-encoded, times the exposure). Directions below a "
                   "vertex's tangent plane take the value of the hemisphere's border (Vanhoey et al. 2015, sec. 7, "
                   "'Exceeding hemispheres'). This is per-vertex evaluation, the Gouraud-like mode of sec. 5.") +
               kCiteVanhoey2015;
    }
    int filterClass() const override { return 0x00010; /* VertexColoring */ }
    int postconditions() const override { return MeshModel::MM_VERTCOLOR; }

    RichParameterList parameters(const MeshDocument&, const MeshModel& m) const override {
        RichParameterList par;
        const Box3m& box = m.cm.bbox;
        const Eigen::Vector3d eye =
            box.IsNull() ? Eigen::Vector3d(0, 0, 3)
                         : Eigen::Vector3d(box.Center()[0], box.Center()[1], box.Center()[2] + 2 * box.Diag());
        addPointParameter(par, "viewpoint", eye, "Viewpoint",
                          "Eye position the radiance is evaluated toward (default: in front of the mesh along +Z).");
        par.addParam(RichFloat("exposure", 1.0f, "Exposure", "Linear scale applied before sRGB encoding."));
        return par;
    }

    void apply(FilterContext& ctx) const override {
        rad::RadianceField field;
        std::string why;
        if (!gatherRadiance(ctx.mesh().cm, field, why)) throw Refusal(why);
        const VertexArrays vertices = collectVertexArrays(ctx.mesh().cm);
        const Eigen::Vector3d eye = pointParameter(ctx.parameters, "viewpoint");
        const double eyeArray[3] = {eye[0], eye[1], eye[2]};
        ctx.progress(10, "Evaluating radiance");
        std::vector<float> rgb(vertices.positions.size());
        rad::radianceTowardViewpoint(field, vertices.positions.data(), eyeArray,
                                     float(ctx.parameters.getFloat("exposure")), rgb.data());
        setVertexColorsFromLinear(ctx.mesh(), rgb);
        ctx.progress(100, "Done");
        ctx.log(formatLine("Evaluated %s radiance toward (%g, %g, %g) on %zu vertices", field.basis.name().c_str(),
                           eye[0], eye[1], eye[2], vertices.count()));
    }
};

}  // namespace

std::unique_ptr<Filter> makeRadianceToVertexColorFilter() { return std::make_unique<RadianceToVertexColorFilter>(); }

}  // namespace radml
