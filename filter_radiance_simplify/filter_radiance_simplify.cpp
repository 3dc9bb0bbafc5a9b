#include "filter_radiance_simplify.h"

#include "radiance_attribute.h"

#include "radiance/material_radiance.h"
#include "radiance/view_colors.h"

#include <QElapsedTimer>

#include <cmath>
#include <vector>

namespace {

const char* kCitation =
    "<br><br>Radiance functions as in <i>K. Vanhoey, B. Sauvage, P. Kraemer, F. Larue, J.-M. Dischler</i>, "
    "<b>\"Simplification of meshes with digitized radiance\"</b>, The Visual Computer 31 (2015).";

// Positions and normals of the live vertices as flat arrays; false with a message when unusable.
bool collectVertices(CMeshO& mesh, std::vector<float>& positions, std::vector<float>& normals, QString& why) {
    positions.clear();
    normals.clear();
    positions.reserve(3 * static_cast<std::size_t>(mesh.vn));
    normals.reserve(3 * static_cast<std::size_t>(mesh.vn));
    for (const CVertexO& v : mesh.vert) {
        if (v.IsD()) continue;
        for (int k = 0; k < 3; ++k) {
            positions.push_back(v.cP()[k]);
            normals.push_back(v.cN()[k]);
        }
    }
    if (positions.empty()) {
        why = "The current mesh has no vertices.";
        return false;
    }
    return true;
}

// Returns a colour parameter as linear RGB in [0, 1] (the dialog shows sRGB colours).
std::array<float, 3> linearColor(const RichParameterList& par, const char* name) {
    const QColor c = par.getColor(name);
    auto decode = [](double s) {
        return static_cast<float>(s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4));
    };
    return {decode(c.redF()), decode(c.greenF()), decode(c.blueF())};
}

// Vertex colours of the live vertices from linear RGB (3 floats per live vertex), sRGB-encoded.
void setVertexColors(MeshModel& m, const std::vector<float>& linearRgb) {
    std::size_t i = 0;
    for (CVertexO& v : m.cm.vert) {
        if (v.IsD()) continue;
        v.C() = vcg::Color4b(rad::encodeSrgb8(linearRgb[3 * i]), rad::encodeSrgb8(linearRgb[3 * i + 1]),
                             rad::encodeSrgb8(linearRgb[3 * i + 2]), 255);
        ++i;
    }
    m.updateDataMask(MeshModel::MM_VERTCOLOR);
}

bool materialFromParameters(const RichParameterList& par, const Box3m& box, rad::AnalyticMaterial& material,
                            rad::AnalyticLighting& lighting, QString& why) {
    const auto albedo = linearColor(par, "albedo");
    const auto specularColor = linearColor(par, "specularColor");
    const float specular = par.getFloat("specular");
    const float shininess = par.getFloat("shininess");
    const float intensity = par.getFloat("lightIntensity");
    const float ambient = par.getFloat("ambient");
    if (!(specular >= 0.0f) || !(shininess >= 0.0f) || !(intensity >= 0.0f) || !(ambient >= 0.0f) ||
        !std::isfinite(specular) || !std::isfinite(shininess) || !std::isfinite(intensity) || !std::isfinite(ambient)) {
        why = "Specular strength, shininess, light intensity and ambient must be finite and >= 0.";
        return false;
    }
    material.albedo = rad::Rgb(albedo[0], albedo[1], albedo[2]);
    material.specular = specular * rad::Rgb(specularColor[0], specularColor[1], specularColor[2]);
    material.exponent = shininess;
    const int stripes = par.getInt("stripes");
    if (stripes < 0 || stripes > 10000) {
        why = "Stripes must be between 0 (uniform material) and 10000.";
        return false;
    }
    if (stripes > 0) {
        const int axisIndex = par.getEnum("stripeAxis");
        Eigen::Vector3d axis = Eigen::Vector3d::Zero();
        axis[axisIndex] = 1.0;
        const double lo = box.IsNull() ? -1.0 : box.min[axisIndex];
        const double hi = box.IsNull() ? 1.0 : box.max[axisIndex];
        material.stripes = rad::StripePattern::covering(axis, lo, hi + 1e-6 * std::max(1.0, hi - lo), stripes);
    }
    const vcg::Point3f lightVector = par.getPoint3f("light");
    const Eigen::Vector3d light(lightVector[0], lightVector[1], lightVector[2]);
    if (!light.allFinite()) {
        why = "The light vector must be finite.";
        return false;
    }
    if (par.getEnum("lightType") == 0) {
        if (light.norm() < 1e-12) {
            why = "The direction toward a directional light cannot be the zero vector.";
            return false;
        }
        rad::DirectionalLight directional;
        directional.direction = light.normalized();
        directional.irradiance = rad::Rgb::Constant(intensity);
        lighting.directional.push_back(directional);
    } else {
        rad::PointLight point;
        point.position = light;
        point.intensity = rad::Rgb::Constant(intensity);
        lighting.points.push_back(point);
    }
    lighting.ambient = rad::Rgb::Constant(ambient);
    return true;
}

}  // namespace

