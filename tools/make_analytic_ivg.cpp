// make_analytic_ivg: a test scene for the "Irradiance Vector Grid" decoration while no grid
// computation exists on this branch: an icosphere (PLY, white vertex colours) and, beside it with the
// same base name, an irradiance vector grid (.ivg, Granier et al. 2007) of an analytic two-colour
// field: red light from the +x side, green light from the -x side (green, not blue: MeshLab's
// background is blue). At every grid vertex and direction delta, per channel, I_delta = pi L delta
// with L = (red(x), green(x), 0), red(x) = clamp(0.5 + 2 x / r, 0, 1) * `radiance`, green = the same
// at -x (r = the sphere's radius): a white diffuse sphere looks red on its +x side and green on its
// -x side whatever its normals, the two mixed in a band |x| < r / 4.
//
//   make_analytic_ivg -o DIR/NAME [--radius 1] [--cells 8] [--radiance 0.9] [--fit MESH.ply] [--from-above]
//
// --from-above: the light mostly from +y, I_delta scaled by 0.5 (+x, -x, +z, -z), 1 (+y), 0.05 (-y),
// so that the shading follows the normals strongly (a normal map's detail shows).
// Writes DIR/NAME.ply and DIR/NAME.ivg (both atomically). With --fit, no sphere: the grid covers
// MESH's bounding box (padded by 10 %), the field centred on the box's centre and r = half the box's
// x extent; only DIR/NAME.ivg is written.
#include "geometry/primitive_meshes.h"
#include "io/radiance_ply.h"
#include "lighting/irradiance_vector_grid.h"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <cstdio>
#include <iostream>
#include <string>

#include "command_line.h"

namespace {

using radtools::UsageError;
using radtools::toNumber;
constexpr double kPi = 3.14159265358979323846;

void usage(std::ostream& out) {
    out << "usage: make_analytic_ivg -o DIR/NAME [--radius 1] [--cells 8] [--radiance 0.9] [--fit MESH.ply] [--from-above]\n";
}

}  // namespace

int main(int argc, char** argv) {
    std::string base, fit;
    bool fromAbove = false;
    double radius = 1.0, radiance = 0.9;
    int cells = 8;
    try {
        for (int i = 1; i < argc; ++i) {
            const std::string a = argv[i];
            const auto value = [&]() -> std::string {
                if (i + 1 >= argc) throw UsageError(a + " needs a value");
                return argv[++i];
            };
            if (a == "-o") base = value();
            else if (a == "--radius") radius = toNumber(a, value());
            else if (a == "--cells") cells = static_cast<int>(toNumber(a, value()));
            else if (a == "--radiance") radiance = toNumber(a, value());
            else if (a == "--fit") fit = value();
            else if (a == "--from-above") fromAbove = true;
            else if (a == "-h" || a == "--help") {
                usage(std::cout);
                return 0;
            } else throw UsageError("unknown argument " + a);
        }
        if (base.empty()) throw UsageError("give the output base name with -o");
        if (!(radius > 0) || cells < 1 || !(radiance >= 0)) throw UsageError("radius > 0, cells >= 1, radiance >= 0");
    } catch (const std::exception& e) {
        std::cerr << "make_analytic_ivg: " << e.what() << "\n";
        usage(std::cerr);
        return 2;
    }
    try {
        std::array<float, 3> boxMin, boxMax;
        double centreX = 0.0;
        if (fit.empty()) {
            const rad::TriangleMesh sphere = rad::makeIcosphere(4, static_cast<float>(radius));
            rad::RadianceMesh mesh;
            mesh.positions = sphere.positions;
            mesh.normals = sphere.normals;
            mesh.faces = sphere.faces;
            mesh.colors.assign(4 * sphere.vertexCount(), 255);
            rad::writeRadiancePly(base + ".ply", mesh);
            std::printf("wrote %s.ply (%zu vertices)\n", base.c_str(), sphere.vertexCount());
            const float r = static_cast<float>(1.2 * radius);
            boxMin = {{-r, -r, -r}};
            boxMax = {{r, r, r}};
        } else {
            const rad::RadianceMesh mesh = rad::readRadiancePly(fit);
            if (mesh.vertexCount() == 0) throw std::runtime_error(fit + " has no vertices");
            boxMin = {{mesh.positions[0], mesh.positions[1], mesh.positions[2]}};
            boxMax = boxMin;
            for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
                for (int a = 0; a < 3; ++a) {
                    boxMin[a] = std::min(boxMin[a], mesh.positions[3 * v + a]);
                    boxMax[a] = std::max(boxMax[a], mesh.positions[3 * v + a]);
                }
            for (int a = 0; a < 3; ++a) {
                const float pad = 0.1f * std::max(boxMax[a] - boxMin[a], 1e-3f);
                boxMin[a] -= pad;
                boxMax[a] += pad;
            }
            centreX = 0.5 * (boxMin[0] + boxMax[0]);
            radius = 0.5 * (boxMax[0] - boxMin[0]) / 1.2;
        }
        rad::IrradianceVectorGrid grid = rad::IrradianceVectorGrid::covering(boxMin, boxMax, {{cells, cells, cells}});
        for (int k = 0; k <= cells; ++k)
            for (int j = 0; j <= cells; ++j)
                for (int i = 0; i <= cells; ++i) {
                    const double x = grid.vertexPosition(i, j, k)[0] - centreX;
                    const double red = radiance * std::clamp(0.5 + 2.0 * x / radius, 0.0, 1.0);
                    const double green = radiance * std::clamp(0.5 - 2.0 * x / radius, 0.0, 1.0);
                    const double L[3] = {red, green, 0.0};
                    for (int d = 0; d < rad::IrradianceVectorGrid::kDirections; ++d) {
                        const std::array<float, 3> delta = rad::gridDirection(d);
                        const double weight = !fromAbove ? 1.0 : d == 2 ? 1.0 : d == 3 ? 0.05 : 0.5;
                        float* out = grid.at(grid.vertexIndex(i, j, k), d);
                        for (int c = 0; c < 3; ++c)
                            for (int a = 0; a < 3; ++a) out[3 * c + a] = static_cast<float>(weight * kPi * L[c] * delta[a]);
                    }
                }
        rad::writeIrradianceVectorGrid(base + ".ivg", grid);
        std::printf("wrote %s.ivg (%d^3 cells)\n", base.c_str(), cells);
    } catch (const std::exception& e) {
        std::cerr << "make_analytic_ivg: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
