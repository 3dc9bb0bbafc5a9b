// "Radiance: Create Radiance Data from Analytic Material": per-vertex radiance functions of a known
// material and light (common/radiance/material_radiance.h), for tests, figures and demonstrations.
#include "radiance_fit_plugin.h"

#include "basis_parameters.h"
#include "citations.h"
#include "radiance_attribute.h"
#include "usable_normals.h"
#include "vertex_colors.h"

#include "radiance/material_radiance.h"
#include "radiance/view_colors.h"

#include <QElapsedTimer>

#include <cmath>

namespace radml {
namespace {

void materialFromParameters(const RichParameterList& par, const Box3m& box, rad::AnalyticMaterial& material,
                            rad::AnalyticLighting& lighting) {
    const auto albedo = linearColorParameter(par, "albedo");
    const auto specularColor = linearColorParameter(par, "specularColor");
    const float specular = par.getFloat("specular");
    const float shininess = par.getFloat("shininess");
    const float intensity = par.getFloat("lightIntensity");
    const float ambient = par.getFloat("ambient");
    // (The core checks the values: rad::checkAnalyticSetup, called by apply.)
    material.albedo = rad::Rgb(albedo[0], albedo[1], albedo[2]);
    material.specular = specular * rad::Rgb(specularColor[0], specularColor[1], specularColor[2]);
    material.exponent = shininess;
    const int stripes = par.getInt("stripes");
    if (stripes < 0 || stripes > 10000) throw Refusal("Stripes must be between 0 (uniform material) and 10000.");
    if (stripes > 0) {
        const int axisIndex = par.getEnum("stripeAxis");
        Eigen::Vector3d axis = Eigen::Vector3d::Zero();
        axis[axisIndex] = 1.0;
        const double lo = box.IsNull() ? -1.0 : box.min[axisIndex];
        const double hi = box.IsNull() ? 1.0 : box.max[axisIndex];
        material.stripes = rad::StripePattern::covering(axis, lo, hi + 1e-6 * std::max(1.0, hi - lo), stripes);
    }
    const Eigen::Vector3d light = pointParameter(par, "light");
    if (par.getEnum("lightType") == 0) {
        rad::DirectionalLight directional;
        directional.direction = light;  // normalised on use
        directional.irradiance = rad::Rgb::Constant(intensity);
        lighting.directional.push_back(directional);
    } else {
        rad::PointLight point;
        point.position = light;
        point.intensity = rad::Rgb::Constant(intensity);
        lighting.points.push_back(point);
    }
    lighting.ambient = rad::Rgb::Constant(ambient);
}

class CreateAnalyticRadianceFilter : public Filter {
public:
    QString name() const override { return "Radiance: Create Radiance Data from Analytic Material"; }
    QString pythonName() const override { return "radiance_create_radiance_data_from_analytic_material"; }
    QString description() const override {
        return QString(
                   "Creates a view-dependent radiance function (RF) on every vertex of the current mesh: the "
                   "outgoing radiance of an analytic material (Lambert albedo plus a normalized Blinn-Phong "
                   "glossy lobe, optionally in alternating diffuse / specular stripes as in Vanhoey et al. 2015, "
                   "Fig. 8) under a directional or point light, projected onto hemispherical polynomials "
                   "PB(d) in each vertex's tangent frame or onto spherical harmonics SH(d) in the global "
                   "frame (Vanhoey et al. 2015, sec. 6). No shadows are cast. Colours are linear; the vertex "
                   "colour is set to the RF's mean over the hemisphere, sRGB-encoded. The data is saved with "
                   "the mesh in the Radiance PLY format (.rply). Uses the current vertex normals: recompute "
                   "them first if they are missing.") +
               kCiteVanhoey2015;
    }
    int filterClass() const override { return 0x00010; /* VertexColoring */ }
    int postconditions() const override { return MeshModel::MM_VERTCOLOR; }