RadianceFilterPlugin::RadianceFilterPlugin() {
    typeList << FP_FIT_FROM_RASTERS << FP_RADIANCE_SIMPLIFICATION << FP_CREATE_ANALYTIC_RADIANCE
             << FP_RADIANCE_TO_VERTEX_COLOR;
    for (FilterIDType id : types()) actionList << new QAction(filterName(id), this);
}

QString RadianceFilterPlugin::filterName(FilterIDType filter) const {
    switch (filter) {
        case FP_CREATE_ANALYTIC_RADIANCE: return "Radiance: Create Radiance Data from Analytic Material";
        case FP_RADIANCE_TO_VERTEX_COLOR: return "Radiance: Evaluate Radiance toward a Viewpoint as Vertex Color";
        case FP_FIT_FROM_RASTERS: return "Radiance: Fit Radiance Functions from Rasters";
        case FP_RADIANCE_SIMPLIFICATION: return "Radiance: Radiance-Aware Simplification";
    }
    return {};
}

QString RadianceFilterPlugin::filterInfo(FilterIDType filter) const {
    switch (filter) {
        case FP_CREATE_ANALYTIC_RADIANCE:
            return QString(
                       "Creates a view-dependent radiance function (RF) on every vertex of the current mesh: the "
                       "outgoing radiance of an analytic material (Lambert albedo plus a normalized Blinn-Phong "
                       "glossy lobe, optionally in alternating diffuse / specular stripes as in Fig. 8 of the "
                       "paper) under a directional or point light, projected onto hemispherical polynomials "
                       "PB(d) in each vertex's tangent frame or onto spherical harmonics SH(d) in the global "
                       "frame (sec. 6). No shadows are cast. Colours are linear; the vertex colour is set to "
                       "the RF's mean over the hemisphere, sRGB-encoded. The data is saved with the mesh in the "
                       "Radiance PLY format (.rply). Uses the current vertex normals: recompute them first if "
                       "they are missing.") +
                   kCitation;
        case FP_RADIANCE_TO_VERTEX_COLOR:
            return QString(
                       "Evaluates every vertex's radiance function toward a viewpoint, L(p, normalize(eye - p)), "
                       "and stores it as the vertex colour (sRGB-encoded, times the exposure). Directions below a "
                       "vertex's tangent plane take the value of the hemisphere's border (sec. 7, 'Exceeding "
                       "hemispheres'). This is per-vertex evaluation, the Gouraud-like mode of sec. 5.") +
                   kCitation;
        case FP_FIT_FROM_RASTERS:
            return QString(
                       "Fits a view-dependent radiance function (RF) to every vertex of the current mesh from the "
                       "calibrated photographs of the document's raster layers (open them with File > Import "
                       "Raster or a project: .mlp, Bundler .out), keeping the view dependence (highlights, gloss) "
                       "that <i>Project active rasters color to current mesh</i> averages away (paper 000 sec. 7, "
                       "'Data acquisition and reconstruction').<br>"
                       "A photograph contributes a sample to a vertex only where the vertex is in front of its "
                       "camera, projects inside the image (minus the border margin), faces the camera within the "
                       "grazing-angle cut-off, and is not hidden by any part of the mesh (an Embree ray cast from "
                       "the vertex toward the camera, ignoring hits closer than the depth tolerance). Pixels are "
                       "read with bilinear interpolation and decoded from sRGB to linear radiance.<br>"
                       "Each vertex's samples are fitted by weighted least squares (weight = cosine of the viewing "
                       "angle) in PB(d) (local frame) or SH(d) (global frame), with a Tikhonov regularisation "
                       "toward the vertex's mean colour. Against overshooting on poorly sampled vertices (few or "
                       "clustered directions; after Vanhoey et al., 'Robust Fitting on Poorly Sampled Data for "
                       "Surface Light Field Rendering and Image Relighting', CGF 2013) the hemisphere directions "
                       "no photograph covers receive virtual samples of the mean colour, and a fit that leaves "
                       "the range of the vertex's observed colours is regularised further, down to the constant "
                       "mean colour. Vertices with fewer samples than the minimum get their mean colour as a "
                       "constant RF; vertices no photograph sees are filled from their neighbours.<br>"
                       "Output: the radiance data (save as .rply), the vertex colour = the mean (diffuse) colour, "
                       "the vertex quality = sample count or fit residual. Cameras with lens distortion are "
                       "skipped (undistort the photographs first); the images must have the cameras' size.") +
                   kCitation;
        case FP_RADIANCE_SIMPLIFICATION:
            return QString(
                       "Simplifies the current mesh by iterative edge collapse so that what is rendered stays close "
                       "to the original (paper 000 sec. 4). A collapse costs w_G E_G + w_R E, with E_G the "
                       "memoryless quadric error (planes of the faces around the edge) and E the radiance error of "
                       "eq. 7: for a half-edge collapse v0 -> v1, the sum over the new triangles of their area times "
                       "the squared L2 distance, over v0's hemisphere, between v0's reflected radiance function and "
                       "the function the triangle extrapolates to v0's position (eq. 4-6); for a full edge collapse "
                       "the new vertex sits at the QEM-optimal position with its function interpolated along the "
                       "edge, and the error is summed at both old positions (sec. 4.3; spherical harmonics only). "
                       "Default weights 1 % / 99 % as in sec. 4.4. Baselines in the same engine: the 2010 "
                       "light-field quadric (paper 003), the extended colour QEM of Garland and Heckbert (1998) on "
                       "the functions' mean colours, and geometry alone.<br>"
                       "Collapses keep the surface a 2-manifold (link condition), never flip a face, optionally "
                       "keep the boundary and valences within bounds. The whole collapse sequence is recorded "
                       "(progressive mesh, sec. 4.5): extra levels of detail become new layers, and the sequence "
                       "can be saved as a .rpm file and replayed with the simplify_radiance tool. The mesh must be "
                       "a clean 2-manifold triangle mesh (no duplicate or zero-area faces, no non-manifold edges); "
                       "the filter says which cleaning filter to run otherwise.") +
                   kCitation;
    }
    return {};
}

