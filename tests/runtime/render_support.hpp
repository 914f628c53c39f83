#pragma once
// What the render tests share: their one GL context, headless EGL on Mesa llvmpipe (golden
// images are llvmpipe's), and a frame looking from one point at another.
#include <dawnforge/runtime/context.hpp>
#include <dawnforge/runtime/renderer.hpp>

#include <glm/glm.hpp>

#include <cstdlib>
#include <memory>

namespace dawnforge::test {

inline runtime::GlContext& llvmpipeContext() {
    static std::unique_ptr<runtime::GlContext> c = [] {
        setenv("GALLIUM_DRIVER", "llvmpipe", 1);
        return runtime::GlContext::headless();
    }();
    return *c;
}

inline runtime::FrameSettings lookingAt(glm::dvec3 eye, glm::dvec3 target, double hours = 15.0, double fov = 50.0) {
    runtime::FrameSettings f;
    f.camera.position = eye;
    f.camera.forward = glm::normalize(target - eye);
    f.camera.fovYDegrees = fov;
    f.timeOfDay = hours;
    return f;
}

}  // namespace dawnforge::test
