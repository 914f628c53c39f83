// DIR/tileset.json: OGC 3D Tiles 1.1 over the world's tiles and HLOD nodes (ARCHITECTURE.md 9.4).
#include "jobs.hpp"

#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/read_file.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>

namespace dawnforge::world {

namespace fs = std::filesystem;

namespace {

using Json = nlohmann::ordered_json;

// An axis-aligned box in a frame's 3D Tiles axes (x east, y north, z up).
struct Box {
    glm::dvec3 lo{std::numeric_limits<double>::max()}, hi{std::numeric_limits<double>::lowest()};
    bool empty() const { return lo.x > hi.x; }
    void add(glm::dvec3 p) { lo = glm::min(lo, p), hi = glm::max(hi, p); }
    void add(const Box& b, glm::dvec3 offset) {
        if (!b.empty()) add(b.lo + offset), add(b.hi + offset);
    }
};

// The bounds of a GLB's meshes, turned from glTF's y-up axes to 3D Tiles' z-up ones.
Box glbBounds(const fs::path& file) {
    Box box;
    for (const MeshNode& n : loadMeshNodes(file, ReadIn::thisProcess))
        for (const glm::vec3& p : n.mesh.positions) {
            const glm::vec4 w = n.world * glm::vec4(p, 1.0f);
            box.add({w.x, -w.z, w.y});
        }
    return box;
}

Json boxJson(const Box& b) {
    const glm::dvec3 c = 0.5 * (b.lo + b.hi), h = glm::max(0.5 * (b.hi - b.lo), glm::dvec3(0.01));
    return {{"box", {c.x, c.y, c.z, h.x, 0.0, 0.0, 0.0, h.y, 0.0, 0.0, 0.0, h.z}}};
}

Json translation(glm::dvec2 d) { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, d.x, d.y, 0, 1}; }

// The square [x0, y0, x1, y1] a node of `tiles` tiles a side from `origin` covers within the
// world, in the node's frame (as its box): the box less the far land, which a reader measures
// screen-space error against.
Json areaJson(const WorldPlan& plan, glm::dvec2 origin, int tiles) {
    const glm::dvec2 hi = glm::min(origin + glm::dvec2(tiles * plan.settings.tileSize), plan.settings.size) - origin;
    return {0.0, 0.0, hi.x, hi.y};
}

struct Built {
    Json tile;
    Box box;            // in the parent's frame... here: in the tile's own frame
    glm::dvec2 origin;  // plan point of the tile's frame
    double error = 0.0;
};

Built leafTile(const fs::path& worldDir, const WorldPlan& plan, const WorldTile& t) {
    const std::string dir = "tiles/" + tileName(t.index);
    Built b;
    b.origin = glm::dvec2(t.index) * plan.settings.tileSize;
    b.box = glbBounds(worldDir / dir / "city.glb");
    Json extras{{"tile", {t.index.x, t.index.y}}, {"origin", {b.origin.x, b.origin.y}}, {"area", areaJson(plan, b.origin, 1)},
                {"city", dir + "/city.json"}, {"bake", fs::exists(worldDir / dir / "bake" / "bake.json") ? Json(dir + "/bake/bake.json") : Json(nullptr)},
                {"buildings", t.buildings.size()}};
    b.tile = {{"boundingVolume", boxJson(b.box)}, {"geometricError", 0.0}, {"content", {{"uri", dir + "/city.glb"}}},
              {"extras", std::move(extras)}};
    return b;
}

// A node of the quadtree with its children (or the tiles, at level 1); a node whose HLOD was not
// built passes its children up. Returns the tiles to hang under the parent.
using Finished = std::function<bool(const std::string& stage, int task)>;

// The task of HLOD node (level, index) in its stage, or -1 when the plan has no such node.
int hlodTask(const WorldPlan& plan, int level, glm::ivec2 index) {
    const std::vector<const HlodNode*> nodes = hlodStageNodes(plan, hlodStage(level));
    const auto it = std::find_if(nodes.begin(), nodes.end(), [&](const HlodNode* n) { return n->index == index; });
    return it == nodes.end() ? -1 : int(it - nodes.begin());
}

std::vector<Built> nodeTiles(const fs::path& worldDir, const WorldPlan& plan, const Finished& finished, int level, glm::ivec2 index) {
    std::vector<Built> children;
    if (level == 0) {
        if (index.x < plan.tileCount.x && index.y < plan.tileCount.y && finished("city", tileTask(plan, index)))
            children.push_back(leafTile(worldDir, plan, findTile(plan, index)));
        return children;
    }
    for (int k = 0; k < 4; ++k) {
        std::vector<Built> c = nodeTiles(worldDir, plan, finished, level - 1, index * 2 + glm::ivec2(k % 2, k / 2));
        std::move(c.begin(), c.end(), std::back_inserter(children));
    }
    const std::string name = format("{}_{}_{}", level, index.x, index.y);
    const fs::path glb = worldDir / "hlod" / (name + ".glb");
    const int task = hlodTask(plan, level, index);
    if (children.empty() || task < 0 || !finished(hlodStage(level), task)) return children;
    Built b;
    b.origin = glm::dvec2(index * (1 << level)) * plan.settings.tileSize;
    b.box = glbBounds(glb);
    const Json info = Json::parse(readTextFile(worldDir / "hlod" / (name + ".json")));
    b.error = info.at("geometric_error").get<double>();
    Json kids = Json::array();
    for (Built& c : children) {
        const glm::dvec2 d = c.origin - b.origin;
        b.box.add(c.box, {d.x, d.y, 0.0});
        c.tile["transform"] = translation(d);
        kids.push_back(std::move(c.tile));
    }
    b.tile = {{"boundingVolume", boxJson(b.box)}, {"geometricError", b.error}, {"refine", "REPLACE"},
              {"content", {{"uri", "hlod/" + name + ".glb"}}},
              {"extras", {{"hlod", name}, {"level", level}, {"origin", {b.origin.x, b.origin.y}},
                          {"area", areaJson(plan, b.origin, 1 << level)}, {"triangles", info.at("triangles")}}},
              {"children", std::move(kids)}};
    return {std::move(b)};
}

}  // namespace

