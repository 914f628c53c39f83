// The CPU half of streaming (tiles.hpp): a world's tileset.json read into runtime coordinates,
// the selection by screen-space error with REPLACE refinement that never leaves a hole, and the
// least-recently-used eviction with its hysteresis.
#include <dawnforge/core/error.hpp>
#include <dawnforge/runtime/tiles.hpp>

#include <nlohmann/json.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

namespace dawnforge::runtime {
namespace {

using Json = nlohmann::json;

// A world of 2 × 2 tiles of 128 m under one HLOD node, as `world build` writes it: each
// tile's box holds its content in its own frame, and the edge tiles carry 1 km of far land.
Json worldTileset() {
    Json tiles = Json::array();
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            const double x = 128.0 * i, y = 128.0 * j;
            tiles.push_back({{"boundingVolume", {{"box", {64 - 500.0 * (i == 0), 64, 10, 64 + 500.0, 0, 0, 0, 64, 0, 0, 0, 12}}}},
                             {"geometricError", 0.0},
                             {"transform", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, x, y, 0, 1}},
                             {"content", {{"uri", "tiles/" + std::to_string(i) + "_" + std::to_string(j) + "/city.glb"}}},
                             {"extras", {{"tile", {i, j}}, {"origin", {x, y}}, {"area", {0, 0, 128, 128}}}}});
        }
    // Around its children's boxes: x from −1000 (tile 0's far land) to 756 (tile 1's).
    Json hlod{{"boundingVolume", {{"box", {-122, 128, 10, 878, 0, 0, 0, 128, 0, 0, 0, 12}}}},
              {"geometricError", 2.0},
              {"refine", "REPLACE"},
              {"transform", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}},
              {"content", {{"uri", "hlod/1_0_0.glb"}}},
              {"extras", {{"hlod", "1_0_0"}, {"level", 1}, {"origin", {0, 0}}, {"area", {0, 0, 256, 256}}}},
              {"children", tiles}};
    return {{"asset", {{"version", "1.1"}}},
            {"geometricError", 1400.0},
            {"root", {{"boundingVolume", {{"box", {-122, 128, 10, 878, 0, 0, 0, 128, 0, 0, 0, 12}}}},
                      {"geometricError", 1400.0},
                      {"refine", "REPLACE"},
                      {"children", Json::array({hlod})}}}};
}

Tileset world() { return parseTileset(worldTileset().dump(), "/w", "/w/tileset.json"); }

int find(const Tileset& t, const std::string& name) {
    for (std::size_t i = 0; i < t.nodes.size(); ++i)
        if (t.nodes[i].name == name) return int(i);
    ADD_FAILURE() << "no node " << name;
    return -1;
}

SelectionCamera looking(glm::dvec3 eye, glm::dvec3 target) {
    SelectionCamera c;
    c.position = eye;
    c.fovYRadians = glm::radians(50.0);
    c.screenHeight = 720.0;
    c.viewProj = glm::perspective(c.fovYRadians, 16.0 / 9.0, 0.5, 4000.0) * glm::lookAt(eye, target, glm::dvec3(0, 1, 0));
    return c;
}

const auto kNone = [](int) { return false; };
const auto kAll = [](int) { return true; };

// A root transform that turns places the world on the globe (dawnforge's east-north-up to ECEF):
// the runtime draws in the root's frame, the same as without it; a turning child is refused.
TEST(Tiles, ARootOnTheGlobeIsDrawnInItsOwnFrame) {
    Json j = worldTileset();
    j["root"]["transform"] = {-0.17364817766693033, 0.984807753012208, 0, 0, -0.7544065067354889, -0.133022221559489,
                              0.6427876096865394, 0, 0.6330222215594891, 0.11161889704894966, 0.766044443118978, 0,
                              4045456.4053408867, 713323.1135414785, 4862789.037706437, 1};
    const Tileset globe = parseTileset(j.dump(), "/w", "/w/tileset.json"), flat = world();
    ASSERT_EQ(globe.nodes.size(), flat.nodes.size());
    for (std::size_t i = 0; i < flat.nodes.size(); ++i) {
        EXPECT_EQ(globe.nodes[i].offset, flat.nodes[i].offset) << flat.nodes[i].name;
        EXPECT_EQ(globe.nodes[i].boxMin, flat.nodes[i].boxMin) << flat.nodes[i].name;
    }
    j["root"]["transform"] = {0.5, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  // a scale: not a place on the globe
    try {
        parseTileset(j.dump(), "/w", "/w/tileset.json");
        ADD_FAILURE() << "a scaling root was read";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("not a translation"), std::string::npos) << e.what();
    }
}

