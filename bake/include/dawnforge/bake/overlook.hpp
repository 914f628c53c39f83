#pragma once
// overlook.exr: what a camera straight above the city sees, on a grid of `texel` metres over
// the city's bounds in x and z (texel (i, j) covers x in [x0 + i·texel, x0 + (i+1)·texel) and
// z in [z0 + j·texel, ...): row j = 0 at the top of the image is the northern edge, z0).
// Three float32 channels (OpenEXR, ZIP, one part):
//   Z       depth below `top` (metres) of the first surface, terrain or building: what the
//           ocean's shore attenuation reads (the runtime drew this at load before bakes)
//   ground  terrain height (the ground meshes alone)
//   roof    height of the highest building surface above the point, or kNoRoof where no
//           building covers it: probes below it and above `ground` are IN, others OUT
// The header's attributes hold x0, z0, texel and top (dawnforge.x0, ...).
#include <dawnforge/core/mesh.hpp>

#include <glm/vec2.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <vector>

namespace dawnforge::bake {

inline constexpr float kNoRoof = -1000.0f;

struct OverlookMap {
    int width = 0, height = 0;
    glm::dvec2 origin{0.0};  // (x0, z0)
    double texel = 0.5;
    double top = 0.0;        // height of the camera plane
    std::vector<float> depth, ground, roof;  // width × height, row 0 first
};

struct OverlookMesh {
    const Mesh* mesh = nullptr;  // world space
    bool building = false;       // counts for `roof`; otherwise for `ground`
};
// The maps of `meshes` over their bounds in x and z, one vertical ray per texel centre (Embree).
OverlookMap bakeOverlook(std::span<const OverlookMesh> meshes, double texel);

void writeOverlook(const OverlookMap& map, const std::filesystem::path& file);
OverlookMap readOverlook(const std::filesystem::path& file);  // throws InputError naming the file

}  // namespace dawnforge::bake
