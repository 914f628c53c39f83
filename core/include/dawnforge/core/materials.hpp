#pragma once
// The 16 material IDs of the project, named once: cities are generated with them, fracture
// gives cut faces one of them, and the runtime's atlas has one block per ID in this order.
// They travel in glTF files in the custom attribute _MATERIAL_ID, each material a glTF
// material of its own (exporters/gltf.hpp).
//
// The shaders see the same names: cmake/EmbedShaders.cmake turns every "kName = N," line of
// this enum into "const uint kName = Nu;" in the generated materials.glsl.
#include <glm/vec3.hpp>

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

// Metres one repeat of the material's tile covers, along both u and v (UVs are in metres).
double materialTileMetres(int material);

// The mean linear colour of the material's tile (material_paint.hpp; brick and plaster: the mean
// of their four variants): what it looks like from afar, what the bake bounces light with.
// tests/runtime/atlas_test.cpp recomputes them from the runtime's atlas and holds them to 0.005.
glm::vec3 materialMeanColour(std::uint8_t id);

// How a material's surface answers light in a glTF reader: metal-roughness and opacity.
struct MaterialSurface {
    float roughness = 1.0f;
    float metallic = 0.0f;
    float opacity = 1.0f;  // below 1: blended (window glass)
};
MaterialSurface materialSurface(std::uint8_t id);

}  // namespace dawnforge
