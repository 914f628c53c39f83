#pragma once
// proxies.json: flat-coloured boxes standing in for the city when irradiance probes capture it
// (the seed talk's "flat-coloured proxies"). Each box is oriented (plan axes u and w, +y up) and
// carries one linear RGB colour per face: the mean colour of the surfaces facing that side,
// weighted by their area projected on it (materialMeanColour() of each material, core/materials.hpp).
//
//   {"format": "dawnforge.proxies", "version": 1,
//    "faces": ["+u", "-u", "+y", "-y", "+w", "-w"],
//    "boxes": [{"name": "building_00012", "part": 0, "kind": "building",
//               "centre": [x, y, z], "u": [ux, 0, uz], "w": [wx, 0, wz], "half_size": [hu, hy, hw],
//               "colours": [[r, g, b] x 6], "overridden": ["+u"]}, ...]}
//
// Boxes: one per section of a building (its LOD1 shell's connected parts: the base and a setback
// tower), cut in two along its long axis while the box is less than 70 % full; one per street
// segment (city.json's streets: asphalt); one per kerb block; per ground tile one per material,
// or one per 20 m square where that material is not flat (hills, the sea floor). No half size
// is below 5 cm (flat ground: a 10 cm slab centred on it).
//
// Artists' overrides live beside the city, in CITY_DIR/proxy_colours.json (so that the generator
// and its recipe stay untouched):
//   {"format": "dawnforge.proxy_colours", "version": 1,
//    "boxes": {"building_00012": {"+u": [0.8, 0.2, 0.1]}, "building_00012/1": {"+y": [0.1, 0.1, 0.1]}}}
// "NAME" sets the face on every part of NAME, "NAME/K" on part K only; colours are linear RGB
// in [0, 1]. An unknown box, part or face is an error.
#include <dawnforge/core/mesh.hpp>

#include <glm/vec3.hpp>

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace dawnforge::bake {

struct ProxyBox {
    std::string name;
    int part = 0;
    std::string kind;                    // "building", "street", "kerb", "ground"
    glm::dvec3 centre{0.0};
    glm::dvec3 u{1, 0, 0}, w{0, 0, 1};   // unit, horizontal
    glm::dvec3 halfSize{0.0};            // along u, y, w
    std::array<glm::vec3, 6> colours{};  // +u, -u, +y, -y, +w, -w
    std::vector<std::string> overridden;
};

inline constexpr std::array<const char*, 6> kProxyFaces{"+u", "-u", "+y", "-y", "+w", "-w"};

// Boxes of a building from its LOD1 shell (world space, material per vertex).
std::vector<ProxyBox> buildingProxies(const std::string& name, const Mesh& lod1);
// Boxes of a ground mesh: its terrain as one box, each kerb (closed part raised above it) as one.
std::vector<ProxyBox> groundProxies(const std::string& name, const Mesh& ground);
// Street boxes from city.json's streets (plan polylines; plan (x, y) at height h is glTF (x, h, -y)).
std::vector<ProxyBox> streetProxies(const std::string& cityJson, const std::string& source);

// Applies CITY_DIR/proxy_colours.json's overrides; throws InputError naming `source`.
void applyProxyOverrides(std::vector<ProxyBox>& boxes, const std::string& json, const std::string& source);

std::string proxiesJson(const std::vector<ProxyBox>& boxes);

}  // namespace dawnforge::bake
