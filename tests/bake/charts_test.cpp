// Lightmap UVs (charts.hpp): no overlap, and no bilinear tap at any kept mip level reads
// another chart's block, on the LOD0 and LOD1 meshes of generated buildings.
#include "scene_builder.hpp"

#include <dawnforge/bake/charts.hpp>
#include <dawnforge/bake/lighting.hpp>
#include <dawnforge/core/materials.hpp>
#include <dawnforge/procgen/city.hpp>

#include <gtest/gtest.h>

#include <algorithm>

namespace dawnforge::bake {
namespace {

struct BuildingMesh {
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> indices;
    std::vector<float> texel;
};

// The first buildings of a small generated city, LOD0, with the bake's texel sizes
// (bake.hpp: 0.25 m outside, 0.5 m in rooms, none on glass).
std::vector<BuildingMesh> generatedBuildings(std::size_t count) {
    procgen::CitySettings settings;
    settings.size = {120.0, 100.0};
    procgen::City city = procgen::generateCity(settings);
    const Scene scene = procgen::takeCityScene(city);
    std::vector<BuildingMesh> out;
    for (const Node& node : scene.nodes) {
        if (!node.name.ends_with("_lod0") || node.mesh < 0 || out.size() == count) continue;
        const Mesh& m = scene.meshes[std::size_t(node.mesh)];
        BuildingMesh b;
        for (const glm::vec3& p : m.positions) b.positions.push_back(node.translation + node.rotation * (node.scale * p));
        b.indices = m.indices;
        for (std::size_t t = 0; t < m.triangleCount(); ++t) {
            const std::uint8_t mat = m.materialIds[m.indices[3 * t]];
            b.texel.push_back(mat == kGlass ? 0.0f : (mat == kInteriorWall || mat == kFloor) ? 0.5f : 0.25f);
        }
        out.push_back(std::move(b));
    }
    return out;
}

TEST(Charts, BlocksDoNotOverlapAndHoldTheirTriangles) {
    for (const BuildingMesh& b : generatedBuildings(3)) {
        const ChartMesh mesh{b.positions, b.indices, b.texel};
        const LightmapLayout layout = packLightmap(mesh, makeCharts(mesh), std::vector<glm::ivec2>{{4, 2}}, "building");
        ASSERT_GT(layout.charts.size(), 10u);
        EXPECT_EQ(layout.conflictingVertices, 0u);
        std::vector<int> cover(std::size_t(layout.size.x) * std::size_t(layout.size.y), 0);
        const auto mark = [&](glm::ivec2 o, glm::ivec2 s) {
            EXPECT_EQ(o.x % kChartAlign, 0);
            EXPECT_EQ(o.y % kChartAlign, 0);
            EXPECT_EQ(s.x % kChartAlign, 0);
            EXPECT_EQ(s.y % kChartAlign, 0);
            ASSERT_LE(o.x + s.x, layout.size.x);
            ASSERT_LE(o.y + s.y, layout.size.y);
            for (int y = o.y; y < o.y + s.y; ++y)
                for (int x = o.x; x < o.x + s.x; ++x) ++cover[std::size_t(y) * std::size_t(layout.size.x) + std::size_t(x)];
        };
        for (const Chart& c : layout.charts) mark(c.origin, c.size);
        mark(layout.extraOrigins[0], layout.extraSizes[0]);
        EXPECT_LE(*std::max_element(cover.begin(), cover.end()), 1) << "two blocks overlap";
        // Every charted triangle's UVs lie in its chart's block, inside the margin.
        for (std::size_t t = 0; t < b.indices.size() / 3; ++t) {
            const std::int32_t c = layout.chartOf[t];
            if (b.texel[t] == 0.0f) {
                EXPECT_EQ(c, -1);
                continue;
            }
            ASSERT_GE(c, 0);
            const Chart& chart = layout.charts[std::size_t(c)];
            for (int k = 0; k < 3; ++k) {
                const glm::vec2 uv = layout.uv[b.indices[3 * t + std::size_t(k)]];
                EXPECT_GE(uv.x, float(chart.origin.x + kChartMargin) - 1e-3f);
                EXPECT_GE(uv.y, float(chart.origin.y + kChartMargin) - 1e-3f);
                EXPECT_LE(uv.x, float(chart.origin.x + chart.size.x - kChartMargin) + 1e-3f);
                EXPECT_LE(uv.y, float(chart.origin.y + chart.size.y - kChartMargin) + 1e-3f);
            }
        }
    }
}

// Bilinear taps at mip level l read the level-l texels around the sample; a level-l texel
// covers 2^l level-0 texels. All of them must belong to the sample's own block, at every kept level.
TEST(Charts, NoMipLevelOrBilinearTapReadsAnotherChart) {
    for (const BuildingMesh& b : generatedBuildings(2)) {
        const ChartMesh mesh{b.positions, b.indices, b.texel};
        const LightmapLayout layout = packLightmap(mesh, makeCharts(mesh), {}, "building");
        const std::vector<std::int32_t> owners = blockOwners(layout);
        std::size_t checked = 0;
        for (std::size_t t = 0; t < b.indices.size() / 3; ++t) {
            const std::int32_t c = layout.chartOf[t];
            if (c < 0) continue;
            for (int k = 0; k < 3; ++k) {
                const glm::vec2 uv = layout.uv[b.indices[3 * t + std::size_t(k)]];
                for (int level = 0; level < kLightmapLevels; ++level) {
                    const float scale = float(1 << level);
                    const glm::vec2 p = uv / scale - 0.5f;  // level-l texel space, centres at integers
                    for (int dy = 0; dy <= 1; ++dy)
                        for (int dx = 0; dx <= 1; ++dx) {
                            const int lx = int(std::floor(p.x)) + dx, ly = int(std::floor(p.y)) + dy;
                            for (int sy = 0; sy < (1 << level); ++sy)
                                for (int sx = 0; sx < (1 << level); ++sx) {
                                    const int x = std::clamp(lx * (1 << level) + sx, 0, layout.size.x - 1);
                                    const int y = std::clamp(ly * (1 << level) + sy, 0, layout.size.y - 1);
                                    ASSERT_EQ(owners[std::size_t(y) * std::size_t(layout.size.x) + std::size_t(x)], c)
                                        << "triangle " << t << " level " << level;
                                    ++checked;
                                }
                        }
                }
            }
        }
        EXPECT_GT(checked, 10000u);
    }
}

TEST(Charts, DilationFillsEachBlockFromItsOwnTexelsOnly) {
    // Two blocks side by side, one sampled texel each: every texel takes its own block's value.
    const glm::ivec2 size{8, 4};
    std::vector<std::int32_t> owners(32);
    for (int i = 0; i < 32; ++i) owners[std::size_t(i)] = (i % 8) < 4 ? 0 : 1;
    std::vector<float> values(32, 0.0f);
    std::vector<std::uint8_t> filled(32, 0);
    values[9] = 1.0f, filled[9] = 1;     // (1, 1) in block 0
    values[14] = 5.0f, filled[14] = 1;   // (6, 1) in block 1
    const float empty = -1.0f;
    dilate(values, 1, filled, owners, size, std::span(&empty, 1));
    for (int i = 0; i < 32; ++i) EXPECT_EQ(values[std::size_t(i)], (i % 8) < 4 ? 1.0f : 5.0f) << i;
}

TEST(Charts, TexelSamplesLieOnTheirTriangles) {
    test::ReceiverBuilder r;
    r.quad({0, 0, 0}, {3.3f, 0, 0}, {0, 2.1f, 0}, {0, 0, 1}, 0.25f);
    r.quad({0, 0, 0}, {0, 0, 1.7f}, {0, 2.1f, 0}, {-1, 0, 0}, 0.25f);
    r.input();
    for (const TexelSample& s : sampleTexels(r.chartMesh(), r.layout)) {
        const bool onFront = std::abs(s.position.z) < 1e-5f && s.position.x >= -1e-5f && s.position.x <= 3.3f + 1e-5f;
        const bool onSide = std::abs(s.position.x) < 1e-5f && s.position.z >= -1e-5f && s.position.z <= 1.7f + 1e-5f;
        EXPECT_TRUE(onFront || onSide) << s.position.x << " " << s.position.y << " " << s.position.z;
        EXPECT_GE(s.position.y, -1e-5f);
        EXPECT_LE(s.position.y, 2.1f + 1e-5f);
    }
}

}  // namespace
}  // namespace dawnforge::bake
