#pragma once
// The leaf picture of the trees' leaf cards (ARCHITECTURE.md 7, Trees and wind): a cluster of
// leaves on a transparent ground, 0..1 across a card. The tree shaders cut the card out where
// alpha is below about 0.5 (leaves.glsl dithers the cutoff by ±0.15), in the colour pass and in
// the shadow pass alike. Made at load, deterministic. The GLBs give the leaf cards the same
// picture (exporters/material_images.hpp, "leaves.png"), cut out by glTF's alpha MASK.
#include <array>
#include <cstdint>
#include <vector>

namespace dawnforge {

inline constexpr int kLeafSize = 256;   // texels per side, level 0
inline constexpr int kLeafLevels = 9;   // 256² .. 1²
inline constexpr float kLeafCutoff = 0.5f;

// sRGB colour (upload as GL_SRGB8_ALPHA8) with linear alpha, level l (kLeafSize >> l)², row 0
// first. Level 0's alpha is each texel's leaf coverage (4 × 4 samples); the colour of texels
// no leaf covers is the leaves' mean, so filtering never darkens an edge. Each further level
// is a 2 × 2 box average (colour in linear light) whose alpha is then scaled so that as many of
// its texels pass the cutoff as level 0's share: distant crowns keep their density.
struct LeafImage {
    std::array<std::vector<std::uint8_t>, kLeafLevels> rgba;
};
LeafImage makeLeafImage();

// The share of level `level`'s texels whose alpha passes kLeafCutoff.
double leafCoverage(const LeafImage& image, int level);

}  // namespace dawnforge
