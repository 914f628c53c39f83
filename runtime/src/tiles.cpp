#include <dawnforge/runtime/tiles.hpp>

#include "frustum.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/read_file.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace dawnforge::runtime {

namespace {

using Json = nlohmann::json;

// Plan (x east, y north, z up) → runtime (x, z, −y).
glm::dvec3 toRuntime(glm::dvec3 p) { return {p.x, p.z, -p.y}; }

// A rigid transform whose 3 × 3 part is a rotation other than the identity (16 numbers,
// column-major, last row 0 0 0 1).
bool placesOnTheGlobe(const Json& t) {
    if (!t.is_array() || t.size() != 16 || !std::all_of(t.begin(), t.end(), [](const Json& v) { return v.is_number(); }))
        return false;
    glm::dmat3 r;
    for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) r[c][k] = t[std::size_t(4 * c + k)].get<double>();
    const glm::dmat3 rrt = r * glm::transpose(r);
    double offIdentity = 0.0, offOrthonormal = 0.0;
    for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) {
            offIdentity = std::max(offIdentity, std::abs(r[c][k] - (c == k ? 1.0 : 0.0)));
            offOrthonormal = std::max(offOrthonormal, std::abs(rrt[c][k] - (c == k ? 1.0 : 0.0)));
        }
    return offIdentity > 1e-12 && offOrthonormal < 1e-9 && glm::determinant(r) > 0.0 && t[3] == 0 && t[7] == 0 &&
           t[11] == 0 && t[15] == 1;
}

struct Reader {
    const std::filesystem::path& dir;
    const std::string& file;
    Tileset out;

    [[noreturn]] void fail(const std::string& what) const { throw InputError(format("{}: {}", file, what)); }

