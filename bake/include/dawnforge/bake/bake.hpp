#pragma once
// `dawnforge bake CITY_DIR`: per-building lightmaps (Dentro, the seed talk), the overlook
// depth and roof heights, and flat-coloured proxies for irradiance probes, written to
// CITY_DIR/bake/ (bake_folder.hpp describes the files). The runtime uses them when present.
//
// What is baked: every building's LOD0 (walls, interiors, roofs) and LOD1 shell, and every
// other mesh of city.glb (the ground tiles with their kerbs), each into its own atlas. Rays
// see LOD0 and the ground, not LOD1 (it lies on LOD0's outer faces) and not window glass
// (light goes through it). Lamps hang in the lit rooms that have windows (roomLampLit()).
#include <dawnforge/bake/lighting.hpp>

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/progress.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace dawnforge::bake {

struct BakeSettings {
    double texel = 0.25;            // metres per lightmap texel on buildings' outsides
    double interiorTexel = 0.5;     // rooms (interior walls, floors, ceilings, stairs): coarser, they are 62 % of the area
    double lod1TexelScale = 2.0;    // LOD1 shells (seen from 90 m on): texel × this
    double groundTexel = 1.0;       // ground tiles and kerbs
    int samples = 32;               // hemisphere rays per texel per pass (64: twice the time, little less noise)
    int sunSamples = 16;            // sun positions per texel along the day's path
    int bounces = 2;
    double aoRadius = 1.0;          // metres
    double overlookTexel = 0.5;     // metres per texel of overlook.exr
    double memoryBudgetMb = 4096;   // the bake refuses settings that would need more
    std::uint64_t seed = 1;
};

// A setting that would need more memory than the budget, or a lightmap larger than the
// runtime takes; `suggestedTexel` is the smallest outside texel that fits when every texel size
// (outside, rooms, ground) grows by the same factor (0 when the meshes alone exceed the budget).
class BakeBudgetError : public InputError {
public:
    BakeBudgetError(const std::string& message, double suggestedTexel) : InputError(message), suggestedTexel_(suggestedTexel) {}
    double suggestedTexel() const { return suggestedTexel_; }

private:
    double suggestedTexel_;
};

struct BakeReport {
    std::size_t buildings = 0, receivers = 0, rooms = 0, lamps = 0, proxies = 0;
    std::size_t texels = 0;            // sampled lightmap texels
    std::size_t atlasTexels = 0;       // all atlases' texels
    std::size_t triangles = 0;         // in the ray scene
    std::size_t hiddenTriangles = 0;   // inside solids: no texels
    double estimatedMb = 0.0;          // the memory estimate checked against the budget
    LightingStats lighting;
    double loadSeconds = 0.0, layoutSeconds = 0.0, lightingSeconds = 0.0, writeSeconds = 0.0, seconds = 0.0;
};

// Reads CITY_DIR/city.glb and city.json (and proxy_colours.json when there), bakes, and writes
// CITY_DIR/bake/ whole: into a temporary folder first, which then replaces any old bake, so a
// failed bake leaves nothing half-written. Throws InputError for a missing or incomplete city
// folder, a bad proxy_colours.json, or settings out of range; BakeBudgetError when the texel
// size needs more than the memory budget.
BakeReport bakeCity(const std::filesystem::path& cityDir, const BakeSettings& settings, const ProgressFn& progress = {});

// A tile of a world and its halo (world/, the bake stage), in the tile's frame: the tile's
// receivers are baked and written; the halo's are baked too, so that their light bounces onto
// the tile, and traced against, but not written. A receiver's result depends on its name and
// its surroundings, not on what else is baked, so a tile's buildings match a whole bake.
struct BakeRegion {
    std::vector<MeshNode> nodes;          // city.glb's nodes with world matrices, the tile's and the halo's
    std::vector<bool> halo;               // per node: in the halo (not written)
    std::string regionCityJson;           // city.json of the tile with its halo: its street lamps all light
    std::string cityJson;                 // the tile's city.json (its streets become proxies)
    std::vector<std::byte> cityGlb;       // the tile's city.glb as written, which bake.json binds to
    double haloTexelScale = 4.0;          // the halo's lightmaps: texels this many times as large (1 to 64)
};

// Writes CITY_DIR/bake/ for `region` as bakeCity writes it for a city folder.
BakeReport bakeRegion(const BakeRegion& region, const std::filesystem::path& cityDir, const BakeSettings& settings,
                      const ProgressFn& progress = {});

// Throws InputError naming the setting when `settings` is out of range.
void checkBakeSettings(const BakeSettings& settings);

}  // namespace dawnforge::bake
