// Whole districts: tiles that match the whole city, byte-identical output on any thread
// count, buildings inside their lots, a report that lists what was made.
#include <dawnforge/core/error.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/procgen/city.hpp>
#include <dawnforge/core/materials.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include <map>

namespace dawnforge::procgen {
namespace {

CitySettings smallCity() {
    CitySettings s;
    s.size = {360.0, 300.0};
    s.tileSize = 180.0;
    s.seed = 11;
    s.recipe.buildings.maxFloors = 4;
    return s;
}

const City& wholeCity() {
    static const City city = generateCity(smallCity());
    return city;
}

TEST(City, HasBuildingsRoomsAndGroundInEveryTile) {
    const City& city = wholeCity();
    EXPECT_EQ(city.tiles.size(), 4u);
    EXPECT_GT(city.buildings.size(), 20u);
    for (const CityTile& t : city.tiles) {
        EXPECT_GT(t.ground.triangleCount(), 0u);
        validateMeshData(t.ground, t.ground.name);
    }
    std::size_t rooms = 0;
    for (const Building& b : city.buildings) rooms += b.rooms.size();
    EXPECT_GT(rooms, city.buildings.size() * 3);
}

TEST(City, ATileAloneIsTheSameTileOfTheWholeCity) {
    const City& whole = wholeCity();
    for (glm::ivec2 index : {glm::ivec2(1, 0), glm::ivec2(0, 1)}) {
        CitySettings s = smallCity();
        s.tile = index;
        const City alone = generateCity(s);
        ASSERT_EQ(alone.tiles.size(), 1u);
        const CityTile* same = nullptr;
        for (const CityTile& t : whole.tiles)
            if (t.index == index) same = &t;
        ASSERT_NE(same, nullptr);
        EXPECT_EQ(alone.tiles[0].ground.positions, same->ground.positions);
        EXPECT_EQ(alone.tiles[0].ground.indices, same->ground.indices);
        EXPECT_EQ(alone.tiles[0].land.positions, same->land.positions);
        EXPECT_EQ(alone.tiles[0].blocks, same->blocks);
        ASSERT_EQ(alone.tiles[0].buildings.size(), same->buildings.size());
        ASSERT_GT(same->buildings.size(), 0u);
        for (std::size_t k = 0; k < same->buildings.size(); ++k) {
            const Building& a = alone.buildings[static_cast<std::size_t>(alone.tiles[0].buildings[k])];
            const Building& b = whole.buildings[static_cast<std::size_t>(same->buildings[k])];
            EXPECT_EQ(a.id, b.id);
            EXPECT_EQ(a.lod0.positions, b.lod0.positions);
            EXPECT_EQ(a.lod0.indices, b.lod0.indices);
            EXPECT_EQ(a.lod0.uv1, b.lod0.uv1);
            EXPECT_EQ(a.lod1.positions, b.lod1.positions);
            EXPECT_EQ(a.rooms.size(), b.rooms.size());
        }
    }
}

// Beyond the city's land edges the ground rises into hills; the city stays flat, the sea
// stays sea, and the terrain meets the city's edge at its height.
TEST(City, TerrainRisesBeyondTheLandEdgesAndTheSeaStaysSea) {
    const City& city = wholeCity();
    const CitySettings s = smallCity();
    const TerrainRecipe& t = s.recipe.terrain;
    double highest = 0.0, farthest = 0.0;
    std::size_t beyond = 0;
    for (const CityTile& tile : city.tiles)
        for (const glm::vec3& p : tile.ground.positions) {
            const double x = p.x, y = -double(p.z), h = p.y;
            const double out = std::max({-x, x - s.size.x, -y, y - s.size.y, 0.0});
            farthest = std::max(farthest, out);
            if (out <= 0.0) {
                EXPECT_LE(h, s.recipe.streets.curbHeight + 1e-6) << "a hill inside the city at " << x << ", " << y;
                continue;
            }
            ++beyond;
            highest = std::max(highest, h);
            EXPECT_LE(h, t.hillHeight + 1e-6);
            EXPECT_GE(h, -s.recipe.coast.seabedDepth - 1e-6);
            if (y < 0.0) EXPECT_LE(h, 0.0) << "south of the city is sea, at " << x << ", " << y;
        }
    EXPECT_GT(beyond, 1000u);
    EXPECT_NEAR(farthest, t.margin, 10.0 + 1e-6);
    EXPECT_GT(highest, 0.5 * t.hillHeight) << "no hills";
    // The far land reaches kilometres out, beyond the margin, sea where the coast runs on.
    double reach = 0.0;
    for (const CityTile& tile : city.tiles)
        for (const glm::vec3& p : tile.land.positions) {
            const double x = p.x, y = -double(p.z);
            const double out = std::max({-x, x - s.size.x, -y, y - s.size.y});
            EXPECT_GE(out, t.margin - 1e-3);
            reach = std::max(reach, out);
            if (y < 0.0) EXPECT_LT(p.y, 0.0);
        }
    EXPECT_GT(reach, 4000.0);
    // No terrain: the ground ends at the city's edge.
    CitySettings flat = smallCity();
    flat.recipe.terrain.margin = 0.0;
    flat.tile = glm::ivec2(0, 0);
    const City bare = generateCity(flat);
    for (const glm::vec3& p : bare.tiles[0].ground.positions) {
        EXPECT_GE(p.x, -1e-4);
        EXPECT_LE(p.z, 1e-4);
    }
}

TEST(City, SameSeedGivesIdenticalBytesOnAnyThreadCount) {
    auto bytes = [](std::size_t threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        City city = generateCity(smallCity());
        const std::string report = cityReportJson(city);
        std::vector<std::byte> glb = exporters::encodeGlb(takeCityScene(city));
        return std::make_pair(report, glb);
    };
    const auto one = bytes(1), two = bytes(2);
    EXPECT_EQ(one.first, two.first);
    EXPECT_TRUE(one.second == two.second);
    CitySettings other = smallCity();
    other.seed = 12;
    City different = generateCity(other);
    EXPECT_NE(cityReportJson(different), one.first);
}

TEST(City, NoBuildingLeavesItsLotAndNoLotTouchesAStreet) {
    const City& city = wholeCity();
    for (const Building& b : city.buildings) {
        const Lot& lot = city.plan.lots[static_cast<std::size_t>(b.lot)];
        for (const glm::vec3& p : b.lod0.positions) {
            const glm::dvec2 plan{p.x, -p.z};
            ASSERT_TRUE(containsPoint(lot.polygon, plan) || distanceToBoundary(lot.polygon, plan) < 1e-3)
                << "building " << b.id << " leaves its lot at " << plan.x << "," << plan.y;
        }
        // Lots keep clear of the streets' carriageways (the plan's own tests check the lots).
        for (const Street& street : city.plan.streets)
            for (std::size_t i = 0; i + 1 < street.polyline.size(); ++i)
                for (glm::dvec2 q : b.footprint)
                    ASSERT_GE(distanceToSegment(q, street.polyline[i], street.polyline[i + 1]), street.width / 2)
                        << "building " << b.id << " on street " << street.id;
    }
    // Lots are disjoint, so buildings inside them cannot overlap: check pairwise centroids.
    for (std::size_t i = 0; i < city.buildings.size(); ++i)
        for (std::size_t j = 0; j < city.buildings.size(); ++j) {
            if (i == j) continue;
            ASSERT_FALSE(containsPoint(city.buildings[i].footprint, centroid(city.buildings[j].footprint)))
                << "buildings " << city.buildings[i].id << " and " << city.buildings[j].id << " overlap";
        }
}

TEST(City, ReportCountsWhatWasMade) {
    City city = generateCity(smallCity());
    const auto j = nlohmann::json::parse(cityReportJson(city));
    EXPECT_EQ(j["seed"], 11);
    EXPECT_EQ(j["buildings"].size(), city.buildings.size());
    EXPECT_EQ(j["counts"]["buildings"], city.buildings.size());
    std::size_t rooms = 0, tri0 = 0;
    for (const auto& b : j["buildings"]) {
        for (const char* key : {"id", "lot", "lot_polygon", "footprint", "height", "floors", "roof", "rooms_per_floor"})
            EXPECT_TRUE(b.contains(key)) << key;
        EXPECT_EQ(b["rooms_per_floor"].size(), b["floors"].get<std::size_t>());
        for (const auto& r : b["rooms_per_floor"]) rooms += r.get<std::size_t>();
        tri0 += b["triangles"]["lod0"].get<std::size_t>();
    }
    EXPECT_EQ(j["counts"]["rooms"], rooms);
    EXPECT_EQ(j["counts"]["triangles"]["lod0"], tri0);
    EXPECT_GT(j["streets"].size(), 4u);
    EXPECT_EQ(j["blocks"].size(), city.plan.blocks.size());
    EXPECT_GT(j["coastline"].size(), 2u);
    std::map<std::string, int> roofs;
    for (const auto& b : j["buildings"]) roofs[b["roof"]]++;
    EXPECT_GE(roofs.size(), 3u) << "expected several roof types";
}

TEST(City, SceneHasATileNodePerTileAndTwoLodsPerBuilding) {
    City city = generateCity(smallCity());
    const std::size_t buildings = city.buildings.size();
    const Scene scene = takeCityScene(city);
    EXPECT_EQ(scene.roots.size(), 4u);
    std::size_t lod0 = 0, lod1 = 0;
    for (const Mesh& m : scene.meshes) {
        lod0 += m.name.ends_with("_lod0");
        lod1 += m.name.ends_with("_lod1");
        for (std::uint8_t id : m.materialIds) ASSERT_LT(id, 16);
    }
    EXPECT_EQ(lod0, buildings);
    EXPECT_EQ(lod1, buildings);
    EXPECT_EQ(scene.nodes[scene.roots[0]].name, "tile_0_0");
}

TEST(City, BadSettingsAreInputErrors) {
    auto fails = [](CitySettings s) {
        EXPECT_THROW(generateCity(s), InputError);
    };
    CitySettings s = smallCity();
    s.size = {-10.0, 100.0};
    fails(s);
    s = smallCity();
    s.tileSize = 0.0;
    fails(s);
    s = smallCity();
    s.tile = glm::ivec2(2, 0);
    fails(s);
    s = smallCity();
    s.recipe.buildings.storeyHeight = 0.0;
    fails(s);
}

}  // namespace
}  // namespace dawnforge::procgen