    // A tile's translation (runtime axes). The root's transform may also turn: that places the
    // tileset on the globe (dawnforge worlds: east-north-up to ECEF), and the runtime draws in
    // the root's own frame.
    glm::dvec3 translation(const Json& tile, const std::string& name, bool root = false) const {
        if (!tile.contains("transform")) return glm::dvec3(0.0);
        if (root && placesOnTheGlobe(tile.at("transform"))) return glm::dvec3(0.0);
        const Json& t = tile.at("transform");
        if (!t.is_array() || t.size() != 16) fail(format("{}: \"transform\" is not 16 numbers", name));
        std::vector<double> m;
        for (const Json& v : t) {
            if (!v.is_number()) fail(format("{}: \"transform\" is not 16 numbers", name));
            m.push_back(v.get<double>());
        }
        const double identity[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
        for (int k = 0; k < 12; ++k)
            if (std::abs(m[std::size_t(k)] - identity[k]) > 1e-12)
                fail(format("{}: its transform is not a translation (the runtime reads dawnforge worlds)", name));
        if (m[15] != 1.0) fail(format("{}: its transform is not a translation", name));
        return toRuntime({m[12], m[13], m[14]});
    }

    // An oriented box → the axis-aligned box around it, runtime coordinates, relative to the frame.
    void box(const Json& tile, const std::string& name, TileNode& n) const {
        const Json* b = tile.contains("boundingVolume") ? &tile.at("boundingVolume") : nullptr;
        if (!b || !b->contains("box") || !b->at("box").is_array() || b->at("box").size() != 12)
            fail(format("{}: the runtime reads box bounding volumes only", name));
        double v[12];
        for (int k = 0; k < 12; ++k) {
            if (!b->at("box")[std::size_t(k)].is_number()) fail(format("{}: \"box\" is not 12 numbers", name));
            v[k] = b->at("box")[std::size_t(k)].get<double>();
        }
        glm::dvec3 half(0.0);
        for (int a = 0; a < 3; ++a) half += glm::abs(glm::dvec3(v[3 + 3 * a], v[4 + 3 * a], v[5 + 3 * a]));
        const glm::dvec3 lo = toRuntime(glm::dvec3(v[0], v[1], v[2]) - half), hi = toRuntime(glm::dvec3(v[0], v[1], v[2]) + half);
        n.boxMin = glm::min(lo, hi) + n.offset;
        n.boxMax = glm::max(lo, hi) + n.offset;
        n.areaMin = n.boxMin, n.areaMax = n.boxMax;
        // extras.area: the square [x0, y0, x1, y1] the node stands for in its frame, far land excluded.
        const Json* extras = tile.contains("extras") ? &tile.at("extras") : nullptr;
        if (extras && extras->is_object() && extras->contains("area")) {
            const Json& a = extras->at("area");
            if (!a.is_array() || a.size() != 4 || !std::all_of(a.begin(), a.end(), [](const Json& x) { return x.is_number(); }))
                fail(format("{}: \"extras.area\" is not 4 numbers", name));
            const glm::dvec3 p = toRuntime({a[0].get<double>(), a[1].get<double>(), 0.0}) + n.offset;
            const glm::dvec3 q = toRuntime({a[2].get<double>(), a[3].get<double>(), 0.0}) + n.offset;
            n.areaMin = glm::dvec3(std::max(n.boxMin.x, std::min(p.x, q.x)), n.boxMin.y, std::max(n.boxMin.z, std::min(p.z, q.z)));
            n.areaMax = glm::dvec3(std::min(n.boxMax.x, std::max(p.x, q.x)), n.boxMax.y, std::min(n.boxMax.z, std::max(p.z, q.z)));
            n.areaMax = glm::max(n.areaMax, n.areaMin);
        }
    }

    void content(const Json& tile, const std::string& name, TileNode& n) const {
        if (!tile.contains("content")) return;
        const Json& c = tile.at("content");
        if (!c.is_object() || !c.contains("uri") || !c.at("uri").is_string()) fail(format("{}: \"content.uri\" is missing", name));
        const std::string uri = c.at("uri").get<std::string>();
        if (!uri.ends_with(".glb")) fail(format("{}: content \"{}\" is not a GLB", name, uri));
        if (uri.find("..") != std::string::npos || uri.starts_with("/"))
            fail(format("{}: content \"{}\" leaves the world's folder", name, uri));
        n.file = dir / uri;
        const Json* extras = tile.contains("extras") ? &tile.at("extras") : nullptr;
        n.hlod = extras && extras->is_object() && extras->contains("hlod");
    }

    std::string nameOf(const Json& tile, int depth) const {
        const Json* extras = tile.contains("extras") ? &tile.at("extras") : nullptr;
        if (extras && extras->is_object()) {
            if (extras->contains("hlod") && extras->at("hlod").is_string()) return "hlod " + extras->at("hlod").get<std::string>();
            if (extras->contains("tile") && extras->at("tile").is_array() && extras->at("tile").size() == 2)
                return format("tile {}_{}", extras->at("tile")[0].dump(), extras->at("tile")[1].dump());
        }
        return depth == 0 ? std::string("root") : format("node {}", out.nodes.size());
    }

    int add(const Json& tile, int parent, glm::dvec3 frame, int depth) {
        if (!tile.is_object()) fail("a tile is not an object");
        if (depth > 64) fail("tiles nest more than 64 levels deep");
        const std::string name = nameOf(tile, depth);
        TileNode n;
        n.name = name;
        n.parent = parent;
        n.depth = depth;
        n.offset = frame + translation(tile, name, depth == 0);
        if (!tile.contains("geometricError") || !tile.at("geometricError").is_number() || tile.at("geometricError").get<double>() < 0.0)
            fail(format("{}: \"geometricError\" is not a number ≥ 0", name));
        n.geometricError = tile.at("geometricError").get<double>();
        if (tile.contains("refine") && tile.at("refine") != "REPLACE")
            fail(format("{}: refine {} (the runtime streams REPLACE tilesets)", name, tile.at("refine").dump()));
        box(tile, name, n);
        content(tile, name, n);
        const int index = int(out.nodes.size());
        out.nodes.push_back(std::move(n));
        if (tile.contains("children")) {
            if (!tile.at("children").is_array()) fail(format("{}: \"children\" is not an array", name));
            for (const Json& child : tile.at("children")) {
                const int c = add(child, index, out.nodes[std::size_t(index)].offset, depth + 1);
                out.nodes[std::size_t(index)].children.push_back(c);
            }
        }
        return index;
    }
};

double distanceToBox(glm::dvec3 p, glm::dvec3 lo, glm::dvec3 hi) { return glm::length(p - glm::clamp(p, lo, hi)); }

struct Selector {
    const Tileset& tiles;
    const SelectionCamera& camera;
    double maxError;
    const std::function<bool(int)>& resident;
    const std::function<bool(int)>& unavailable;
    TileSelection out;

    bool hasContent(int i) const { return !tiles.nodes[std::size_t(i)].file.empty() && !unavailable(i); }

    void want(int i) {
        if (hasContent(i)) out.wanted.push_back(i);
    }

    // Appends what draws node i's part of the picture to `draw`; false when it cannot be drawn
    // from resident content (its parent then stands in).
    bool visit(int i, std::vector<int>& draw) {
        const TileNode& n = tiles.nodes[std::size_t(i)];
        if (outsideFrustum(camera.viewProj, n.boxMin, n.boxMax)) return true;
        const bool refine = !n.children.empty() && (!hasContent(i) || screenSpaceError(n, camera) > maxError);
        if (refine) {
            std::vector<int> below;
            bool ready = true;
            for (int c : n.children) ready = visit(c, below) && ready;  // every child, so all are requested
            // Without content of its own (the root, a broken HLOD) a node can only give what
            // its children have; a parent with content stands in for all of them instead.
            if (ready || !hasContent(i)) draw.insert(draw.end(), below.begin(), below.end());
            if (ready) return true;
        }
        // A leaf whose content is missing or broken: its parent stands in for it.
        if (!hasContent(i)) return n.file.empty() && n.children.empty();
        want(i);
        if (!resident(i)) {
            out.complete = false;
            return false;
        }
        draw.push_back(i);
        return true;
    }
};

}  // namespace

