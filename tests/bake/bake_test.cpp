// `bakeCity` on a small generated city, checked from the files it writes (bake_folder.hpp):
// rooms darker than roofs, lit rooms with lamp light, overlook heights that match the
// buildings, proxies, byte-identical files on any thread count, and bad input.
#include "probe_reference.hpp"
#include "render_support.hpp"
#include "test_support.hpp"

#include <dawnforge/bake/bake.hpp>
#include <dawnforge/bake/bake_folder.hpp>
#include <dawnforge/bake/lighting.hpp>
#include <dawnforge/bake/overlook.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/materials.hpp>
#include <dawnforge/core/read_file.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/procgen/city.hpp>
#include <dawnforge/runtime/probe_math.hpp>
#include <dawnforge/runtime/probe_placement.hpp>
#include <dawnforge/runtime/renderer.hpp>
#include <dawnforge/runtime/sky.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <optional>
#include <set>

namespace dawnforge::bake {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

// A coarse bake: seconds, yet every channel and file is there.
BakeSettings quickSettings() {
    BakeSettings s;
    s.texel = 0.5;
    s.interiorTexel = 0.75;
    s.groundTexel = 2.0;
    s.samples = 16;
    s.sunSamples = 4;
    s.bounces = 1;
    return s;
}

void writeCity(const fs::path& dir) {
    procgen::CitySettings settings;
    settings.size = {120.0, 100.0};
    procgen::City city = procgen::generateCity(settings);
    const std::string report = procgen::cityReportJson(city);
    const Scene scene = procgen::takeCityScene(city);
    fs::create_directories(dir);
    exporters::writeGlb(scene, dir / "city.glb");
    test::writeText(dir / "city.json", report);
}

// One city baked on 1 and on 2 threads, shared by the tests of the suite.
class BakeCity : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new TempDir();
        for (const char* name : {"one", "two"}) {
            writeCity(dir() / name);
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism, name[0] == 'o' ? 1 : 2);
            report_ = bakeCity(dir() / name, quickSettings());
        }
    }
    static void TearDownTestSuite() {
        delete dir_;
        dir_ = nullptr;
    }
    static fs::path dir() { return dir_->path(); }
    static TempDir* dir_;
    static BakeReport report_;
};
TempDir* BakeCity::dir_ = nullptr;
BakeReport BakeCity::report_;

// The four decoded channels of the lightmap texel nearest uv.
glm::vec4 texelAt(const BakedReceiver& r, glm::vec2 uv) {
    const int x = std::clamp(int(uv.x * float(r.width)), 0, r.width - 1);
    const int y = std::clamp(int(uv.y * float(r.height)), 0, r.height - 1);
    const std::uint8_t* p = &r.rgba[4 * (std::size_t(y) * std::size_t(r.width) + std::size_t(x))];
    return {decodeChannel(p[0], 0), decodeChannel(p[1], 1), decodeChannel(p[2], 2), decodeChannel(p[3], 3)};
}

// The lightmap value at the centroid of each triangle (nearest texel), by material, for every
// receiver of the bake: what the runtime reads, taken from the files.
struct Samples {
    std::map<int, std::vector<glm::vec4>> byMaterial;
};

Samples sampleCentroids(const fs::path& cityDir) {
    const std::vector<std::byte> glb = readBinaryFile(cityDir / "city.glb");
    const BakeFolder folder = readBake(cityDir, glb);
    std::map<std::string, const Mesh*> meshes;
    const std::vector<MeshNode> nodes = loadMeshNodes(cityDir / "city.glb");
    for (const MeshNode& n : nodes) meshes[n.name] = &n.mesh;
    Samples out;
    for (const BakedReceiver& r : folder.receivers)
        for (const BakedMesh& bm : r.meshes) {
            if (!bm.node.ends_with("_lod0")) continue;
            const Mesh& m = *meshes.at(bm.node);
            for (std::size_t t = 0; t < m.triangleCount(); ++t) {
                const std::uint32_t* idx = &m.indices[3 * t];
                const glm::vec2 uv = (bm.uv[idx[0]] + bm.uv[idx[1]] + bm.uv[idx[2]]) / 3.0f;
                out.byMaterial[m.materialIds[idx[0]]].push_back(texelAt(r, uv));
            }
        }
    return out;
}

