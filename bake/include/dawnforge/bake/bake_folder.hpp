#pragma once
// CITY_DIR/bake/: what `dawnforge bake` writes and the runtime reads.
//
//   bake.json       {"format": "dawnforge.bake", "version": 1, "city_glb": {"bytes": N, "hash": "16 hex digits"},
//                    "settings": {...}, "channels": {...}, "receivers": [{"name", "kind", "lightmap", "uv",
//                    "size": [w, h], "meshes": [{"node", "vertices"}], "rooms", "room_table": [x, y]}], ...}
//   <name>.png      the receiver's lightmap, RGBA8 (lighting.hpp: R sky, G sun bounce, B AO, A lamps,
//                   each stored as round(255·sqrt(v / range))); row 0 at the top = v 0
//   <name>.uv       little-endian float32 (u, v) per vertex in [0, 1], for each mesh of the receiver
//                   in the order "meshes" lists (a building: its _lod0 node, then its _lod1 node),
//                   each in the vertex order of that node's mesh in city.glb; window glass points
//                   at its room's block of the room table
//   overlook.exr    top-down maps (overlook.hpp)
//   proxies.json    oriented boxes with one colour per face (proxies.hpp)
//
// The hash is of city.glb's bytes: a bake made from another city.glb is refused.
#include <dawnforge/bake/overlook.hpp>

#include <glm/vec2.hpp>

#include <cstdint>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace dawnforge::bake {

struct BakedMesh {
    std::string node;               // the city.glb node whose vertices the UVs follow
    std::vector<glm::vec2> uv;      // one per vertex
};

struct BakedReceiver {
    std::string name;               // building_NNNNN, ground_I_J, ...
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgba; // width × height × 4, row 0 at the top
    std::vector<BakedMesh> meshes;
};

struct BakeFolder {
    std::vector<BakedReceiver> receivers;
    std::optional<OverlookMap> overlook;
};

// A 64-bit hash of a file's bytes (SplitMix64 over 8-byte little-endian words and the length).
std::uint64_t hashFileBytes(std::span<const std::byte> bytes);
std::string hashText(std::uint64_t hash);  // 16 lower-case hex digits

// Whether CITY_DIR/bake/bake.json exists.
bool hasBake(const std::filesystem::path& cityDir);

// Reads CITY_DIR/bake/ for a city whose city.glb has these bytes. Throws InputError naming the
// file for anything missing or malformed, and for a bake of another city.glb.
BakeFolder readBake(const std::filesystem::path& cityDir, std::span<const std::byte> cityGlb);

}  // namespace dawnforge::bake
