#pragma once
// The procedural material textures: one tileable picture per material ID (brick and plaster in
// four colour variants), painted texel by texel. The runtime's atlas packs them into its blocks
// (runtime/src/atlas.cpp); the glTF writer gives each its own image (exporters/material_images.hpp).
//
// Determinism: every texel is a pure function of (material, variant, u, v): integer hashes and
// float arithmetic only, no libm function that may round differently from one CPU to another.
#include <glm/vec3.hpp>

#include <cstdint>
#include <string_view>

namespace dawnforge {

// The sRGB colour (each channel in [0,1]) of `material`'s tile at tile coordinates (u, v):
// u along the wall or plan x, v up or plan y, one repeat per unit; periodic in both with period 1.
// `variant` (0..3) matters only where materialHasVariants().
glm::vec3 paintMaterial(int material, int variant, float u, float v);

// Brick and plaster come in four colour variants; every other material in one.
bool materialHasVariants(int material);

// The variant a building wears for `material` (0..3; 0 for a material without variants):
// a hash of the building's id, the same in the runtime's atlas and in the glTF files.
int materialVariant(std::uint32_t buildingId, int material);

// The building id whose variants a mesh wears: NNNNN for the city's building_NNNNN_lod0 and
// _lod1 (any name that starts building_ and a number), else 0xffff, which the runtime gives
// every mesh that is not a building's.
std::uint32_t variantBuilding(std::string_view meshName);

}  // namespace dawnforge
