// An offscreen OpenGL context with a framebuffer, for the GL tests and the frame-time benchmark
// (Qt's QOffscreenSurface; needs an X display, e.g. Xvfb, like MeshLab itself). Compatibility
// profile, as MeshLab 2020.09's context, so the decoration's shaders run exactly as in MeshLab.
#pragma once

#include "camera/pinhole_camera.h"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace radgl {

class OffscreenGl {
public:
    // Creates the application object if none exists, the context and a width x height RGBA8 + depth
    // framebuffer; initialises GLEW. Throws std::runtime_error when any step fails.
    OffscreenGl(int width, int height);
    ~OffscreenGl();

    // Clears to `background` (8-bit sRGB grey level) and sets the fixed-function matrices so that
    // the framebuffer is the camera's image (row 0 at the top): projection = the camera's frustum
    // between zNear and zFar, modelview = world -> OpenGL eye space.
    void beginFrame(const rad::PinholeCamera& camera, double zNear, double zFar, std::uint8_t background = 0);
    // glFinish, then the framebuffer as RGB bytes, row 0 at the TOP.
    std::vector<std::uint8_t> readRgb();
    void finish();

    int width() const { return width_; }
    int height() const { return height_; }

    // The column-major GL matrices used by beginFrame (for tests of the camera conversion).
    static std::array<double, 16> projectionMatrix(const rad::PinholeCamera& camera, double zNear, double zFar);
    static std::array<double, 16> modelviewMatrix(const rad::PinholeCamera& camera);

private:
    struct State;
    std::unique_ptr<State> state_;
    int width_, height_;
};

}  // namespace radgl
