// A building of a generated city, destroyed as a user would: fracture --building, simulate
// in its city, vat, and a scene that swaps the building for its destruction.
#include "test_support.hpp"

#include <dawnforge/core/import.hpp>
#include <dawnforge/core/materials.hpp>
#include <dawnforge/core/validate.hpp>
#include <dawnforge/exporters/image.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <map>
#include <numeric>

using namespace dawnforge;
using dawnforge::test::RunResult;
using dawnforge::test::TempDir;
using Json = nlohmann::json;

namespace {

// One small city for the whole suite, and the smallest building of it with glass and a door.
class CliBuilding : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new TempDir();
        const RunResult r = test::runDawnforge({"--quiet", "city", "-o", city().string(), "--size", "120x100", "--seed", "3"});
        ASSERT_EQ(r.exitCode, 0) << r.err;
        const Json json = Json::parse(test::readText(city() / "city.json"));
        std::size_t fewest = SIZE_MAX;
        for (const Json& b : json["buildings"]) {
            bool glass = false, door = false;
            for (const Json& p : b["parts"]) glass |= p[0] == "window", door |= p[0] == "door";
            const std::size_t triangles = b["triangles"]["lod0"].get<std::size_t>();
            if (glass && door && triangles < fewest) fewest = triangles, building_ = b["id"].get<int>();
        }
        ASSERT_GE(building_, 0) << "no building with windows and a door";
    }
    static void TearDownTestSuite() {
        delete dir_;
        dir_ = nullptr;
    }
    static std::filesystem::path city() { return dir_->path() / "city"; }
    static std::string id() { return std::to_string(building_); }
    // fracture --building into DIR/NAME with few Voronoi cells (the glass and the door add theirs).
    static RunResult fracture(const std::string& name, std::vector<std::string> extra = {}) {
        std::vector<std::string> args{"--quiet",  "fracture", city().string(), "--building", id(), "-o",
                                      (dir_->path() / name).string(), "--pieces", "12"};
        args.insert(args.end(), extra.begin(), extra.end());
        return test::runDawnforge(args);
    }
    static std::filesystem::path path(const std::string& name) { return dir_->path() / name; }

    static inline TempDir* dir_ = nullptr;
    static inline int building_ = -1;
};

double area(const Mesh& m, bool (*keep)(std::uint8_t)) {
    double a = 0.0;
    for (std::size_t t = 0; t < m.triangleCount(); ++t) {
        if (!m.materialIds.empty() && !keep(m.materialIds[m.indices[3 * t]])) continue;
        const glm::dvec3 p(m.positions[m.indices[3 * t]]), q(m.positions[m.indices[3 * t + 1]]),
            r(m.positions[m.indices[3 * t + 2]]);
        a += 0.5 * glm::length(glm::cross(q - p, r - p));
    }
    return a;
}

Mesh buildingLod0(const std::filesystem::path& city, int id) {
    char name[40];
    std::snprintf(name, sizeof name, "building_%05d_lod0", id);
    for (const MeshNode& node : loadMeshNodes(city / "city.glb"))
        if (node.name == name) return node.mesh;
    ADD_FAILURE() << "no " << name;
    return {};
}

// Parts joined through bonds: how many groups they make.
std::size_t partGroups(const Json& fracture) {
    const std::size_t n = fracture["parts"].size();
    std::vector<std::size_t> parent(n);
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](std::size_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    for (const Json& b : fracture["bonds"])
        parent[find(fracture["pieces"][b["a"].get<std::size_t>()]["part"].get<std::size_t>())] =
            find(fracture["pieces"][b["b"].get<std::size_t>()]["part"].get<std::size_t>());
    std::size_t groups = 0;
    for (std::size_t i = 0; i < n; ++i) groups += find(i) == i;
    return groups;
}