glm::vec4 mean(const std::vector<glm::vec4>& v) {
    glm::vec4 s(0.0f);
    for (const glm::vec4& x : v) s += x;
    return v.empty() ? s : s / float(v.size());
}

TEST_F(BakeCity, WritesEveryFileOfTheFolder) {
    const fs::path bake = dir() / "one" / "bake";
    const nlohmann::json j = nlohmann::json::parse(test::readText(bake / "bake.json"));
    EXPECT_EQ(j["format"], "dawnforge.bake");
    EXPECT_GT(report_.buildings, 3u);
    EXPECT_EQ(j["receivers"].size(), report_.receivers);
    for (const nlohmann::json& r : j["receivers"]) {
        EXPECT_TRUE(fs::exists(bake / r["lightmap"].get<std::string>()));
        EXPECT_TRUE(fs::exists(bake / r["uv"].get<std::string>()));
    }
    EXPECT_TRUE(fs::exists(bake / "overlook.exr"));
    EXPECT_TRUE(fs::exists(bake / "proxies.json"));
    for (const fs::directory_entry& e : fs::directory_iterator(dir() / "one"))
        EXPECT_FALSE(e.path().filename().string().starts_with("bake.")) << "a temporary folder was left: " << e.path();
}

TEST_F(BakeCity, SameBytesOnOneAndTwoThreads) {
    std::size_t files = 0;
    for (const fs::directory_entry& e : fs::directory_iterator(dir() / "one" / "bake")) {
        const fs::path other = dir() / "two" / "bake" / e.path().filename();
        ASSERT_TRUE(fs::exists(other)) << other;
        EXPECT_EQ(test::readBytes(e.path()), test::readBytes(other)) << e.path().filename();
        ++files;
    }
    EXPECT_GT(files, 10u);
}

TEST_F(BakeCity, RoomsAreDarkerThanRoofsAndOpenWallsInBetween) {
    const Samples s = sampleCentroids(dir() / "one");
    const glm::vec4 floors = mean(s.byMaterial.at(kFloor)), roofs = mean(s.byMaterial.at(kRoofTiles));
    const glm::vec4 rooms = mean(s.byMaterial.at(kInteriorWall));
    // Roofs see most of the sky and little occludes them; rooms see the sky through windows only.
    EXPECT_GT(roofs.r, 0.6f);
    EXPECT_LT(floors.r, 0.25f * roofs.r);
    EXPECT_LT(rooms.r, 0.25f * roofs.r);
    EXPECT_LT(floors.b, roofs.b);  // AO
    EXPECT_LT(rooms.b, roofs.b);
    EXPECT_GT(roofs.b, 0.9f);
    // Outer walls: about half the sky, minus their neighbours.
    const glm::vec4 walls = mean(s.byMaterial.at(kPlaster));
    EXPECT_GT(walls.r, floors.r);
    EXPECT_LT(walls.r, roofs.r);
}

