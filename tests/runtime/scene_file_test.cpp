// scene.json: every value read, defaults filled, the writer round-trips, and each kind of
// mistake is an InputError whose message names the key (or the missing folder).
#include "test_support.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/runtime/scene_file.hpp>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace dawnforge::runtime {

namespace {

using test::inputErrorOf;
using test::contains;

const std::filesystem::path kFile = std::filesystem::path("/scenes/harbour/scene.json");

const std::string kFull = R"({
  "format": "dawnforge.scene", "version": 1,
  "city": "city",
  "time_of_day": 17.5, "time": 3.0, "fps": 24,
  "ocean": { "level": -1.25, "grid": [96, 80], "shore_depth": 6.5 },
  "wind": { "direction": [3, 7, 4], "speed": 12.5 },
  "destruction": [
    { "vat": "vat", "name": "tower_native", "position": [1, 2.5, -3], "yaw_degrees": 90, "start_time": 1.0,
      "replaces": 14 },
    { "vat": "/data/other_vat", "name": "bridge" }
  ],
  "cameras": [
    { "name": "overview", "position": [0, 40, 120], "target": [0, 0, 0], "fov_degrees": 60 },
    { "name": "street", "position": [5, 1.7, 5] }
  ],
  "lens_flares": false,
  "probes": { "preset": "high", "face_size": 128, "anti_leak": false, "multi_bounce": false, "show": true }
})";

// kFull with `from` replaced by `to` (which must occur).
std::string edited(const std::string& from, const std::string& to) {
    std::string s = kFull;
    const std::size_t at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return at == std::string::npos ? s : s.replace(at, from.size(), to);
}

}  // namespace

TEST(SceneFile, ParsesEveryValue) {
    const SceneFile s = parseSceneJson(kFull, kFile);
    EXPECT_EQ(s.file, kFile);
    ASSERT_TRUE(s.cityDir);
    EXPECT_EQ(*s.cityDir, std::filesystem::path("/scenes/harbour/city"));
    EXPECT_EQ(s.timeOfDay, 17.5);
    EXPECT_EQ(s.time, 3.0);
    EXPECT_EQ(s.fps, 24.0);
    ASSERT_TRUE(s.ocean);
    EXPECT_EQ(s.ocean->level, -1.25);
    EXPECT_EQ(s.ocean->columns, 96);
    EXPECT_EQ(s.ocean->rows, 80);
    EXPECT_EQ(s.ocean->shoreDepth, 6.5);
    EXPECT_NEAR(glm::length(s.wind.direction - glm::dvec3(0.6, 0.0, 0.8)), 0.0, 1e-12) << "level and unit";
    EXPECT_EQ(s.wind.speed, 12.5);
    EXPECT_EQ(s.probes.preset, "high");
    EXPECT_EQ(s.probes.faceSize, 128);
    EXPECT_FALSE(s.probes.antiLeak);
    EXPECT_FALSE(s.probes.multiBounce);
    EXPECT_TRUE(s.probes.show);
    ASSERT_EQ(s.destruction.size(), 2u);
    EXPECT_EQ(s.destruction[0].vatDir, std::filesystem::path("/scenes/harbour/vat"));
    EXPECT_EQ(s.destruction[0].name, "tower_native");
    EXPECT_EQ(s.destruction[0].position, glm::dvec3(1, 2.5, -3));
    EXPECT_EQ(s.destruction[0].yawDegrees, 90.0);
    EXPECT_EQ(s.destruction[0].startTime, 1.0);
    EXPECT_EQ(s.destruction[0].replaces, 14);
    EXPECT_FALSE(s.destruction[1].replaces);
    EXPECT_EQ(s.destruction[1].vatDir, std::filesystem::path("/data/other_vat"));
    EXPECT_EQ(s.destruction[1].position, glm::dvec3(0));
    EXPECT_EQ(s.destruction[1].yawDegrees, 0.0);
    EXPECT_EQ(s.destruction[1].startTime, 0.0);
    ASSERT_EQ(s.cameras.size(), 2u);
    EXPECT_EQ(s.cameras[0].name, "overview");
    EXPECT_EQ(s.cameras[0].position, glm::dvec3(0, 40, 120));
    EXPECT_EQ(s.cameras[0].target, glm::dvec3(0, 0, 0));
    EXPECT_EQ(s.cameras[0].fovDegrees, 60.0);
    EXPECT_EQ(s.cameras[1].target, glm::dvec3(0, 0, -1));
    EXPECT_EQ(s.cameras[1].fovDegrees, 50.0);
    EXPECT_EQ(findCamera(s, "street"), &s.cameras[1]);
    EXPECT_EQ(findCamera(s, "nowhere"), nullptr);
    EXPECT_FALSE(s.lensFlares);
}

