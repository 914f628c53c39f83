// The building texture atlas: block layout, the wrap/LOD arithmetic the shader mirrors
// (shaders/atlas.glsl), and the atlas image of core's procedural material tiles (material_paint).
//
// Determinism: every texel is a pure function of its position (integer hashes, no shared
// state, no reductions), so the result does not depend on the thread count; build with
// -ffp-contract=off like the rest of dawnforge so float expressions round the same way.
#include <dawnforge/runtime/atlas.hpp>

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/materials.hpp>
#include <dawnforge/core/material_paint.hpp>

#include <glm/common.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace dawnforge::runtime {

namespace {

constexpr int kHalfCell = kAtlasCell / 2;
constexpr int kCellsPerRow = kAtlasSize / kAtlasCell;

void checkBlock(AtlasBlock b) {
    DAWNFORGE_ASSERT(b.slot >= 0 && b.slot < 16, "slot must be 0..15");
    DAWNFORGE_ASSERT(b.quadrant >= -1 && b.quadrant < 4, "quadrant must be -1..3");
}

struct TexelSquare {
    glm::ivec2 origin;  // level-0 texels
    int size = 0;
};

TexelSquare cellTexels(AtlasBlock b) {
    checkBlock(b);
    TexelSquare cell{{b.slot % kCellsPerRow * kAtlasCell, b.slot / kCellsPerRow * kAtlasCell}, kAtlasCell};
    if (b.quadrant >= 0) {
        cell.origin += glm::ivec2(b.quadrant % 2, b.quadrant / 2) * kHalfCell;
        cell.size = kHalfCell;
    }
    return cell;
}

TexelSquare interiorTexels(AtlasBlock b) {
    TexelSquare cell = cellTexels(b);
    return {cell.origin + kAtlasPadding, cell.size - 2 * kAtlasPadding};
}

AtlasRect toUv(TexelSquare s) {
    return {glm::dvec2(s.origin) / double(kAtlasSize), glm::dvec2(s.size) / double(kAtlasSize)};
}

int wrapIndex(int i, int period) {
    int r = i % period;
    return r < 0 ? r + period : r;
}

std::uint8_t toByte(float x) { return std::uint8_t(std::clamp(int(x * 255.0f + 0.5f), 0, 255)); }

// ---- Layout of the generated atlas --------------------------------------------------------

struct PlacedBlock {
    AtlasBlock block;
    int material = 0, variant = 0;
};

std::vector<PlacedBlock> atlasLayout() {
    std::vector<PlacedBlock> blocks;
    for (int material = 0; material < kMaterialCount; ++material) {
        if (materialHasVariants(material))
            for (int variant = 0; variant < 4; ++variant) blocks.push_back({materialBlock(material, variant), material, variant});
        else
            blocks.push_back({materialBlock(material, 0), material, 0});
    }
    return blocks;
}

// ---- sRGB ⇄ linear for the mip chain ------------------------------------------------------

struct SrgbTables {
    std::array<std::uint16_t, 256> toLinear{};     // sRGB8 → linear · 65535
    std::vector<std::uint8_t> fromLinear;          // linear · 65535 → nearest sRGB8
};

double srgbToLinear(double s) { return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4); }
double linearToSrgb(double l) { return l <= 0.0031308 ? l * 12.92 : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055; }

const SrgbTables& srgbTables() {
    static const SrgbTables tables = [] {
        SrgbTables t;
        for (int k = 0; k < 256; ++k) t.toLinear[k] = std::uint16_t(std::lround(srgbToLinear(k / 255.0) * 65535.0));
        t.fromLinear.resize(65536);
        for (int x = 0; x < 65536; ++x) t.fromLinear[x] = std::uint8_t(std::lround(linearToSrgb(x / 65535.0) * 255.0));
        return t;
    }();
    return tables;
}

void downsample(const std::vector<std::uint8_t>& src, int srcSize, std::vector<std::uint8_t>& dst) {
    const int size = srcSize / 2;
    dst.assign(std::size_t(size) * size * 4, 0);
    const SrgbTables& t = srgbTables();
    tbb::parallel_for(tbb::blocked_range<int>(0, size, 16), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y)
            for (int x = 0; x < size; ++x) {
                const std::uint8_t* a = &src[(std::size_t(2 * y) * srcSize + 2 * x) * 4];
                const std::uint8_t* b = a + std::size_t(srcSize) * 4;
                std::uint8_t* out = &dst[(std::size_t(y) * size + x) * 4];
                for (int c = 0; c < 3; ++c) {
                    const unsigned sum = t.toLinear[a[c]] + t.toLinear[a[c + 4]] + t.toLinear[b[c]] + t.toLinear[b[c + 4]];
                    out[c] = t.fromLinear[(sum + 2) / 4];
                }
                out[3] = std::uint8_t((a[3] + a[7] + b[3] + b[7] + 2) / 4);
            }
    });
}

}  // namespace

std::uint32_t encodeBlock(AtlasBlock b) {
    checkBlock(b);
    if (b.quadrant < 0) return std::uint32_t(b.slot);
    return std::uint32_t(b.slot) | (1U << 4) | (std::uint32_t(b.quadrant) << 5);
}

AtlasBlock decodeBlock(std::uint32_t code) {
    const bool half = (code >> 4 & 1U) != 0;
    return {int(code & 15U), half ? int(code >> 5 & 3U) : -1};
}

AtlasRect blockInterior(AtlasBlock b) { return toUv(interiorTexels(b)); }

AtlasRect blockCell(AtlasBlock b) { return toUv(cellTexels(b)); }