TEST(Tiles, ReadsFramesBoxesAreasAndErrorsInRuntimeCoordinates) {
    const Tileset t = world();
    ASSERT_EQ(t.nodes.size(), 6u);
    const TileNode& root = t.nodes[0];
    EXPECT_TRUE(root.file.empty());
    EXPECT_EQ(root.geometricError, 1400.0);
    const TileNode& hlod = t.nodes[std::size_t(find(t, "hlod 1_0_0"))];
    EXPECT_TRUE(hlod.hlod);
    EXPECT_EQ(hlod.file, std::filesystem::path("/w/hlod/1_0_0.glb"));
    EXPECT_EQ(hlod.children.size(), 4u);
    // Tile (1, 1): plan origin (128, 128) → runtime (128, 0, −128); its box (far land and all)
    // spans x from 128 + 64 − 564 to 128 + 64 + 564, y (up) from −2 to 22, plan y 128..256 → z −256..−128.
    const TileNode& tile = t.nodes[std::size_t(find(t, "tile 1_1"))];
    EXPECT_FALSE(tile.hlod);
    EXPECT_EQ(tile.file, std::filesystem::path("/w/tiles/1_1/city.glb"));
    EXPECT_EQ(tile.offset, glm::dvec3(128.0, 0.0, -128.0));
    EXPECT_NEAR(tile.boxMin.x, 128.0 + 64.0 - 564.0, 1e-9);
    EXPECT_NEAR(tile.boxMax.x, 128.0 + 64.0 + 564.0, 1e-9);
    EXPECT_NEAR(tile.boxMin.y, -2.0, 1e-9);
    EXPECT_NEAR(tile.boxMax.y, 22.0, 1e-9);
    EXPECT_NEAR(tile.boxMin.z, -256.0, 1e-9);
    EXPECT_NEAR(tile.boxMax.z, -128.0, 1e-9);
    // The area leaves the far land out: the tile's own square.
    EXPECT_NEAR(tile.areaMin.x, 128.0, 1e-9);
    EXPECT_NEAR(tile.areaMax.x, 256.0, 1e-9);
    EXPECT_NEAR(tile.areaMin.z, -256.0, 1e-9);
    EXPECT_NEAR(tile.areaMax.z, -128.0, 1e-9);
    EXPECT_NEAR(t.boundsMin.x, 0.0, 1e-9);
    EXPECT_NEAR(t.boundsMax.x, 256.0, 1e-9);
}

TEST(Tiles, RefusesWhatItCannotStreamWithOneLineNamingTheFile) {
    const auto refused = [](const Json& j, const std::string& words) {
        try {
            parseTileset(j.dump(), "/w", "/w/tileset.json");
            ADD_FAILURE() << "accepted: " << words;
        } catch (const InputError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find("/w/tileset.json"), std::string::npos) << what;
            EXPECT_NE(what.find(words), std::string::npos) << what;
            EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        }
    };
    EXPECT_THROW(parseTileset("{not json", "/w", "/w/tileset.json"), InputError);
    Json j = worldTileset();
    j["asset"]["version"] = "2.0";
    refused(j, "3D Tiles 1.x");
    j = worldTileset();
    j["root"]["children"][0]["transform"][1] = 0.5;  // a rotation
    refused(j, "not a translation");
    j = worldTileset();
    j["root"]["children"][0]["boundingVolume"] = {{"region", {0, 0, 1, 1, 0, 10}}};
    refused(j, "box bounding volumes");
    j = worldTileset();
    j["root"]["children"][0]["refine"] = "ADD";
    refused(j, "REPLACE");
    j = worldTileset();
    j["root"]["children"][0]["content"]["uri"] = "hlod/1_0_0.b3dm";
    refused(j, "not a GLB");
    j = worldTileset();
    j["root"]["children"][0]["content"]["uri"] = "../elsewhere/x.glb";
    refused(j, "leaves the world's folder");
    j = worldTileset();
    j["root"]["children"][0]["geometricError"] = -1;
    refused(j, "geometricError");
    EXPECT_THROW(readTileset("/nonexistent/world"), InputError);
}