TEST_F(BakeCity, LitRoomsHaveLampLightAndUnlitOnesLess) {
    // Glass points at its room's block of the room table: A there is the lamp light of the
    // room's surfaces seen through the window; lit rooms are the runtime's lit windows.
    const fs::path city = dir() / "one";
    const BakeFolder folder = readBake(city, readBinaryFile(city / "city.glb"));
    std::map<std::string, const Mesh*> meshes;
    const std::vector<MeshNode> nodes = loadMeshNodes(city / "city.glb");
    for (const MeshNode& n : nodes) meshes[n.name] = &n.mesh;
    double litSum = 0.0, unlitSum = 0.0;
    std::size_t lit = 0, unlit = 0, darkLit = 0;
    for (const BakedReceiver& r : folder.receivers) {
        if (!r.name.starts_with("building_")) continue;
        const auto building = std::uint32_t(std::stoul(r.name.substr(9)));
        const BakedMesh& bm = r.meshes.front();
        const Mesh& m = *meshes.at(bm.node);
        std::map<std::uint32_t, float> rooms;
        for (std::size_t t = 0; t < m.triangleCount(); ++t) {
            const std::uint32_t v = m.indices[3 * t];
            if (m.materialIds[v] != kGlass || m.uv1[v].x <= 0.0f) continue;
            const int x = int(bm.uv[v].x * float(r.width)), y = int(bm.uv[v].y * float(r.height));
            rooms[std::uint32_t(std::lround(m.uv1[v].y))] = decodeChannel(r.rgba[4 * (std::size_t(y) * std::size_t(r.width) + std::size_t(x)) + 3], 3);
        }
        for (const auto& [room, a] : rooms) {
            if (roomLampLit(building, room)) {
                litSum += a, ++lit;
                darkLit += a <= 0.0f;
            } else {
                unlitSum += a, ++unlit;
            }
        }
    }
    ASSERT_GT(lit, 20u);
    ASSERT_GT(unlit, 20u);
    EXPECT_LE(darkLit, lit / 20) << "lit rooms without lamp light";
    EXPECT_GT(litSum / double(lit), 0.1);
    EXPECT_GT(litSum / double(lit), 4.0 * unlitSum / double(unlit));
}

TEST_F(BakeCity, OverlookHeightsMatchTheBuildings) {
    const fs::path city = dir() / "one";
    const OverlookMap map = readOverlook(city / "bake" / "overlook.exr");
    ASSERT_GT(map.width, 100);
    const std::vector<MeshNode> nodes = loadMeshNodes(city / "city.glb");
    std::size_t buildings = 0;
    for (const MeshNode& n : nodes) {
        if (!n.name.ends_with("_lod1")) continue;
        glm::vec3 lo(1e9f), hi(-1e9f);
        for (const glm::vec3& p : n.mesh.positions) {
            const glm::vec3 w(n.world * glm::vec4(p, 1.0f));
            lo = glm::min(lo, w), hi = glm::max(hi, w);
        }
        float highest = kNoRoof;
        for (int j = 0; j < map.height; ++j)
            for (int i = 0; i < map.width; ++i) {
                const double x = map.origin.x + (i + 0.5) * map.texel, z = map.origin.y + (j + 0.5) * map.texel;
                if (x < lo.x || x > hi.x || z < lo.z || z > hi.z) continue;
                const std::size_t k = std::size_t(j) * std::size_t(map.width) + std::size_t(i);
                highest = std::max(highest, map.roof[k]);
                if (map.roof[k] != kNoRoof) {
                    // The first surface from above is the roof: depth = top - roof.
                    EXPECT_NEAR(map.depth[k], map.top - map.roof[k], 1e-3);
                    EXPECT_GE(map.roof[k], map.ground[k] - 1e-3f);
                }
            }
        // The highest roof texel within half a texel's slope of the building's top (ridges).
        EXPECT_LE(highest, hi.y + 1e-3f) << n.name;
        EXPECT_GE(highest, hi.y - 0.6f) << n.name;
        ++buildings;
    }
    EXPECT_GT(buildings, 3u);
}

TEST_F(BakeCity, ProxiesCoverEveryBuildingWithColoursInRange) {
    const nlohmann::json j = nlohmann::json::parse(test::readText(dir() / "one" / "bake" / "proxies.json"));
    EXPECT_EQ(j["format"], "dawnforge.proxies");
    std::map<std::string, int> kinds;
    std::set<std::string> buildings;
    for (const nlohmann::json& b : j["boxes"]) {
        ++kinds[b["kind"].get<std::string>()];
        if (b["kind"] == "building") buildings.insert(b["name"].get<std::string>());
        ASSERT_EQ(b["colours"].size(), 6u);
        for (const nlohmann::json& c : b["colours"])
            for (int k = 0; k < 3; ++k) {
                EXPECT_GE(c[k].get<double>(), 0.0);
                EXPECT_LE(c[k].get<double>(), 1.0);
            }
        for (int k = 0; k < 3; ++k) EXPECT_GT(b["half_size"][k].get<double>(), 0.0);
        // Hills and the sea floor come in chunks: no ground box reaches from a valley to a hilltop.
        if (b["kind"] == "ground") {
            EXPECT_LE(b["half_size"][1].get<double>(), 3.5) << b["name"] << " " << b["part"];
        }
    }
    EXPECT_EQ(buildings.size(), report_.buildings);
    EXPECT_GT(kinds["ground"], 0);
}

