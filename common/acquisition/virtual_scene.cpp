#include "acquisition/virtual_scene.h"

#include "geometry/mesh_normals.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace rad {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Three fixed directions, none along an axis nor in a coordinate plane, so that the pattern has no
// preferred axis on scans aligned with the axes (unit).
const Eigen::Vector3d kWaveDirections[3] = {Eigen::Vector3d(1.0, 0.31, -0.47).normalized(),
                                            Eigen::Vector3d(-0.38, 1.0, 0.59).normalized(),
                                            Eigen::Vector3d(0.23, -0.71, 1.0).normalized()};
// Phases per modulation (rows: albedo R, G, B, common albedo brightness, ks), fixed and distinct so
// the modulations decorrelate.
const double kWavePhases[5][3] = {{0.0, 1.3, 2.9}, {2.1, 0.4, 4.4}, {4.2, 3.3, 0.8}, {5.3, 2.6, 1.9}, {1.1, 5.0, 3.7}};

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

}  // namespace

double smoothModulation(int which, const Eigen::Vector3d& p, const Eigen::Vector3d& centre, double wavelength) {
    if (which < 0 || which > 4) throw std::out_of_range("smoothModulation: modulation index must lie in 0..4");
    const Eigen::Vector3d d = p - centre;
    double s = 0.0;
    for (int j = 0; j < 3; ++j)
        s += std::sin(2.0 * kPi * kWaveDirections[j].dot(d) / wavelength + kWavePhases[which][j]);
    return s / 3.0;
}

VirtualScene::VirtualScene(TriangleMesh mesh, AnalyticMaterial material, AnalyticLighting lighting,
                           VirtualSceneOptions options)
    : mesh_(std::move(mesh)), material_(std::move(material)), lighting_(std::move(lighting)), options_(options) {
    const std::string problem = mesh_.validate();
    if (!problem.empty()) throw VirtualSceneError("virtual scene: " + problem);
    if (mesh_.faceCount() == 0) throw VirtualSceneError("virtual scene: the mesh has no faces");
    if (!mesh_.hasNormals()) computeAreaWeightedNormals(mesh_);
    for (std::size_t v = 0; v < mesh_.vertexCount(); ++v) {
        float* n = &mesh_.normals[3 * v];
        const double len = std::sqrt(double(n[0]) * n[0] + double(n[1]) * n[1] + double(n[2]) * n[2]);
        if (!(len > 0.0)) {
            std::ostringstream why;
            why << "virtual scene: vertex " << v << " has a zero normal (isolated vertex or degenerate faces); "
                << "remove it or repair the mesh";
            throw VirtualSceneError(why.str());
        }
        for (int k = 0; k < 3; ++k) n[k] = static_cast<float>(n[k] / len);
    }
    if (!finite(material_.albedo) || !finite(material_.specular) || !std::isfinite(material_.exponent) ||
        material_.exponent < 0.0)
        throw VirtualSceneError("virtual scene: the material has non-finite values or a negative exponent");
    for (const DirectionalLight& l : lighting_.directional)
        if (!finite(l.direction) || !finite(l.irradiance) || l.direction.norm() == 0.0)
            throw VirtualSceneError("virtual scene: a directional light has a zero or non-finite direction or irradiance");
    for (const PointLight& l : lighting_.points)
        if (!finite(l.position) || !finite(l.intensity))
            throw VirtualSceneError("virtual scene: a point light has a non-finite position or intensity");
    if (!finite(lighting_.ambient)) throw VirtualSceneError("virtual scene: the ambient radiance is not finite");
    const SmoothVariation& var = options_.variation;
    if (!std::isfinite(var.wavelength) || !(var.albedoAmplitude >= 0.0 && var.albedoAmplitude <= 1.0) ||
        !(var.specularAmplitude >= 0.0 && var.specularAmplitude <= 1.0))
        throw VirtualSceneError("virtual scene: variation amplitudes must lie in [0, 1] and the wavelength be finite");
    if (!(options_.shadowOffset >= 0.0) || !std::isfinite(options_.shadowOffset))
        throw VirtualSceneError("virtual scene: the shadow offset must be finite and non-negative");

    bounds_.setEmpty();
    for (std::size_t v = 0; v < mesh_.vertexCount(); ++v)
        bounds_.extend(Eigen::Vector3d(mesh_.positions[3 * v], mesh_.positions[3 * v + 1], mesh_.positions[3 * v + 2]));
    const double diag = diagonal();
    if (!(diag > 0.0)) throw VirtualSceneError("virtual scene: the mesh has zero extent");
    wavelength_ = var.wavelength > 0.0 ? var.wavelength : 0.25 * diag;
    offset_ = options_.shadowOffset * diag;
    rays_ = std::make_unique<RayScene>(mesh_.positions.data(), mesh_.vertexCount(), mesh_.faces.data(),
                                       mesh_.faceCount());
}

AnalyticMaterial VirtualScene::materialAt(const Eigen::Vector3d& p) const {
    AnalyticMaterial m = material_;
    const SmoothVariation& var = options_.variation;
    if (!var.enabled) return m;
    const Eigen::Vector3d c = bounds_.center();
    const double brightness = smoothModulation(3, p, c, wavelength_);
    for (int ch = 0; ch < 3; ++ch) {
        const double s = 0.75 * brightness + 0.25 * smoothModulation(ch, p, c, wavelength_);
        m.albedo[ch] = std::clamp(material_.albedo[ch] * (1.0 + var.albedoAmplitude * s), 0.0, 1.0);
    }
    const double spec = 1.0 + var.specularAmplitude * smoothModulation(4, p, c, wavelength_);
    for (int ch = 0; ch < 3; ++ch) m.specular[ch] = std::clamp(material_.specular[ch] * spec, 0.0, 1.0);
    return m;
}

