// The world's plan (world/include/dawnforge/world/plan.hpp): owners, halos, the quadtree, the
// jobs, plan.json, and the settings it refuses.
#include <dawnforge/world/plan.hpp>

#include "jobs.hpp"
#include "test_support.hpp"

#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/procgen/building.hpp>
#include <dawnforge/procgen/geometry2d.hpp>
#include <dawnforge/procgen/plan.hpp>

#include <gtest/gtest.h>

#include <map>
#include <set>

namespace dawnforge {
namespace {

world::WorldSettings smallWorld() {
    world::WorldSettings s;
    s.size = {600.0, 400.0};
    s.tileSize = 150.0;
    s.halo = 40.0;
    s.seed = 3;
    return s;
}

// Every lot that the city puts a building on has exactly one owner tile, the one holding its
// centroid: computed here from generateCity of the whole city, not from the plan's code.
TEST(WorldPlan, EveryBuildingOfTheCityHasExactlyOneOwnerTile) {
    const world::WorldPlan plan = world::planWorld(smallWorld());
    ASSERT_EQ(plan.tileCount, glm::ivec2(4, 3));
    ASSERT_EQ(plan.tiles.size(), 12u);
    std::map<int, glm::ivec2> owner;
    for (const world::WorldTile& t : plan.tiles)
        for (int b : t.buildings) EXPECT_TRUE(owner.emplace(b, t.index).second) << "building " << b << " has two owners";
    procgen::CitySettings cs;
    cs.size = plan.settings.size;
    cs.seed = plan.settings.seed;
    cs.tileSize = plan.settings.tileSize;
    const procgen::City city = procgen::generateCity(cs);
    ASSERT_GT(city.buildings.size(), 20u);
    EXPECT_EQ(owner.size(), city.buildings.size());
    for (const procgen::Building& b : city.buildings) {
        ASSERT_TRUE(owner.contains(b.id)) << "building " << b.id;
        const glm::dvec2 c = procgen::centroid(city.plan.lots[std::size_t(b.lot)].polygon);
        EXPECT_EQ(owner[b.id], glm::ivec2(glm::floor(c / cs.tileSize))) << "building " << b.id;
    }
}

// A halo building lies within the halo of its tile and is owned by another; the halo's tiles
// are the neighbours the halo square reaches.
TEST(WorldPlan, HalosHoldTheNeighboursWithinTheirReach) {
    const world::WorldPlan plan = world::planWorld(smallWorld());
    const procgen::CityPlan city = procgen::planCity(plan.settings.recipe, plan.settings.seed, plan.settings.size);
    std::size_t halos = 0;
    for (const world::WorldTile& t : plan.tiles) {
        const glm::dvec2 lo = glm::dvec2(t.index) * 150.0 - 40.0, hi = glm::dvec2(t.index) * 150.0 + 190.0;
        for (int b : t.haloBuildings) {
            EXPECT_EQ(std::count(t.buildings.begin(), t.buildings.end(), b), 0);
            glm::dvec2 a(1e9), z(-1e9);
            for (glm::dvec2 p : city.lots[std::size_t(b)].polygon) a = glm::min(a, p), z = glm::max(z, p);
            EXPECT_TRUE(a.x <= hi.x && a.y <= hi.y && z.x >= lo.x && z.y >= lo.y) << "building " << b;
            ++halos;
        }
        // An inner tile's halo reaches its eight neighbours.
        if (t.index == glm::ivec2(1, 1)) {
            EXPECT_EQ(t.haloTiles.size(), 8u);
        }
        if (t.index == glm::ivec2(0, 0)) {
            EXPECT_EQ(t.haloTiles.size(), 3u);
        }
    }
    EXPECT_GT(halos, 10u);
    world::WorldSettings none = smallWorld();
    none.halo = 0.0;
    for (const world::WorldTile& t : world::planWorld(none).tiles) EXPECT_TRUE(t.haloTiles.empty() && t.haloBuildings.empty());
}

// The quadtree holds every tile once per level, the root all of them; the jobs follow it.
TEST(WorldPlan, TheQuadtreeCoversEveryTileOncePerLevel) {
    const world::WorldPlan plan = world::planWorld(smallWorld());
    ASSERT_EQ(plan.hlodLevels, 2);
    for (int level = 1; level <= 2; ++level) {
        std::multiset<std::pair<int, int>> seen;
        for (const world::HlodNode& n : plan.hlod)
            if (n.level == level)
                for (glm::ivec2 t : n.tiles) {
                    seen.insert({t.x, t.y});
                    EXPECT_EQ(t / (1 << level), n.index);
                }
        EXPECT_EQ(seen.size(), 12u);
        const std::set<std::pair<int, int>> distinct(seen.begin(), seen.end());
        EXPECT_EQ(distinct.size(), 12u);
    }
    EXPECT_EQ(world::stageJobs(plan, "hlod1").size(), 4u);
    EXPECT_EQ(world::stageJobs(plan, "hlod2").size(), 1u);
    EXPECT_EQ(world::stageJobs(plan, "bake").size(), 12u);
    const std::vector<std::string> stages{"city", "hlod1", "hlod2"};
    EXPECT_EQ(world::expandStages(plan, {"hlod", "city"}), stages);
}

TEST(WorldPlan, PlanJsonIsTheSameBytesAndReadsBack) {
    world::WorldSettings s = smallWorld();
    s.destroyPerTile = 1;
    const world::WorldPlan plan = world::planWorld(s);
    EXPECT_EQ(plan.destroy.size(), 12u);
    const std::string json = world::planJson(plan);
    EXPECT_EQ(json, world::planJson(world::planWorld(s)));
    test::TempDir dir;
    writeFileAtomically(dir / "plan.json", json);
    EXPECT_EQ(world::planJson(world::readPlan(dir.path())), json);
    test::writeText(dir / "plan.json", json.substr(0, json.size() / 2));
    EXPECT_TRUE(test::contains(test::inputErrorOf([&] { world::readPlan(dir.path()); }), "plan.json"));
}

TEST(WorldPlan, RefusesBadSettingsNamingTheOption) {
    const auto refused = [](auto edit) {
        world::WorldSettings s = smallWorld();
        edit(s);
        return test::inputErrorOf([&] { world::planWorld(s); });
    };
    EXPECT_TRUE(test::contains(refused([](auto& s) { s.tileSize = 0.0; }), "--tile-size"));
    EXPECT_TRUE(test::contains(refused([](auto& s) { s.tileSize = -5.0; }), "--tile-size"));
    EXPECT_TRUE(test::contains(refused([](auto& s) { s.tileSize = 601.0; }), "larger than the world"));
    EXPECT_TRUE(test::contains(refused([](auto& s) { s.size = {0.0, 100.0}; }), "--size"));
    EXPECT_TRUE(test::contains(refused([](auto& s) { s.halo = -1.0; }), "--halo"));
    EXPECT_TRUE(test::contains(refused([](auto& s) { s.destroy = {999999}; }), "999999"));
}

}  // namespace
}  // namespace dawnforge
