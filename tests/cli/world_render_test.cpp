// `dawnforge render` of a scene that names a world, as a user runs it: the picture, what it
// streamed, the same bytes on any llvmpipe thread count, and bad input.
#include "test_support.hpp"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <cstdlib>
#include <map>

namespace dawnforge {
namespace {

namespace fs = std::filesystem;
using test::RunResult;

void writeScene(const fs::path& file, const std::string& worldKey) {
    test::writeText(file, R"({"format": "dawnforge.scene", "version": 1, )" + worldKey + R"(,
        "cameras": [{"name": "street", "position": [124, 1.7, -90], "target": [129, 1.7, -200]},
                    {"name": "aerial", "position": [128, 260, 220], "target": [128, 0, -128]}]})");
}

TEST(CliWorldRender, DrawsAWorldAndSaysWhatItStreamed) {
    test::TempDir dir;
    writeScene(dir / "scene.json", "\"world\": \"" + test::streamWorld().string() + "\"");
    const RunResult r = test::runDawnforge({"render", (dir / "scene.json").string(), "--camera", "street", "--size", "160x120",
                                            "-o", (dir / "street.png").string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(test::contains(r.out, "streamed 4 of 6 tiles and HLOD nodes")) << r.out;
    EXPECT_TRUE(r.err.empty()) << r.err;
    const RunResult s = test::runDawnforge({"render", (dir / "scene.json").string(), "--camera", "aerial", "--size", "160x120",
                                            "-o", (dir / "aerial.png").string(), "--stats", "--repeat", "1"});
    ASSERT_EQ(s.exitCode, 0) << s.err;
    const nlohmann::json stats = nlohmann::json::parse(s.out);
    EXPECT_EQ(stats["streaming"]["drawn"], 1);  // the HLOD node alone
    EXPECT_EQ(stats["streaming"]["nodes"], 6);
    EXPECT_GT(stats["streaming"]["resident_mb"].get<double>(), 0.5);
    EXPECT_GT(stats["streaming"]["wait_ms"].get<double>(), 0.0);
    EXPECT_TRUE(stats["streaming"]["complete"].get<bool>());
}

TEST(CliWorldRender, SameBytesOnOneAndThreeLlvmpipeThreads) {
    test::TempDir dir;
    writeScene(dir / "scene.json", "\"world\": \"" + test::streamWorld().string() + "\"");
    std::map<std::string, std::vector<unsigned char>> images;
    for (const char* camera : {"street", "aerial"})
        for (const char* threads : {"1", "3"}) {
            setenv("LP_NUM_THREADS", threads, 1);
            const RunResult r = test::runDawnforge({"-q", "render", (dir / "scene.json").string(), "--camera", camera, "--size",
                                                    "160x120", "-o", (dir / "out.png").string(), "--stream-threads", threads});
            ASSERT_EQ(r.exitCode, 0) << r.err;
            images[std::string(camera) + threads] = test::readBytes(dir / "out.png");
        }
    unsetenv("LP_NUM_THREADS");
    EXPECT_EQ(images["street1"], images["street3"]);
    EXPECT_EQ(images["aerial1"], images["aerial3"]);
    EXPECT_NE(images["street1"], images["aerial1"]);
}

// `view` of a world: it streams without waiting, frame after frame, in a window.
TEST(CliWorldRender, ViewFliesThroughAWorld) {
    if (!fs::exists("/usr/bin/xvfb-run")) GTEST_SKIP() << "xvfb-run is not installed (./run installs it)";
    test::TempDir dir;
    writeScene(dir / "scene.json", "\"world\": \"" + test::streamWorld().string() + "\"");
    // The X and GLX client libraries keep allocations until exit (see CliView): no leak check here.
    const char* asan = std::getenv("ASAN_OPTIONS");
    const std::string saved = asan ? asan : "";
    setenv("ASAN_OPTIONS", (saved.empty() ? std::string("detect_leaks=0") : saved + ":detect_leaks=0").c_str(), 1);
    const RunResult r = test::run("/usr/bin/xvfb-run", {"-a", "-s", "-screen 0 640x480x24", DAWNFORGE_EXE, "view",
                                                        (dir / "scene.json").string(), "--size", "320x240", "--frames", "40"});
    if (asan) setenv("ASAN_OPTIONS", saved.c_str(), 1);
    else unsetenv("ASAN_OPTIONS");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(test::contains(r.out, "showed 40 frames")) << r.out;
}

TEST(CliWorldRender, BadWorldsExit2WithOneLineAndNoPicture) {
    test::TempDir dir;
    fs::create_directories(dir / "unbuilt");
    const std::vector<std::pair<std::string, std::string>> cases{
        {"\"world\": \"unbuilt\"", "tileset.json is missing"},
        {"\"world\": \"nowhere\"", "does not exist"},
        {"\"world\": \"" + test::streamWorld().string() + "\", \"city\": \"unbuilt\"", "both"},
    };
    for (const auto& [key, words] : cases) {
        writeScene(dir / "scene.json", key);
        const RunResult r = test::runDawnforge({"render", (dir / "scene.json").string(), "-o", (dir / "out.png").string()});
        EXPECT_EQ(r.exitCode, 2) << key;
        EXPECT_EQ(test::lineCount(r.err), 1u) << r.err;
        EXPECT_TRUE(test::contains(r.err, words)) << r.err;
        EXPECT_FALSE(fs::exists(dir / "out.png")) << key;
    }
    // A manifest that is not 3D Tiles.
    fs::create_directories(dir / "odd");
    test::writeText(dir / "odd" / "tileset.json", R"({"asset": {"version": "0.0"}, "root": {}})");
    writeScene(dir / "scene.json", "\"world\": \"odd\"");
    const RunResult r = test::runDawnforge({"render", (dir / "scene.json").string(), "-o", (dir / "out.png").string()});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(test::lineCount(r.err), 1u) << r.err;
    EXPECT_TRUE(test::contains(r.err, "3D Tiles")) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out.png"));
}

}  // namespace
}  // namespace dawnforge
