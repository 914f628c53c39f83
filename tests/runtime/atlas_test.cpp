#include <dawnforge/runtime/atlas.hpp>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

using namespace dawnforge::runtime;

namespace {

// A block's rectangle in level-0 texels (exact: all layout numbers are multiples of 1/2048).
struct Texels {
    glm::ivec2 min, max;
};
Texels texels(AtlasRect r) {
    const glm::dvec2 lo = r.origin * double(kAtlasSize), hi = (r.origin + r.size) * double(kAtlasSize);
    return {glm::ivec2(std::lround(lo.x), std::lround(lo.y)), glm::ivec2(std::lround(hi.x), std::lround(hi.y))};
}

bool overlaps(Texels a, Texels b) {
    return a.min.x < b.max.x && b.min.x < a.max.x && a.min.y < b.max.y && b.min.y < a.max.y;
}

bool inside(TexelBox box, Texels cell) {
    return box.min.x >= cell.min.x && box.min.y >= cell.min.y && box.max.x <= cell.max.x && box.max.y <= cell.max.y;
}

std::vector<AtlasBlock> allBlocks() {  // 16 slots × {full, 4 quadrants}
    std::vector<AtlasBlock> blocks;
    for (int slot = 0; slot < 16; ++slot)
        for (int quadrant = -1; quadrant < 4; ++quadrant) blocks.push_back({slot, quadrant});
    return blocks;
}

struct MaterialBlock {
    int material, variant;
    AtlasBlock block;
};
std::vector<MaterialBlock> materialBlocks() {  // what generateAtlas lays out: 14 full + 8 half
    std::vector<MaterialBlock> out;
    for (int material = 0; material < 16; ++material) {
        const int variants = (material == 2 || material == 4) ? 4 : 1;
        for (int variant = 0; variant < variants; ++variant) out.push_back({material, variant, materialBlock(material, variant)});
    }
    return out;
}

const AtlasImage& atlas() {
    static const AtlasImage image = generateAtlas();
    return image;
}

const std::uint8_t* texel(const AtlasImage& image, int level, int x, int y) {
    const int size = image.size >> level;
    return &image.rgba[level][(std::size_t(y) * size + x) * 4];
}

}  // namespace

TEST(AtlasLayout, EncodeDecodeRoundTripsEveryBlock) {
    std::vector<std::uint32_t> codes;
    for (AtlasBlock b : allBlocks()) {
        const std::uint32_t code = encodeBlock(b);
        EXPECT_LT(code, 128U);
        EXPECT_EQ(decodeBlock(code), b) << "code " << code;
        codes.push_back(code);
    }
    std::sort(codes.begin(), codes.end());
    EXPECT_EQ(std::unique(codes.begin(), codes.end()), codes.end()) << "two blocks share a code";
    EXPECT_EQ(encodeBlock({5, -1}), 5U);
    EXPECT_EQ(encodeBlock({2, 3}), 2U | 16U | (3U << 5));
}

TEST(AtlasLayout, InteriorsHaveSixteenTexelsOfPaddingInsideTheirCell) {
    for (AtlasBlock b : allBlocks()) {
        const Texels interior = texels(blockInterior(b)), cell = texels(blockCell(b));
        const int cellSize = b.quadrant < 0 ? kAtlasCell : kAtlasCell / 2;
        EXPECT_EQ(cell.max - cell.min, glm::ivec2(cellSize));
        EXPECT_EQ(interior.min - cell.min, glm::ivec2(kAtlasPadding)) << "slot " << b.slot << " quadrant " << b.quadrant;
        EXPECT_EQ(cell.max - interior.max, glm::ivec2(kAtlasPadding)) << "slot " << b.slot << " quadrant " << b.quadrant;
        EXPECT_EQ(interior.max - interior.min, glm::ivec2(b.quadrant < 0 ? 480 : 224));
        EXPECT_EQ(cell.min % 16, glm::ivec2(0)) << "cells must stay aligned to level-4 texels";
    }
}

