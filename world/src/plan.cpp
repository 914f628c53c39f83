// planWorld, plan.json and reading it back (plan.hpp).
#include <dawnforge/world/plan.hpp>

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/read_file.hpp>
#include <dawnforge/core/seed.hpp>
#include <dawnforge/procgen/building.hpp>
#include <dawnforge/procgen/geometry2d.hpp>
#include <dawnforge/procgen/plan.hpp>

#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

namespace dawnforge::world {

namespace {

using Json = nlohmann::ordered_json;

constexpr int kMaxTiles = 65536;

void checkSettings(const WorldSettings& s) {
    if (!(std::isfinite(s.size.x) && std::isfinite(s.size.y) && s.size.x > 0.0 && s.size.y > 0.0))
        throw InputError(format("--size: the world must be larger than 0 x 0 m (got {} x {})", s.size.x, s.size.y));
    if (s.size.x > 20000.0 || s.size.y > 20000.0)
        throw InputError(format("--size: a world is at most 20000 x 20000 m (got {} x {})", s.size.x, s.size.y));
    if (!std::isfinite(s.tileSize) || s.tileSize <= 0.0)
        throw InputError(format("--tile-size: must be a positive number of metres (got {})", s.tileSize));
    if (s.tileSize > std::max(s.size.x, s.size.y))
        throw InputError(format("--tile-size: {} m is larger than the world ({} x {} m)", s.tileSize, s.size.x, s.size.y));
    if (s.tileSize < 10.0) throw InputError(format("--tile-size: must be at least 10 m (got {})", s.tileSize));
    const double tiles = std::ceil(s.size.x / s.tileSize - 1e-9) * std::ceil(s.size.y / s.tileSize - 1e-9);
    if (tiles > kMaxTiles)
        throw InputError(format("--tile-size: {} m makes {} tiles, more than {}: choose larger tiles", s.tileSize, tiles, kMaxTiles));
    if (!std::isfinite(s.halo) || s.halo < 0.0 || s.halo > std::max(s.size.x, s.size.y))
        throw InputError(format("--halo: must be 0 to the world's size, {} m (got {})", std::max(s.size.x, s.size.y), s.halo));
    if (!(s.haloTexelScale >= 1.0 && s.haloTexelScale <= 64.0))
        throw InputError(format("--bake-halo-texel-scale: must be 1 to 64 (got {})", s.haloTexelScale));
    const GeoOrigin& o = s.origin;
    if (!(o.longitude >= -180.0 && o.longitude <= 180.0 && o.latitude >= -90.0 && o.latitude <= 90.0 &&
          o.height >= -11000.0 && o.height <= 100000.0))
        throw InputError(format("--origin: longitude -180 to 180, latitude -90 to 90, height -11000 to 100000 m "
                                "(got {}, {}, {})", o.longitude, o.latitude, o.height));
    if (s.destroyPerTile < 0 || s.destroyPerTile > 1000)
        throw InputError(format("--destroy: must be 0 to 1000 buildings per tile (got {})", s.destroyPerTile));
}

procgen::CitySettings citySettings(const WorldSettings& s) {
    procgen::CitySettings c;
    c.recipe = s.recipe;
    c.seed = s.seed;
    c.size = s.size;
    c.tileSize = s.tileSize;
    return c;
}

// Owned and halo buildings of every tile: a lot holds a building when buildBuilding puts one
// on it; it belongs to the tile of its centroid and is in the halo of every other tile it
// comes within `halo` metres of.
void assignBuildings(WorldPlan& plan, const procgen::CityPlan& city, const ProgressFn& progress) {
    const procgen::CitySettings cs = citySettings(plan.settings);
    std::vector<std::uint8_t> holds(city.lots.size());
    tbb::parallel_for(std::size_t{0}, city.lots.size(), [&](std::size_t k) {
        holds[k] = procgen::lotHoldsBuilding(city.lots[k], cs.recipe, cs.seed) ? 1 : 0;
    });
    if (!progress(0.8)) throw Cancelled();
    const double halo = plan.settings.halo;
    for (std::size_t k = 0; k < city.lots.size(); ++k) {
        if (!holds[k]) continue;
        const procgen::Lot& lot = city.lots[k];
        const glm::ivec2 owner = procgen::tileOf(cs, procgen::centroid(lot.polygon));
        plan.tiles[std::size_t(tileTask(plan, owner))].buildings.push_back(lot.id);
        if (halo <= 0.0) continue;
        // The tiles whose halo generation holds the owner (as generateCity decides it).
        const int reach = int(std::ceil(halo / cs.tileSize)) + 1;
        const glm::ivec2 lo = glm::max(owner - reach, glm::ivec2(0)), hi = glm::min(owner + reach, plan.tileCount - 1);
        for (int j = lo.y; j <= hi.y; ++j)
            for (int i = lo.x; i <= hi.x; ++i) {
                const auto [first, last] = procgen::haloTiles(cs, {i, j}, halo);
                const bool generated = glm::all(glm::greaterThanEqual(owner, first)) && glm::all(glm::lessThanEqual(owner, last));
                if (glm::ivec2(i, j) != owner && generated && procgen::lotNearTile(cs, {i, j}, lot, halo))
                    plan.tiles[std::size_t(tileTask(plan, {i, j}))].haloBuildings.push_back(lot.id);
            }
    }
}

void planHalos(WorldPlan& plan) {
    const procgen::CitySettings cs = citySettings(plan.settings);
    if (plan.settings.halo <= 0.0) return;
    for (WorldTile& t : plan.tiles) {
        const auto [lo, hi] = procgen::haloTiles(cs, t.index, plan.settings.halo);
        for (int j = lo.y; j <= hi.y; ++j)
            for (int i = lo.x; i <= hi.x; ++i)
                if (glm::ivec2(i, j) != t.index) t.haloTiles.emplace_back(i, j);
    }
}

void planHlod(WorldPlan& plan) {
    const int largest = std::max(plan.tileCount.x, plan.tileCount.y);
    while ((1 << plan.hlodLevels) < largest) ++plan.hlodLevels;
    for (int level = 1; level <= plan.hlodLevels; ++level) {
        const int span = 1 << level;
        const glm::ivec2 nodes = (plan.tileCount + span - 1) / span;
        for (int y = 0; y < nodes.y; ++y)
            for (int x = 0; x < nodes.x; ++x) {
                HlodNode node{level, {x, y}, {}};
                for (int j = y * span; j < std::min((y + 1) * span, plan.tileCount.y); ++j)
                    for (int i = x * span; i < std::min((x + 1) * span, plan.tileCount.x); ++i) node.tiles.emplace_back(i, j);
                plan.hlod.push_back(std::move(node));
            }
    }
}

// `destroy` ids, or per tile the `destroyPerTile` buildings that come first in a seeded order.
void planDestroy(WorldPlan& plan) {
    const WorldSettings& s = plan.settings;
    std::map<int, glm::ivec2> owner;
    for (const WorldTile& t : plan.tiles)
        for (int b : t.buildings) owner[b] = t.index;
    std::set<int> chosen;
    for (int id : s.destroy) {
        if (!owner.contains(id)) throw InputError(format("--destroy-ids: building {} is not in this world (no lot holds it)", id));
        chosen.insert(id);
    }
    for (const WorldTile& t : plan.tiles) {
        std::vector<int> order = t.buildings;
        const auto key = [&](int id) { return mix64(s.seed ^ mix64(std::uint64_t(id) + 0x5eedu)); };
        std::sort(order.begin(), order.end(), [&](int a, int b) { return key(a) < key(b) || (key(a) == key(b) && a < b); });
        for (std::size_t k = 0; k < order.size() && k < std::size_t(s.destroyPerTile); ++k) chosen.insert(order[k]);
    }
    for (int id : chosen) plan.destroy.push_back({id, owner[id]});
}

Json ivec(glm::ivec2 v) { return Json::array({v.x, v.y}); }

}  // namespace

std::string tileName(glm::ivec2 t) { return format("{}_{}", t.x, t.y); }
std::string hlodName(const HlodNode& n) { return format("{}_{}_{}", n.level, n.index.x, n.index.y); }

std::string buildingName(int id) {
    char text[32];
    std::snprintf(text, sizeof text, "building_%05d", id);
    return text;
}

const WorldTile& findTile(const WorldPlan& plan, glm::ivec2 tile) {
    DAWNFORGE_ASSERT(tile.x >= 0 && tile.y >= 0 && tile.x < plan.tileCount.x && tile.y < plan.tileCount.y, "findTile(): no such tile");
    return plan.tiles[std::size_t(tileTask(plan, tile))];
}

int tileTask(const WorldPlan& plan, glm::ivec2 tile) { return tile.y * plan.tileCount.x + tile.x; }

std::string hlodStage(int level) { return format("hlod{}", level); }

std::vector<const HlodNode*> hlodStageNodes(const WorldPlan& plan, const std::string& stage) {
    std::vector<const HlodNode*> nodes;
    for (const HlodNode& n : plan.hlod)
        if (hlodStage(n.level) == stage) nodes.push_back(&n);
    return nodes;
}

WorldPlan planWorld(const WorldSettings& settings, const ProgressFn& progress) {
    checkSettings(settings);
    bake::checkBakeSettings(settings.bake);
    procgen::validateRecipe(settings.recipe, "recipe");
    WorldPlan plan;
    plan.settings = settings;
    plan.tileCount = procgen::tileCount(citySettings(settings));
    for (int j = 0; j < plan.tileCount.y; ++j)
        for (int i = 0; i < plan.tileCount.x; ++i) plan.tiles.push_back({{i, j}, {}, {}, {}});
    const procgen::CityPlan city = procgen::planCity(settings.recipe, settings.seed, settings.size,
                                                     [&](double f) { return progress(0.5 * f); });
    assignBuildings(plan, city, progress);
    for (WorldTile& t : plan.tiles) std::sort(t.haloBuildings.begin(), t.haloBuildings.end());
    planHalos(plan);
    planHlod(plan);
    planDestroy(plan);
    if (!progress(1.0)) throw Cancelled();
    return plan;
}

procgen::CitySettings tileCitySettings(const WorldPlan& plan, glm::ivec2 tile, double halo) {
    procgen::CitySettings c = citySettings(plan.settings);
    c.tile = tile;
    c.halo = halo;
    c.origin = procgen::tileCorner(c, tile);
    return c;
}

std::string planJson(const WorldPlan& plan) {
    const WorldSettings& s = plan.settings;
    Json j;
    j["format"] = "dawnforge.world";
    j["version"] = 1;
    j["generator"] = "dawnforge world plan";
    j["seed"] = s.seed;
    j["size"] = {s.size.x, s.size.y};
    j["tile_size"] = s.tileSize;
    j["halo"] = s.halo;
    j["coordinates"] = "plan metres: x east, y north; a tile's city.glb is in its own frame, origin at its south-west corner";
    j["origin"] = {{"longitude", s.origin.longitude}, {"latitude", s.origin.latitude}, {"height", s.origin.height}};
    j["tile_count"] = ivec(plan.tileCount);
    j["recipe"] = Json::parse(procgen::recipeJson(s.recipe));
    const bake::BakeSettings& b = s.bake;
    j["bake"] = {{"texel", b.texel},       {"interior_texel", b.interiorTexel}, {"ground_texel", b.groundTexel},
                 {"samples", b.samples},   {"sun_samples", b.sunSamples},        {"bounces", b.bounces},
                 {"ao_radius", b.aoRadius}, {"memory_budget", b.memoryBudgetMb}, {"seed", b.seed},
                 {"halo_texel_scale", s.haloTexelScale}};
    Json tiles = Json::array();
    for (const WorldTile& t : plan.tiles) {
        Json halo{{"tiles", Json::array()}, {"buildings", t.haloBuildings}};
        for (glm::ivec2 h : t.haloTiles) halo["tiles"].push_back(ivec(h));
        const glm::dvec2 origin = glm::dvec2(t.index) * s.tileSize;
        tiles.push_back({{"tile", ivec(t.index)}, {"name", tileName(t.index)}, {"origin", {origin.x, origin.y}},
                         {"buildings", t.buildings}, {"halo", std::move(halo)}});
    }
    j["tiles"] = std::move(tiles);
    Json nodes = Json::array();
    for (const HlodNode& n : plan.hlod) {
        Json under = Json::array();
        for (glm::ivec2 t : n.tiles) under.push_back(ivec(t));
        nodes.push_back({{"name", hlodName(n)}, {"level", n.level}, {"index", ivec(n.index)}, {"tiles", std::move(under)}});
    }
    j["hlod"] = {{"levels", plan.hlodLevels}, {"nodes", std::move(nodes)}};
    Json destroy = Json::array();
    for (const DestroyJob& d : plan.destroy) destroy.push_back({{"building", d.building}, {"tile", ivec(d.tile)}});
    j["destroy"] = std::move(destroy);
    // The jobs of every stage: task K of a stage works on entry K of its list.
    Json jobs = Json::object();
    Json perTile = Json::array();
    for (const WorldTile& t : plan.tiles) perTile.push_back(tileName(t.index));
    jobs["city"] = perTile;
    jobs["bake"] = perTile;
    for (int level = 1; level <= plan.hlodLevels; ++level) {
        Json list = Json::array();
        for (const HlodNode* n : hlodStageNodes(plan, hlodStage(level))) list.push_back(hlodName(*n));
        jobs[hlodStage(level)] = std::move(list);
    }
    Json destroyJobs = Json::array();
    for (const DestroyJob& d : plan.destroy) destroyJobs.push_back(buildingName(d.building));
    jobs["destroy"] = std::move(destroyJobs);
    j["jobs"] = std::move(jobs);
    return j.dump(1) + "\n";
}

namespace {

glm::ivec2 readIvec(const Json& j) { return {j.at(0).get<int>(), j.at(1).get<int>()}; }

WorldPlan parsePlan(const Json& j, const std::string& source) {
    if (j.value("format", "") != "dawnforge.world" || j.value("version", 0) != 1)
        throw InputError(format("{}: not a world plan (expected \"format\": \"dawnforge.world\", \"version\": 1)", source));
    WorldPlan plan;
    WorldSettings& s = plan.settings;
    s.seed = j.at("seed").get<std::uint64_t>();
    s.size = {j.at("size").at(0).get<double>(), j.at("size").at(1).get<double>()};
    s.tileSize = j.at("tile_size").get<double>();
    s.halo = j.at("halo").get<double>();
    if (j.contains("origin")) {  // plans written before it have the default
        const Json& o = j.at("origin");
        s.origin = {o.at("longitude").get<double>(), o.at("latitude").get<double>(), o.at("height").get<double>()};
    }
    s.recipe = procgen::parseRecipe(j.at("recipe").dump(), source + ": recipe");
    const Json& b = j.at("bake");
    s.bake.texel = b.at("texel").get<double>();
    s.bake.interiorTexel = b.at("interior_texel").get<double>();
    s.bake.groundTexel = b.at("ground_texel").get<double>();
    s.bake.samples = b.at("samples").get<int>();
    s.bake.sunSamples = b.at("sun_samples").get<int>();
    s.bake.bounces = b.at("bounces").get<int>();
    s.bake.aoRadius = b.at("ao_radius").get<double>();
    s.bake.memoryBudgetMb = b.at("memory_budget").get<double>();
    s.bake.seed = b.at("seed").get<std::uint64_t>();
    s.haloTexelScale = b.at("halo_texel_scale").get<double>();
    checkSettings(s);
    bake::checkBakeSettings(s.bake);
    plan.tileCount = procgen::tileCount(citySettings(s));
    if (readIvec(j.at("tile_count")) != plan.tileCount || j.at("tiles").size() != std::size_t(plan.tileCount.x * plan.tileCount.y))
        throw InputError(format("{}: the tiles do not match the size and tile size", source));
    for (const Json& t : j.at("tiles")) {
        WorldTile tile{readIvec(t.at("tile")), t.at("buildings").get<std::vector<int>>(),
                       t.at("halo").at("buildings").get<std::vector<int>>(), {}};
        for (const Json& h : t.at("halo").at("tiles")) tile.haloTiles.push_back(readIvec(h));
        plan.tiles.push_back(std::move(tile));
    }
    plan.hlodLevels = j.at("hlod").at("levels").get<int>();
    for (const Json& n : j.at("hlod").at("nodes")) {
        HlodNode node{n.at("level").get<int>(), readIvec(n.at("index")), {}};
        for (const Json& t : n.at("tiles")) node.tiles.push_back(readIvec(t));
        plan.hlod.push_back(std::move(node));
    }
    for (const Json& d : j.at("destroy")) plan.destroy.push_back({d.at("building").get<int>(), readIvec(d.at("tile"))});
    return plan;
}

}  // namespace

WorldPlan readPlan(const std::filesystem::path& worldDir) {
    const std::filesystem::path file = worldDir / "plan.json";
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
        throw InputError(format("{}: no plan.json: not a world folder (dawnforge world plan writes one)", worldDir.string()));
    try {
        return parsePlan(Json::parse(readTextFile(file)), file.string());
    } catch (const Json::exception& e) {
        throw InputError(format("{}: {}", file.string(), oneLine(e.what())));
    }
}

}  // namespace dawnforge::world