Tileset parseTileset(const std::string& text, const std::filesystem::path& dir, const std::string& file) {
    Json j;
    try {
        j = Json::parse(text);
    } catch (const Json::exception& e) {
        throw InputError(format("{}: not JSON ({})", file, oneLine(e.what())));
    }
    Reader r{dir, file, {}};
    if (!j.is_object() || !j.contains("asset") || !j.at("asset").is_object() || !j.at("asset").contains("version") ||
        !j.at("asset").at("version").is_string() || !j.at("asset").at("version").get<std::string>().starts_with("1."))
        r.fail("not a 3D Tiles 1.x tileset (asset.version)");
    if (!j.contains("root")) r.fail("no \"root\"");
    r.out.dir = dir;
    r.add(j.at("root"), -1, glm::dvec3(0.0), 0);
    const TileNode& root = r.out.nodes.front();
    r.out.boundsMin = root.areaMin;
    r.out.boundsMax = root.areaMax;
    // The root's area: the union of its children's (a root without content carries no extras.area).
    if (!root.children.empty()) {
        r.out.boundsMin = glm::dvec3(std::numeric_limits<double>::max());
        r.out.boundsMax = glm::dvec3(-std::numeric_limits<double>::max());
        for (int c : root.children) {
            r.out.boundsMin = glm::min(r.out.boundsMin, r.out.nodes[std::size_t(c)].areaMin);
            r.out.boundsMax = glm::max(r.out.boundsMax, r.out.nodes[std::size_t(c)].areaMax);
        }
    }
    return std::move(r.out);
}

Tileset readTileset(const std::filesystem::path& dir) {
    const std::filesystem::path file = dir / "tileset.json";
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
        throw InputError(format("{}: no tileset.json (build the world with `dawnforge world build`)", dir.string()));
    return parseTileset(readTextFile(file), dir, file.string());
}

double screenSpaceError(const TileNode& node, const SelectionCamera& camera) {
    const double d = distanceToBox(camera.position, node.areaMin, node.areaMax);
    if (d <= 0.0) return node.geometricError > 0.0 ? std::numeric_limits<double>::infinity() : 0.0;
    return node.geometricError * camera.screenHeight / (2.0 * d * std::tan(0.5 * camera.fovYRadians));
}

TileSelection selectTiles(const Tileset& tiles, const SelectionCamera& camera, double maxScreenError,
                          const std::function<bool(int)>& resident, const std::function<bool(int)>& unavailable) {
    Selector s{tiles, camera, maxScreenError, resident, unavailable, {}};
    if (tiles.nodes.empty()) return s.out;
    std::vector<int> draw;
    s.visit(0, draw);
    s.out.draw = std::move(draw);
    // Coarse before fine, then near before far: a parent is loaded before what replaces it.
    std::vector<double> distance(tiles.nodes.size(), 0.0);
    for (int i : s.out.wanted)
        distance[std::size_t(i)] = distanceToBox(camera.position, tiles.nodes[std::size_t(i)].areaMin, tiles.nodes[std::size_t(i)].areaMax);
    std::stable_sort(s.out.wanted.begin(), s.out.wanted.end(), [&](int a, int b) {
        const int da = tiles.nodes[std::size_t(a)].depth, db = tiles.nodes[std::size_t(b)].depth;
        return da != db ? da < db : distance[std::size_t(a)] < distance[std::size_t(b)];
    });
    return s.out;
}

std::vector<int> chooseEvictions(std::span<const ResidentTile> resident, std::size_t budget, double lowWater,
                                 std::uint64_t frame, std::uint64_t keepFrames) {
    std::size_t total = 0;
    for (const ResidentTile& r : resident) total += r.bytes;
    std::vector<int> out;
    if (total <= budget) return out;
    std::vector<std::size_t> order(resident.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return resident[a].lastUsed != resident[b].lastUsed ? resident[a].lastUsed < resident[b].lastUsed
                                                            : resident[a].node < resident[b].node;
    });
    const double target = lowWater * double(budget);
    for (std::size_t k : order) {
        if (double(total) <= target) break;
        const ResidentTile& r = resident[k];
        if (r.lastUsed + keepFrames > frame) break;  // sorted: every later one is more recent
        out.push_back(r.node);
        total -= r.bytes;
    }
    return out;
}

}  // namespace dawnforge::runtime