TEST(AtlasLayout, CellsTileTheAtlasAndQuadrantsTileTheirCell) {
    std::vector<int> cover(std::size_t(kAtlasSize) * kAtlasSize / 256, 0);  // counts per 16² texels
    for (int slot = 0; slot < 16; ++slot) {
        const Texels cell = texels(blockCell({slot, -1}));
        EXPECT_EQ(cell.min, glm::ivec2(slot % 4, slot / 4) * kAtlasCell) << "slot " << slot;
        for (int y = cell.min.y; y < cell.max.y; y += 16)
            for (int x = cell.min.x; x < cell.max.x; x += 16) ++cover[std::size_t(y / 16) * (kAtlasSize / 16) + x / 16];
        std::vector<int> quadrantCover(32 * 32, 0);
        for (int q = 0; q < 4; ++q) {
            const Texels quadrant = texels(blockCell({slot, q}));
            for (int y = quadrant.min.y; y < quadrant.max.y; y += 16)
                for (int x = quadrant.min.x; x < quadrant.max.x; x += 16) {
                    ASSERT_TRUE(x >= cell.min.x && x < cell.max.x && y >= cell.min.y && y < cell.max.y);
                    ++quadrantCover[std::size_t((y - cell.min.y) / 16) * 32 + (x - cell.min.x) / 16];
                }
        }
        EXPECT_TRUE(std::all_of(quadrantCover.begin(), quadrantCover.end(), [](int c) { return c == 1; })) << "slot " << slot;
    }
    EXPECT_TRUE(std::all_of(cover.begin(), cover.end(), [](int c) { return c == 1; }));
    // Quadrant 1 is to the right of 0, quadrant 2 below it (further from image row 0).
    EXPECT_GT(blockCell({0, 1}).origin.x, blockCell({0, 0}).origin.x);
    EXPECT_GT(blockCell({0, 2}).origin.y, blockCell({0, 0}).origin.y);
}

TEST(AtlasLayout, MaterialBlocksAreDisjoint) {
    const std::vector<MaterialBlock> blocks = materialBlocks();
    ASSERT_EQ(blocks.size(), 22U);
    for (std::size_t i = 0; i < blocks.size(); ++i) {
        EXPECT_EQ(blocks[i].block.slot, blocks[i].material);
        for (std::size_t j = i + 1; j < blocks.size(); ++j)
            EXPECT_FALSE(overlaps(texels(blockCell(blocks[i].block)), texels(blockCell(blocks[j].block))))
                << "material " << blocks[i].material << "/" << blocks[i].variant << " and " << blocks[j].material << "/" << blocks[j].variant;
    }
    EXPECT_EQ(materialBlock(2, 3), (AtlasBlock{2, 3}));
    EXPECT_EQ(materialBlock(7, 3), (AtlasBlock{7, -1})) << "materials without variants ignore the variant";
}

TEST(AtlasSampling, UvWrapsInsideTheInterior) {
    const AtlasBlock b = materialBlock(2, 1);
    const AtlasRect r = blockInterior(b);
    const double tile = dawnforge::materialTileMetres(2);
    EXPECT_EQ(atlasUv(b, {0.0, 0.0}, tile), r.origin);
    EXPECT_EQ(atlasUv(b, {1.0, 0.5}, tile), r.origin + glm::dvec2(0.5, 0.25) * r.size);
    EXPECT_EQ(atlasUv(b, {-0.5, 2.0 * tile}, tile), r.origin + glm::dvec2(0.75, 0.0) * r.size);
    EXPECT_EQ(atlasUv(b, {1.0 + 7.0 * tile, -1.0 - 3.0 * tile}, tile), atlasUv(b, {1.0, -1.0}, tile));
}

TEST(AtlasSampling, LodFollowsTheUnwrappedGradient) {
    const AtlasBlock full = materialBlock(0, 0);
    const double tile = dawnforge::materialTileMetres(0);
    const double metresPerTexel = tile / 480.0;
    EXPECT_DOUBLE_EQ(atlasLod(full, {metresPerTexel, 0}, {0, metresPerTexel}, tile), 0.0);
    EXPECT_NEAR(atlasLod(full, {4 * metresPerTexel, 0}, {0, metresPerTexel}, tile), 2.0, 1e-12);
    EXPECT_NEAR(atlasLod(full, {0, 0}, {0, -8 * metresPerTexel}, tile), 3.0, 1e-12);
    EXPECT_DOUBLE_EQ(atlasLod(full, {0.1 * metresPerTexel, 0}, {0, 0}, tile), 0.0);
    EXPECT_DOUBLE_EQ(atlasLod(full, {1e3, 0}, {0, 1e3}, tile), 4.0);
    EXPECT_DOUBLE_EQ(atlasLod(full, {0, 0}, {0, 0}, tile), 0.0);
    // A half block packs the same tile into 224 texels: one level-0 texel is tile/224 metres.
    const AtlasBlock half = materialBlock(4, 2);
    EXPECT_NEAR(atlasLod(half, {2 * dawnforge::materialTileMetres(4) / 224.0, 0}, {0, 0}, dawnforge::materialTileMetres(4)), 1.0, 1e-12);
}

