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
    EXPECT_TRUE(test::contains(json, "\"origin\"")) << "the globe origin is in the plan";
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
    EXPECT_TRUE(test::contains(refused([](auto& s) { s.origin.latitude = 91.0; }), "--origin"));
    EXPECT_TRUE(test::contains(refused([](auto& s) { s.origin.longitude = -181.0; }), "--origin"));
    EXPECT_TRUE(test::contains(refused([](auto& s) { s.origin.height = std::nan(""); }), "--origin"));
}

// The plan's east-north-up frame on WGS84, against values worked out by hand: at 0° E, 0° N
// east is +y, north +z, up +x and the origin is a from the centre; at the pole, up is +z and
// the origin b = a √(1 − e²) from it; elsewhere the frame is orthonormal, right-handed, and a
// height moves the origin along up.
TEST(WorldPlan, TheOriginsEastNorthUpFrameOnTheEllipsoid) {
    constexpr double a = 6378137.0, b = 6356752.314245;
    const glm::dmat4 equator = world::enuToEcef({0.0, 0.0, 0.0});
    EXPECT_NEAR(glm::distance(glm::dvec3(equator[0]), glm::dvec3(0, 1, 0)), 0.0, 1e-15);
    EXPECT_NEAR(glm::distance(glm::dvec3(equator[1]), glm::dvec3(0, 0, 1)), 0.0, 1e-15);
    EXPECT_NEAR(glm::distance(glm::dvec3(equator[2]), glm::dvec3(1, 0, 0)), 0.0, 1e-15);
    EXPECT_NEAR(glm::distance(glm::dvec3(equator[3]), glm::dvec3(a, 0, 0)), 0.0, 1e-6);
    const glm::dmat4 pole = world::enuToEcef({0.0, 90.0, 100.0});
    EXPECT_NEAR(glm::distance(glm::dvec3(pole[3]), glm::dvec3(0, 0, b + 100.0)), 0.0, 1e-3);
    EXPECT_NEAR(glm::distance(glm::dvec3(pole[2]), glm::dvec3(0, 0, 1)), 0.0, 1e-15);
    const world::GeoOrigin somewhere{-122.4783, 37.808, 20.0};
    const glm::dmat4 m = world::enuToEcef(somewhere);
    const glm::dmat3 r(m);
    EXPECT_NEAR(glm::determinant(r), 1.0, 1e-12);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(glm::dot(r[i], r[j]), i == j ? 1.0 : 0.0, 1e-12);
    const glm::dmat4 ground = world::enuToEcef({somewhere.longitude, somewhere.latitude, 0.0});
    EXPECT_NEAR(glm::distance(glm::dvec3(m[3]), glm::dvec3(ground[3]) + 20.0 * glm::dvec3(m[2])), 0.0, 1e-6);
    // Up is the ellipsoid's normal: it leans from the radius towards the equator's plane.
    const double geocentric = std::asin(glm::normalize(glm::dvec3(ground[3])).z) * 180.0 / 3.14159265358979323846;
    EXPECT_LT(geocentric, somewhere.latitude);
    EXPECT_GT(geocentric, somewhere.latitude - 0.2);
}

}  // namespace
}  // namespace dawnforge
