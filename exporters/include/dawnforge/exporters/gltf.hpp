#pragma once
// glTF 2.0 output (GLB). One glTF mesh per Scene mesh, one node per Scene node.
// Attributes: POSITION, NORMAL, TEXCOORD_0..3 and the custom attributes _MATERIAL_ID (the
// material ID 0..15), _PIECE_ID and _FEATURE_ID_0 (float scalars: glTF vertex attributes
// cannot be 32-bit integers; exact up to 2^24). A mesh with material IDs has one primitive per
// material it uses (triangles by their first vertex's ID; all share the vertex accessors),
// each with a glTF material a reader understands: named as the material ("brick_2",
// "asphalt"), metal-roughness and opacity from core's materialSurface, and a base colour: the
// material's mean colour, or its picture (material_images.hpp) repeated every
// materialTileMetres() of TEXCOORD_0 through KHR_texture_transform, repeat wrapping, mipmaps.
// A mesh without material IDs (or any mesh, with primitivePerMaterial off) has one primitive
// of a plain light grey material, "default".
// Scene animations become glTF animations: per track a translation and a rotation channel,
// LINEAR samplers.
#include <dawnforge/core/scene.hpp>

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace dawnforge::exporters {

// Where the materials' pictures come from.
enum class MaterialImages {
    kNone,      // plain colours: each material's mean colour (materialMeanColour), no texture
    kEmbedded,  // each picture a material uses, once, in the GLB's binary chunk: a file on its own
    kLinked,    // URIs imageFolder + materialImageName(): one set of files shared by many GLBs
};

struct GltfSettings {
    std::string generator = "dawnforge";
    MaterialImages images = MaterialImages::kNone;
    std::string imageFolder;  // kLinked: the pictures' folder relative to the GLB, ending in '/'
    // false: every mesh one primitive of the plain "default" material, for meshes an engine's
    // own material draws (the VAT meshes: the Labs shaders), so that they import with one slot.
    bool primitivePerMaterial = true;
};

// The GLB bytes of `scene` (deterministic: same scene, same bytes).
std::vector<std::byte> encodeGlb(const Scene& scene, const GltfSettings& settings = {});

// Writes `scene` as GLB atomically (temporary file + rename).
void writeGlb(const Scene& scene, const std::filesystem::path& file, const GltfSettings& settings = {});

}  // namespace dawnforge::exporters