TEST(AtlasSampling, WrappedSamplesNeverReadOutsideTheirBlockAtAnyMip) {
    std::mt19937_64 rng(20240611);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::uniform_int_distribution<int> kind(0, 5);
    for (const MaterialBlock& m : materialBlocks()) {
        const double tile = dawnforge::materialTileMetres(m.material);
        const Texels cell = texels(blockCell(m.block));
        auto coordinate = [&]() {
            switch (kind(rng)) {
                case 0: return (unit(rng) * 2.0 - 1.0) * 1e4;                                      // huge, either sign
                case 1: return std::round((unit(rng) * 2.0 - 1.0) * 5000.0) * tile;                // exact tile multiples
                case 2: return std::nextafter(std::round((unit(rng) - 0.5) * 100.0) * tile, -1e9);  // just below a multiple
                case 3: return -std::ldexp(1.0, -int(unit(rng) * 60.0) - 20);                       // tiny negative: fract → 1
                case 4: return (unit(rng) * 2.0 - 1.0) * 10.0;
                default: return 0.0;
            }
        };
        auto gradient = [&]() {
            const double length = std::pow(10.0, -5.0 + 8.0 * unit(rng));  // 1e-5 .. 1e3 metres per pixel
            const double angle = 2.0 * 3.141592653589793 * unit(rng);
            return glm::dvec2(std::cos(angle), std::sin(angle)) * length;
        };
        for (int n = 0; n < 20000; ++n) {
            const glm::dvec2 uvMetres(coordinate(), coordinate());
            const glm::dvec2 dx = gradient(), dy = gradient();
            const glm::dvec2 uv = atlasUv(m.block, uvMetres, tile);
            const double lod = atlasLod(m.block, dx, dy, tile);
            ASSERT_GE(lod, 0.0);
            ASSERT_LE(lod, kAtlasLevels - 1.0);
            const TexelBox box = sampleFootprint(uv, lod);
            ASSERT_TRUE(inside(box, cell)) << "material " << m.material << "/" << m.variant << " uv metres (" << uvMetres.x << ", "
                                           << uvMetres.y << ") lod " << lod << " reads [" << box.min.x << "," << box.max.x << ")×["
                                           << box.min.y << "," << box.max.y << ")";
        }
        // The extremes: both interior corners, at the coarsest level.
        for (glm::dvec2 uvMetres : {glm::dvec2(0.0), glm::dvec2(-1e-300), glm::dvec2(std::nextafter(tile, 0.0))})
            EXPECT_TRUE(inside(sampleFootprint(atlasUv(m.block, uvMetres, tile), kAtlasLevels - 1.0), cell));
    }
}

TEST(AtlasSampling, CounterCheckALongerMipChainWouldBleed) {
    // The property above is not vacuous: with the level clamp removed, a far-away sample
    // (lod 5 reads levels 5 and 6) at the interior's edge reads texels of the neighbouring cell.
    for (const MaterialBlock& m : materialBlocks()) {
        const double tile = dawnforge::materialTileMetres(m.material);
        const Texels cell = texels(blockCell(m.block));
        const glm::dvec2 corner = atlasUv(m.block, {0.0, 0.0}, tile);
        EXPECT_TRUE(inside(sampleFootprint(corner, 5.0), cell));
        EXPECT_FALSE(inside(sampleFootprint(corner, 5.0, /*maxLevel=*/11), cell)) << "material " << m.material;
        // So does a sample that forgot to wrap.
        EXPECT_FALSE(inside(sampleFootprint(blockInterior(m.block).origin + blockInterior(m.block).size * 1.1, 0.0), cell));
    }
}