// Probes placed from the bake's proxies along every street of the city: none inside a
// building's LOD1 shell (tested against the shell's own triangles by a vertical ray count),
// none under the ground, and some everywhere the camera goes.
TEST_F(BakeCity, ProbesFromTheProxiesStayOutOfBuildingsAndTheGround) {
    const fs::path city = dir() / "one";
    const runtime::ProbeField field(runtime::parseProbeBoxes(test::readText(city / "bake" / "proxies.json"), "proxies.json"));
    std::vector<Mesh> shells;
    for (MeshNode& n : loadMeshNodes(city / "city.glb"))
        if (n.name.ends_with("_lod1")) {
            for (glm::vec3& p : n.mesh.positions) p = glm::vec3(n.world * glm::vec4(p, 1.0f));
            shells.push_back(std::move(n.mesh));
        }
    // Inside a closed shell: an odd number of its triangles above the point (a ray straight up).
    const auto insideShell = [&](glm::dvec3 p) {
        for (const Mesh& m : shells) {
            int crossings = 0;
            for (std::size_t t = 0; t < m.triangleCount(); ++t) {
                const glm::dvec3 a(m.positions[m.indices[3 * t]]), b(m.positions[m.indices[3 * t + 1]]), c(m.positions[m.indices[3 * t + 2]]);
                const double d = (b.z - c.z) * (a.x - c.x) + (c.x - b.x) * (a.z - c.z);
                if (std::abs(d) < 1e-12) continue;
                const double u = ((b.z - c.z) * (p.x - c.x) + (c.x - b.x) * (p.z - c.z)) / d;
                const double v = ((c.z - a.z) * (p.x - c.x) + (a.x - c.x) * (p.z - c.z)) / d;
                if (u < 0.0 || v < 0.0 || u + v > 1.0) continue;
                crossings += (u * a.y + v * b.y + (1.0 - u - v) * c.y) > p.y;
            }
            if (crossings % 2 == 1) return true;
        }
        return false;
    };
    std::size_t placed = 0, inside = 0, under = 0;
    for (double x = 10.0; x < 120.0; x += 25.0)
        for (double z = -10.0; z > -100.0; z -= 25.0) {
            const std::vector<runtime::PlacedProbe> probes = field.place({x, 1.7, z}, {7.5, 4.0, 7.5}, 2.0);
            placed += probes.size();
            for (const runtime::PlacedProbe& p : probes) {
                inside += insideShell(p.position);
                under += p.position.y < 0.0;
            }
        }
    EXPECT_GT(placed, 500u);
    EXPECT_EQ(inside, 0u);
    EXPECT_EQ(under, 0u);
}