MeshFilterInterface::FilterClass RadianceFilterPlugin::getClass(QAction* action) {
    if (ID(action) == FP_RADIANCE_SIMPLIFICATION) return MeshFilterInterface::Remeshing;
    if (ID(action) == FP_FIT_FROM_RASTERS)
        return FilterClass(MeshFilterInterface::VertexColoring | MeshFilterInterface::Camera |
                           MeshFilterInterface::RasterLayer);
    return MeshFilterInterface::VertexColoring;
}

int RadianceFilterPlugin::getPreConditions(QAction*) const { return MeshModel::MM_NONE; }

int RadianceFilterPlugin::postCondition(QAction* action) const {
    if (ID(action) == FP_FIT_FROM_RASTERS) return MeshModel::MM_VERTCOLOR | MeshModel::MM_VERTQUALITY;
    if (ID(action) == FP_RADIANCE_SIMPLIFICATION) return MeshModel::MM_GEOMETRY_AND_TOPOLOGY_CHANGE;
    return MeshModel::MM_VERTCOLOR;
}

void RadianceFilterPlugin::initParameterSet(QAction* action, MeshModel& m, RichParameterList& par) {
    switch (ID(action)) {
        case FP_FIT_FROM_RASTERS: addFitParameters(m, par); break;
        case FP_RADIANCE_SIMPLIFICATION: addSimplifyParameters(m, par); break;
        case FP_CREATE_ANALYTIC_RADIANCE:
            par.addParam(RichEnum("basis", 0,
                                  QStringList() << "Hemispherical polynomials PB(d), local frame"
                                                << "Spherical harmonics SH(d), global frame",
                                  "Basis", "Function basis of the radiance functions (paper 000 sec. 6)."));
            par.addParam(RichInt("degree", 4, "Degree",
                                 QString("Degree d: PB(d) has (d+1)(d+2)/2 coefficients per channel (1..%1), SH(d) "
                                         "has (d+1)^2 (0..%2). The paper uses PB(4) and SH(6), SH(8).")
                                     .arg(rad::kMaxPolynomialDegree)
                                     .arg(rad::kMaxHarmonicDegree)));
            par.addParam(RichBool("reflected", false, "Store reflected functions",
                                  "Store the reflected RF L~(w) = L(R_n w) (sec. 3.1) instead of L. Either "
                                  "evaluates to the same radiance."));
            par.addParam(RichColor("albedo", QColor(230, 60, 40), "Diffuse albedo",
                                   "Lambertian albedo (the colour is read as sRGB and used linear)."));
            par.addParam(RichColor("specularColor", QColor(255, 255, 255), "Specular colour",
                                   "Colour of the glossy lobe."));
            par.addParam(RichFloat("specular", 0.5f, "Specular strength",
                                   "Scale of the glossy lobe (0 = purely diffuse), times the specular colour."));
            par.addParam(RichFloat("shininess", 40.0f, "Shininess",
                                   "Blinn-Phong exponent of the glossy lobe (energy-normalized)."));
            par.addParam(RichInt("stripes", 0, "Stripes",
                                 "0: uniform material. N > 0: N bands along the axis over the mesh's bounding "
                                 "box, alternating diffuse-only and diffuse + specular (paper 000 Fig. 8)."));
            par.addParam(RichEnum("stripeAxis", 1, QStringList() << "X" << "Y" << "Z", "Stripe axis",
                                  "Axis along which the stripes alternate."));
            par.addParam(RichEnum("lightType", 0, QStringList() << "Directional" << "Point", "Light",
                                  "Directional light (the vector is the direction toward the light) or point "
                                  "light (the vector is its position; inverse-square falloff)."));
            par.addParam(RichPoint3f("light", vcg::Point3f(0.5f, 1.0f, 1.0f), "Light vector",
                                     "Direction toward the light, or the point light's position."));
            par.addParam(RichFloat("lightIntensity", 3.0f, "Light intensity",
                                   "Irradiance of the directional light at normal incidence, or the point "
                                   "light's intensity (linear units)."));
            par.addParam(RichFloat("ambient", 0.05f, "Ambient", "Constant ambient radiance added to the diffuse term."));
            par.addParam(RichBool("setColor", true, "Set vertex colour to the mean colour",
                                  "Vertex colour := the RF's mean over its hemisphere (sRGB-encoded)."));
            break;
        case FP_RADIANCE_TO_VERTEX_COLOR: {
            const Box3m& box = m.cm.bbox;
            const vcg::Point3f eye = box.IsNull() ? vcg::Point3f(0, 0, 3)
                                                  : vcg::Point3f(box.Center() + Point3m(0, 0, 2 * box.Diag()));
            par.addParam(RichPoint3f("viewpoint", eye, "Viewpoint",
                                     "Eye position the radiance is evaluated toward (default: in front of the "
                                     "mesh along +Z)."));
            par.addParam(RichFloat("exposure", 1.0f, "Exposure", "Linear scale applied before sRGB encoding."));
            break;
        }
        default: break;
    }
}

