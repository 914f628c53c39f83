#pragma once
// One building of a written city folder (city.glb + city.json), taken apart for destruction:
// its LOD0 parts as closed solids with what they are made of, and what stands around it
// (the other buildings' LOD1 shells, the ground with its kerbs and sea floor) as the static
// world it falls into.
#include <dawnforge/core/mesh.hpp>
#include <dawnforge/procgen/building.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace dawnforge::procgen {

struct CityBuildingPart {
    PartKind kind = PartKind::Wall;
    std::uint8_t material = 0;  // what it is made of (city.json), not its surface
    Mesh mesh;                  // world space, closed
};

struct CityBuilding {
    int id = 0;
    std::string name;                     // building_NNNNN
    std::vector<CityBuildingPart> parts;  // in city.json's order
    Mesh lod0;                            // the whole LOD0 mesh, world space
    Bounds bounds;                        // of LOD0
    std::vector<Mesh> neighbours;         // other buildings' LOD1 shells near it, world space
    std::vector<Mesh> ground;             // the ground_I_J meshes' triangles as near (streets, kerbs, sea floor; positions only)
};

// Reads building `id` of CITY_DIR. Neighbours are the buildings whose LOD1 bounds come within
// `neighbourRadius` (m) of this building's bounds. Throws InputError (one line naming the folder)
// when city.json or city.glb is missing or unreadable, when the id is not in the folder (saying
// so when the folder holds one tile only), or when the building has no parts listed.
CityBuilding loadCityBuilding(const std::filesystem::path& cityDir, int id, double neighbourRadius = 30.0);

}  // namespace dawnforge::procgen
