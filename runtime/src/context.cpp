// EGL (headless) and GLFW (window) contexts. libepoxy resolves GL entry points for both;
// its epoxy/egl.h is included instead of EGL/egl.h, whose KHRONOS_* types clash with it.
#include <dawnforge/runtime/context.hpp>

#include <dawnforge/core/format.hpp>

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <vector>

namespace dawnforge::runtime {

std::string GlContext::description() const {
    const auto text = [](GLenum name) {
        const auto* s = reinterpret_cast<const char*>(glGetString(name));
        return std::string(s ? s : "?");
    };
    return text(GL_RENDERER) + ", OpenGL " + text(GL_VERSION);
}

namespace {

[[noreturn]] void fail(const std::string& what) { throw std::runtime_error(what); }

class EglContext final : public GlContext {
public:
    EglContext() {
        // Mesa's surfaceless platform first (llvmpipe in CI, any Mesa GPU); then an EGL
        // device (the NVIDIA driver), then the default display. DAWNFORGE_EGL_DEVICE=N asks
        // for EGL device N first (a GPU on a machine that also has Mesa).
        const auto initialised = [](EGLDisplay d) { return d != EGL_NO_DISPLAY && eglInitialize(d, nullptr, nullptr); };
        const auto device = [](int index) {
            if (!epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_device_enumeration")) return EGLDisplay(EGL_NO_DISPLAY);
            EGLDeviceEXT devices[16];
            EGLint count = 0;
            if (!eglQueryDevicesEXT(16, devices, &count) || index >= count) return EGLDisplay(EGL_NO_DISPLAY);
            return eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[index], nullptr);
        };
        const auto surfaceless = [] {
            return epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless")
                       ? eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr)
                       : EGLDisplay(EGL_NO_DISPLAY);
        };
        std::vector<std::function<EGLDisplay()>> candidates;
        if (const char* wanted = std::getenv("DAWNFORGE_EGL_DEVICE"))
            candidates.push_back([&device, index = std::max(0, std::atoi(wanted))] { return device(index); });
        candidates.push_back(surfaceless);
        candidates.push_back([&device] { return device(0); });
        candidates.push_back([] { return eglGetDisplay(EGL_DEFAULT_DISPLAY); });
        for (const auto& candidate : candidates)
            if (initialised(display_ = candidate())) break;
            else display_ = EGL_NO_DISPLAY;
        if (display_ == EGL_NO_DISPLAY) fail("no EGL display (install Mesa's libegl-mesa0 and libgl1-mesa-dri)");
        if (!eglBindAPI(EGL_OPENGL_API)) fail("EGL cannot bind the desktop OpenGL API");
        const EGLint configAttributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
        EGLConfig config = nullptr;
        EGLint configs = 0;
        if (!eglChooseConfig(display_, configAttributes, &config, 1, &configs) || configs == 0) config = nullptr;
        const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                            EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
        context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, contextAttributes);
        if (context_ == EGL_NO_CONTEXT) fail(format("EGL refused an OpenGL 4.5 core context (EGL error {})", eglGetError()));
        if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) fail("EGL cannot make the context current");
    }
    // The display stays initialised until the process ends (EGL displays are per process,
    // and terminating one lets Mesa unload its driver, whose few unfreed allocations then
    // show as leaks of an unknown module that no sanitizer suppression can name).
    ~EglContext() override {
        eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display_, context_);
    }

private:
    EGLDisplay display_ = EGL_NO_DISPLAY;
    EGLContext context_ = EGL_NO_CONTEXT;
};

class GlfwContext final : public GlContext {
public:
    GlfwContext(glm::ivec2 size, const std::string& title) {
        if (!glfwInit()) fail("GLFW cannot start (no display? use `dawnforge render` headless)");
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
        glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
        glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
        window_ = glfwCreateWindow(size.x, size.y, title.c_str(), nullptr, nullptr);
        if (!window_) {
            glfwTerminate();
            fail("GLFW cannot open an OpenGL 4.5 core window");
        }
        glfwMakeContextCurrent(window_);
        glfwSwapInterval(1);
        glfwGetCursorPos(window_, &last_.x, &last_.y);
    }
    ~GlfwContext() override {
        glfwDestroyWindow(window_);
        glfwTerminate();
    }
    glm::ivec2 framebufferSize() const override {
        glm::ivec2 s;
        glfwGetFramebufferSize(window_, &s.x, &s.y);
        return s;
    }
    void swapBuffers() override { glfwSwapBuffers(window_); }
    WindowInput poll() override {
        glfwPollEvents();
        WindowInput in;
        in.closeRequested = glfwWindowShouldClose(window_) || key(GLFW_KEY_ESCAPE);
        glm::dvec2 cursor;
        glfwGetCursorPos(window_, &cursor.x, &cursor.y);
        if (glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS) in.mouseDelta = cursor - last_;
        last_ = cursor;
        in.move = {double(key(GLFW_KEY_D)) - double(key(GLFW_KEY_A)), double(key(GLFW_KEY_E)) - double(key(GLFW_KEY_Q)),
                   double(key(GLFW_KEY_W)) - double(key(GLFW_KEY_S))};
        in.fast = key(GLFW_KEY_LEFT_SHIFT);
        for (int k = 0; k < 9; ++k)
            if (pressed(GLFW_KEY_1 + k)) in.cameraKey = k;
        in.timeOfDayDelta = (key(GLFW_KEY_RIGHT_BRACKET) ? 0.05 : 0.0) - (key(GLFW_KEY_LEFT_BRACKET) ? 0.05 : 0.0);
        in.restart = pressed(GLFW_KEY_R);
        return in;
    }

private:
    bool key(int k) const { return glfwGetKey(window_, k) == GLFW_PRESS; }
    // True on the poll where the key went down.
    bool pressed(int k) {
        const bool down = key(k);
        const bool was = down_[std::size_t(k) % down_.size()];
        down_[std::size_t(k) % down_.size()] = down;
        return down && !was;
    }
    GLFWwindow* window_ = nullptr;
    glm::dvec2 last_{0.0};
    std::vector<bool> down_ = std::vector<bool>(512, false);
};

}  // namespace

std::unique_ptr<GlContext> GlContext::headless() { return std::make_unique<EglContext>(); }
std::unique_ptr<GlContext> GlContext::window(glm::ivec2 size, const std::string& title) {
    return std::make_unique<GlfwContext>(size, title);
}

}  // namespace dawnforge::runtime
