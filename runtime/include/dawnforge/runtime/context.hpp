#pragma once
// An OpenGL 4.5 core context: headless through EGL (Mesa's surfaceless platform, or the
// NVIDIA EGL device) or in a GLFW window, behind one interface. The renderer draws into
// its own framebuffers either way; a window only adds presenting and input.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <memory>
#include <string>

namespace dawnforge::runtime {

// What the window saw since the last poll (fly camera input).
struct WindowInput {
    bool closeRequested = false;
    glm::dvec2 mouseDelta{0.0};  // pixels, while the left button is held
    glm::dvec3 move{0.0};        // WASD/QE: x right, y up, z forward, each -1..1
    bool fast = false;           // shift held
    int cameraKey = -1;          // 1..9 pressed: choose that named camera (0-based)
    double timeOfDayDelta = 0.0; // hours: [ and ] keys
    bool restart = false;        // R: restart the destruction
};

class GlContext {
public:
    virtual ~GlContext() = default;
    // The GL_RENDERER and GL_VERSION strings.
    std::string description() const;
    // Window only: the framebuffer size, presenting the back buffer, and input.
    virtual glm::ivec2 framebufferSize() const { return {0, 0}; }
    virtual void swapBuffers() {}
    virtual WindowInput poll() { return {}; }

    // Throws std::runtime_error with a one-line reason when no context can be made.
    static std::unique_ptr<GlContext> headless();
    static std::unique_ptr<GlContext> window(glm::ivec2 size, const std::string& title);
};

}  // namespace dawnforge::runtime
