// The GL tests' context: one offscreen Mesa context per test program (created on first use) of
// kWidth x kHeight pixels, and its capabilities.
#pragma once
#include "gl_capabilities.h"
#include "offscreen_gl.h"

namespace gltest {

constexpr int kWidth = 160, kHeight = 120;

inline radgl::OffscreenGl& gl() {
    static radgl::OffscreenGl context(kWidth, kHeight);
    return context;
}

inline radgl::GlCapabilities capabilities() {
    gl();
    return radgl::queryGlCapabilities();
}

}  // namespace gltest