    RichParameterList parameters(const MeshDocument&, const MeshModel&) const override {
        RichParameterList par;
        addBasisParameters(par, "Vanhoey et al. 2015 use PB(4) and SH(6), SH(8).");
        par.addParam(RichBool("reflected", false, "Store reflected functions",
                              "Store the reflected RF L~(w) = L(R_n w) (Vanhoey et al. 2015, sec. 3.1) instead "
                              "of L. Either evaluates to the same radiance."));
        par.addParam(RichColor("albedo", QColor(230, 60, 40), "Diffuse albedo",
                               "Lambertian albedo (the colour is read as sRGB and used linear)."));
        par.addParam(RichColor("specularColor", QColor(255, 255, 255), "Specular colour",
                               "Colour of the glossy lobe."));
        par.addParam(RichFloat("specular", 0.5f, "Specular strength",
                               "Scale of the glossy lobe (0 = purely diffuse), times the specular colour."));
        par.addParam(RichFloat("shininess", 40.0f, "Shininess",
                               "Blinn-Phong exponent of the glossy lobe (energy-normalized)."));
        par.addParam(RichInt("stripes", 0, "Stripes",
                             "0: uniform material. N > 0: N bands along the axis over the mesh's bounding box, "
                             "alternating diffuse-only and diffuse + specular (Vanhoey et al. 2015, Fig. 8)."));
        par.addParam(RichEnum("stripeAxis", 1, QStringList() << "X" << "Y" << "Z", "Stripe axis",
                              "Axis along which the stripes alternate."));
        par.addParam(RichEnum("lightType", 0, QStringList() << "Directional" << "Point", "Light",
                              "Directional light (the vector is the direction toward the light) or point light "
                              "(the vector is its position; inverse-square falloff)."));
        addPointParameter(par, "light", Eigen::Vector3d(0.5, 1.0, 1.0), "Light vector",
                          "Direction toward the light, or the point light's position.");
        par.addParam(RichFloat("lightIntensity", 3.0f, "Light intensity",
                               "Irradiance of the directional light at normal incidence, or the point light's "
                               "intensity (linear units)."));
        par.addParam(RichFloat("ambient", 0.05f, "Ambient", "Constant ambient radiance added to the diffuse term."));
        par.addParam(RichBool("setColor", true, "Set vertex colour to the mean colour",
                              "Vertex colour := the RF's mean over its hemisphere (sRGB-encoded)."));
        return par;
    }

    void apply(FilterContext& ctx) const override {
        const RichParameterList& par = ctx.parameters;
        MeshModel& m = ctx.mesh();
        QElapsedTimer timer;
        timer.start();
        rad::MaterialRadianceOptions options;
        options.basis = basisParameters(par);
        options.reflected = par.getBool("reflected");
        VertexArrays vertices = collectVertexArrays(m.cm);
        makeNormalsUsable(ctx, vertices.positions, vertices.faces, vertices.normals);
        const std::size_t n = vertices.count();
        const std::string inputProblem =
            rad::checkMaterialRadianceInput(vertices.positions.data(), vertices.normals.data(), n, options);
        if (!inputProblem.empty()) throw Refusal(inputProblem);

        rad::AnalyticMaterial material;
        rad::AnalyticLighting lighting;
        materialFromParameters(par, m.cm.bbox, material, lighting);
        if (const std::string problem = rad::checkAnalyticSetup(material, lighting); !problem.empty())
            throw Refusal(problem);

        // Everything is computed aside; the layer changes only once all of it succeeded.
        ctx.progress.setPhase(0, 90, "Projecting radiance onto the basis");
        rad::RadianceField field = rad::makeMaterialRadiance(vertices.positions.data(), vertices.normals.data(), n,
                                                             material, lighting, options, ctx.progress.forCore());
        const bool setColor = par.getBool("setColor");
        std::vector<float> meanColors;
        if (setColor) {
            meanColors.resize(3 * n);
            rad::meanHemisphereColors(field, meanColors.data());
        }
        attachRadiance(m.cm, std::move(field));
        if (setColor) setVertexColorsFromLinear(m, meanColors);
        ctx.progress.setPhase(100, 100, "Done");
        ctx.log(formatLine("Created %s radiance functions%s on %zu vertices (%d floats per vertex, %.1f MB) in %.2f s",
                           options.basis.name().c_str(), options.reflected ? " (reflected)" : "", n,
                           3 * options.basis.coefficientCount(),
                           double(n) * 3 * options.basis.coefficientCount() * sizeof(float) / 1e6,
                           timer.elapsed() / 1000.0));
    }
};

}  // namespace

std::unique_ptr<Filter> makeCreateAnalyticRadianceFilter() { return std::make_unique<CreateAnalyticRadianceFilter>(); }

}  // namespace radml
