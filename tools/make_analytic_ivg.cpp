// make_analytic_ivg: a test scene for the "Irradiance Vector Grid" decoration while no grid
// computation exists on this branch: an icosphere (PLY, white vertex colours) and, beside it with the
// same base name, an irradiance vector grid (.ivg, Granier et al. 2007) of an analytic two-colour
// field: red light from the +x side, green light from the -x side (green, not blue: MeshLab's
// background is blue). At every grid vertex and direction delta, per channel, I_delta = pi L delta
// with L = (red(x), green(x), 0), red(x) = clamp(0.5 + 2 x / r, 0, 1) * `radiance`, green = the same
// at -x (r = the sphere's radius): a white diffuse sphere looks red on its +x side and green on its
// -x side whatever its normals, the two mixed in a band |x| < r / 4.
//
//   make_analytic_ivg -o DIR/NAME [--radius 1] [--cells 8] [--radiance 0.9]
//
// Writes DIR/NAME.ply and DIR/NAME.ivg (both atomically).
#include "geometry/primitive_meshes.h"
#include "io/radiance_ply.h"
#include "lighting/irradiance_vector_grid.h"

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <string>

#include "command_line.h"

namespace {

using radtools::UsageError;
using radtools::toNumber;
constexpr double kPi = 3.14159265358979323846;

void usage(std::ostream& out) { out << "usage: make_analytic_ivg -o DIR/NAME [--radius 1] [--cells 8] [--radiance 0.9]\n"; }

}  // namespace

int main(int argc, char** argv) {
    std::string base;
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
        const rad::TriangleMesh sphere = rad::makeIcosphere(4, static_cast<float>(radius));
        rad::RadianceMesh mesh;
        mesh.positions = sphere.positions;
        mesh.normals = sphere.normals;
        mesh.faces = sphere.faces;
        mesh.colors.assign(4 * sphere.vertexCount(), 255);
        rad::writeRadiancePly(base + ".ply", mesh);

        const float r = static_cast<float>(1.2 * radius);
        rad::IrradianceVectorGrid grid = rad::IrradianceVectorGrid::covering({{-r, -r, -r}}, {{r, r, r}}, {{cells, cells, cells}});
        for (int k = 0; k <= cells; ++k)
            for (int j = 0; j <= cells; ++j)
                for (int i = 0; i <= cells; ++i) {
                    const double x = grid.vertexPosition(i, j, k)[0];
                    const double red = radiance * std::clamp(0.5 + 2.0 * x / radius, 0.0, 1.0);
                    const double green = radiance * std::clamp(0.5 - 2.0 * x / radius, 0.0, 1.0);
                    const double L[3] = {red, green, 0.0};
                    for (int d = 0; d < rad::IrradianceVectorGrid::kDirections; ++d) {
                        const std::array<float, 3> delta = rad::gridDirection(d);
                        float* out = grid.at(grid.vertexIndex(i, j, k), d);
                        for (int c = 0; c < 3; ++c)
                            for (int a = 0; a < 3; ++a) out[3 * c + a] = static_cast<float>(kPi * L[c] * delta[a]);
                    }
                }
        rad::writeIrradianceVectorGrid(base + ".ivg", grid);
        std::printf("wrote %s.ply (%zu vertices) and %s.ivg (%d^3 cells)\n", base.c_str(), sphere.vertexCount(), base.c_str(), cells);
    } catch (const std::exception& e) {
        std::cerr << "make_analytic_ivg: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
