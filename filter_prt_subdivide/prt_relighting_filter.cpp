// "Radiance: PRT Relighting as Vertex Color": every vertex shaded from its PRT transfer vector,
// L = <t, l> (Sloan et al. 2002), under an HDR environment map or a directional light
// (common/prt/prt_lighting.h).
#include "prt_subdivide_plugin.h"

#include "citations.h"
#include "prt_subdivision_common.h"
#include "transfer_attribute.h"

#include "lighting/environment_map.h"
#include "prt/prt_lighting.h"

#include <cmath>

namespace radml {
namespace {

enum LightingChoice { kLightEnvironment = 0, kLightDirectional = 1 };

class PrtRelightingFilter : public Filter {
public:
    QString name() const override { return "Radiance: PRT Relighting as Vertex Color"; }
    QString pythonName() const override { return "radiance_prt_relighting_as_vertex_color"; }
    QString description() const override {
        return QString(
                   "Shades every vertex from its PRT transfer vector, L = &lt;t, l&gt; (Sloan et al. 2002), under a "
                   "distant lighting: an HDR environment map (equirectangular .exr or .hdr, projected onto "
                   "spherical harmonics) or a directional light (its SH projection "
                   "smoothed by a Hanning window so that it does not ring, Sloan 2008); either is scaled by the "
                   "intensity and turned about the up axis by the rotation. Vertex colour = exposure "
                   "times L, sRGB-encoded; vertex quality = the luminance of L.") +
               kCiteSloan2002Krivanek2004;
    }
    int filterClass() const override { return 0x00010; /* VertexColoring */ }
    int postconditions() const override { return MeshModel::MM_VERTCOLOR | MeshModel::MM_VERTQUALITY; }

    RichParameterList parameters(const MeshDocument&, const MeshModel&) const override {
        RichParameterList par;
        par.addParam(RichEnum("lighting", kLightDirectional,
                              QStringList() << "HDR environment map" << "Directional light", "Lighting",
                              "An equirectangular HDR map (.exr, .hdr) or a directional light."));
        par.addParam(RichString("environmentMap", "", "Environment map file",
                                "Path of the equirectangular .exr or .hdr map (for the environment lighting)."));
        par.addParam(RichFloat("rotation", 0.0f, "Rotation (degrees)",
                               "Turns the light (environment map or directional light) about the up axis."));
        // One axis list, in the core's order, shared with the decoration (prt/prt_lighting.h).
        QStringList axes;
        for (const char* axis : rad::kUpAxisNames) axes << axis;
        par.addParam(RichEnum("upAxis", static_cast<int>(rad::UpAxis::Z), axes, "Up axis",
                              "The mesh's up direction: the map's zenith is put there, and the light turns about it."));
        addDirectionParameter(par, "lightDirection", Eigen::Vector3d(0.5, 0.5, 1.0), "Direction toward the light",
                              "For the directional light, in the mesh's coordinates (before the rotation).");
        par.addParam(RichFloat("lightIntensity", 3.0f, "Light intensity",
                               "Scale of the light (linear units): the directional light's irradiance at normal "
                               "incidence, or the factor on the environment map's radiance."));
        par.addParam(RichFloat("exposure", 1.0f, "Exposure", "Linear scale applied before sRGB encoding."));
        return par;
    }

    void apply(FilterContext& ctx) const override {
        const RichParameterList& par = ctx.parameters;
        StoredTransfer stored;
        std::string why;
        if (!gatherTransfer(ctx.mesh().cm, stored, why)) throw Refusal(why);
        const int degree = stored.field.degree;
        const float exposure = par.getFloat("exposure");
        if (!(exposure >= 0.0f) || !std::isfinite(exposure))
            throw Refusal("The exposure must be a finite number >= 0.");
        // The one PRT lighting of the filter and the decoration; the core validates every value.
        rad::PrtLightingSettings settings;
        settings.source = par.getEnum("lighting") == kLightEnvironment ? rad::PrtLightSource::EnvironmentMap
                                                                        : rad::PrtLightSource::Directional;
        settings.upAxis = static_cast<rad::UpAxis>(par.getEnum("upAxis"));
        settings.rotationDegrees = par.getFloat("rotation");
        settings.intensity = par.getFloat("lightIntensity");
        settings.direction = pointParameter(par, "lightDirection");
        settings.degree = degree;
        std::vector<double> lighting;
        std::string description;
        if (settings.source == rad::PrtLightSource::EnvironmentMap) {
            const QString path = par.getString("environmentMap").trimmed();
            if (path.isEmpty()) throw Refusal("Choose an environment map file (.exr or .hdr), or the directional light.");
            ctx.progress(10, "Reading the environment map");
            const rad::EnvironmentMap map = rad::readEnvironmentMap(path.toStdString());
            lighting = rad::prtLightingSH(settings, &map);
            description = formatLine("environment map %s (%d x %d)", qUtf8Printable(path), map.width(), map.height());
        } else {
            lighting = rad::prtLightingSH(settings);
            description = formatLine("directional light toward (%g, %g, %g)", settings.direction.x(),
                                     settings.direction.y(), settings.direction.z());
        }
        description += formatLine(", intensity %g, rotated %g degrees about %s", settings.intensity,
                                  settings.rotationDegrees, rad::kUpAxisNames[static_cast<int>(settings.upAxis)]);
        const std::size_t n = stored.field.vertexCount();
        const std::vector<float> rgb =
            rad::relightVertices(stored.field.values.data(), n, degree, stored.field.channels, lighting, degree);
        setShading(ctx.mesh(), rgb, exposure);
        ctx.progress(100, "Done");
        ctx.log(formatLine("Relit %zu vertices from SH order %d transfer (Sloan et al. 2002) under the %s", n,
                           degree + 1, description.c_str()));
    }
};

}  // namespace

std::unique_ptr<Filter> makePrtRelightingFilter() { return std::make_unique<PrtRelightingFilter>(); }

}  // namespace radml
