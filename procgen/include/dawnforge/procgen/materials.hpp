#pragma once
// The 16 material IDs of generated cities (COLOR_0, id = R + 2G + 4B + 8A). The runtime's
// atlas has one block per ID in this order.
#include <cstdint>

namespace dawnforge::procgen {

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

const char* materialName(std::uint8_t id);  // "asphalt", "paving", ...

}  // namespace dawnforge::procgen