AtlasBlock materialBlock(int material, int variant) {
    DAWNFORGE_ASSERT(material >= 0 && material < kMaterialCount, "material must be 0..15");
    DAWNFORGE_ASSERT(variant >= 0 && variant < 4, "variant must be 0..3");
    return materialHasVariants(material) ? AtlasBlock{material, variant} : AtlasBlock{material, -1};
}

glm::dvec2 atlasUv(AtlasBlock b, glm::dvec2 uvMetres, double tileMetres) {
    const AtlasRect r = blockInterior(b);
    const glm::dvec2 t = uvMetres / tileMetres;
    return r.origin + (t - glm::floor(t)) * r.size;
}

double atlasLod(AtlasBlock b, glm::dvec2 dUvMetresDx, glm::dvec2 dUvMetresDy, double tileMetres) {
    const double texelsPerMetre = blockInterior(b).size.x / tileMetres * kAtlasSize;
    const double rho = std::max(std::hypot(dUvMetresDx.x, dUvMetresDx.y), std::hypot(dUvMetresDy.x, dUvMetresDy.y)) * texelsPerMetre;
    if (!(rho > 1.0)) return 0.0;
    return std::min(std::log2(rho), double(kAtlasLevels - 1));
}

TexelBox sampleFootprint(glm::dvec2 uv, double lod, int maxLevel) {
    DAWNFORGE_ASSERT(maxLevel >= 0 && (kAtlasSize >> maxLevel) >= 1, "maxLevel out of range");
    const int first = int(std::clamp(std::floor(lod), 0.0, double(maxLevel)));
    const int levels[2] = {first, std::min(first + 1, maxLevel)};
    TexelBox box{glm::ivec2(kAtlasSize * 2), glm::ivec2(-kAtlasSize * 2)};
    for (int level : levels) {
        const double size = double(kAtlasSize >> level);
        const int scale = 1 << level;
        const glm::ivec2 i(int(std::floor(uv.x * size - 0.5)), int(std::floor(uv.y * size - 0.5)));
        box.min = glm::min(box.min, i * scale);
        box.max = glm::max(box.max, (i + 2) * scale);
    }
    return box;
}

AtlasImage generateAtlas() {
    AtlasImage image;
    std::vector<std::uint8_t>& level0 = image.rgba[0];
    level0.assign(std::size_t(kAtlasSize) * kAtlasSize * 4, 255);

    // 1. Each block's tile at its interior resolution, one task per group of rows.
    const std::vector<PlacedBlock> blocks = atlasLayout();
    std::vector<std::vector<std::uint8_t>> tiles(blocks.size());
    std::vector<int> firstRow(blocks.size() + 1, 0);
    for (std::size_t k = 0; k < blocks.size(); ++k) {
        const int n = interiorTexels(blocks[k].block).size;
        tiles[k].resize(std::size_t(n) * n * 3);
        firstRow[k + 1] = firstRow[k] + n;
    }
    tbb::parallel_for(tbb::blocked_range<int>(0, firstRow.back(), 8), [&](const tbb::blocked_range<int>& rows) {
        for (int r = rows.begin(); r < rows.end(); ++r) {
            const std::size_t k = std::size_t(std::upper_bound(firstRow.begin(), firstRow.end(), r) - firstRow.begin() - 1);
            const int n = firstRow[k + 1] - firstRow[k], j = r - firstRow[k];
            const float v = (float(j) + 0.5f) / float(n);
            std::uint8_t* out = &tiles[k][std::size_t(j) * n * 3];
            for (int i = 0; i < n; ++i) {
                const glm::vec3 c = paintMaterial(blocks[k].material, blocks[k].variant, (float(i) + 0.5f) / float(n), v);
                out[3 * i] = toByte(c.r);
                out[3 * i + 1] = toByte(c.g);
                out[3 * i + 2] = toByte(c.b);
            }
        }
    });

    // Each tile's mean in linear light, summed in a fixed order.
    const SrgbTables& srgb = srgbTables();
    for (std::size_t k = 0; k < blocks.size(); ++k) {
        double sum[3] = {0.0, 0.0, 0.0};
        for (std::size_t t = 0; t < tiles[k].size(); ++t) sum[t % 3] += srgb.toLinear[tiles[k][t]];
        const double n = double(tiles[k].size() / 3) * 65535.0;
        image.blockMean[encodeBlock(blocks[k].block)] = glm::vec4(float(sum[0] / n), float(sum[1] / n), float(sum[2] / n), 1.0f);
    }

    // 2. Fill every cell, interior and padding, from the tile at the wrapped position.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size()), [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t k = range.begin(); k < range.end(); ++k) {
            const TexelSquare cell = cellTexels(blocks[k].block);
            const int n = cell.size - 2 * kAtlasPadding;
            for (int y = 0; y < cell.size; ++y) {
                const std::uint8_t* row = &tiles[k][std::size_t(wrapIndex(y - kAtlasPadding, n)) * n * 3];
                std::uint8_t* out = &level0[(std::size_t(cell.origin.y + y) * kAtlasSize + cell.origin.x) * 4];
                for (int x = 0; x < cell.size; ++x) {
                    const std::uint8_t* texel = row + wrapIndex(x - kAtlasPadding, n) * 3;
                    out[4 * x] = texel[0];
                    out[4 * x + 1] = texel[1];
                    out[4 * x + 2] = texel[2];
                }
            }
        }
    });

    // 3. The mip chain, box-filtered in linear light.
    for (int level = 1; level < kAtlasLevels; ++level) downsample(image.rgba[level - 1], kAtlasSize >> (level - 1), image.rgba[level]);
    return image;
}

}  // namespace dawnforge::runtime
