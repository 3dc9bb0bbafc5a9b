#include "offscreen_gl.h"

#include <GL/glew.h>

#include <QGuiApplication>
#include <QOffscreenSurface>
#include <QOpenGLContext>
#include <QOpenGLFramebufferObject>
#include <QSurfaceFormat>

#include <stdexcept>

namespace radgl {

struct OffscreenGl::State {
    std::unique_ptr<QGuiApplication> app;
    std::unique_ptr<QOffscreenSurface> surface;  // made after the application object
    std::unique_ptr<QOpenGLContext> context;
    std::unique_ptr<QOpenGLFramebufferObject> fbo;
};

namespace {
int g_argc = 1;
char g_name[] = "radiance_gl";
char* g_argv[] = {g_name, nullptr};
}  // namespace

OffscreenGl::OffscreenGl(int width, int height) : state_(std::make_unique<State>()), width_(width), height_(height) {
    if (!QGuiApplication::instance()) state_->app = std::make_unique<QGuiApplication>(g_argc, g_argv);
    QSurfaceFormat format;
    // No version: a legacy context request, which Mesa answers with its highest compatibility
    // profile (4.5 on llvmpipe), as it does for MeshLab's QGLWidget. Asking for "3.2 compatibility"
    // through Qt's GLX integration gave a core profile here.
    format.setDepthBufferSize(24);
    state_->surface = std::make_unique<QOffscreenSurface>();
    state_->context = std::make_unique<QOpenGLContext>();
    state_->surface->setFormat(format);
    state_->surface->create();
    state_->context->setFormat(format);
    if (!state_->context->create()) throw std::runtime_error("cannot create an OpenGL context (is there an X display?)");
    if (!state_->context->makeCurrent(state_->surface.get())) throw std::runtime_error("cannot make the OpenGL context current");
    glewExperimental = GL_TRUE;
    if (glewInit() != GLEW_OK) throw std::runtime_error("GLEW initialisation failed");
    while (glGetError() != GL_NO_ERROR) {
    }
    // Depth and stencil, as MeshLab's view has (the normal-map renderer's erase pass uses the stencil).
    state_->fbo = std::make_unique<QOpenGLFramebufferObject>(width, height, QOpenGLFramebufferObject::CombinedDepthStencil);
    if (!state_->fbo->isValid()) throw std::runtime_error("cannot create the framebuffer");
    state_->fbo->bind();
}

OffscreenGl::~OffscreenGl() {
    state_->context->makeCurrent(state_->surface.get());
    state_->fbo.reset();
    state_->context->doneCurrent();
}

std::array<double, 16> OffscreenGl::projectionMatrix(const rad::PinholeCamera& c, double n, double f) {
    // glFrustum(l, r, b, t, n, f) with the image plane at distance n: pixel u maps to x = (u - cx) n / fx,
    // image rows grow downward while GL's y grows upward.
    const double l = -c.cx * n / c.fx, r = (c.width - c.cx) * n / c.fx;
    const double t = c.cy * n / c.fy, b = -(c.height - c.cy) * n / c.fy;
    std::array<double, 16> m{};
    m[0] = 2 * n / (r - l);
    m[5] = 2 * n / (t - b);
    m[8] = (r + l) / (r - l);
    m[9] = (t + b) / (t - b);
    m[10] = -(f + n) / (f - n);
    m[11] = -1;
    m[14] = -2 * f * n / (f - n);
    return m;
}

std::array<double, 16> OffscreenGl::modelviewMatrix(const rad::PinholeCamera& c) {
    // GL eye space = (x, -y, -z) of the camera space (x right, y down, z forward).
    Eigen::Matrix3d R = c.rotation;
    R.row(1) *= -1.0;
    R.row(2) *= -1.0;
    const Eigen::Vector3d t = -R * c.center;
    std::array<double, 16> m{};
    for (int col = 0; col < 3; ++col)
        for (int row = 0; row < 3; ++row) m[col * 4 + row] = R(row, col);
    for (int row = 0; row < 3; ++row) m[12 + row] = t[row];
    m[15] = 1;
    return m;
}

void OffscreenGl::beginFrame(const rad::PinholeCamera& camera, double zNear, double zFar, std::uint8_t background) {
    state_->context->makeCurrent(state_->surface.get());
    state_->fbo->bind();
    glViewport(0, 0, width_, height_);
    const float g = background / 255.0f;
    glClearColor(g, g, g, 1.0f);
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    const auto p = projectionMatrix(camera, zNear, zFar);
    const auto mv = modelviewMatrix(camera);
    glMatrixMode(GL_PROJECTION);
    glLoadMatrixd(p.data());
    glMatrixMode(GL_MODELVIEW);
    glLoadMatrixd(mv.data());
}

void OffscreenGl::finish() { glFinish(); }

std::vector<std::uint8_t> OffscreenGl::readRgb() {
    glFinish();
    std::vector<std::uint8_t> rgba(static_cast<std::size_t>(width_) * height_ * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    std::vector<std::uint8_t> rgb(static_cast<std::size_t>(width_) * height_ * 3);
    for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x) {
            const std::size_t src = (static_cast<std::size_t>(height_ - 1 - y) * width_ + x) * 4;
            const std::size_t dst = (static_cast<std::size_t>(y) * width_ + x) * 3;
            for (int c = 0; c < 3; ++c) rgb[dst + c] = rgba[src + c];
        }
    return rgb;
}

}  // namespace radgl
