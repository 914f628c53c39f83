#pragma once
// A world: a city plan cut into square tiles, each built by its own jobs (ARCHITECTURE.md,
// section 9). `planWorld` decides everything the jobs need and nothing they compute: the
// tiles, the owner tile of every building (the tile holding its lot's centroid: exactly one),
// each tile's halo (the neighbours' buildings its bake traces against), the HLOD quadtree
// over the tiles, the buildings to destroy, and the jobs of every stage. A world of size S
// and seed X holds exactly the buildings, streets, trees and lamps of
// `dawnforge city --size S --seed X`.
#include <dawnforge/bake/bake.hpp>
#include <dawnforge/procgen/city.hpp>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace dawnforge::world {

// Where the plan's origin (its south-west corner at ground level) lies on the globe, WGS84.
struct GeoOrigin {
    double longitude = 10.0;  // degrees east
    double latitude = 50.0;   // degrees north
    double height = 0.0;      // metres above the ellipsoid
};

// The plan's east-north-up frame (x east, y north, z up, metres from the origin) to ECEF
// (WGS84, metres): the root transform of tileset.json, as CesiumJS's
// Transforms.eastNorthUpToFixedFrame gives it (world/src/globe.cpp).
glm::dmat4 enuToEcef(const GeoOrigin& origin);

struct WorldSettings {
    procgen::CityRecipe recipe;
    GeoOrigin origin;                 // where tileset.json puts the world on the globe
    std::uint64_t seed = 1;
    glm::dvec2 size{1024.0, 1024.0};  // metres, x by y
    double tileSize = 256.0;          // metres
    double halo = 64.0;               // metres around a tile that its bake traces against
    int destroyPerTile = 0;           // buildings per tile to fracture, simulate and bake into VATs
    std::vector<int> destroy;         // or these buildings (ids)
    bake::BakeSettings bake;          // every tile's bake
    double haloTexelScale = 4.0;      // the halo's lightmaps (lit, not written): texels this many times as large
};

struct WorldTile {
    glm::ivec2 index{0};
    std::vector<int> buildings;       // owned: ids (= lot ids), ascending
    std::vector<int> haloBuildings;   // other tiles' buildings within the halo, ascending
    std::vector<glm::ivec2> haloTiles;  // the tiles the halo reaches (the tile excluded)
};

// A node of the HLOD quadtree: level L covers 2^L × 2^L tiles from (x·2^L, y·2^L).
struct HlodNode {
    int level = 1;
    glm::ivec2 index{0};
    std::vector<glm::ivec2> tiles;    // the tiles under it that exist
};

struct DestroyJob {
    int building = 0;
    glm::ivec2 tile{0};
};

struct WorldPlan {
    WorldSettings settings;
    glm::ivec2 tileCount{1};
    std::vector<WorldTile> tiles;     // row by row
    std::vector<HlodNode> hlod;       // by level, then row by row
    int hlodLevels = 0;               // the root's level (0: a single tile, no HLOD)
    std::vector<DestroyJob> destroy;  // ascending building id
};

// The stages of `world build`, in the order they run. "hlod" stands for one stage per
// quadtree level ("hlod1", "hlod2", ...), each reading the level below.
inline constexpr const char* kStages[] = {"city", "bake", "hlod", "destroy"};

// Throws InputError for a tile size that is not positive, larger than the world, or makes more
// than 65,536 tiles, a bad size, halo, origin or recipe, or a destroyed building that is not in
// the plan.
WorldPlan planWorld(const WorldSettings& settings, const ProgressFn& progress = {});

// The settings of `procgen::generateCity` for one tile of the world: the tile alone in its own
// frame (origin at its south-west corner), with `halo` metres of its neighbours when > 0.
procgen::CitySettings tileCitySettings(const WorldPlan& plan, glm::ivec2 tile, double halo = 0.0);

std::string tileName(glm::ivec2 tile);                 // "I_J"
std::string hlodName(const HlodNode& node);            // "L_X_Y"
std::string buildingName(int id);                      // "building_NNNNN", as city.glb names it
const WorldTile& findTile(const WorldPlan& plan, glm::ivec2 tile);  // asserts that it exists
int tileTask(const WorldPlan& plan, glm::ivec2 tile);  // the tile's task in the city and bake stages (row by row)
std::string hlodStage(int level);                      // "hlodL": the stage of quadtree level L
// The nodes of stage `stage` ("hlodL") in task order; none for another stage.
std::vector<const HlodNode*> hlodStageNodes(const WorldPlan& plan, const std::string& stage);

// plan.json (ARCHITECTURE.md 9.2), and reading it back: readPlan throws InputError naming the
// file for a missing or malformed plan.
std::string planJson(const WorldPlan& plan);
WorldPlan readPlan(const std::filesystem::path& worldDir);

}  // namespace dawnforge::world