// The largest distance (per axis) any piece's centre moved between frame 0 and `frame` of a
// simulation folder's transforms.bin.
double largestMove(const std::filesystem::path& simDir, std::size_t pieces, std::size_t frame) {
    const std::vector<unsigned char> bytes = test::readBytes(simDir / "transforms.bin");
    std::vector<float> t(bytes.size() / 4);
    std::memcpy(t.data(), bytes.data(), bytes.size());
    const std::size_t last = frame * pieces * 7;
    EXPECT_LE(last + pieces * 7, t.size());
    double move = 0.0;
    for (std::size_t j = 0; j < pieces && last + 7 * j + 2 < t.size(); ++j)
        for (int k = 0; k < 3; ++k) move = std::max(move, double(std::abs(t[last + 7 * j + k] - t[7 * j + k])));
    return move;
}

}  // namespace

TEST_F(CliBuilding, FracturesEveryPartByItsMaterialIntoClosedPiecesGluedTogether) {
    const RunResult r = fracture("f");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const Json f = Json::parse(test::readText(path("f") / "fracture.json"));
    EXPECT_EQ(f["input"]["building"].get<int>(), building_);
    const Json cityJson = Json::parse(test::readText(city() / "city.json"));
    Json parts;
    for (const Json& b : cityJson["buildings"])
        if (b["id"] == building_) parts = b["parts"];
    ASSERT_EQ(f["parts"].size(), parts.size());
    std::vector<double> volume(parts.size(), 0.0);
    for (const Json& p : f["pieces"]) {
        EXPECT_TRUE(p["closed"].get<bool>()) << p["name"];
        const std::size_t part = p["part"].get<std::size_t>();
        EXPECT_EQ(p["material"], parts[part][1]) << p["name"];
        volume[part] += p["volume"].get<double>();
    }
    std::map<std::string, std::string> styles;
    for (std::size_t i = 0; i < parts.size(); ++i) {
        const Json& part = f["parts"][i];
        EXPECT_NEAR(volume[i], part["volume"].get<double>(), 1e-6 * part["volume"].get<double>()) << i;
        styles[part["material"].get<std::string>()] = part["style"].get<std::string>();
    }
    EXPECT_EQ(styles["glass"], "shards");
    EXPECT_EQ(styles["wood"], "splinters");
    EXPECT_EQ(partGroups(f), 1u) << "every part is glued to the rest of the building";
    double glass = 1e300, concrete = 0.0;
    for (const Json& b : f["bonds"]) {
        const std::string ma = f["pieces"][b["a"].get<std::size_t>()]["material"];
        const std::string mb = f["pieces"][b["b"].get<std::size_t>()]["material"];
        if (ma == "glass" || mb == "glass") glass = std::min(glass, b["strength"].get<double>());
        if (ma == "concrete" && mb == "concrete") concrete = std::max(concrete, b["strength"].get<double>());
    }
    EXPECT_LT(glass, concrete);
    // Each piece closed and manifold as written, no window attributes on glass.
    for (const MeshNode& node : loadMeshNodes(path("f") / "fragments.glb")) {
        const MeshReport report = inspectMesh(node.mesh);
        EXPECT_TRUE(report.closed && report.manifold && report.degenerateTriangles == 0) << node.name;
        EXPECT_TRUE(node.mesh.uv1.empty() && node.mesh.uv2.empty()) << node.name;
    }
    test::expectValidGltf(path("f") / "fragments.glb");
}

TEST_F(CliBuilding, SameBytesOnOneAndTwoThreads) {
    ASSERT_EQ(fracture("t1", {"--threads", "1"}).exitCode, 0);
    ASSERT_EQ(fracture("t2", {"--threads", "2"}).exitCode, 0);
    for (const char* file : {"fragments.glb", "fracture.json"})
        EXPECT_EQ(test::readBytes(path("t1") / file), test::readBytes(path("t2") / file)) << file;
}