TEST(SceneFile, Defaults) {
    const SceneFile s = parseSceneJson(R"({"format": "dawnforge.scene", "version": 1})", "scene.json");
    EXPECT_FALSE(s.cityDir);
    EXPECT_EQ(s.timeOfDay, 15.0);
    EXPECT_EQ(s.time, 0.0);
    EXPECT_EQ(s.fps, 30.0);
    EXPECT_FALSE(s.ocean);
    EXPECT_NEAR(glm::length(s.wind.direction), 1.0, 1e-6);
    EXPECT_EQ(s.wind.direction.y, 0.0);
    EXPECT_EQ(s.wind.speed, 4.0);
    EXPECT_TRUE(s.destruction.empty());
    EXPECT_TRUE(s.cameras.empty());
    EXPECT_TRUE(s.lensFlares);
    EXPECT_EQ(s.probes.preset, "off");

    const SceneFile nullOcean = parseSceneJson(R"({"format": "dawnforge.scene", "version": 1, "ocean": null})", "s.json");
    EXPECT_FALSE(nullOcean.ocean);
    const SceneFile emptyOcean = parseSceneJson(R"({"format": "dawnforge.scene", "version": 1, "ocean": {}})", "s.json");
    ASSERT_TRUE(emptyOcean.ocean);
    EXPECT_EQ(emptyOcean.ocean->level, -0.8);
    EXPECT_EQ(emptyOcean.ocean->columns, 192);
    EXPECT_EQ(emptyOcean.ocean->rows, 160);
    EXPECT_EQ(emptyOcean.ocean->shoreDepth, 4.0);
    // Relative to a file given without a folder: relative to the working directory.
    const SceneFile bare = parseSceneJson(R"({"format": "dawnforge.scene", "version": 1, "city": "./c/../city/"})", "s.json");
    EXPECT_EQ(*bare.cityDir, std::filesystem::path("city"));
}