bool VirtualScene::reaches(const DirectionalLight& light, const Eigen::Vector3d& p, const Eigen::Vector3d& n) const {
    if (!options_.castShadows) return true;
    const Eigen::Vector3f origin = (p + offset_ * n).cast<float>();
    const Eigen::Vector3f dir = light.direction.normalized().cast<float>();
    return !rays_->occluded(origin, dir, 0.0f, std::numeric_limits<float>::infinity());
}

bool VirtualScene::reaches(const PointLight& light, const Eigen::Vector3d& p, const Eigen::Vector3d& n) const {
    if (!options_.castShadows) return true;
    const Eigen::Vector3d origin = p + offset_ * n;
    const Eigen::Vector3d d = light.position - origin;
    const double dist = d.norm();
    if (!(dist > 0.0)) return true;
    // Stop just short of the light: a light lying on the surface is not shadowed by that surface.
    return !rays_->occluded(origin.cast<float>(), (d / dist).cast<float>(), 0.0f, static_cast<float>(dist * (1.0 - 1e-5)));
}

Rgb VirtualScene::radiance(const Eigen::Vector3d& p, const Eigen::Vector3d& n, const Eigen::Vector3d& wo) const {
    const double nLen = n.norm(), woLen = wo.norm();
    if (!(nLen > 0.0) || !(woLen > 0.0) || !std::isfinite(nLen) || !std::isfinite(woLen)) return Rgb::Zero();
    const Eigen::Vector3d nn = n / nLen;
    const Eigen::Vector3d w = clampToHemisphere(nn, wo / woLen);  // as outgoingRadiance() does
    const AnalyticMaterial m = materialAt(p);
    Rgb L = m.albedo.cwiseProduct(lighting_.ambient);  // unshadowed ambient (file comment)
    // A light's contribution is computed first: the shadow ray is only cast when it is non-zero.
    for (const DirectionalLight& light : lighting_.directional) {
        const Rgb c = lightContribution(m, light, p, nn, w);
        if (!c.isZero() && reaches(light, p, nn)) L += c;
    }
    for (const PointLight& light : lighting_.points) {
        const Rgb c = lightContribution(m, light, p, nn, w);
        if (!c.isZero() && reaches(light, p, nn)) L += c;
    }
    return L;
}

// ---- Sample scenes ---------------------------------------------------------------------------

SampleMaterial parseSampleMaterial(const std::string& name) {
    if (name == "glossy") return SampleMaterial::Glossy;
    if (name == "diffuse") return SampleMaterial::Diffuse;
    if (name == "stripes") return SampleMaterial::Stripes;
    throw std::invalid_argument("unknown material '" + name + "' (glossy, diffuse or stripes)");
}

AnalyticMaterial makeSampleMaterial(SampleMaterial kind, const Eigen::AlignedBox3d& bounds, const Eigen::Vector3d& up) {
    AnalyticMaterial m;
    m.albedo = Rgb(0.60, 0.45, 0.32);
    m.specular = Rgb::Constant(kind == SampleMaterial::Diffuse ? 0.0 : 0.18);
    m.exponent = 30.0;
    if (kind == SampleMaterial::Stripes) {
        const Eigen::Vector3d u = up.normalized();
        // Extent of the box along `up`: project its 8 corners.
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (int c = 0; c < 8; ++c) {
            const double t = bounds.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c)).dot(u);
            lo = std::min(lo, t);
            hi = std::max(hi, t);
        }
        m.stripes = StripePattern::covering(u, lo, hi, 8);
    }
    return m;
}

void sampleFrame(const Eigen::Vector3d& up, Eigen::Vector3d& east, Eigen::Vector3d& north) {
    const Eigen::Vector3d u = up.normalized();
    int k = 0;  // the world axis least aligned with up (first on ties)
    for (int i = 1; i < 3; ++i)
        if (std::fabs(u[i]) < std::fabs(u[k])) k = i;
    const Eigen::Vector3d axis = Eigen::Vector3d::Unit(k);
    east = (axis - axis.dot(u) * u).normalized();
    north = u.cross(east);
}

AnalyticLighting makeSampleLighting(const Eigen::Vector3d& centre, double radius, const Eigen::Vector3d& up) {
    Eigen::Vector3d e, n;
    sampleFrame(up, e, n);
    const Eigen::Vector3d u = up.normalized();
    AnalyticLighting l;
    l.directional.push_back({(0.45 * e - 0.35 * n + u).normalized(), Rgb(2.0, 1.92, 1.8)});
    const double distance = 2.5 * radius;
    // Intensity I gives irradiance I / d^2 at the centre.
    l.points.push_back({centre + distance * (-0.8 * e + 0.5 * n + 0.4 * u).normalized(),
                        Rgb(0.4, 0.45, 0.55) * distance * distance});
    l.ambient = Rgb::Constant(0.05);
    return l;
}

}  // namespace rad
