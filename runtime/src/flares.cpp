// Lens flares (flares.hpp): the element table, the lights of a frame, city.json's lamps and
// the one instanced draw. Sources: the seed talk's VFX chapter (depth-buffer visibility and
// element placement in the vertex shader, parameters in an instance buffer) and Unity SRP's
// LensFlareCommon.hlsl (occlusion from depth samples on a disc around the light).
#include "flares.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/read_file.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace dawnforge::runtime {

namespace {

using Json = nlohmann::json;

constexpr double kSunRadius = 0.03;      // radians: the sky's sun disk (sunDisk() in common.glsl)
constexpr double kLampRadius = 0.3;      // m: a lamp's bulb and shade, for the depth samples
constexpr double kLampFalloff = 15.0;    // m: nearer lamps flare at full strength, farther ones fade as 1/d²
constexpr double kLampStrength = 0.6;    // a lamp's flare against the sun's (whose colour is up to 3.2)

// A lens's look: a warm glow and a faint halo ring at the light, then ghosts of the aperture
// (round and hexagonal) in cool and warm tints, small near the light, larger and fainter past
// the centre. Tints are small: the flare is added to the HDR image before exposure.
constexpr FlareElement kElements[] = {
    {FlareShape::Glow, 1.0f, 0.085f, {0.55f, 0.5f, 0.42f}},
    {FlareShape::Halo, 1.0f, 0.26f, {0.02f, 0.018f, 0.026f}},
    {FlareShape::Ghost, 0.6f, 0.022f, {0.035f, 0.063f, 0.085f}},
    {FlareShape::HexGhost, 0.3f, 0.035f, {0.07f, 0.05f, 0.025f}},
    {FlareShape::HexGhost, -0.2f, 0.06f, {0.021f, 0.042f, 0.028f}},
    {FlareShape::Ghost, -0.5f, 0.1f, {0.021f, 0.021f, 0.042f}},
    {FlareShape::HexGhost, -0.85f, 0.045f, {0.05f, 0.025f, 0.035f}},
    {FlareShape::Ghost, -1.25f, 0.15f, {0.013f, 0.021f, 0.032f}},
};

[[noreturn]] void fail(const std::string& file, const std::string& what) { throw InputError(file + ": " + what); }

// A fixed-size array of finite numbers at `path`.
std::vector<double> numbers(const Json& j, std::size_t n, const std::string& file, const std::string& path) {
    if (!j.is_array() || j.size() != n || !std::all_of(j.begin(), j.end(), [](const Json& v) { return v.is_number(); }))
        fail(file, format("\"{}\" must be an array of {} numbers (got {})", path, n, oneLine(j.dump())));
    std::vector<double> v;
    for (const Json& x : j) v.push_back(x.get<double>());
    if (!std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); }))
        fail(file, format("\"{}\" must hold finite numbers", path));
    return v;
}

StreetLamp readLamp(const Json& j, const std::string& file, const std::string& path) {
    if (!j.is_object()) fail(file, format("\"{}\" must be an object {{\"light\": [x, y, h], \"colour\": [r, g, b], ...}}", path));
    for (const char* key : {"light", "colour"})
        if (!j.contains(key)) fail(file, format("\"{}.{}\" is missing", path, key));
    if (j.contains("id") && !j["id"].is_number_integer()) fail(file, format("\"{}.id\" must be an integer", path));
    if (j.contains("tile")) numbers(j["tile"], 2, file, path + ".tile");
    if (j.contains("foot")) numbers(j["foot"], 2, file, path + ".foot");
    const std::vector<double> p = numbers(j["light"], 3, file, path + ".light");
    const std::vector<double> c = numbers(j["colour"], 3, file, path + ".colour");
    if (std::any_of(c.begin(), c.end(), [](double x) { return x < 0.0 || x > 1.0; }))
        fail(file, format("\"{}.colour\" must be linear RGB in [0, 1] (got {})", path, j["colour"].dump()));
    return {glm::dvec3(p[0], p[2], -p[1]), glm::dvec3(c[0], c[1], c[2])};
}

}  // namespace

std::span<const FlareElement> flareElements() { return kElements; }