TEST(SceneFile, RoundTrips) {
    SceneFile s = parseSceneJson(kFull, kFile);
    s.time = 0.1;  // not exactly representable: the writer must keep every digit
    s.cameras[1].fovDegrees = 100.0 / 3.0;
    for (const std::filesystem::path& folder : {std::filesystem::path("/scenes/harbour"), std::filesystem::path("/elsewhere/x")}) {
        const std::string json = sceneFileJson(s, folder);
        const SceneFile back = parseSceneJson(json, folder / "scene.json");
        EXPECT_EQ(back.cityDir, s.cityDir) << json;
        EXPECT_EQ(back.timeOfDay, s.timeOfDay);
        EXPECT_EQ(back.time, s.time);
        EXPECT_EQ(back.fps, s.fps);
        ASSERT_TRUE(back.ocean);
        EXPECT_EQ(back.ocean->level, s.ocean->level);
        EXPECT_EQ(back.ocean->columns, s.ocean->columns);
        EXPECT_EQ(back.ocean->rows, s.ocean->rows);
        EXPECT_EQ(back.ocean->shoreDepth, s.ocean->shoreDepth);
        EXPECT_EQ(back.wind.direction, s.wind.direction);
        EXPECT_EQ(back.wind.speed, s.wind.speed);
        ASSERT_EQ(back.destruction.size(), s.destruction.size());
        for (std::size_t i = 0; i < s.destruction.size(); ++i) {
            EXPECT_EQ(back.destruction[i].vatDir, s.destruction[i].vatDir) << json;
            EXPECT_EQ(back.destruction[i].name, s.destruction[i].name);
            EXPECT_EQ(back.destruction[i].position, s.destruction[i].position);
            EXPECT_EQ(back.destruction[i].yawDegrees, s.destruction[i].yawDegrees);
            EXPECT_EQ(back.destruction[i].startTime, s.destruction[i].startTime);
            EXPECT_EQ(back.destruction[i].replaces, s.destruction[i].replaces);
        }
        ASSERT_EQ(back.cameras.size(), s.cameras.size());
        for (std::size_t i = 0; i < s.cameras.size(); ++i) {
            EXPECT_EQ(back.cameras[i].name, s.cameras[i].name);
            EXPECT_EQ(back.cameras[i].position, s.cameras[i].position);
            EXPECT_EQ(back.cameras[i].target, s.cameras[i].target);
            EXPECT_EQ(back.cameras[i].fovDegrees, s.cameras[i].fovDegrees);
        }
        EXPECT_EQ(back.lensFlares, s.lensFlares);
        EXPECT_EQ(back.probes.preset, s.probes.preset);
        EXPECT_EQ(back.probes.faceSize, s.probes.faceSize);
        EXPECT_EQ(back.probes.antiLeak, s.probes.antiLeak);
        EXPECT_EQ(back.probes.multiBounce, s.probes.multiBounce);
        EXPECT_EQ(back.probes.show, s.probes.show);
    }
    // Relative paths where they can be: the scene folder's own city is written as "city".
    EXPECT_TRUE(contains(sceneFileJson(s, "/scenes/harbour"), "\"city\": \"city\""));
    const SceneFile none = parseSceneJson(sceneFileJson(SceneFile{}, "/x"), "/x/scene.json");
    EXPECT_FALSE(none.ocean);
    EXPECT_FALSE(none.cityDir);
    EXPECT_TRUE(none.lensFlares);
}