// The probes of a baked district against the ground truth: probes captured on llvmpipe from
// the bake's proxies (the sun's shadow from the city's own shadow map) and an Embree reference
// traced from the same boxes (proxies.json read here), one bounce, at three street spots.
TEST_F(BakeCity, ProbesAgreeWithAnEmbreeReferenceFromTheProxies) {
    test::llvmpipeContext();
    const fs::path city = dir() / "one";
    const nlohmann::json proxies = nlohmann::json::parse(test::readText(city / "bake" / "proxies.json"));
    const auto vec = [](const nlohmann::json& v) { return glm::dvec3(v[0].get<double>(), v[1].get<double>(), v[2].get<double>()); };
    std::vector<test::ReferenceBox> boxes;
    for (const nlohmann::json& b : proxies["boxes"]) {
        test::ReferenceBox r;
        r.centre = vec(b["centre"]);
        r.axes = {vec(b["u"]), glm::dvec3(0, 1, 0), vec(b["w"])};
        r.half = vec(b["half_size"]);
        for (std::size_t f = 0; f < 6; ++f) r.colours[f] = vec(b["colours"][f]);
        boxes.push_back(r);
    }
    runtime::SceneFile scene;
    scene.cityDir = city;
    scene.lensFlares = false;
    scene.probes.preset = "mid";
    scene.probes.multiBounce = false;
    runtime::RendererOptions options;
    options.size = {64, 48};
    runtime::Renderer renderer(scene, options);
    for (const glm::dvec3 spot : {glm::dvec3(35, 1.7, -35), glm::dvec3(85, 1.7, -60), glm::dvec3(60, 1.7, -85)})
        renderer.render(test::lookingAt(spot, spot + glm::dvec3(10, 0, 0), 15.0));
    const std::vector<runtime::CapturedProbe> probes = renderer.capturedProbes();
    ASSERT_GT(probes.size(), 60u);
    const test::ProbeReference reference(boxes);
    const runtime::Lighting light = runtime::lightingAt(15.0);
    double squaredError = 0.0, squaredReference = 0.0;
    for (const runtime::CapturedProbe& p : probes)
        for (const glm::dvec3 n : {glm::dvec3(1, 0, 0), glm::dvec3(-1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, -1, 0),
                                   glm::dvec3(0, 0, 1), glm::dvec3(0, 0, -1)}) {
            const glm::dvec3 gpu = runtime::shIrradiance(p.radiance, n), cpu = reference.irradiance(p.position, n, light, 2048);
            squaredError += glm::dot(gpu - cpu, gpu - cpu);
            squaredReference += glm::dot(cpu, cpu);
        }
    const double rms = std::sqrt(squaredError / squaredReference);
    std::printf("district probes: %zu, relative RMS error %.4f\n", probes.size(), rms);
    EXPECT_LT(rms, 0.05);
}

TEST_F(BakeCity, ABakeOfAnotherCityIsRefused) {
    std::vector<std::byte> glb = readBinaryFile(dir() / "one" / "city.glb");
    glb.back() = std::byte(int(glb.back()) ^ 1);
    EXPECT_TRUE(test::contains(test::inputErrorOf([&] { readBake(dir() / "one", glb); }), "another city.glb"));
}

// The lamp channel of the ground under a plan point (x, y): the highest upward triangle of
// any ground_ mesh over it, its UV interpolated, the nearest texel decoded.
std::optional<float> groundLamp(const BakeFolder& folder, const std::map<std::string, const Mesh*>& meshes, glm::dvec2 p) {
    std::optional<float> best;
    float bestHeight = -1e9f;
    const glm::vec2 q(float(p.x), float(-p.y));  // glTF (x, z)
    for (const BakedReceiver& r : folder.receivers)
        for (const BakedMesh& bm : r.meshes) {
            if (!bm.node.starts_with("ground_")) continue;
            const Mesh& m = *meshes.at(bm.node);
            for (std::size_t t = 0; t < m.triangleCount(); ++t) {
                const std::uint32_t* idx = &m.indices[3 * t];
                const glm::vec3 a = m.positions[idx[0]], b = m.positions[idx[1]], c = m.positions[idx[2]];
                if (glm::normalize(glm::cross(b - a, c - a)).y < 0.9f) continue;
                // Barycentric coordinates of q in the triangle's xz projection.
                const glm::vec2 v0(b.x - a.x, b.z - a.z), v1(c.x - a.x, c.z - a.z), v2(q.x - a.x, q.y - a.z);
                const float den = v0.x * v1.y - v1.x * v0.y;
                const float u = (v2.x * v1.y - v1.x * v2.y) / den, v = (v0.x * v2.y - v2.x * v0.y) / den;
                if (u < 0.0f || v < 0.0f || u + v > 1.0f) continue;
                const float h = a.y + u * (b.y - a.y) + v * (c.y - a.y);
                if (h <= bestHeight) continue;
                const glm::vec2 uv = bm.uv[idx[0]] + u * (bm.uv[idx[1]] - bm.uv[idx[0]]) + v * (bm.uv[idx[2]] - bm.uv[idx[0]]);
                bestHeight = h;
                best = texelAt(r, uv).a;
            }
        }
    return best;
}