std::vector<StreetLamp> parseStreetLamps(const std::string& cityJson, const std::string& file) {
    Json root;
    try {
        root = Json::parse(cityJson);
    } catch (const Json::exception& e) {
        fail(file, format("not valid JSON: {}", oneLine(e.what())));
    }
    if (!root.is_object() || !root.contains("lamps")) return {};
    const Json& list = root["lamps"];
    if (!list.is_array()) fail(file, "\"lamps\" must be an array of {\"light\": [x, y, h], \"colour\": [r, g, b], ...}");
    // A world's tile (ARCHITECTURE.md 4.5, "origin") has city.glb in its own frame.
    glm::dvec3 origin(0.0);
    if (root.contains("origin")) {
        const std::vector<double> o = numbers(root["origin"], 2, file, "origin");
        origin = glm::dvec3(o[0], 0.0, -o[1]);
    }
    std::vector<StreetLamp> lamps;
    for (std::size_t i = 0; i < list.size(); ++i) {
        lamps.push_back(readLamp(list[i], file, format("lamps[{}]", i)));
        lamps.back().position -= origin;
    }
    return lamps;
}

std::vector<StreetLamp> readStreetLamps(const std::filesystem::path& cityDir) {
    const std::filesystem::path file = cityDir / "city.json";
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) return {};
    return parseStreetLamps(readTextFile(file), file.string());
}

std::vector<FlareLight> flareLights(const Lighting& lighting, std::span<const StreetLamp> lamps) {
    std::vector<FlareLight> lights;
    if (lighting.elevation > 0.0 && lighting.night < 1.0)
        lights.push_back({glm::dvec4(lighting.sunDirection, 0.0), lighting.sunColor, kSunRadius, 0.0});
    if (lighting.night > 0.0)
        for (const StreetLamp& lamp : lamps)
            lights.push_back({glm::dvec4(lamp.position, 1.0), lamp.colour * (kLampStrength * lighting.night), kLampRadius, kLampFalloff});
    return lights;
}

std::vector<FlareInstance> flareInstances(std::span<const FlareLight> lights) {
    std::vector<FlareInstance> out;
    out.reserve(lights.size() * std::size(kElements));
    for (const FlareLight& l : lights)
        for (const FlareElement& e : kElements)
            out.push_back({glm::vec4(l.position), glm::vec4(glm::vec3(l.colour) * e.tint, float(l.radius)),
                           glm::vec4(e.axis, e.size, float(e.shape), float(l.falloff))});
    return out;
}

void FlarePass::load() {
    program_ = gl::makeProgram("flare.vert", "flare.frag");
    vao_ = gl::makeVertexArray();
    for (GLuint a = 0; a < 3; ++a) {
        glVertexArrayAttribFormat(vao_.id(), a, 4, GL_FLOAT, GL_FALSE, GLuint(a * sizeof(glm::vec4)));
        glEnableVertexArrayAttrib(vao_.id(), a);
        glVertexArrayAttribBinding(vao_.id(), a, 0);
    }
    glVertexArrayBindingDivisor(vao_.id(), 0, 1);
}

std::size_t FlarePass::draw(std::span<const FlareLight> lights, GLuint depth, glm::vec4 lens) {
    const std::vector<FlareInstance> instances = flareInstances(lights);
    if (instances.empty()) return 0;
    if (instances.size() > capacity_) {
        capacity_ = std::max(instances.size(), 2 * capacity_);
        instances_ = gl::makeBuffer(nullptr, capacity_ * sizeof(FlareInstance), GL_DYNAMIC_STORAGE_BIT);
        glVertexArrayVertexBuffer(vao_.id(), 0, instances_.id(), 0, sizeof(FlareInstance));
    }
    glNamedBufferSubData(instances_.id(), 0, GLsizeiptr(instances.size() * sizeof(FlareInstance)), instances.data());
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    glUseProgram(program_.id());
    glUniform4fv(0, 1, &lens.x);
    glBindTextureUnit(0, depth);
    glBindVertexArray(vao_.id());
    glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, GLsizei(instances.size()));
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
    return 1;
}

}  // namespace dawnforge::runtime