TEST(SceneFile, RejectsBadValuesNamingTheKey) {
    const std::vector<std::pair<std::string, std::string>> cases = {
        // {the document, what the message must contain}
        {edited(R"("shore_depth": 6.5)", R"("shore_depth": 6.5, "heigth": 2)"), "\"ocean.heigth\""},
        {edited(R"("shore_depth": 6.5)", R"("shore_depth": 6.5, "heigth": 2)"), "allowed: level, grid, shore_depth"},
        {edited(R"("fps": 24)", R"("fps": 24, "sun": 1)"), "\"sun\""},
        {edited(R"("yaw_degrees": 90)", R"("yaw": 90)"), "\"destruction[0].yaw\""},
        {edited(R"("fov_degrees": 60)", R"("fov": 60)"), "\"cameras[0].fov\""},
        {edited(R"("format": "dawnforge.scene")", R"("format": "dawnforge.vat")"), "format"},
        {edited(R"("format": "dawnforge.scene", )", ""), "format"},
        {edited(R"("version": 1)", R"("version": 2)"), "version"},
        {edited(R"("time_of_day": 17.5)", R"("time_of_day": 24)"), "time_of_day"},
        {edited(R"("time_of_day": 17.5)", R"("time_of_day": -0.5)"), "time_of_day"},
        {edited(R"("time_of_day": 17.5)", R"("time_of_day": "noon")"), "time_of_day"},
        // nlohmann refuses a number that overflows as it parses (no key to name, the value is shown):
        {edited(R"("time": 3.0)", R"("time": 1e999)"), "1e999"},
        {edited(R"("time": 3.0)", R"("time": -1)"), "time"},
        {edited(R"("fps": 24)", R"("fps": 0)"), "fps"},
        {edited(R"("fps": 24)", R"("fps": -30)"), "fps"},
        {edited(R"("grid": [96, 80])", R"("grid": [1, 80])"), "ocean.grid[0]"},
        {edited(R"("grid": [96, 80])", R"("grid": [96, 1025])"), "ocean.grid[1]"},
        {edited(R"("grid": [96, 80])", R"("grid": [96.5, 80])"), "ocean.grid[0]"},
        {edited(R"("grid": [96, 80])", R"("grid": [96])"), "ocean.grid"},
        {edited(R"("level": -1.25)", R"("level": "low")"), "ocean.level"},
        {edited(R"("shore_depth": 6.5)", R"("shore_depth": 0)"), "ocean.shore_depth"},
        {R"({"format": "dawnforge.scene", "version": 1, "ocean": 3})", "\"ocean\" must be an object"},
        {edited(R"("speed": 12.5)", R"("speed": -1)"), "wind.speed"},
        {edited(R"("speed": 12.5)", R"("speed": 61)"), "wind.speed"},
        {edited(R"("speed": 12.5)", R"("gust": 3)"), "\"wind.gust\""},
        {edited(R"("direction": [3, 7, 4])", R"("direction": [0, 5, 0])"), "wind.direction"},
        {edited(R"("direction": [3, 7, 4])", R"("direction": [1, 0])"), "wind.direction"},
        {R"({"format": "dawnforge.scene", "version": 1, "wind": 3})", "\"wind\" must be an object"},
        {edited(R"("fov_degrees": 60)", R"("fov_degrees": 179)"), "cameras[0].fov_degrees"},
        {edited(R"("fov_degrees": 60)", R"("fov_degrees": 1)"), "cameras[0].fov_degrees"},
        {edited(R"("target": [0, 0, 0])", R"("target": [0, 40, 120])"), "cameras[0]"},
        {edited(R"("name": "street")", R"("name": "overview")"), "cameras[1].name"},
        {edited(R"("name": "street")", R"("name": "")"), "cameras[1].name"},
        {edited(R"("name": "street", )", ""), "cameras[1].name"},
        {edited(R"("name": "tower_native")", R"("name": "")"), "destruction[0].name"},
        {edited(R"({ "vat": "/data/other_vat", "name": "bridge" })", R"({ "name": "bridge" })"), "destruction[1].vat"},
        {edited(R"("position": [1, 2.5, -3])", R"("position": [1, 2.5])"), "destruction[0].position"},
        {edited(R"("position": [1, 2.5, -3])", R"("position": [1, "a", 3])"), "destruction[0].position[1]"},
        {edited(R"("start_time": 1.0)", R"("start_time": null)"), "destruction[0].start_time"},
        {edited(R"("replaces": 14)", R"("replaces": -1)"), "destruction[0].replaces"},
        {edited(R"("replaces": 14)", R"("replaces": "building_00014")"), "destruction[0].replaces"},
        {edited(R"("city": "city")", R"("city": 7)"), "city"},
        {R"({"format": "dawnforge.scene", "version": 1, "cameras": {}})", "\"cameras\" must be an array"},
        {edited(R"("lens_flares": false)", R"("lens_flares": 0)"), "\"lens_flares\" must be true or false"},
        {edited(R"("preset": "high")", R"("preset": "ultra")"), "\"probes.preset\" must be \"off\", \"low\", \"mid\" or \"high\""},
        {edited(R"("face_size": 128)", R"("face_size": 512)"), "\"probes.face_size\""},
        {edited(R"("face_size": 128)", R"("face_size": 4)"), "\"probes.face_size\""},
        {edited(R"("anti_leak": false)", R"("anti_leak": 1)"), "\"probes.anti_leak\""},
        {edited(R"("multi_bounce": false)", R"("bounces": 2)"), "unknown key \"probes.bounces\""},
        {edited(R"("lens_flares": false)", R"("lens_flares": "on")"), "\"lens_flares\""},
        {edited(R"("lens_flares": false)", R"("lens_flares": null)"), "\"lens_flares\""},
        {edited(R"("lens_flares": false)", R"("lens_flare": true)"), "unknown key \"lens_flare\""},
    };
    for (const auto& [json, key] : cases) {
        const std::string message = inputErrorOf([&] { parseSceneJson(json, kFile); });
        EXPECT_TRUE(contains(message, key)) << "expected \"" << key << "\" in: " << message;
        EXPECT_EQ(message.rfind(kFile.string() + ": ", 0), 0u) << message;
        EXPECT_FALSE(contains(message, "\n")) << message;
    }
}