TEST(AtlasImageTest, HasFiveLevelsOfTheRightSizeAndIsOpaque) {
    const AtlasImage& image = atlas();
    ASSERT_EQ(image.size, kAtlasSize);
    for (int level = 0; level < kAtlasLevels; ++level) {
        const std::size_t size = std::size_t(kAtlasSize >> level);
        ASSERT_EQ(image.rgba[level].size(), size * size * 4) << "level " << level;
        for (std::size_t i = 3; i < image.rgba[level].size(); i += 4) ASSERT_EQ(image.rgba[level][i], 255);
    }
}

TEST(AtlasImageTest, PaddingContinuesTheTilePeriodically) {
    const AtlasImage& image = atlas();
    for (const MaterialBlock& m : materialBlocks()) {
        const Texels cell = texels(blockCell(m.block)), interior = texels(blockInterior(m.block));
        const int n = interior.max.x - interior.min.x;
        int mismatches = 0;
        for (int y = cell.min.y; y < cell.max.y; ++y)
            for (int x = cell.min.x; x < cell.max.x; ++x) {
                const int wx = interior.min.x + ((x - interior.min.x) % n + n) % n;
                const int wy = interior.min.y + ((y - interior.min.y) % n + n) % n;
                if (!std::equal(texel(image, 0, x, y), texel(image, 0, x, y) + 4, texel(image, 0, wx, wy))) ++mismatches;
            }
        EXPECT_EQ(mismatches, 0) << "material " << m.material << "/" << m.variant;
    }
}

TEST(AtlasImageTest, TilesHaveNoVisibleSeamAtTheWrap) {
    // The tile is a periodic function, so the step from the last interior column to the
    // first padding column (= tile column 0) is no larger than the usual steps inside the
    // tile. Checked on the materials without joints; in patterned ones (bricks, ribs, boards)
    // a joint may legitimately fall on the seam and the step statistics cannot tell.
    const AtlasImage& image = atlas();
    for (const MaterialBlock& m : materialBlocks()) {
        if (!(m.material == 0 || m.material == 4 || m.material == 5 || m.material == 9 || m.material == 11 || m.material == 13 ||
              m.material == 14))
            continue;
        const Texels interior = texels(blockInterior(m.block));
        const int n = interior.max.x - interior.min.x;
        for (int axis = 0; axis < 2; ++axis) {
            auto step = [&](int k) {  // mean |difference| between line k and line k + 1
                double sum = 0.0;
                for (int t = 0; t < n; ++t) {
                    const glm::ivec2 a = axis == 0 ? glm::ivec2(interior.min.x + k, interior.min.y + t) : glm::ivec2(interior.min.x + t, interior.min.y + k);
                    const glm::ivec2 b = a + (axis == 0 ? glm::ivec2(1, 0) : glm::ivec2(0, 1));
                    for (int c = 0; c < 3; ++c) sum += std::abs(int(texel(image, 0, a.x, a.y)[c]) - int(texel(image, 0, b.x, b.y)[c]));
                }
                return sum / (3.0 * n);
            };
            std::vector<double> steps;
            for (int k = 0; k < n - 1; ++k) steps.push_back(step(k));
            std::sort(steps.begin(), steps.end());
            const double typical = steps[steps.size() * 95 / 100];  // 95th percentile: edges of joints and mortar stay above
            EXPECT_LE(step(n - 1), typical + 1.0) << "material " << m.material << "/" << m.variant << " axis " << axis;
        }
    }
}

TEST(AtlasImageTest, MipLevelsAreLinearLightBoxAverages) {
    const AtlasImage& image = atlas();
    auto toLinear = [](int s) {
        const double x = s / 255.0;
        return x <= 0.04045 ? x / 12.92 : std::pow((x + 0.055) / 1.055, 2.4);
    };
    auto toSrgb = [](double l) { return 255.0 * (l <= 0.0031308 ? l * 12.92 : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055); };
    for (int level = 1; level < kAtlasLevels; ++level) {
        const int size = kAtlasSize >> level;
        int worst = 0;
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x)
                for (int c = 0; c < 3; ++c) {
                    double sum = 0.0;
                    for (int k = 0; k < 4; ++k) sum += toLinear(texel(image, level - 1, 2 * x + k % 2, 2 * y + k / 2)[c]);
                    const double expected = toSrgb(sum / 4.0);
                    worst = std::max(worst, int(std::ceil(std::abs(texel(image, level, x, y)[c] - expected) - 0.5)));
                }
        // 8-bit rounding of the result (and the 16-bit linear intermediate) allows one step.
        EXPECT_LE(worst, 1) << "level " << level;
    }
}

