// Baked lightmaps into one texture array (lightmaps.hpp).
#include <dawnforge/runtime/lightmaps.hpp>

#include <dawnforge/bake/bake_folder.hpp>
#include <dawnforge/core/error.hpp>

#include <algorithm>
#include <cstring>
#include <numeric>

namespace dawnforge::runtime {

namespace {

constexpr int kMinLayerSize = 256;
constexpr int kPreferredLayerSize = 2048;  // 16 MB a layer: a district's few layers stay small

}  // namespace

LightmapPlacement placeLightmaps(std::span<const glm::ivec2> sizes, std::span<const std::string> names) {
    LightmapPlacement out;
    int largest = kMinLayerSize;
    std::size_t total = 0;
    for (glm::ivec2 s : sizes) {
        largest = std::max({largest, s.x, s.y});
        total += std::size_t(s.x) * std::size_t(s.y);
    }
    int layer = kMinLayerSize;
    while (layer < largest) layer *= 2;
    // Small cities fit one smaller layer; others use kPreferredLayerSize layers.
    while (layer < kPreferredLayerSize && std::size_t(layer) * std::size_t(layer) < total + total / 4) layer *= 2;
    out.layerSize = layer;
    std::vector<std::size_t> order(sizes.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        if (sizes[a].y != sizes[b].y) return sizes[a].y > sizes[b].y;
        return names[a] < names[b];
    });
    out.placed.assign(sizes.size(), glm::ivec3(0));
    int x = 0, y = 0, shelf = 0, current = 0;
    for (std::size_t i : order) {
        const glm::ivec2 s = sizes[i];
        if (x + s.x > layer) x = 0, y += shelf, shelf = 0;
        if (y + s.y > layer) x = 0, y = 0, shelf = 0, ++current;
        out.placed[i] = glm::ivec3(x, y, current);
        x += s.x;
        shelf = std::max(shelf, s.y);
    }
    out.layers = sizes.empty() ? 0 : current + 1;
    return out;
}

std::optional<BakedCity> loadBakedCity(const std::filesystem::path& cityDir, std::span<const std::byte> cityGlb) {
    if (!bake::hasBake(cityDir)) return std::nullopt;
    const bake::BakeFolder folder = bake::readBake(cityDir, cityGlb);
    BakedCity city;
    std::vector<glm::ivec2> sizes;
    std::vector<std::string> names;
    for (const bake::BakedReceiver& r : folder.receivers) {
        sizes.emplace_back(r.width, r.height);
        names.push_back(r.name);
    }
    const LightmapPlacement placement = placeLightmaps(sizes, names);
    LightmapArray& array = city.lightmaps;
    array.size = placement.layerSize;
    array.layers = placement.layers;
    const std::size_t side = std::size_t(array.size);
    array.rgba.assign(side * side * 4 * std::size_t(array.layers), 0);
    for (std::size_t i = 0; i < folder.receivers.size(); ++i) {
        const bake::BakedReceiver& r = folder.receivers[i];
        const glm::ivec3 at = placement.placed[i];
        const std::size_t layerBase = side * side * 4 * std::size_t(at.z);
        for (int row = 0; row < r.height; ++row)
            std::memcpy(&array.rgba[layerBase + ((std::size_t(at.y) + std::size_t(row)) * side + std::size_t(at.x)) * 4],
                        &r.rgba[std::size_t(row) * std::size_t(r.width) * 4], std::size_t(r.width) * 4);
        const glm::vec2 scale = glm::vec2(r.width, r.height) / float(array.size);
        const glm::vec2 offset = glm::vec2(at.x, at.y) / float(array.size);
        for (const bake::BakedMesh& m : r.meshes) {
            std::vector<glm::vec3>& uv = array.nodeUv[m.node];
            uv.reserve(m.uv.size());
            for (glm::vec2 t : m.uv) uv.emplace_back(offset + t * scale, float(at.z));
        }
    }
    if (folder.overlook) {
        const bake::OverlookMap& map = *folder.overlook;
        OverlookDepth o;
        o.width = map.width, o.height = map.height;
        o.origin = glm::vec2(map.origin);
        o.extent = glm::vec2(float(map.width * map.texel), float(map.height * map.texel));
        o.top = float(map.top);
        o.depth = map.depth;
        city.overlook = std::move(o);
    }
    return city;
}

}  // namespace dawnforge::runtime
