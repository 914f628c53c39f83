#pragma once
// Lightmap UVs: charts from planar faces, packed into one atlas per mesh group (a building's
// LOD0 and LOD1 together, or a ground tile).
//
//  - A patch is a set of triangles that share vertex indices (a generated polygon: its fan
//    shares its corners). Patches are never split, so every vertex gets exactly one UV.
//  - Faces: patches that touch (welded positions, 0.1 mm grid) along an edge, lie in the same
//    plane (normals within about 1°, offsets within 2 mm) and want the same texel size.
//    Triangles with texel size 0 (window glass) get no chart.
//  - Charts grow by unfolding: starting from the largest face not yet placed (projected on its
//    plane, u horizontal on walls, x/z on floors), each face that shares an edge with the chart
//    is turned about that edge into the chart's plane (an isometry, no stretch) and kept when it
//    lands on free texels. So a window's reveals fold into the hole they line, the faces of a
//    storey's wall ring and of a flight of stairs become strips, and few charts are left tiny
//    (each tiny chart costs a whole aligned block). A chart stops growing at kMaxChartTexels;
//    one face longer than that is cut into grid cells of patches. Each chart is finally turned
//    to its minimum-area bounding rectangle.
//  - Blocks: each chart's texel rectangle grows by kChartMargin texels on every side and is
//    rounded up to a multiple of kChartAlign, and blocks sit at multiples of kChartAlign. So at
//    every kept mip level (0..kLightmapLevels-1) no texel straddles two blocks, and a bilinear
//    tap from inside a chart never leaves its block (level l reads half a level-l texel, i.e.
//    2^(l-1) level-0 texels, beyond the sample: kChartMargin covers the last kept level).
//    Dilation fills each block with its own chart's values, so no mip or tap reads another
//    chart (tested in tests/bake/charts_test.cpp).
//  - Packing: skyline bottom-left, tallest blocks first, in a width chosen from the total area.
//  - Extra fixed blocks (the room table) are packed with the charts.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace dawnforge::bake {

inline constexpr int kLightmapLevels = 2;                          // mip levels 0..1 (GL_TEXTURE_MAX_LEVEL = 1)
inline constexpr int kChartAlign = 1 << (kLightmapLevels - 1);     // blocks start and end on multiples of this
inline constexpr int kChartMargin = 1 << (kLightmapLevels - 2);    // texels around a chart's content in its block
inline constexpr int kMaxChartTexels = 1024;                       // longer charts are cut
inline constexpr int kMaxLightmapSize = 4096;                      // an atlas's side, at most

struct ChartMesh {
    std::span<const glm::vec3> positions;    // world space, metres
    std::span<const std::uint32_t> indices;  // three per triangle
    std::span<const float> texelMetres;      // one per triangle; 0: no chart (no lightmap texels)
    std::span<const std::uint8_t> group = {};  // per triangle, or empty: triangles of different groups never
                                               // join (a building's LOD1 shell lies on its LOD0's faces)
};

struct Chart {
    glm::ivec2 origin{0}, size{0};        // its block, texels
    double texelMetres = 0.25;
    std::vector<std::uint32_t> triangles; // in increasing order
    std::vector<glm::dvec2> corners;      // 3 per triangle (same order): texel coordinates in the
                                          // atlas (x right, y down the image), once packed
};

// The charts of a mesh, projected but not yet packed (Chart::origin unset), and the texels
// they need: lets a caller check a memory budget before anything is allocated.
struct ChartSet {
    std::vector<Chart> charts;
    std::vector<std::int32_t> chartOf;  // per triangle, -1: none
    std::size_t blockTexels = 0;        // sum of the charts' block areas
    glm::ivec2 largestBlock{0};
};
ChartSet makeCharts(const ChartMesh& mesh);

struct LightmapLayout {
    glm::ivec2 size{0};                   // atlas width and height in texels (multiples of kChartAlign)
    std::vector<glm::vec2> uv;            // per vertex: texel coordinates in the atlas (divide by size for [0,1])
    std::vector<std::int32_t> chartOf;    // per triangle, -1: none
    std::vector<Chart> charts;
    std::vector<glm::ivec2> extraOrigins; // where each requested extra block went
    std::vector<glm::ivec2> extraSizes;
    std::size_t conflictingVertices = 0;  // vertices shared by two charts (0 for generated cities)
};

// Packs the charts (and extra blocks of the given sizes, each a multiple of kChartAlign) into
// one atlas; throws InputError naming `name` when it would exceed kMaxLightmapSize.
LightmapLayout packLightmap(const ChartMesh& mesh, ChartSet charts, std::span<const glm::ivec2> extraBlocks,
                            const std::string& name);

// Per texel of the atlas: the index of the chart whose block holds it, kExtraBlock + i for
// extra block i, or kUnowned.
inline constexpr std::int32_t kUnowned = -1;
inline constexpr std::int32_t kExtraBlock = 1 << 24;
std::vector<std::int32_t> blockOwners(const LightmapLayout& layout);

// One lightmap texel to bake: where it samples the surface. Covered texels are those within
// half a texel diagonal of a chart triangle (conservative); the sample point is the texel
// centre when a triangle holds it, else the nearest point of the nearest triangle, so that no
// sample leaves its surface (Godot's leaks through corners: a sample off its triangle).
struct TexelSample {
    std::uint32_t texel = 0;     // y * width + x
    std::uint32_t triangle = 0;  // of the mesh
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f};      // its triangle's
};
std::vector<TexelSample> sampleTexels(const ChartMesh& mesh, const LightmapLayout& layout);

}  // namespace dawnforge::bake
