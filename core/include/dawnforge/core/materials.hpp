#pragma once
// The 16 material IDs of the project, named once: cities are generated with them, fracture
// gives cut faces one of them, and the runtime's atlas has one block per ID in this order.
// They travel in COLOR_0 as binary RGBA, id = R + 2G + 4B + 8A (mesh.hpp).
//
// The shaders see the same names: cmake/EmbedShaders.cmake turns every "kName = N," line of
// this enum into "const uint kName = Nu;" in the generated materials.glsl.
#include <cstdint>

namespace dawnforge {

enum Material : std::uint8_t {
    kAsphalt = 0,
    kPaving = 1,        // sidewalks, kerbs
    kBrick = 2,
    kConcrete = 3,
    kPlaster = 4,
    kGlass = 5,         // window glass: carries the interior-mapping attributes
    kMetal = 6,         // railings, frames, shutters
    kTrim = 7,          // stone bands, sills, cornices, coping
    kRoofTiles = 8,
    kRoofFlat = 9,
    kWood = 10,         // doors
    kInteriorWall = 11,
    kFloor = 12,        // slabs, stairs
    kGround = 13,       // unbuilt land
    kSand = 14,         // shore and sea floor
    kRubble = 15,       // fracture cut faces
};
inline constexpr int kMaterialCount = 16;

const char* materialName(std::uint8_t id);  // "asphalt", "paving", ..., "rubble"; id must be below 16

}  // namespace dawnforge