bool RadianceFilterPlugin::applyFilter(QAction* action, MeshDocument& md, const RichParameterList& par,
                                       vcg::CallBackPos* cb) {
    MeshModel* m = md.mm();
    if (m == nullptr) {
        errorMessage = "There is no current mesh.";
        return false;
    }
    bool ok = false;
    errorMessage.clear();
    try {
        switch (ID(action)) {
            case FP_CREATE_ANALYTIC_RADIANCE: ok = createAnalyticRadiance(*m, par, cb); break;
            case FP_RADIANCE_TO_VERTEX_COLOR: ok = radianceToVertexColor(*m, par, cb); break;
            case FP_FIT_FROM_RASTERS: ok = fitFromRasters(md, *m, par, cb); break;
            case FP_RADIANCE_SIMPLIFICATION: ok = simplifyRadiance(md, *m, par, cb); break;
            default: errorMessage = "Unknown filter."; break;
        }
    } catch (const std::bad_alloc&) {
        errorMessage = "Out of memory: the radiance data of this mesh does not fit; choose a lower degree.";
    } catch (const std::exception& e) {
        errorMessage = QString("Internal error: %1").arg(e.what());
    }
    // The GUI shows errorMessage in a dialog; meshlabserver only prints the log, so log it too.
    if (!ok) Log(GLLogStream::WARNING, qUtf8Printable(filterName(ID(action)) + ": " + errorMessage));
    return ok;
}

