// make_fig6_quad: the toy scene of Vanhoey et al. 2015 Fig. 6 as a radiance mesh (.rply): the quad of
// makeDivergingQuad (4 vertices, 2 triangles, corner normals tilted outwards) carrying the RF of a
// dark glossy material under a directional light along the quad's normal +z, so that a camera in
// front of the quad (+z, as MeshLab's default and "Front" views) sees the lobe's peak only near the
// quad's centre:
//  - at vertex i (normal n_i tilted by `tilt` outwards) the lobe peaks toward the mirror direction of
//    +z about n_i, 2 tilt away from +z, outwards; the frontal camera sees the corner from a direction
//    tilted inwards, far from that peak: every vertex is dark toward the eye;
//  - per-vertex shading (Vanhoey et al. 2015 sec. 5) interpolates those dark colours: no highlight (Fig. 6 left);
//  - per-fragment shading (eq. 8) evaluates the reflected RF at R_n w with the interpolated normal,
//    which is +z at the centre: L~_i(R_z w) = L_i(R_{n_i} z) for w = z, the lobe's peak of every
//    vertex: a highlight in the middle (Fig. 6 right).
//
//   make_fig6_quad -o quad.rply [--tilt 30] [--size 1] [--basis PB6] [--reflected]
//                  [--exponent 40] [--specular 0.6] [--albedo 0.1] [--irradiance 1] [--ambient 0.05]
//
// Material: radiance/analytic_material.h (Lambert + normalised Blinn-Phong), projected onto the basis
// by radiance/material_radiance.h. Vertex colour = the RF's hemisphere mean (sRGB), as the other tools.
#include "geometry/primitive_meshes.h"
#include "io/radiance_ply.h"
#include "radiance/material_radiance.h"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "command_line.h"
#include "scene_setup.h"

namespace {

using radtools::UsageError;
using radtools::toNumber;

constexpr double kPi = 3.14159265358979323846;

void usage(std::ostream& out) {
    out << "usage: make_fig6_quad -o OUT.rply [options]\n"
           "  --tilt DEG        outward tilt of the corner normals [30]\n"
           "  --size S          half size of the square [1]\n"
           "  --basis PB6|SH8   basis of the radiance functions [PB6]\n"
           "  --reflected       store reflected functions (Vanhoey et al. 2015 sec. 3.1)\n"
           "  --exponent E      Blinn-Phong exponent [40]\n"
           "  --specular KS     lobe reflectance (grey) [0.6]\n"
           "  --albedo A        Lambert reflectance (grey) [0.1]\n"
           "  --irradiance E    directional light along +z [1]\n"
           "  --ambient A       uniform ambient radiance [0.05]\n";
}

int run(int argc, char** argv) {
    std::string output, basisName = "PB6";
    double tilt = 30.0, size = 1.0, exponent = 40.0, specular = 0.6, albedo = 0.1, irradiance = 1.0, ambient = 0.05;
    bool reflected = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "-h" || a == "--help") {
            usage(std::cout);
            return 0;
        }
        if (a == "--reflected") {
            reflected = true;
            continue;
        }
        if (i + 1 >= argc) throw UsageError("option " + a + " needs a value");
        const std::string v = argv[++i];
        if (a == "-o" || a == "--output") output = v;
        else if (a == "--basis") basisName = v;
        else if (a == "--tilt") tilt = toNumber(a, v);
        else if (a == "--size") size = toNumber(a, v);
        else if (a == "--exponent") exponent = toNumber(a, v);
        else if (a == "--specular") specular = toNumber(a, v);
        else if (a == "--albedo") albedo = toNumber(a, v);
        else if (a == "--irradiance") irradiance = toNumber(a, v);
        else if (a == "--ambient") ambient = toNumber(a, v);
        else throw UsageError("unknown option '" + a + "'");
    }
    if (output.empty()) throw UsageError("no output (-o OUT.rply)");
    const auto basis = rad::BasisSpec::parse(basisName);
    if (!basis) throw UsageError("--basis needs PB1..PB8 or SH0..SH10, got '" + basisName + "'");
    if (!(tilt > 0.0 && tilt < 45.0)) throw UsageError("--tilt must lie in (0, 45) degrees (the mirror direction must stay above the horizon)");
    if (!(size > 0.0)) throw UsageError("--size must be positive");
    if (!(exponent >= 0.0) || !(specular >= 0.0) || !(albedo >= 0.0) || !(irradiance >= 0.0) || !(ambient >= 0.0))
        throw UsageError("--exponent, --specular, --albedo, --irradiance and --ambient must be >= 0");

    const rad::TriangleMesh quad = rad::makeDivergingQuad(static_cast<float>(tilt * kPi / 180.0), static_cast<float>(size));
    rad::AnalyticMaterial material;
    material.albedo = rad::Rgb::Constant(albedo);
    material.specular = rad::Rgb::Constant(specular);
    material.exponent = exponent;
    rad::AnalyticLighting lighting;
    lighting.directional.push_back({Eigen::Vector3d::UnitZ(), rad::Rgb::Constant(irradiance)});
    lighting.ambient = rad::Rgb::Constant(ambient);
    rad::MaterialRadianceOptions options;
    options.basis = *basis;
    options.reflected = reflected;
    if (const std::string why = rad::checkMaterialRadianceInput(quad.positions.data(), quad.normals.data(),
                                                                quad.vertexCount(), options);
        !why.empty())
        throw std::runtime_error(why);

    rad::RadianceMesh out;
    out.positions = quad.positions;
    out.faces = quad.faces;
    out.radiance = rad::makeMaterialRadiance(quad.positions.data(), quad.normals.data(), quad.vertexCount(), material,
                                             lighting, options);
    radtools::setMeanColors(out);
    rad::writeRadiancePly(output, out);
    std::printf("%s: Fig. 6 quad (tilt %g deg, half size %g), %s%s RF of Blinn-Phong e = %g, ks = %g, albedo %g under "
                "a directional light along +z\n",
                output.c_str(), tilt, size, basis->name().c_str(), reflected ? " reflected" : "", exponent, specular,
                albedo);
    return 0;
}

}  // namespace

int main(int argc, char** argv) { return radtools::runTool("make_fig6_quad", argc, argv, run, usage); }
