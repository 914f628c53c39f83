#pragma once
// The building texture atlas: one 2048² RGBA8 texture of 16 cells, each either one full block
// or four half-size blocks, every block a tileable material texture surrounded by a padding
// ring that continues the tile periodically. Meshes carry UVs in metres; the pixel shader
// wraps them with fract() inside a block and samples with textureGrad() using the gradients
// of the unwrapped coordinate (shaders/atlas.glsl mirrors the functions below).
// Technique: "Tiling based on Atlas and Dynamic UV" (UNDAWN building rendering talk).
//
// Why nothing bleeds: the atlas has mip levels 0..4 only (GL_TEXTURE_MAX_LEVEL = 4). A
// bilinear sample at level l reads at most half a level-l texel (2^(l-1) level-0 texels)
// beyond the sample point, so level 4 reaches 8 of the 16 padding texels; all cells and
// quadrants are aligned to 16 level-0 texels, so no level-1..4 texel straddles two blocks.
#include <dawnforge/core/materials.hpp>  // materialTileMetres

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

namespace dawnforge::runtime {

inline constexpr int kAtlasSize = 2048;   // texels per side, level 0
inline constexpr int kAtlasCell = 512;    // a cell: 4×4 cells tile the atlas
inline constexpr int kAtlasPadding = 16;  // padding ring around every block, level-0 texels
inline constexpr int kAtlasLevels = 5;    // mip levels 0..4 (GL_TEXTURE_MAX_LEVEL = 4)

// Slot s is the cell at column s % 4, row s / 4, where row 0 is the first row of the image
// (atlas v from 0). quadrant -1: the full cell (interior 480²); 0..3: a half-size block
// (interior 224²) at 0 top-left, 1 top-right, 2 bottom-left, 3 bottom-right in image rows.
struct AtlasBlock {
    int slot = 0;
    int quadrant = -1;
    friend bool operator==(const AtlasBlock&, const AtlasBlock&) = default;
};

// 8 bits: bits 0-3 slot, bit 4 half, bits 5-6 quadrant (the per-instance code of the shader).
std::uint32_t encodeBlock(AtlasBlock b);
AtlasBlock decodeBlock(std::uint32_t code);  // bits above 6 are ignored

struct AtlasRect {
    glm::dvec2 origin, size;  // atlas UV units [0,1]
};
AtlasRect blockInterior(AtlasBlock b);  // the usable interior the wrapped UV covers
AtlasRect blockCell(AtlasBlock b);      // interior + padding: all texels a sample may read

// The block a material wears by default. Brick (slot 2) and plaster (slot 4) cells hold four
// half-size colour variants chosen by `variant` (0..3); every other material is the full
// block in slot == material id and ignores `variant`.
AtlasBlock materialBlock(int material, int variant = 0);

// The atlas UV the shader samples: origin + fract(uvMetres / tile) · size, fract = x − floor(x).
glm::dvec2 atlasUv(AtlasBlock b, glm::dvec2 uvMetres, double tileMetres);

// The LOD textureGrad picks for the screen gradients of the UNWRAPPED atlas coordinate
// (uvMetres derivatives times size / tile): log2 of the longer gradient in level-0 texels,
// clamped to [0, kAtlasLevels − 1] (the GL formula without anisotropy).
double atlasLod(AtlasBlock b, glm::dvec2 dUvMetresDx, glm::dvec2 dUvMetresDy, double tileMetres);

// A box of level-0 texels: inclusive min, exclusive max.
struct TexelBox {
    glm::ivec2 min, max;
};

// The level-0 texels a GL_LINEAR_MIPMAP_LINEAR sample at `uv`, `lod` reads: levels floor(lod)
// and floor(lod) + 1, both clamped to [0, maxLevel]; bilinear at level l reads texels i, i+1
// with i = floor(u · size_l − 0.5), and level-l texel i covers level-0 texels [i·2^l, (i+1)·2^l).
// No wrapping or clamping at the atlas edge: a box outside [0, kAtlasSize) means a bad sample.
// `maxLevel` exists so that tests can show what a longer mip chain would read.
TexelBox sampleFootprint(glm::dvec2 uv, double lod, int maxLevel = kAtlasLevels - 1);

inline constexpr int kAtlasCodes = 128;  // block codes (encodeBlock) are 7 bits

// The procedural atlas, sRGB 8-bit (upload as GL_SRGB8_ALPHA8), alpha 255 everywhere.
// Level l is (size >> l)² RGBA8, row 0 first. Levels 1..4 are 2×2 box averages of the level
// above in LINEAR light (what glGenerateMipmap does for sRGB textures), alpha averaged as is.
// blockMean[code] is each block's tile averaged in linear light (rgb; a = 1; unused codes 0):
// what the tile looks like where a pixel covers many of its repeats, which atlas.glsl fades to
// beyond the last level. Byte-identical on every run and any thread count.
struct AtlasImage {
    int size = kAtlasSize;
    std::array<std::vector<std::uint8_t>, kAtlasLevels> rgba;
    std::array<glm::vec4, kAtlasCodes> blockMean{};
};
AtlasImage generateAtlas();

}  // namespace dawnforge::runtime
