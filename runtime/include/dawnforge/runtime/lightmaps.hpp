#pragma once
// The baked lightmaps of a city (CITY_DIR/bake/, written by `dawnforge bake`) as the renderer
// holds them: every receiver's atlas placed in the layers of one RGBA8 texture array, so that
// every building and ground tile reads its lightmap with one fetch, and each baked vertex's
// lightmap coordinate (u, v, layer) in that array.
//
// Placement: receivers sorted by height (then by name), left to right in shelves, a new layer
// when one is full. Atlas sizes are even (bake/charts.hpp, kChartAlign) and so are the offsets,
// so mip level 1 of the array never mixes two receivers, and the charts' own margins keep every
// bilinear tap inside its chart.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace dawnforge::runtime {

struct LightmapArray {
    int size = 0;                              // a layer's side, texels
    int layers = 0;
    std::vector<std::uint8_t> rgba;            // size × size × 4 per layer, layer 0 first, row 0 = v 0
    std::map<std::string, std::vector<glm::vec3>> nodeUv;  // city.glb node -> per vertex (u, v, layer)
};

struct OverlookDepth {
    int width = 0, height = 0;
    glm::vec2 origin{0.0f}, extent{1.0f};  // xz of the first texel's corner, xz size of the map (m)
    float top = 0.0f;                      // camera height: depth is metres below it
    std::vector<float> depth;              // width × height, row 0 at z = origin.y
};

struct BakedCity {
    LightmapArray lightmaps;
    std::optional<OverlookDepth> overlook;
};

// Reads CITY_DIR/bake/ for the city whose city.glb has these bytes, or nothing when the city
// has no bake. Throws InputError for a bake that is broken or made from another city.glb.
std::optional<BakedCity> loadBakedCity(const std::filesystem::path& cityDir, std::span<const std::byte> cityGlb);

// The shelf placement of atlases of these sizes (texels, even): per atlas its layer and
// texel offset; `layerSize` the side of a layer (a power of two, at least 256 and at least
// the largest atlas side).
struct LightmapPlacement {
    int layerSize = 0, layers = 0;
    std::vector<glm::ivec3> placed;  // x, y, layer
};
LightmapPlacement placeLightmaps(std::span<const glm::ivec2> sizes, std::span<const std::string> names);

}  // namespace dawnforge::runtime
