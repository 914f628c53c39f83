#pragma once
// glTF 2.0 output (GLB). One glTF mesh per Scene mesh, one node per Scene node.
// Attributes: POSITION, NORMAL, TEXCOORD_0, TEXCOORD_1, COLOR_0 (binary RGBA material
// ID, unsigned byte normalized) and the custom attribute _PIECE_ID (float scalar: glTF
// vertex attributes cannot be 32-bit integers; exact up to 2^24 pieces). Scene animations
// become glTF animations: per track a translation and a rotation channel, LINEAR samplers.
#include <dawnforge/core/scene.hpp>

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace dawnforge::exporters {

struct GltfSettings {
    std::string generator = "dawnforge";
};

// The GLB bytes of `scene` (deterministic: same scene, same bytes).
std::vector<std::byte> encodeGlb(const Scene& scene, const GltfSettings& settings = {});

// Writes `scene` as GLB atomically (temporary file + rename).
void writeGlb(const Scene& scene, const std::filesystem::path& file, const GltfSettings& settings = {});

}  // namespace dawnforge::exporters