TEST(SceneFile, ParseErrorsGiveTheLine) {
    const std::string message = inputErrorOf([&] { parseSceneJson("{\n  \"format\": \"dawnforge.scene\",\n  ]", kFile); });
    EXPECT_TRUE(contains(message, "line 3")) << message;
    EXPECT_FALSE(contains(message, "\n")) << message;
    EXPECT_TRUE(contains(inputErrorOf([&] { parseSceneJson("[1, 2]", kFile); }), "object"));
}

// "world" names a folder that `world build` made; a scene names a city or a world, not both.
TEST(SceneFile, AWorldInsteadOfACity) {
    const test::TempDir dir;
    const std::filesystem::path scene = dir / "scene.json";
    const SceneFile s = parseSceneJson(R"({"format": "dawnforge.scene", "version": 1, "world": "w"})", scene);
    ASSERT_TRUE(s.worldDir.has_value());
    EXPECT_EQ(*s.worldDir, dir / "w");
    EXPECT_FALSE(s.cityDir.has_value());
    EXPECT_EQ(parseSceneJson(sceneFileJson(s, dir.path()), scene).worldDir, s.worldDir);
    EXPECT_TRUE(contains(inputErrorOf([&] {
        parseSceneJson(R"({"format": "dawnforge.scene", "version": 1, "world": "w", "city": "c"})", scene);
    }), "both"));
    test::writeText(scene, R"({"format": "dawnforge.scene", "version": 1, "world": "w"})");
    EXPECT_TRUE(contains(inputErrorOf([&] { loadSceneFile(scene); }), "does not exist"));
    std::filesystem::create_directory(dir / "w");
    const std::string message = inputErrorOf([&] { loadSceneFile(scene); });
    EXPECT_TRUE(contains(message, "tileset.json")) << message;
    EXPECT_TRUE(contains(message, "world build")) << message;
    test::writeText(dir / "w" / "tileset.json", "{}");  // only its presence is checked here
    EXPECT_EQ(loadSceneFile(scene).worldDir, dir / "w");
}

TEST(SceneFile, LoadChecksTheFolders) {
    const test::TempDir dir;
    const std::filesystem::path scene = dir / "scene.json";
    const std::string document = R"({"format": "dawnforge.scene", "version": 1, "city": "city",
        "destruction": [{"vat": "vat", "name": "tower"}]})";

    EXPECT_TRUE(contains(inputErrorOf([&] { loadSceneFile(scene); }), "no such file"));
    test::writeText(scene, document);
    std::string message = inputErrorOf([&] { loadSceneFile(scene); });
    EXPECT_TRUE(contains(message, "\"city\"")) << message;
    EXPECT_TRUE(contains(message, "does not exist")) << message;
    EXPECT_EQ(message.rfind(scene.string(), 0), 0u) << message;

    std::filesystem::create_directory(dir / "city");
    message = inputErrorOf([&] { loadSceneFile(scene); });
    EXPECT_TRUE(contains(message, "city.glb")) << message;

    test::writeText(dir / "city" / "city.glb", "glTF");  // only its presence is checked here
    message = inputErrorOf([&] { loadSceneFile(scene); });
    EXPECT_TRUE(contains(message, "destruction[0].vat")) << message;
    EXPECT_TRUE(contains(message, "does not exist")) << message;

    std::filesystem::create_directory(dir / "vat");
    message = inputErrorOf([&] { loadSceneFile(scene); });
    EXPECT_TRUE(contains(message, "tower_data.json")) << message;

    test::writeText(dir / "vat" / "tower_data.json", "{}");
    const SceneFile loaded = loadSceneFile(scene);
    EXPECT_EQ(loaded.file, scene);
    EXPECT_EQ(*loaded.cityDir, dir / "city");
    EXPECT_EQ(loaded.destruction.at(0).vatDir, dir / "vat");

    test::writeText(scene, "{\"format\": \"dawnforge.scene\",\n \"version\": 1,\n \"time\": }");
    message = inputErrorOf([&] { loadSceneFile(scene); });
    EXPECT_TRUE(contains(message, "line 3")) << message;
}

}  // namespace dawnforge::runtime
