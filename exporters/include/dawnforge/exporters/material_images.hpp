#pragma once
// The pictures a glTF reader paints our materials with: one tileable PNG per material ID (brick
// and plaster: one per colour variant), painted from core's procedural tiles (material_paint.hpp)
// at kMaterialImageSize² texels, one repeat per image; a reader repeats it every
// materialTileMetres() through KHR_texture_transform (gltf.hpp).
#include <glm/vec3.hpp>

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace dawnforge::exporters {

inline constexpr int kMaterialImageSize = 256;

// The trees' leaf cards (a tree's `ground` triangles, as the runtime draws them) wear the leaf
// picture of core/leaves.hpp, "leaves.png": the key that stands for it where a material ID would.
inline constexpr int kLeafCards = 16;

// "brick_2.png", "asphalt.png", "leaves.png": the file name of a material's picture (variant
// ignored where the material has none).
std::string materialImageName(int material, int variant);

// The PNG bytes of that picture (the same bytes on every run and thread count; made once per
// process and kept).
const std::vector<std::byte>& materialImagePng(int material, int variant);

// The leaf picture's colour averaged in linear light, weighted by coverage (plain files' leaves).
glm::vec3 leafMeanColour();

// Writes every material's pictures (and the leaves') (created if missing), each atomically; a file
// that already holds the same bytes is left as it is. Returns how many files it wrote.
int writeMaterialImages(const std::filesystem::path& dir);

}  // namespace dawnforge::exporters