TEST(Tiles, ScreenSpaceErrorIsThe3dTilesFormula) {
    const Tileset t = world();
    const TileNode& hlod = t.nodes[std::size_t(find(t, "hlod 1_0_0"))];
    // 100 m above the area's top (22 m): d = 100, error 2 m, 720 px, 50°.
    const SelectionCamera c = looking({128, 122, -128}, {128, 0, -129});
    EXPECT_NEAR(screenSpaceError(hlod, c), 2.0 * 720.0 / (2.0 * 100.0 * std::tan(glm::radians(25.0))), 1e-9);
    // Inside the area: infinitely large for any error, zero for none.
    EXPECT_TRUE(std::isinf(screenSpaceError(hlod, looking({100, 5, -100}, {0, 5, -100}))));
    EXPECT_EQ(screenSpaceError(t.nodes[std::size_t(find(t, "tile 0_0"))], looking({100, 5, -100}, {0, 5, -100})), 0.0);
}

TEST(Tiles, FarCamerasDrawTheHlodNearCamerasTheTiles) {
    const Tileset t = world();
    const int hlod = find(t, "hlod 1_0_0");
    // 2 km away: the HLOD's 2 m is 1.5 px.
    TileSelection far = selectTiles(t, looking({128, 300, 2000}, {128, 0, -128}), 16.0, kAll, kNone);
    EXPECT_EQ(far.draw, std::vector<int>{hlod});
    EXPECT_TRUE(far.complete);
    // In the street of tile 0_0 looking north-east: the tiles it sees, no HLOD.
    TileSelection near = selectTiles(t, looking({64, 2, -64}, {200, 2, -200}), 16.0, kAll, kNone);
    EXPECT_FALSE(near.draw.empty());
    for (int i : near.draw) EXPECT_FALSE(t.nodes[std::size_t(i)].hlod);
    EXPECT_NE(std::find(near.draw.begin(), near.draw.end(), find(t, "tile 1_1")), near.draw.end());
    // A larger tolerance keeps the HLOD from farther.
    const SelectionCamera mid = looking({128, 40, 300}, {128, 0, -128});
    EXPECT_EQ(selectTiles(t, mid, 64.0, kAll, kNone).draw, std::vector<int>{hlod});
    EXPECT_NE(selectTiles(t, mid, 4.0, kAll, kNone).draw, std::vector<int>{hlod});
}

TEST(Tiles, AParentStaysUntilAllItsChildrenAreResident) {
    const Tileset t = world();
    const int hlod = find(t, "hlod 1_0_0"), missing = find(t, "tile 1_1");
    const SelectionCamera street = looking({64, 2, -64}, {200, 2, -200});
    // Nothing resident: nothing drawn, the HLOD wanted before any tile.
    TileSelection s = selectTiles(t, street, 16.0, kNone, kNone);
    EXPECT_TRUE(s.draw.empty());
    EXPECT_FALSE(s.complete);
    ASSERT_FALSE(s.wanted.empty());
    EXPECT_EQ(s.wanted.front(), hlod);
    // The HLOD and three tiles: the HLOD stands in for all four, and the fourth is wanted.
    s = selectTiles(t, street, 16.0, [&](int i) { return i != missing; }, kNone);
    EXPECT_EQ(s.draw, std::vector<int>{hlod});
    EXPECT_FALSE(s.complete);
    EXPECT_NE(std::find(s.wanted.begin(), s.wanted.end(), missing), s.wanted.end());
    // A tile that cannot be read: the HLOD stands in for it for good, and the selection is complete.
    s = selectTiles(t, street, 16.0, kAll, [&](int i) { return i == missing; });
    EXPECT_EQ(s.draw, std::vector<int>{hlod});
    EXPECT_TRUE(s.complete);
    EXPECT_EQ(std::find(s.wanted.begin(), s.wanted.end(), missing), s.wanted.end());
}