TEST_F(CliBuilding, BadInputExits2WithOneLineAndWritesNothing) {
    const auto bad = [](std::vector<std::string> args, const std::string& mention) {
        const RunResult r = test::runDawnforge(args);
        EXPECT_EQ(r.exitCode, 2) << r.err;
        EXPECT_EQ(test::lineCount(r.err), 1u) << r.err;
        EXPECT_NE(r.err.find(mention), std::string::npos) << r.err;
    };
    const std::string out = path("bad").string();
    bad({"fracture", city().string(), "--building", "99999", "-o", out}, "no building 99999");
    bad({"fracture", path("").string(), "--building", id(), "-o", out}, "no city.json");
    std::filesystem::create_directories(path("tile"));
    test::writeText(path("tile") / "city.json", R"({"tile": [1, 0], "buildings": []})");
    bad({"fracture", path("tile").string(), "--building", id(), "-o", out}, "holds tile 1,0 only");
    bad({"fracture", city().string(), "--building", id(), "-o", out, "--strength", "glass:3"}, "MATERIAL=PA");
    bad({"fracture", city().string(), "--building", id(), "-o", out, "--density", "300"}, "--density");
    bad({"fracture", test::dataFile("cube_quads.obj").string(), "-o", out, "--shard-size", "1"}, "--building");
    EXPECT_FALSE(std::filesystem::exists(out));
}