// The street lamps of city.json light the pavement under them (the lamp channel), and
// nothing lights the ground far from them.
TEST_F(BakeCity, StreetLampsLightTheGroundUnderThem) {
    const fs::path city = dir() / "one";
    const BakeFolder folder = readBake(city, readBinaryFile(city / "city.glb"));
    const std::vector<MeshNode> nodes = loadMeshNodes(city / "city.glb");
    std::map<std::string, const Mesh*> meshes;
    for (const MeshNode& n : nodes) meshes[n.name] = &n.mesh;
    const nlohmann::json j = nlohmann::json::parse(test::readText(city / "city.json"));
    std::vector<glm::dvec2> lights;
    for (const nlohmann::json& l : j["lamps"]) lights.emplace_back(l["light"][0].get<double>(), l["light"][1].get<double>());
    ASSERT_GE(lights.size(), 3u);
    std::vector<float> near, far;
    for (double x = 1.0; x < 120.0; x += 1.5)
        for (double y = 1.0; y < 100.0; y += 1.5) {
            double d = 1e9;
            for (glm::dvec2 l : lights) d = std::min(d, glm::length(l - glm::dvec2(x, y)));
            if (d > 1.5 && d < 9.0) continue;
            const std::optional<float> a = groundLamp(folder, meshes, {x, y});
            if (a) (d <= 1.5 ? near : far).push_back(*a);
        }
    ASSERT_GT(near.size(), 3u);
    ASSERT_GT(far.size(), 100u);
    const auto average = [](const std::vector<float>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / double(v.size()); };
    EXPECT_GT(average(near), 0.3) << "under a lamp";
    EXPECT_LT(average(far), 0.02) << "out of every lamp's reach";
}

TEST(BakeInput, MissingOrIncompleteCitiesAndBudgetsAreRefusedWithNothingWritten) {
    TempDir dir;
    EXPECT_TRUE(test::contains(test::inputErrorOf([&] { bakeCity(dir / "nowhere", quickSettings()); }), "no such city folder"));
    writeCity(dir / "city");
    fs::remove(dir / "city" / "city.json");
    EXPECT_TRUE(test::contains(test::inputErrorOf([&] { bakeCity(dir / "city", quickSettings()); }), "city.json"));
    test::writeText(dir / "city" / "city.json", R"({"counts": {"buildings": 999}})");
    EXPECT_TRUE(test::contains(test::inputErrorOf([&] { bakeCity(dir / "city", quickSettings()); }), "999"));
    writeCity(dir / "city");
    BakeSettings huge = quickSettings();
    huge.texel = huge.interiorTexel = 0.05;
    huge.memoryBudgetMb = 64;
    const std::string message = test::inputErrorOf([&] { bakeCity(dir / "city", huge); });
    EXPECT_TRUE(test::contains(message, "budget of 64 MB")) << message;
    huge.texel = huge.interiorTexel = 0.01;  // a wall wider than a chart can hold
    huge.memoryBudgetMb = 1e6;
    bool budget = false;
    try {
        bakeCity(dir / "city", huge);
    } catch (const BakeBudgetError& e) {
        budget = test::contains(e.what(), "texels of 0.01 m");
    }
    EXPECT_TRUE(budget);
    BakeSettings bad = quickSettings();
    bad.samples = 0;
    EXPECT_TRUE(test::contains(test::inputErrorOf([&] { bakeCity(dir / "city", bad); }), "sample count"));
    std::vector<std::string> left;
    for (const fs::directory_entry& e : fs::directory_iterator(dir / "city")) left.push_back(e.path().filename().string());
    std::sort(left.begin(), left.end());
    EXPECT_EQ(left, (std::vector<std::string>{"city.glb", "city.json"}));
}

}  // namespace
}  // namespace dawnforge::bake
