#pragma once
// A whole district, or one tile of it: the plan (streets, blocks, lots), the ground, the
// buildings, and what `dawnforge city` writes (city.glb, city.json).
//
// Tiles: tile (i, j) covers plan x in [i*M, (i+1)*M) and y in [j*M, (j+1)*M) for tile size
// M. A building belongs to the tile holding its lot's centroid, a block's kerb to the tile
// holding its centroid, a ground cell to the tile holding its centre. The plan is the whole
// city's whatever is generated, and every entity's randomness comes from its own sub-seed,
// so a tile generated alone is identical to the same tile of the whole city.
#include <dawnforge/core/mesh.hpp>
#include <dawnforge/core/progress.hpp>
#include <dawnforge/core/scene.hpp>
#include <dawnforge/procgen/building.hpp>
#include <dawnforge/procgen/dressing.hpp>
#include <dawnforge/procgen/plan.hpp>
#include <dawnforge/procgen/recipe.hpp>

#include <glm/vec2.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace dawnforge::procgen {

struct CitySettings {
    CityRecipe recipe;
    std::uint64_t seed = 1;
    glm::dvec2 size{500.0, 500.0};       // metres, x by y
    double tileSize = 250.0;
    std::optional<glm::ivec2> tile;      // generate this tile only
    double halo = 0.0;                   // with `tile`: also the buildings of other tiles whose lot comes within
                                         // this many metres of it, and those tiles' ground (a world bake's halo)
    glm::dvec2 origin{0.0};              // plan point at city.glb's origin: a world's tile is tile-local
};

struct CityTile {
    glm::ivec2 index{0};
    Mesh ground;                 // terrain cells (streets are the ground between blocks) and block kerbs
    Mesh land;                   // on the city's edge tiles: the far rings of terrain beyond the margin
    std::vector<int> buildings;  // indices into City::buildings
    std::vector<int> blocks;     // ids of the blocks whose kerb is in this tile
    std::vector<int> trees, lamps;  // indices into City::dressing's trees and lamps (by their foot's tile)
};

struct City {
    CitySettings settings;
    CityPlan plan;
    std::vector<Building> buildings;  // of the generated tiles, in lot order (only lots that hold one)
    std::vector<CityTile> tiles;      // the generated tiles, row by row
    Dressing dressing;                // its trees and lamps: those of the generated tiles (ids of the whole city)
};

// The number of tiles along x and y.
glm::ivec2 tileCount(const CitySettings& settings);
// The tile holding plan point p (clamped to the city).
glm::ivec2 tileOf(const CitySettings& settings, glm::dvec2 p);

// The tile's south-west corner in plan metres.
glm::dvec2 tileCorner(const CitySettings& settings, glm::ivec2 tile);

// The first and last tile (inclusive) that tile `tile` generates with a halo of `metres`: those
// its square grown by `metres` reaches, or the tile alone for no halo.
std::pair<glm::ivec2, glm::ivec2> haloTiles(const CitySettings& settings, glm::ivec2 tile, double metres);

// Whether `lot`'s bounding box comes within `metres` of tile `tile`'s square.
bool lotNearTile(const CitySettings& settings, glm::ivec2 tile, const Lot& lot, double metres);

// Throws InputError for a bad size, tile size or tile index, or a bad recipe.
City generateCity(const CitySettings& settings, const ProgressFn& progress = noProgress);

// What a generated city holds (city.json's "counts", the CLI's summary, the benchmark).
struct CityCounts {
    std::size_t buildings = 0, floors = 0, rooms = 0, windows = 0;
    std::size_t trees = 0, lamps = 0;
    std::size_t trianglesLod0 = 0, trianglesLod1 = 0, trianglesGround = 0, trianglesDressing = 0;
};
CityCounts countCity(const City& city);

// city.json: seed, size, tiles, recipe, counts, coastline, streets, blocks, lots, buildings,
// tree species, trees and lamps.
std::string cityReportJson(const City& city);

// The glTF scene: one root node per tile ("tile_I_J") holding its ground ("ground_I_J"), on
// edge tiles the far land ("land_I_J"), and
// one node per building ("building_NNNNN") whose children show its LOD0 and LOD1 meshes
// ("building_NNNNN_lod0", "..._lod1"), one node hierarchy per tree ("tree_NNNNN", the trunk,
// and "tree_NNNNN_<element>" below it, sharing its species' meshes) and one node per lamp
// ("lamp_NNNNN", sharing the mesh "lamp"). Positions are relative to `settings.origin` (the
// plan point (x, y) at height h is (x - origin.x, h, origin.y - y)). Moves the meshes out of `city`.
Scene takeCityScene(City& city);

}  // namespace dawnforge::procgen