bool RadianceFilterPlugin::createAnalyticRadiance(MeshModel& m, const RichParameterList& par, vcg::CallBackPos* cb) {
    QElapsedTimer timer;
    timer.start();
    rad::MaterialRadianceOptions options;
    options.basis.kind = par.getEnum("basis") == 0 ? rad::BasisKind::HemisphericalPolynomial
                                                   : rad::BasisKind::SphericalHarmonics;
    options.basis.degree = par.getInt("degree");
    options.reflected = par.getBool("reflected");
    if (!options.basis.isValid()) {
        errorMessage = QString("Degree %1 is not supported for %2: use PB degrees 0..%3 or SH degrees 0..%4.")
                           .arg(options.basis.degree)
                           .arg(options.basis.kind == rad::BasisKind::SphericalHarmonics ? "SH" : "PB")
                           .arg(rad::kMaxPolynomialDegree)
                           .arg(rad::kMaxHarmonicDegree);
        return false;
    }

    std::vector<float> positions, normals;
    QString why;
    if (!collectVertices(m.cm, positions, normals, why)) {
        errorMessage = why;
        return false;
    }
    const std::size_t n = positions.size() / 3;
    const std::string inputProblem = rad::checkMaterialRadianceInput(positions.data(), normals.data(), n, options);
    if (!inputProblem.empty()) {
        errorMessage = QString::fromStdString(inputProblem);
        return false;
    }

    rad::AnalyticMaterial material;
    rad::AnalyticLighting lighting;
    if (!materialFromParameters(par, m.cm.bbox, material, lighting, why)) {
        errorMessage = why;
        return false;
    }

    // Everything is computed aside; the layer changes only once all of it succeeded.
    rad::RadianceField field = rad::makeMaterialRadiance(
        positions.data(), normals.data(), n, material, lighting, options,
        [cb](int percent) { if (cb) cb(percent * 9 / 10, "Projecting radiance onto the basis"); });
    const bool setColor = par.getBool("setColor");
    std::vector<float> meanColors;
    if (setColor) {
        meanColors.resize(3 * n);
        rad::meanHemisphereColors(field, meanColors.data());
    }
    radml::attachRadiance(m.cm, std::move(field));
    if (setColor) setVertexColors(m, meanColors);
    if (cb) cb(100, "Done");
    Log("Created %s radiance functions%s on %zu vertices (%d floats per vertex, %.1f MB) in %.2f s",
        options.basis.name().c_str(), options.reflected ? " (reflected)" : "", n,
        3 * options.basis.coefficientCount(),
        double(n) * 3 * options.basis.coefficientCount() * sizeof(float) / 1e6, timer.elapsed() / 1000.0);
    return true;
}

bool RadianceFilterPlugin::radianceToVertexColor(MeshModel& m, const RichParameterList& par, vcg::CallBackPos* cb) {
    rad::RadianceField field;
    std::string why;
    if (!radml::gatherRadiance(m.cm, field, why)) {
        errorMessage = QString::fromStdString(why);
        return false;
    }
    std::vector<float> positions, normals;
    QString problem;
    if (!collectVertices(m.cm, positions, normals, problem)) {
        errorMessage = problem;
        return false;
    }
    const vcg::Point3f eye = par.getPoint3f("viewpoint");
    const double eyeArray[3] = {eye[0], eye[1], eye[2]};
    if (!std::isfinite(eyeArray[0]) || !std::isfinite(eyeArray[1]) || !std::isfinite(eyeArray[2])) {
        errorMessage = "The viewpoint must be a finite point.";
        return false;
    }
    if (cb) cb(10, "Evaluating radiance");
    std::vector<float> rgb(positions.size());
    rad::radianceTowardViewpoint(field, positions.data(), eyeArray, par.getFloat("exposure"), rgb.data());
    setVertexColors(m, rgb);
    if (cb) cb(100, "Done");
    Log("Evaluated %s radiance toward (%g, %g, %g) on %zu vertices", field.basis.name().c_str(), eye[0], eye[1],
        eye[2], positions.size() / 3);
    return true;
}

MESHLAB_PLUGIN_NAME_EXPORTER(RadianceFilterPlugin)