void writeTileset(const fs::path& worldDir, const WorldPlan& plan, const Finished& finished) {
    std::vector<Built> top = nodeTiles(worldDir, plan, finished, plan.hlodLevels, {0, 0});
    // The root: the world's frame (plan origin), holding what the quadtree gives.
    Box box;
    double error = 0.0;
    Json children = Json::array();
    for (Built& c : top) {
        box.add(c.box, {c.origin.x, c.origin.y, 0.0});
        error = std::max(error, c.error);
        c.tile["transform"] = translation(c.origin);
        children.push_back(std::move(c.tile));
    }
    if (box.empty()) box.add(glm::dvec3(0.0));
    // The root has no content: drawn alone it loses the whole world, so its error is the
    // world's extent, and a reader refines it at any distance.
    const double rootError = std::max(glm::length(box.hi - box.lo), 2.0 * error);
    // The root's transform places the plan's east-north-up frame on the globe (a reader that
    // has no globe, dawnforge's runtime among them, may draw in the root's frame).
    const glm::dmat4 globe = enuToEcef(plan.settings.origin);
    Json transform = Json::array();
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) transform.push_back(globe[c][r]);
    Json root{{"boundingVolume", boxJson(box)}, {"geometricError", rootError}, {"refine", "REPLACE"},
              {"transform", std::move(transform)}, {"children", std::move(children)}};
    Json j{{"asset", {{"version", "1.1"}, {"generator", "dawnforge world build"}}},
           {"geometricError", rootError},
           {"root", std::move(root)},
           {"extras", {{"plan", "plan.json"}, {"coordinates", "x east, y north, z up, metres from the plan's origin"},
                       {"origin", {{"longitude", plan.settings.origin.longitude}, {"latitude", plan.settings.origin.latitude},
                                   {"height", plan.settings.origin.height}}},
                       {"tiles", plan.tileCount.x * plan.tileCount.y}, {"hlod_levels", plan.hlodLevels}}}};
    writeFileAtomically(worldDir / "tileset.json", j.dump(1) + "\n");
}

}  // namespace dawnforge::world
