#include <dawnforge/core/materials.hpp>

#include <dawnforge/core/error.hpp>

#include <glm/vec3.hpp>

namespace dawnforge {

const char* materialName(std::uint8_t id) {
    static const char* const kNames[kMaterialCount] = {
        "asphalt", "paving", "brick", "concrete", "plaster", "glass", "metal", "trim",
        "roof_tiles", "roof_flat", "wood", "interior_wall", "floor", "ground", "sand", "rubble"};
    DAWNFORGE_ASSERT(id < kMaterialCount, "material id above 15");
    return kNames[id];
}


double materialTileMetres(int material) {
    static constexpr double kTile[kMaterialCount] = {
        4.0,  // asphalt
        2.0,  // paving: 0.5 m slabs
        2.0,  // brick: 30 courses of 6.7 cm, 8 bricks of 25 cm
        3.0,  // concrete: 1.5 m panels
        3.0,  // plaster
        2.0,  // glass
        2.0,  // metal: 0.25 m ribs
        1.0,  // trim
        2.0,  // roof tiles: 0.25 m rows
        4.0,  // flat roof gravel
        2.0,  // wood: 0.125 m boards
        3.0,  // interior wall
        2.0,  // floor: 0.4 m tiles
        4.0,  // ground
        4.0,  // sand
        2.0,  // rubble: 20 cm chunks
    };
    DAWNFORGE_ASSERT(material >= 0 && material < kMaterialCount, "material must be 0..15");
    return kTile[material];
}

glm::vec3 materialMeanColour(std::uint8_t id) {
    static constexpr glm::vec3 kColours[kMaterialCount] = {
        {0.0497f, 0.0497f, 0.0539f},  // asphalt
        {0.4430f, 0.3512f, 0.2610f},  // paving
        {0.3063f, 0.2062f, 0.1484f},  // brick
        {0.3267f, 0.3267f, 0.3036f},  // concrete
        {0.5860f, 0.4653f, 0.3653f},  // plaster
        {0.0193f, 0.0325f, 0.0540f},  // glass
        {0.1019f, 0.1215f, 0.1510f},  // metal
        {0.5807f, 0.5169f, 0.3760f},  // trim
        {0.3203f, 0.0647f, 0.0277f},  // roof tiles
        {0.2039f, 0.1735f, 0.1391f},  // flat roof
        {0.2040f, 0.0849f, 0.0287f},  // wood
        {0.7874f, 0.7677f, 0.7105f},  // interior wall
        {0.3395f, 0.2691f, 0.1848f},  // floor
        {0.0795f, 0.1429f, 0.0275f},  // ground
        {0.6025f, 0.4759f, 0.2627f},  // sand
        {0.2652f, 0.2235f, 0.1833f},  // rubble
    };
    DAWNFORGE_ASSERT(id < kMaterialCount, "material id above 15");
    return kColours[id];
}

MaterialSurface materialSurface(std::uint8_t id) {
    DAWNFORGE_ASSERT(id < kMaterialCount, "material id above 15");
    switch (id) {
        case kGlass: return {0.05f, 0.0f, 0.55f};     // smooth, and the rooms behind show through
        case kMetal: return {0.45f, 0.6f, 1.0f};      // painted steel: partly bare
        case kSand: case kGround: return {1.0f, 0.0f, 1.0f};
        case kAsphalt: return {0.9f, 0.0f, 1.0f};
        case kRoofTiles: case kTrim: case kPaving: return {0.8f, 0.0f, 1.0f};
        case kFloor: case kWood: return {0.6f, 0.0f, 1.0f};
        default: return {0.9f, 0.0f, 1.0f};
    }
}

}  // namespace dawnforge