TEST(AtlasImageTest, MaterialsLookDifferent) {
    const AtlasImage& image = atlas();
    auto meanColour = [&](AtlasBlock b) {
        const Texels t = texels(blockInterior(b));
        glm::dvec3 sum(0.0);
        for (int y = t.min.y; y < t.max.y; ++y)
            for (int x = t.min.x; x < t.max.x; ++x) sum += glm::dvec3(texel(image, 0, x, y)[0], texel(image, 0, x, y)[1], texel(image, 0, x, y)[2]);
        return sum / double((t.max.x - t.min.x) * (t.max.y - t.min.y));
    };
    std::vector<glm::dvec3> cells;
    for (int slot = 0; slot < 16; ++slot) {
        const bool half = slot == 2 || slot == 4;
        glm::dvec3 mean(0.0);
        if (half)
            for (int q = 0; q < 4; ++q) mean += meanColour({slot, q}) / 4.0;
        else
            mean = meanColour({slot, -1});
        cells.push_back(mean);
    }
    constexpr double kMargin = 12.0;  // 8-bit sRGB units, Euclidean
    for (int i = 0; i < 16; ++i)
        for (int j = i + 1; j < 16; ++j)
            EXPECT_GT(glm::length(cells[i] - cells[j]), kMargin) << "slots " << i << " and " << j;
    for (int material : {2, 4})
        for (int a = 0; a < 4; ++a)
            for (int b = a + 1; b < 4; ++b)
                EXPECT_GT(glm::length(meanColour({material, a}) - meanColour({material, b})), kMargin)
                    << "material " << material << " variants " << a << " and " << b;
}

TEST(AtlasImageTest, IsIdenticalOnEveryRunAndThreadCount) {
    const AtlasImage& first = atlas();
    const AtlasImage again = generateAtlas();
    AtlasImage serial;
    {
        tbb::global_control oneThread(tbb::global_control::max_allowed_parallelism, 1);
        serial = generateAtlas();
    }
    for (int level = 0; level < kAtlasLevels; ++level) {
        EXPECT_TRUE(first.rgba[level] == again.rgba[level]) << "level " << level;
        EXPECT_TRUE(first.rgba[level] == serial.rgba[level]) << "level " << level;
    }
}

// Each laid-out block's mean (what atlas.glsl fades to beyond level 4) is the mean of its
// interior's level-0 texels in linear light, decoded here with the sRGB formula; every other
// code is zero.
TEST(AtlasImageTest, BlockMeansAreTheirInteriorsLinearMeans) {
    const AtlasImage& image = atlas();
    std::vector<bool> used(kAtlasCodes, false);
    const auto linear = [](std::uint8_t v) { const double s = v / 255.0; return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4); };
    for (const MaterialBlock& m : materialBlocks()) {
        const std::uint32_t code = encodeBlock(m.block);
        used[code] = true;
        const Texels t = texels(blockInterior(m.block));
        glm::dvec3 sum(0.0);
        for (int y = t.min.y; y < t.max.y; ++y)
            for (int x = t.min.x; x < t.max.x; ++x)
                for (int c = 0; c < 3; ++c) sum[c] += linear(texel(image, 0, x, y)[c]);
        const glm::dvec3 mean = sum / double((t.max.x - t.min.x) * (t.max.y - t.min.y));
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(image.blockMean[code][c], mean[c], 2e-4) << "material " << m.material << " variant " << m.variant;
        EXPECT_EQ(image.blockMean[code].a, 1.0f);
    }
    for (int code = 0; code < kAtlasCodes; ++code)
        if (!used[std::size_t(code)]) {
            EXPECT_EQ(image.blockMean[std::size_t(code)], glm::vec4(0.0f)) << "code " << code;
        }
}