TEST(Tiles, CulledTilesAreNeitherDrawnNorWanted) {
    const Tileset t = world();
    // In tile 1_1 looking north, away from the tiles of row 0 (they lie behind the camera).
    const TileSelection s = selectTiles(t, looking({192, 2, -140}, {192, 2, -400}), 16.0, kAll, kNone);
    for (const std::string name : {"tile 0_0", "tile 1_0"}) {
        const int i = find(t, name);
        EXPECT_EQ(std::find(s.draw.begin(), s.draw.end(), i), s.draw.end()) << name;
        EXPECT_EQ(std::find(s.wanted.begin(), s.wanted.end(), i), s.wanted.end()) << name;
    }
    EXPECT_NE(std::find(s.draw.begin(), s.draw.end(), find(t, "tile 1_1")), s.draw.end());
}

// Any residency, any camera: every tile in view is drawn exactly once, by itself or by one
// ancestor, whenever any of them is resident; never a drawn node under a drawn node.
TEST(Tiles, NeverAHoleNeverTwiceForAnyResidencyAndCamera) {
    const Tileset t = world();
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-300.0, 600.0), h(1.0, 400.0);
    for (int trial = 0; trial < 2000; ++trial) {
        std::vector<bool> resident(t.nodes.size());
        for (std::size_t i = 0; i < resident.size(); ++i) resident[i] = (rng() & 1u) != 0;
        const glm::dvec3 eye(u(rng), h(rng), -u(rng));
        const SelectionCamera c = looking(eye, {u(rng), 0.0, -u(rng)});
        const TileSelection s = selectTiles(t, c, 16.0, [&](int i) { return bool(resident[std::size_t(i)]); }, kNone);
        const std::set<int> drawn(s.draw.begin(), s.draw.end());
        ASSERT_EQ(drawn.size(), s.draw.size());
        for (int i : s.draw) ASSERT_TRUE(resident[std::size_t(i)]);
        const int hlod = find(t, "hlod 1_0_0");
        for (int leaf : t.nodes[std::size_t(hlod)].children) {
            const TileNode& n = t.nodes[std::size_t(leaf)];
            const glm::dmat4 m = glm::transpose(c.viewProj);
            bool outside = false;
            for (const glm::dvec4& p : {m[3] + m[0], m[3] - m[0], m[3] + m[1], m[3] - m[1], m[3] + m[2], m[3] - m[2]}) {
                const glm::dvec3 far(p.x > 0 ? n.boxMax.x : n.boxMin.x, p.y > 0 ? n.boxMax.y : n.boxMin.y, p.z > 0 ? n.boxMax.z : n.boxMin.z);
                outside = outside || glm::dot(glm::dvec3(p), far) + p.w < 0.0;
            }
            if (outside) continue;
            const int covering = int(drawn.count(leaf)) + int(drawn.count(hlod));
            ASSERT_LE(covering, 1) << "trial " << trial;
            if (resident[std::size_t(hlod)]) ASSERT_EQ(covering, 1) << "trial " << trial << ": a hole at " << n.name;
        }
    }
}

TEST(Tiles, EvictionIsLeastRecentlyUsedWithHysteresis) {
    const std::vector<ResidentTile> held{{1, 100, 50}, {2, 100, 10}, {3, 100, 30}, {4, 100, 99}, {5, 100, 20}};
    // 500 held under a budget of 500: nothing leaves.
    EXPECT_TRUE(chooseEvictions(held, 500, 0.6, 100, 5).empty());
    // Over a budget of 400: the least recently used go until at most 0.6 × 400 = 240 remain.
    EXPECT_EQ(chooseEvictions(held, 400, 0.6, 100, 5), (std::vector<int>{2, 5, 3}));
    // Never what was used within the last 75 frames (now 100): 2 (frame 10) and 5 (20) go, 3 (30) stays.
    EXPECT_EQ(chooseEvictions(held, 400, 0.6, 100, 75), (std::vector<int>{2, 5}));
    // Ties in age go by node, so the choice is the same on every run.
    const std::vector<ResidentTile> ties{{9, 100, 1}, {3, 100, 1}, {6, 100, 1}};
    EXPECT_EQ(chooseEvictions(ties, 250, 0.5, 100, 5), (std::vector<int>{3, 6}));
}

}  // namespace
}  // namespace dawnforge::runtime
