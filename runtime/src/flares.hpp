#pragma once
// Lens flares (issue 15 item 4), private to the renderer. The seed talk's approach: every
// flare element of every light is one instance of one instanced draw; the vertex shader
// (flare.vert) projects the light, reads the scene's depth texture at 32 points of a disc
// around it to find how much of the light is visible (same frame, no occlusion query, no
// read-back), and places, scales and fades the element on the line from the light through
// the screen centre. The draw count is 1 whatever the number of lights (0 without any).
#include "gl.hpp"

#include <dawnforge/runtime/sky.hpp>

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace dawnforge::runtime {

// The shapes flare.frag draws (its kGlow... constants).
enum class FlareShape : std::uint32_t { Glow = 0, Ghost = 1, HexGhost = 2, Halo = 3 };

// One element of every light's flare.
struct FlareElement {
    FlareShape shape = FlareShape::Glow;
    float axis = 1.0f;          // on the line light → centre: 1 at the light, 0 at the centre, -1 mirrored
    float size = 0.1f;          // radius, a fraction of the screen height
    glm::vec3 tint{1.0f};       // linear, times the light's colour
};

// The element table: a glow and a halo at the light, ghosts along the axis.
std::span<const FlareElement> flareElements();

// A light that makes a flare.
struct FlareLight {
    glm::dvec4 position{0.0, 1.0, 0.0, 0.0};  // w = 1: a point (m); w = 0: a direction (the sun)
    glm::dvec3 colour{1.0};                   // linear, times each element's tint
    double radius = 0.25;                     // what the depth samples cover: m (point) or radians (direction)
    double falloff = 0.0;                     // point lights: full brightness nearer than this (m), then 1/d²
};

// A street lamp of city.json's "lamps" (ARCHITECTURE.md 4.5), in runtime axes.
struct StreetLamp {
    glm::dvec3 position{0.0};  // the light: plan (x, y, h) → (x, h, -y)
    glm::dvec3 colour{1.0};    // linear, max component 1
};

// The "lamps" of a city.json document; an absent key means none. A malformed entry is an
// InputError naming `file` and the entry.
std::vector<StreetLamp> parseStreetLamps(const std::string& cityJson, const std::string& file);
// The lamps of CITY_DIR/city.json; none when there is no city.json.
std::vector<StreetLamp> readStreetLamps(const std::filesystem::path& cityDir);

// The lights of a frame: the sun while it is above the horizon, the lamps as night falls.
std::vector<FlareLight> flareLights(const Lighting& lighting, std::span<const StreetLamp> lamps);

// One instance of the flare draw (flare.vert's attributes 0..2): 48 bytes.
struct FlareInstance {
    glm::vec4 light;    // FlareLight::position
    glm::vec4 colour;   // light colour × tint; w: FlareLight::radius
    glm::vec4 element;  // axis, size, shape, FlareLight::falloff
};
std::vector<FlareInstance> flareInstances(std::span<const FlareLight> lights);

// The GPU side: the program, the instance buffer (grown as needed) and its vertex layout.
class FlarePass {
public:
    void load();
    // Draws additively into the framebuffer bound now (which must not hold `depth`); returns
    // the number of draw calls. `lens` is (near, far, projection[1][1], unused).
    std::size_t draw(std::span<const FlareLight> lights, GLuint depth, glm::vec4 lens);

private:
    gl::Program program_;
    gl::VertexArray vao_;
    gl::Buffer instances_;
    std::size_t capacity_ = 0;
};

}  // namespace dawnforge::runtime