// Left alone it stands; a light hit (2 t at 10 m/s, a car) breaks next to nothing; the default
// ball (20 t at 40 m/s) brings it down. Measured on this house: 0, then 573 of 620 bonds.
TEST_F(CliBuilding, StandsInItsCityWhenLeftAloneAndFallsOnlyWhenHitHard) {
    ASSERT_EQ(fracture("s").exitCode, 0);
    const std::string frac = path("s").string();
    RunResult r = test::runDawnforge({"--quiet", "simulate", frac, "-o", path("still").string(), "--frames", "300"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    Json sim = Json::parse(test::readText(path("still") / "sim.json"));
    EXPECT_GT(sim["colliders"].get<int>(), 0) << "the ground and neighbours";
    EXPECT_EQ(sim["glue"]["broken"].get<int>(), 0);
    const std::size_t pieces = sim["pieces"].get<std::size_t>();
    EXPECT_LT(largestMove(path("still"), pieces, 300 - 1), 0.02) << "sag after 10 s";

    const Json f = Json::parse(test::readText(path("s") / "fracture.json"));
    glm::dvec3 lo(1e300), hi(-1e300);
    for (const Json& p : f["pieces"])
        for (int k = 0; k < 3; ++k)
            lo[k] = std::min(lo[k], p["center_of_mass"][k].get<double>()), hi[k] = std::max(hi[k], p["center_of_mass"][k].get<double>());
    const std::string target = std::to_string(0.5 * (lo.x + hi.x)) + "," + std::to_string(0.5 * (lo.y + hi.y)) + "," +
                               std::to_string(0.5 * (lo.z + hi.z));
    const auto hit = [&](const std::string& name, std::vector<std::string> ball) {
        std::vector<std::string> args{"--quiet", "simulate", frac, "-o", path(name).string(), "--frames", "60",
                                      "--projectile", target, "--projectile-radius", "1.5"};
        args.insert(args.end(), ball.begin(), ball.end());
        const RunResult run = test::runDawnforge(args);
        EXPECT_EQ(run.exitCode, 0) << run.err;
    };
    // Pieces that end at least a storey below where they started.
    const auto fallen = [&](const std::string& name) {
        const std::vector<unsigned char> bytes = test::readBytes(path(name) / "transforms.bin");
        std::vector<float> h(bytes.size() / 4);
        std::memcpy(h.data(), bytes.data(), bytes.size());
        const std::size_t end = (60 - 1) * pieces * 7;
        std::size_t count = 0;
        for (std::size_t j = 0; j < pieces && end + 7 * j + 1 < h.size(); ++j) count += h[end + 7 * j + 1] < h[7 * j + 1] - 2.5f;
        return count;
    };
    const auto broken = [&](const std::string& name) {
        return Json::parse(test::readText(path(name) / "sim.json"))["glue"]["broken"].get<std::size_t>();
    };
    hit("light", {"--projectile-mass", "2000", "--projectile-speed", "10"});
    EXPECT_LT(50 * broken("light"), f["bonds"].size()) << "under 2 %";
    EXPECT_EQ(fallen("light"), 0u);
    for (const char* threads : {"1", "2"}) hit(std::string("hit") + threads, {"--threads", threads});
    EXPECT_EQ(test::readBytes(path("hit1") / "transforms.bin"), test::readBytes(path("hit2") / "transforms.bin"));
    EXPECT_GT(2 * broken("hit1"), f["bonds"].size()) << "over half";
    EXPECT_GT(fallen("hit1"), pieces / 20) << "of " << pieces;
}

// The tallest building, with its stairs and its interior walls on the slabs, in 50 Voronoi
// cells: it stood only in part before the stair flights stood on the slab below and the
// bonds' rest loads were measured over the run's own first steps.
TEST_F(CliBuilding, TallestBuildingStandsTenSecondsWhenLeftAlone) {
    const Json json = Json::parse(test::readText(city() / "city.json"));
    int tallest = -1, floors = 0;
    for (const Json& b : json["buildings"])
        if (b["floors"].get<int>() > floors) floors = b["floors"].get<int>(), tallest = b["id"].get<int>();
    ASSERT_GE(floors, 4);
    RunResult r = test::runDawnforge({"--quiet", "fracture", city().string(), "--building", std::to_string(tallest), "-o",
                                      path("tall").string(), "--pieces", "50"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    // Every flight is glued to a slab at its foot and at its top, a storey apart.
    const Json f = Json::parse(test::readText(path("tall") / "fracture.json"));
    std::map<std::size_t, std::pair<double, double>> flightBonds;  // stairs part -> lowest, highest bond to a slab
    const auto partOf = [&](const Json& piece) { return f["pieces"][piece.get<std::size_t>()]["part"].get<std::size_t>(); };
    for (const Json& b : f["bonds"]) {
        const std::size_t pa = partOf(b["a"]), pb = partOf(b["b"]);
        for (auto [stairs, other] : {std::pair{pa, pb}, std::pair{pb, pa}}) {
            if (f["parts"][stairs]["kind"] != "stairs" || f["parts"][other]["kind"] != "slab") continue;
            const double y = b["centroid"][1].get<double>();
            auto [it, added] = flightBonds.try_emplace(stairs, y, y);
            it->second = {std::min(it->second.first, y), std::max(it->second.second, y)};
        }
    }
    std::size_t flights = 0;
    for (const Json& part : f["parts"]) flights += part["kind"] == "stairs";
    EXPECT_EQ(flightBonds.size(), flights);
    for (const auto& [part, span] : flightBonds) EXPECT_GT(span.second - span.first, 2.0) << "flight " << part;
    r = test::runDawnforge({"--quiet", "simulate", path("tall").string(), "-o", path("tall_still").string(), "--frames", "300"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const Json sim = Json::parse(test::readText(path("tall_still") / "sim.json"));
    EXPECT_GT(sim["glue"]["bonds"].get<int>(), 1000);
    EXPECT_EQ(sim["glue"]["broken"].get<int>(), 0);
    EXPECT_LT(largestMove(path("tall_still"), sim["pieces"].get<std::size_t>(), 300 - 1), 0.02) << "sag after 10 s";
}

TEST_F(CliBuilding, VatRestPoseIsTheBuildingsSurface) {
    ASSERT_EQ(fracture("v").exitCode, 0);
    ASSERT_EQ(test::runDawnforge({"--quiet", "simulate", path("v").string(), "-o", path("vs").string(), "--frames", "3"}).exitCode, 0);
    ASSERT_EQ(test::runDawnforge({"--quiet", "vat", path("vs").string(), "-o", path("vv").string()}).exitCode, 0);
    const Mesh rest = loadMesh(path("vv") / "vat_mesh.glb");
    const Mesh lod0 = buildingLod0(city(), building_);
    const Bounds a = computeBounds(rest.positions), b = computeBounds(lod0.positions);
    EXPECT_LT(glm::length(a.min - b.min) + glm::length(a.max - b.max), 1e-4);
    // The pieces' outer faces are the building's faces, all of them and nothing more: cut
    // faces (rubble) are inside.
    const double outer = area(rest, [](std::uint8_t m) { return m != kRubble; });
    EXPECT_NEAR(outer / area(lod0, [](std::uint8_t) { return true; }), 1.0, 1e-5);
}

namespace {

// Per-pixel comparison of two pictures of the same size: the share of pixels with a channel
// more than 8 apart, and the mean absolute difference over all channels.
std::pair<double, double> pictureDifference(const exporters::Image& a, const exporters::Image& b) {
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.height, b.height);
    std::size_t differing = 0;
    double sum = 0.0;
    const std::size_t pixels = std::size_t(a.width) * std::size_t(a.height);
    for (std::size_t i = 0; i < pixels; ++i) {
        bool differs = false;
        for (std::size_t c = 0; c < 4; ++c) {
            const int d = std::abs(int(a.rgba[4 * i + c]) - int(b.rgba[4 * i + c]));
            differs |= d > 8;
            sum += d;
        }
        differing += differs;
    }
    return {double(differing) / double(pixels), sum / double(4 * pixels)};
}

}  // namespace

TEST_F(CliBuilding, SceneSwapsTheBuildingForItsDestructionWithoutAPop) {
    ASSERT_EQ(fracture("r").exitCode, 0);
    const Json f = Json::parse(test::readText(path("r") / "fracture.json"));
    glm::dvec3 lo(1e300), hi(-1e300);
    for (const Json& p : f["pieces"])
        for (int k = 0; k < 3; ++k)
            lo[k] = std::min(lo[k], p["center_of_mass"][k].get<double>()), hi[k] = std::max(hi[k], p["center_of_mass"][k].get<double>());
    const glm::dvec3 c = 0.5 * (lo + hi);
    const std::string target = std::to_string(c.x) + "," + std::to_string(c.y) + "," + std::to_string(c.z);
    // Twelve cells make pieces glued over many m², which the default ball only dents: a brittle glue.
    ASSERT_EQ(test::runDawnforge({"--quiet", "simulate", path("r").string(), "-o", path("rs").string(), "--frames", "30",
                                  "--projectile", target, "--projectile-radius", "1.5", "--impact-time", "0.0005"})
                  .exitCode,
              0);
    ASSERT_EQ(test::runDawnforge({"--quiet", "vat", path("rs").string(), "-o", path("rv").string(), "--name", "b"}).exitCode, 0);
    const auto num = [](double v) { return std::to_string(v); };
    test::writeText(path("swap.json"),
                    R"({"format": "dawnforge.scene", "version": 1, "city": "city", "time_of_day": 12, "fps": 30, "exposure": {"fixed": 1},
                        "destruction": [{"vat": "rv", "name": "b", "start_time": 1.0, "replaces": )" + id() + R"(}],
                        "cameras": [{"name": "near", "position": [)" + num(c.x + 14) + "," + num(c.y + 12) + "," +
                        num(c.z + 22) + "], \"target\": [" + num(c.x) + "," + num(c.y) + "," + num(c.z) + "]}]}");
    std::map<int, exporters::Image> frames;
    for (int frame : {29, 30, 59}) {  // scene time 0.967 s (the building), 1 s (the VAT's rest pose), 1.97 s (its last frame)
        const std::string png = path("swap" + std::to_string(frame) + ".png").string();
        const RunResult r = test::runDawnforge({"--quiet", "render", path("swap.json").string(), "-o", png, "--size",
                                                "160x120", "--frame", std::to_string(frame)});
        ASSERT_EQ(r.exitCode, 0) << r.err;
        frames[frame] = exporters::readPng(png);
    }
    // The rest pose is the building face for face; what differs is the glass, which the
    // building draws as rooms behind windows and the shards as plain glass, and shading
    // where cut faces meet (a few pixels): at most 3 % of the pixels, mean 1.5 levels.
    const auto [swapShare, swapMean] = pictureDifference(frames[29], frames[30]);
    EXPECT_LT(swapShare, 0.03);
    EXPECT_LT(swapMean, 1.5);
    // Once hit, it does not look like the building any more: the comparison can tell.
    const auto [hitShare, hitMean] = pictureDifference(frames[29], frames[59]);
    EXPECT_GT(hitShare, 4 * swapShare + 0.01);
    std::printf("swap: %.4f of pixels differ, mean %.3f; hit: %.4f, mean %.3f\n", swapShare, swapMean, hitShare, hitMean);
}
