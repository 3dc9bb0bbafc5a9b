// probe_decoration_view: brightness of a screenshot of MeshLab around object-space points, located
// with the view file the "Radiance Field" decoration writes (camera/gl_view_camera.h), not with
// hard-coded pixel positions: the GUI tests ask "is there a highlight at the quad's centre?".
//
//   probe_decoration_view --view VIEW.txt --screenshot S.png --point X,Y,Z [--point ...] [--radius R]
//
// For each point, one line:
//   point K X Y Z screen SX SY peak P mean M pixels N
// SX, SY: the point's position in the screenshot (pixels, origin top-left, continuous); P and M the
// largest and mean luma Y' = 0.2126 R + 0.7152 G + 0.0722 B of the 8-bit sRGB codes (Rec. 709
// weights on the encoded values) over the N pixels of the viewport whose centres lie within R pixels
// of (SX, SY). Exit status 1 when a point is behind the camera or no pixel of its disc is inside the
// viewport.
#include "camera/gl_view_camera.h"
#include "image/image_io.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "command_line.h"

namespace {

using radtools::UsageError;

void usage(std::ostream& out) {
    out << "usage: probe_decoration_view --view VIEW.txt --screenshot S.png --point X,Y,Z [--point ...] [--radius R]\n"
           "  --radius R   disc radius in pixels [6]\n"
           "prints per point: point K X Y Z screen SX SY peak P mean M pixels N  (luma of 8-bit sRGB codes)\n";
}

int run(int argc, char** argv) {
    std::string viewPath, shotPath;
    std::vector<Eigen::Vector3d> points;
    double radius = 6.0;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "-h" || a == "--help") {
            usage(std::cout);
            return 0;
        }
        if (i + 1 >= argc) throw UsageError("option " + a + " needs a value");
        const std::string v = argv[++i];
        if (a == "--view") viewPath = v;
        else if (a == "--screenshot") shotPath = v;
        else if (a == "--radius") radius = radtools::toNumber(a, v);
        else if (a == "--point") {
            const std::vector<double> p = radtools::numberList(a, v, ',');
            if (p.size() != 3) throw UsageError("--point needs X,Y,Z");
            points.emplace_back(p[0], p[1], p[2]);
        } else throw UsageError("unknown option '" + a + "'");
    }
    if (viewPath.empty() || shotPath.empty() || points.empty())
        throw UsageError("--view, --screenshot and at least one --point are required");
    if (!(radius >= 0.5 && radius <= 500)) throw UsageError("--radius must lie in [0.5, 500]");

    const rad::DecorationViewFile view = rad::readDecorationViewFile(viewPath);
    const rad::PinholeCamera camera = rad::cameraFromGlView(view.view);
    const rad::ScreenRect rect = rad::viewportInScreen(view);
    const rad::Image8 shot = rad::readImage8(shotPath);
    if (rect.x < 0 || rect.y < 0 || rect.x + rect.width > shot.width || rect.y + rect.height > shot.height)
        throw std::runtime_error("the viewport (" + std::to_string(rect.width) + " x " + std::to_string(rect.height) +
                                 " at " + std::to_string(rect.x) + ", " + std::to_string(rect.y) + ") is not inside " +
                                 shotPath);
    int status = 0;
    for (std::size_t k = 0; k < points.size(); ++k) {
        const Eigen::Vector3d& X = points[k];
        double u = 0, v = 0;
        if (!camera.project(X, u, v)) {
            std::fprintf(stderr, "probe_decoration_view: point %zu (%g, %g, %g) is behind the camera\n", k, X.x(), X.y(), X.z());
            status = 1;
            continue;
        }
        double peak = 0, sum = 0;
        std::size_t n = 0;
        const int r0 = std::max(0, int(std::floor(v - radius))), r1 = std::min(rect.height - 1, int(std::ceil(v + radius)));
        const int c0 = std::max(0, int(std::floor(u - radius))), c1 = std::min(rect.width - 1, int(std::ceil(u + radius)));
        for (int r = r0; r <= r1; ++r)
            for (int c = c0; c <= c1; ++c) {
                const double du = c + 0.5 - u, dv = r + 0.5 - v;
                if (du * du + dv * dv > radius * radius) continue;
                const std::uint8_t* p = shot.rgb.data() + (std::size_t(rect.y + r) * shot.width + rect.x + c) * 3;
                const double luma = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
                peak = std::max(peak, luma);
                sum += luma;
                ++n;
            }
        std::printf("point %zu %g %g %g screen %.2f %.2f peak %.1f mean %.1f pixels %zu\n", k, X.x(), X.y(), X.z(),
                    rect.x + u, rect.y + v, peak, n ? sum / n : 0.0, n);
        if (n == 0) {
            std::fprintf(stderr, "probe_decoration_view: point %zu falls outside the viewport\n", k);
            status = 1;
        }
    }
    return status;
}

}  // namespace

int main(int argc, char** argv) { return radtools::runTool("probe_decoration_view", argc, argv, run, usage); }
