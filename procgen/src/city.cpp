// The district: plan, ground, buildings (in parallel, one sub-seed each), report and scene.
#include <dawnforge/procgen/city.hpp>
#include <dawnforge/core/materials.hpp>
#include "mesh_builder.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/seed.hpp>

#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <tuple>
#include <map>
#include <mutex>
#include <numbers>
#include <span>

namespace dawnforge::procgen {

namespace {

constexpr double kCellSize = 10.0;  // ground grid
// The sea floor starts falling this far out from the coastline: ground cells are coarser
// than the coast's curve, and a cell that dipped early would cut into the promenade.
constexpr double kQuay = 1.5 * kCellSize;

// Ground height at a plan point: 0 on land and along the quay, falling under the sea.
double groundHeight(const CityPlan& plan, const CoastRecipe& coast, glm::dvec2 p) {
    const double fall = coastY(plan, p.x) - kQuay - p.y;
    if (fall <= 0.0) return 0.0;
    return -std::min(coast.seabedDepth, fall * coast.seabedSlope);
}

double smoothstep(double e0, double e1, double x) {
    const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// The hills' three crossed waves: each a direction and a phase, turned and shifted by the seed.
struct Hills {
    std::array<glm::dvec2, 3> dir;
    std::array<double, 3> phase;
};

Hills hillsOf(std::uint64_t seed) {
    Hills h;
    for (std::uint64_t k = 0; k < 3; ++k) {
        Rng rng(deriveSeed(seed, "hills", k));
        const double angle = rng.uniform(0.0, 6.283185307179586);
        h.phase[k] = rng.uniform(0.0, 6.283185307179586);
        h.dir[k] = {std::cos(angle), std::sin(angle)};
    }
    return h;
}

// The land beyond the city's edge: the city's ground where that is sea, and otherwise hills
// that rise from 0 at the edge (and at the shore) over 0.4 wavelengths: the three waves of
// `hills` at the recipe's wavelength.
double terrainHeight(const City& city, const Hills& hills, glm::dvec2 p) {
    const CitySettings& s = city.settings;
    const TerrainRecipe& t = s.recipe.terrain;
    const double ground = groundHeight(city.plan, s.recipe.coast, p);
    const glm::dvec2 outside = glm::max(glm::max(-p, p - s.size), glm::dvec2(0.0));
    const double beyond = glm::length(outside);
    if (ground < 0.0 || beyond <= 0.0 || t.hillHeight <= 0.0) return ground;
    const double shore = p.y - (coastY(city.plan, p.x) - kQuay);  // +inf without a sea
    double wave = 0.0;
    for (std::size_t k = 0; k < 3; ++k)
        wave += std::sin(glm::dot(p, hills.dir[k]) * 6.283185307179586 / t.hillWavelength + hills.phase[k]) / 3.0;
    const double rise = 0.4 * t.hillWavelength;
    return t.hillHeight * smoothstep(0.0, rise, beyond) * smoothstep(0.0, rise, shore) * (0.5 + 0.5 * wave);
}

// Beyond the terrain's margin, rings of cells growing by kFarGrowth reach kFarRings out
// (about 4.7 km for 10 m cells): land to the horizon, or sea where the coast runs on.
constexpr int kFarRings = 12;
constexpr double kFarGrowth = 1.6;

// Where cell boundary i lies along an axis of `size` metres with `cells` cells and `margin`
// margin cells each side: every kCellSize metres inside (the last cell may be narrower) and
// in the margin, then growing rings.
double cellEdge(int i, int cells, double size, int margin) {
    const auto far = [](int k) { return kCellSize * (std::pow(kFarGrowth, k) - 1.0) / (kFarGrowth - 1.0); };
    if (i < -margin) return -(margin * kCellSize + far(-margin - i));
    if (i > cells + margin) return size + margin * kCellSize + far(i - cells - margin);
    return i >= cells ? size + (i - cells) * kCellSize : i * kCellSize;
}

// One ground cell: asphalt in the city, grass beyond it, sand where a corner is under water.
void addCell(MeshBuilder& mb, const City& city, const Hills& hills, glm::dvec2 lo, glm::dvec2 hi, bool inCity) {
    const glm::dvec2 c[4] = {lo, {hi.x, lo.y}, hi, {lo.x, hi.y}};
    glm::dvec3 p[4];
    bool wet = false;
    for (int k = 0; k < 4; ++k) {
        p[k] = {c[k], terrainHeight(city, hills, c[k])};
        wet = wet || p[k].z < 0.0;
    }
    const std::uint8_t material = wet ? kSand : inCity ? kAsphalt : kGround;
    // Two triangles, each with its own flat normal (cells slope under the sea and on the hills).
    const glm::dvec3 a[3] = {p[0], p[1], p[2]}, b[3] = {p[0], p[2], p[3]};
    mb.polygon(a, MeshBuilder::faceNormal(a), material, {});
    mb.polygon(b, MeshBuilder::faceNormal(b), material, {});
}

// The ground of one tile: its cells and the kerbs of `blocks` (sidewalk prisms). The tiles on
// the city's edge also hold the terrain's cells beyond it (terrain.margin metres), and in
// `land` the far rings beyond those (a backdrop the bake and the scene's bounds leave out).
Mesh tileGround(const City& city, glm::ivec2 tile, std::span<const int> blocks, Mesh& land) {
    const CitySettings& s = city.settings;
    Mesh mesh;
    mesh.name = format("ground_{}_{}", tile.x, tile.y);
    land.name = format("land_{}_{}", tile.x, tile.y);
    MeshBuilder mb(mesh), far(land);
    // Only the cells near the tile: a cell belongs to the tile holding its centre.
    const glm::ivec2 count = tileCount(s);
    const int nx = static_cast<int>(std::ceil(s.size.x / kCellSize)), ny = static_cast<int>(std::ceil(s.size.y / kCellSize));
    const int margin = static_cast<int>(std::ceil(s.recipe.terrain.margin / kCellSize));
    const int rings = margin > 0 ? kFarRings : 0;
    const Hills hills = hillsOf(s.seed);
    auto cellRange = [&](int t, int tiles, int cells) {
        const int lo = t == 0 ? -margin - rings : std::max(0, static_cast<int>(std::floor(t * s.tileSize / kCellSize)) - 1);
        const int hi = t == tiles - 1 ? cells + margin + rings
                                      : std::min(cells, static_cast<int>(std::ceil((t + 1) * s.tileSize / kCellSize)) + 1);
        return std::make_pair(lo, hi);
    };
    const auto [i0, i1] = cellRange(tile.x, count.x, nx);
    const auto [j0, j1] = cellRange(tile.y, count.y, ny);
    for (int j = j0; j < j1; ++j)
        for (int i = i0; i < i1; ++i) {
            const glm::dvec2 lo{cellEdge(i, nx, s.size.x, margin), cellEdge(j, ny, s.size.y, margin)};
            const glm::dvec2 hi{cellEdge(i + 1, nx, s.size.x, margin), cellEdge(j + 1, ny, s.size.y, margin)};
            const glm::dvec2 centre = 0.5 * (lo + hi);
            if (tileOf(s, centre) != tile) continue;
            const bool inCity = centre.x > 0.0 && centre.y > 0.0 && centre.x < s.size.x && centre.y < s.size.y;
            const bool inFar = i < -margin || j < -margin || i >= nx + margin || j >= ny + margin;
            addCell(inFar ? far : mb, city, hills, lo, hi, inCity);
        }
    land.uv1.clear();
    land.uv2.clear();
    for (int id : blocks)
        mb.prismAny(city.plan.blocks[static_cast<std::size_t>(id)].curb, 0.0, s.recipe.streets.curbHeight, kPaving, kPaving);
    // uv1/uv2 carry nothing on the ground.
    mesh.uv1.clear();
    mesh.uv2.clear();
    return mesh;
}

std::string entityName(const char* kind, int id) {
    char name[32];
    std::snprintf(name, sizeof name, "%s_%05d", kind, id);
    return name;
}
std::string buildingName(int id) { return entityName("building", id); }

// The whole city's trees and lamps, each kept when its foot is in a generated tile.
template <typename TileSlot>
void dressTiles(City& city, TileSlot tileSlot) {
    Dressing all = dressCity(city.plan, city.settings.recipe, city.settings.seed);
    city.dressing.species = std::move(all.species);
    city.dressing.lamp = std::move(all.lamp);
    // Each entity into the tile of its foot, when that tile is generated.
    const auto keep = [&](const auto& from, auto& to, auto tileList) {
        for (const auto& e : from) {
            const int slot = tileSlot(tileOf(city.settings, e.foot));
            if (slot < 0) continue;
            (city.tiles[std::size_t(slot)].*tileList).push_back(int(to.size()));
            to.push_back(e);
        }
    };
    keep(all.trees, city.dressing.trees, &CityTile::trees);
    keep(all.lamps, city.dressing.lamps, &CityTile::lamps);
}

double round3(double v) { return std::round(v * 1000.0) / 1000.0; }
nlohmann::ordered_json point(glm::dvec2 p) { return nlohmann::ordered_json::array({round3(p.x), round3(p.y)}); }
nlohmann::ordered_json points(std::span<const glm::dvec2> ps) {
    auto out = nlohmann::ordered_json::array();
    for (glm::dvec2 p : ps) out.push_back(point(p));
    return out;
}

// city.json's "tree_species", "trees" and "lamps".
void addDressingJson(nlohmann::ordered_json& j, const City& city) {
    using Json = nlohmann::ordered_json;
    const Dressing& d = city.dressing;
    Json species = Json::array();
    for (const TreeSpecies& s : d.species) {
        Json elements = Json::array();
        for (const TreeElement& e : s.elements) elements.push_back({{"name", e.name}, {"parent", e.parent}});
        species.push_back({{"name", s.name}, {"crown_radius", round3(s.crownRadius)}, {"elements", std::move(elements)}});
    }
    j["tree_species"] = std::move(species);
    Json trees = Json::array();
    for (const StreetTree& t : d.trees) {
        const glm::ivec2 tile = tileOf(city.settings, t.foot);
        trees.push_back({{"id", t.id},
                         {"name", entityName("tree", t.id)},
                         {"species", d.species[std::size_t(t.species)].name},
                         {"tile", {tile.x, tile.y}},
                         {"foot", point(t.foot)},
                         {"height", round3(t.height)},
                         {"yaw_degrees", round3(t.yaw * 180.0 / std::numbers::pi)},
                         {"scale", round3(t.scale)}});
    }
    j["trees"] = std::move(trees);
    Json lamps = Json::array();
    for (const StreetLamp& l : d.lamps) {
        const glm::ivec2 tile = tileOf(city.settings, l.foot);
        lamps.push_back({{"id", l.id},
                         {"name", entityName("lamp", l.id)},
                         {"tile", {tile.x, tile.y}},
                         {"foot", point(l.foot)},
                         {"light", {round3(l.light.x), round3(l.light.y), round3(l.light.z)}},
                         {"colour", {round3(l.colour.r), round3(l.colour.g), round3(l.colour.b)}}});
    }
    j["lamps"] = std::move(lamps);
}

// Mesh indices of the species' elements and of the lamp, added to the scene at first use.
struct SharedMeshes {
    std::map<int, std::vector<std::int32_t>> species;
    std::int32_t lamp = -1;
};

// Moves a mesh made in plan coordinates to the frame whose origin is the plan point `origin`.
void shiftPositions(Mesh& mesh, glm::dvec2 origin) {
    if (origin == glm::dvec2(0.0)) return;
    for (glm::vec3& p : mesh.positions) p = glm::vec3(float(double(p.x) - origin.x), p.y, float(double(p.z) + origin.y));
}

std::uint32_t addNode(Scene& scene, std::uint32_t parent, Node node) {
    const auto index = static_cast<std::uint32_t>(scene.nodes.size());
    scene.nodes.push_back(std::move(node));
    scene.nodes[parent].children.push_back(index);
    return index;
}

// A tile's trees (each its species' element hierarchy, the trunk placed, turned and scaled)
// and lamps, under the tile's node.
void addDressingNodes(Scene& scene, const City& city, const CityTile& tile, std::uint32_t tileNode, SharedMeshes& shared) {
    const Dressing& d = city.dressing;
    const glm::dvec2 origin = city.settings.origin;
    const auto sharedMesh = [&](const Mesh& mesh) {
        scene.meshes.push_back(mesh);
        return std::int32_t(scene.meshes.size() - 1);
    };
    for (int index : tile.trees) {
        const StreetTree& tree = d.trees[std::size_t(index)];
        const TreeSpecies& species = d.species[std::size_t(tree.species)];
        auto [it, added] = shared.species.try_emplace(tree.species);
        if (added)
            for (const TreeElement& e : species.elements) it->second.push_back(sharedMesh(e.mesh));
        const std::string name = entityName("tree", tree.id);
        std::vector<std::uint32_t> nodes;
        for (std::size_t k = 0; k < species.elements.size(); ++k) {
            const TreeElement& e = species.elements[k];
            Node n;
            n.name = e.parent < 0 ? name : name + "_" + e.name;
            n.mesh = it->second[k];
            n.translation = e.translation;
            n.rotation = e.rotation;
            if (e.parent < 0) {
                n.translation = toWorld(tree.foot - origin, tree.height);
                // Stood up as speciesNodes stands the trunk (+X onto +Y), then turned.
                n.rotation = glm::angleAxis(float(tree.yaw), glm::vec3(0, 1, 0)) *
                             glm::angleAxis(float(0.5 * std::numbers::pi), glm::vec3(0, 0, 1)) * e.rotation;
                n.scale = glm::vec3(float(tree.scale));
                n.extrasJson = format(R"({{"species":"{}"}})", species.name);
            }
            nodes.push_back(addNode(scene, e.parent < 0 ? tileNode : nodes[std::size_t(e.parent)], std::move(n)));
        }
    }
    for (int index : tile.lamps) {
        const StreetLamp& lamp = d.lamps[std::size_t(index)];
        if (shared.lamp < 0) shared.lamp = sharedMesh(d.lamp);
        Node n;
        n.name = entityName("lamp", lamp.id);
        n.mesh = shared.lamp;
        n.translation = toWorld(lamp.foot - origin, lamp.height);
        n.rotation = glm::angleAxis(float(lamp.yaw), glm::vec3(0, 1, 0));
        addNode(scene, tileNode, std::move(n));
    }
}

}  // namespace

glm::ivec2 tileCount(const CitySettings& s) {
    return {std::max(1, static_cast<int>(std::ceil(s.size.x / s.tileSize - 1e-9))),
            std::max(1, static_cast<int>(std::ceil(s.size.y / s.tileSize - 1e-9)))};
}

glm::dvec2 tileCorner(const CitySettings& s, glm::ivec2 tile) { return glm::dvec2(tile) * s.tileSize; }

std::pair<glm::ivec2, glm::ivec2> haloTiles(const CitySettings& s, glm::ivec2 tile, double metres) {
    if (!(metres > 0.0)) return {tile, tile};
    const glm::dvec2 corner = tileCorner(s, tile);
    return {tileOf(s, corner - metres), tileOf(s, corner + s.tileSize + metres)};
}

bool lotNearTile(const CitySettings& s, glm::ivec2 tile, const Lot& lot, double metres) {
    const glm::dvec2 lo = tileCorner(s, tile) - metres, hi = tileCorner(s, tile) + s.tileSize + metres;
    glm::dvec2 a(std::numeric_limits<double>::max()), b(std::numeric_limits<double>::lowest());
    for (glm::dvec2 p : lot.polygon) a = glm::min(a, p), b = glm::max(b, p);
    return a.x <= hi.x && a.y <= hi.y && b.x >= lo.x && b.y >= lo.y;
}

glm::ivec2 tileOf(const CitySettings& s, glm::dvec2 p) {
    const glm::ivec2 n = tileCount(s);
    return {std::clamp(static_cast<int>(std::floor(p.x / s.tileSize)), 0, n.x - 1),
            std::clamp(static_cast<int>(std::floor(p.y / s.tileSize)), 0, n.y - 1)};
}

City generateCity(const CitySettings& settings, const ProgressFn& progress) {
    auto report = [&](double f) {
        if (!progress(f)) throw Cancelled();
    };
    if (!(std::isfinite(settings.size.x) && std::isfinite(settings.size.y) && settings.size.x > 0 && settings.size.y > 0))
        throw InputError(format("the city size must be larger than 0 x 0 m (got {} x {})", settings.size.x, settings.size.y));
    if (settings.size.x > 20000 || settings.size.y > 20000)
        throw InputError(format("the city size is at most 20000 x 20000 m (got {} x {})", settings.size.x, settings.size.y));
    if (!(std::isfinite(settings.tileSize) && settings.tileSize >= 10.0))
        throw InputError(format("the tile size must be at least 10 m (got {})", settings.tileSize));
    const glm::ivec2 count = tileCount(settings);
    if (settings.tile && (settings.tile->x < 0 || settings.tile->y < 0 || settings.tile->x >= count.x || settings.tile->y >= count.y))
        throw InputError(format("tile {},{} is outside the city, which has {} x {} tiles of {} m (0,0 to {},{})",
                                settings.tile->x, settings.tile->y, count.x, count.y, settings.tileSize, count.x - 1,
                                count.y - 1));
    validateRecipe(settings.recipe, "recipe");

    City city;
    city.settings = settings;
    city.plan = planCity(settings.recipe, settings.seed, settings.size,
                         [&](double f) { return progress(0.1 * f); });
    report(0.1);

    // The generated tiles: all, or `tile` and those within `tileReach` of it, row by row.
    glm::ivec2 lo(0), hi = count - 1;
    const double halo = settings.tile ? std::max(0.0, settings.halo) : 0.0;
    if (settings.tile) std::tie(lo, hi) = haloTiles(settings, *settings.tile, halo);
    for (int j = lo.y; j <= hi.y; ++j)
        for (int i = lo.x; i <= hi.x; ++i) {
            city.tiles.emplace_back();
            city.tiles.back().index = {i, j};
        }
    // Where tile t sits in city.tiles, or -1 when it is not generated.
    auto tileSlot = [&](glm::ivec2 t) -> int {
        if (t.x < lo.x || t.y < lo.y || t.x > hi.x || t.y > hi.y) return -1;
        return (t.y - lo.y) * (hi.x - lo.x + 1) + (t.x - lo.x);
    };
    for (const Block& block : city.plan.blocks) {
        const int slot = tileSlot(tileOf(settings, centroid(block.curb)));
        if (slot >= 0) city.tiles[static_cast<std::size_t>(slot)].blocks.push_back(block.id);
    }
    // The lots of the generated tiles, in lot order.
    std::vector<const Lot*> lots;
    for (const Lot& lot : city.plan.lots) {
        const glm::ivec2 owner = tileOf(settings, centroid(lot.polygon));
        const bool owned = !settings.tile || owner == *settings.tile;
        if (tileSlot(owner) >= 0 && (owned || (halo > 0.0 && lotNearTile(settings, *settings.tile, lot, halo)))) lots.push_back(&lot);
    }
    std::vector<Building> built(lots.size());
    std::atomic<std::size_t> done{0};
    std::mutex progressMutex;
    bool cancelled = false;
    tbb::parallel_for(std::size_t(0), lots.size(), [&](std::size_t k) {
        built[k] = buildBuilding(*lots[k], settings.recipe, settings.seed);
        const std::size_t finished = ++done;
        if (finished % 16 == 0) {
            std::lock_guard lock(progressMutex);
            if (!progress(0.1 + 0.8 * double(finished) / double(lots.size()))) cancelled = true;
        }
    });
    if (cancelled) throw Cancelled();
    for (Building& b : built) {
        if (b.floors == 0) continue;
        const int slot = tileSlot(tileOf(settings, centroid(city.plan.lots[static_cast<std::size_t>(b.lot)].polygon)));
        city.tiles[static_cast<std::size_t>(slot)].buildings.push_back(static_cast<int>(city.buildings.size()));
        city.buildings.push_back(std::move(b));
    }
    report(0.9);
    dressTiles(city, [&](glm::ivec2 t) { return tileSlot(t); });
    tbb::parallel_for(std::size_t(0), city.tiles.size(), [&](std::size_t k) {
        city.tiles[k].ground = tileGround(city, city.tiles[k].index, city.tiles[k].blocks, city.tiles[k].land);
    });
    report(1.0);
    return city;
}

CityCounts countCity(const City& city) {
    CityCounts c;
    c.buildings = city.buildings.size();
    for (const Building& b : city.buildings) {
        c.floors += static_cast<std::size_t>(b.floors);
        c.rooms += b.rooms.size();
        c.windows += b.windows.size();
        c.trianglesLod0 += b.lod0.triangleCount();
        c.trianglesLod1 += b.lod1.triangleCount();
    }
    for (const CityTile& t : city.tiles) c.trianglesGround += t.ground.triangleCount() + t.land.triangleCount();
    c.trees = city.dressing.trees.size();
    c.lamps = city.dressing.lamps.size();
    for (const StreetTree& tree : city.dressing.trees)
        for (const TreeElement& e : city.dressing.species[std::size_t(tree.species)].elements)
            c.trianglesDressing += e.mesh.triangleCount();
    c.trianglesDressing += c.lamps * city.dressing.lamp.triangleCount();
    return c;
}

std::string cityReportJson(const City& city) {
    using Json = nlohmann::ordered_json;
    const CitySettings& s = city.settings;
    Json j;
    j["generator"] = "dawnforge city";
    j["seed"] = s.seed;
    j["size"] = {s.size.x, s.size.y};
    j["coordinates"] = "plan metres: x east, y north; glTF position = (x, height, -y)";
    j["tile_size"] = s.tileSize;
    const glm::ivec2 count = tileCount(s);
    j["tiles"] = {count.x, count.y};
    j["tile"] = s.tile ? Json::array({s.tile->x, s.tile->y}) : Json(nullptr);
    if (s.origin != glm::dvec2(0.0)) j["origin"] = {s.origin.x, s.origin.y};
    j["recipe"] = Json::parse(recipeJson(s.recipe));

    const CityCounts counts = countCity(city);
    std::vector<int> blockIds;
    for (const CityTile& t : city.tiles) blockIds.insert(blockIds.end(), t.blocks.begin(), t.blocks.end());
    std::sort(blockIds.begin(), blockIds.end());
    std::size_t lotCount = 0;
    for (int id : blockIds) lotCount += city.plan.blocks[static_cast<std::size_t>(id)].lots.size();
    // Streets: those that reach a generated tile.
    Json streets = Json::array();
    for (const Street& street : city.plan.streets) {
        bool reaches = !s.tile;
        for (glm::dvec2 p : street.polyline) reaches = reaches || tileOf(s, p) == *s.tile;
        if (!reaches) continue;
        streets.push_back({{"id", street.id}, {"major", street.major}, {"width", street.width}, {"polyline", points(street.polyline)}});
    }
    j["counts"] = {{"streets", streets.size()},
                   {"blocks", blockIds.size()},
                   {"lots", lotCount},
                   {"buildings", counts.buildings},
                   {"floors", counts.floors},
                   {"rooms", counts.rooms},
                   {"windows", counts.windows},
                   {"trees", counts.trees},
                   {"lamps", counts.lamps},
                   {"triangles",
                    {{"lod0", counts.trianglesLod0},
                     {"lod1", counts.trianglesLod1},
                     {"ground", counts.trianglesGround},
                     {"dressing", counts.trianglesDressing}}}};
    j["coastline"] = points(city.plan.coastline);
    j["streets"] = std::move(streets);
    Json blocks = Json::array();
    for (int id : blockIds) {
        const Block& block = city.plan.blocks[static_cast<std::size_t>(id)];
        Json lots = Json::array();
        for (int lotId : block.lots) {
            const Lot& lot = city.plan.lots[static_cast<std::size_t>(lotId)];
            lots.push_back({{"id", lot.id}, {"polygon", points(lot.polygon)}, {"front_edge", lot.frontEdge}});
        }
        blocks.push_back({{"id", block.id}, {"curb", points(block.curb)}, {"lots", std::move(lots)}});
    }
    j["blocks"] = std::move(blocks);
    Json buildings = Json::array();
    for (const Building& b : city.buildings) {
        const Lot& lot = city.plan.lots[static_cast<std::size_t>(b.lot)];
        const glm::ivec2 tile = tileOf(s, centroid(lot.polygon));
        Json rpf = Json::array();
        for (int r : b.roomsPerFloor) rpf.push_back(r);
        Json one = {{"id", b.id},
                    {"name", buildingName(b.id)},
                    {"lot", b.lot},
                    {"tile", {tile.x, tile.y}},
                    {"lot_polygon", points(lot.polygon)},
                    {"footprint", points(b.footprint)},
                    {"height", std::round(b.height * 1000.0) / 1000.0},
                    {"floors", b.floors},
                    {"roof", roofTypeName(b.roof)},
                    {"wall_material", materialName(b.wallMaterial)},
                    {"rooms_per_floor", std::move(rpf)},
                    {"windows", b.windows.size()},
                    {"triangles", {{"lod0", b.lod0.triangleCount()}, {"lod1", b.lod1.triangleCount()}}}};
        if (!b.towerFootprint.empty()) {
            one["tower_footprint"] = points(b.towerFootprint);
            one["tower_floors"] = b.floors - b.baseFloors;
        }
        // LOD0's closed solids: [kind, material, first triangle, triangles].
        Json parts = Json::array();
        for (const BuildingPart& part : b.parts)
            parts.push_back(Json::array({partKindName(part.kind), materialName(part.material), part.firstTriangle,
                                         part.triangles}));
        one["parts"] = std::move(parts);
        buildings.push_back(std::move(one));
    }
    j["buildings"] = std::move(buildings);
    addDressingJson(j, city);
    return j.dump(1) + "\n";
}

// A row of the scene's building table (glTF EXT_structural_metadata, class "building"): id,
// floors, height, roof and wall material, so that a 3D Tiles or glTF reader can pick a building
// and show them. Returns the row.
std::int32_t addBuildingFeature(FeatureTable& table, const Building& b) {
    if (table.className.empty()) {
        table.className = "building";
        for (const char* name : {"id", "floors", "height", "roof", "wall_material"}) table.properties.push_back({name, {}, {}, {}});
    }
    auto& p = table.properties;
    p[0].uints.push_back(std::uint32_t(b.id));
    p[1].uints.push_back(std::uint32_t(b.floors));
    p[2].floats.push_back(float(b.height));
    p[3].strings.emplace_back(roofTypeName(b.roof));
    p[4].strings.emplace_back(materialName(b.wallMaterial));
    return std::int32_t(table.count++);
}

Scene takeCityScene(City& city) {
    Scene scene;
    SharedMeshes sharedMeshes;
    for (CityTile& tile : city.tiles) {
        const auto tileNode = static_cast<std::uint32_t>(scene.nodes.size());
        Node node;
        node.name = format("tile_{}_{}", tile.index.x, tile.index.y);
        scene.nodes.push_back(node);
        scene.roots.push_back(tileNode);
        auto addChild = [&](std::uint32_t parent, Node child) { return addNode(scene, parent, std::move(child)); };
        auto meshNode = [&](Mesh mesh) {
            shiftPositions(mesh, city.settings.origin);
            Node n;
            n.name = mesh.name;
            n.mesh = static_cast<std::int32_t>(scene.meshes.size());
            scene.meshes.push_back(std::move(mesh));
            return n;
        };
        if (!tile.ground.positions.empty()) addChild(tileNode, meshNode(std::move(tile.ground)));
        if (!tile.land.positions.empty()) addChild(tileNode, meshNode(std::move(tile.land)));
        for (int index : tile.buildings) {
            Building& b = city.buildings[static_cast<std::size_t>(index)];
            Node bn;
            bn.name = buildingName(b.id);
            bn.extrasJson = format(R"({{"lot":{},"floors":{},"roof":"{}","rooms":{}}})", b.lot, b.floors, roofTypeName(b.roof),
                                   b.rooms.size());
            const std::uint32_t buildingNode = addChild(tileNode, bn);
            b.lod0.name = buildingName(b.id) + "_lod0";
            b.lod1.name = buildingName(b.id) + "_lod1";
            b.lod0.featureId = b.lod1.featureId = addBuildingFeature(scene.features, b);
            addChild(buildingNode, meshNode(std::move(b.lod0)));
            addChild(buildingNode, meshNode(std::move(b.lod1)));
        }
        addDressingNodes(scene, city, tile, tileNode, sharedMeshes);
    }
    return scene;
}

}  // namespace dawnforge::procgen
