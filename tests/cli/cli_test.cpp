// End-to-end tests of the dawnforge executable, as a user runs it.
#include "test_support.hpp"

#include <dawnforge/bake/bake.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/core/seed.hpp>
#include <dawnforge/exporters/animation.hpp>
#include <dawnforge/exporters/image.hpp>
#include <dawnforge/exporters/vat.hpp>
#include <dawnforge/procgen/city.hpp>
#include <dawnforge/runtime/renderer.hpp>
#include <dawnforge/sim/fracture.hpp>
#include <dawnforge/sim/fracture_parts.hpp>
#include <dawnforge/sim/rigidbody.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <cstring>
#include <functional>
#include <map>
#include <regex>
#include <set>
#include <sstream>

using namespace dawnforge;
using namespace dawnforge::exporters;
using dawnforge::test::RunResult;
using dawnforge::test::TempDir;

namespace {

// Bad input: exit code 2, exactly one line on stderr that contains `mention`, nothing on stdout.
void expectBadInput(const std::vector<std::string>& args, const std::string& mention) {
    const RunResult r = test::runDawnforge(args);
    std::string cmd;
    for (const std::string& a : args) cmd += a + " ";
    EXPECT_EQ(r.exitCode, 2) << cmd << "\n" << r.err;
    EXPECT_EQ(test::lineCount(r.err), 1u) << cmd << "\n" << r.err;
    EXPECT_NE(r.err.find(mention), std::string::npos) << cmd << "\n" << r.err;
    EXPECT_TRUE(r.out.empty()) << cmd << "\n" << r.out;
}

// The demo's bake at its coarsest: seconds instead of a minute (the bake's own tests check quality).
const std::string kQuickBake[8] = {"--bake-texel", "1", "--bake-interior-texel", "2", "--bake-samples", "4", "--bake-bounces", "1"};

std::size_t occurrences(const std::string& text, const std::string& part) {
    std::size_t n = 0;
    for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
    return n;
}

// The text of `html` from `from` up to `to` (or its end).
std::string between(const std::string& html, const std::string& from, const std::string& to) {
    const std::size_t a = html.find(from);
    if (a == std::string::npos) return {};
    const std::size_t b = html.find(to, a);
    return html.substr(a, b == std::string::npos ? std::string::npos : b - a);
}

// The demo's report.html as a reader sees it: Debian's chromium, headless
// (tools/browser-check), loads it without a console error, a page error or any request beyond
// its own data: URIs, every image decodes and every plot draws. Without node, chromium or the
// npm package the test is reported as skipped with the reason.
void expectReportOpensInChromium(const std::filesystem::path& report, int images, int plots) {
    const std::filesystem::path check(DAWNFORGE_BROWSER_CHECK);
    if (std::string(DAWNFORGE_NODE).empty() || std::string(DAWNFORGE_CHROMIUM).empty())
        GTEST_SKIP() << "node or chromium was not found when configuring: report.html was not opened";
    if (!std::filesystem::exists(check.parent_path() / "node_modules/puppeteer-core/package.json"))
        GTEST_SKIP() << "tools/browser-check is not installed (npm ci there): report.html was not opened";
    const RunResult r = test::run(DAWNFORGE_NODE, {check.string(), report.string(), "--browser", DAWNFORGE_CHROMIUM, "--min-images",
                                                   std::to_string(images), "--min-svgs", std::to_string(plots), "--no-scripts"});
    EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("\"ok\":true"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(format("\"images\":{},", images)), std::string::npos) << r.out;
}

}  // namespace

TEST(Cli, HelpListsEveryCommandOfTheArchitecture) {
    const RunResult r = test::runDawnforge({"--help"});
    EXPECT_EQ(r.exitCode, 0);
    for (const char* cmd :
         {"inspect", "city", "fracture", "simulate", "vat", "anim", "bake", "render", "view", "demo", "pivots"}) {
        EXPECT_NE(r.out.find(std::string("\n  ") + cmd + " "), std::string::npos) << cmd;
        EXPECT_EQ(test::runDawnforge({cmd, "--help"}).exitCode, 0) << cmd;
    }
}

// Each command's options with a default, as `dawnforge COMMAND --help` shows them:
// "--pieces INT:POSITIVE=50" gives {"--pieces", "50"}.
std::map<std::string, std::string> helpDefaults(const std::string& command) {
    const RunResult r = test::runDawnforge({command, "--help"});
    EXPECT_EQ(r.exitCode, 0) << command;
    static const std::regex kOption(R"(^\s+(?:-\w,)?(--[\w-]+) [A-Z]+(?::[A-Z]+(?: in \[[^\]]*\])?)?=(\S+))");
    std::map<std::string, std::string> defaults;
    std::istringstream lines(r.out);
    std::smatch m;
    for (std::string line; std::getline(lines, line);)
        if (std::regex_search(line, m, kOption)) defaults[m[1].str()] = m[2].str();
    return defaults;
}

std::string shown(double v) {  // as CLI11 prints a default
    std::ostringstream s;
    s << v;
    return s.str();
}

TEST(Cli, EveryHelpDefaultIsTheLibrarysDefault) {
    const sim::FractureSettings f;
    const sim::PartsFractureSettings fp;
    const sim::SimulationSettings s;
    const sim::Projectile p;
    const sim::Explosion e;
    const exporters::VatSettings v;
    const exporters::AnimationSettings a;
    const procgen::CitySettings c;
    const runtime::RendererOptions ro;
    const bake::BakeSettings b;
    const std::string imageSize = shown(ro.size.x) + "x" + shown(ro.size.y);
    // render and view share the streaming options.
    const auto streaming = [&](std::map<std::string, std::string> m) {
        const runtime::StreamingOptions& so = ro.streaming;
        m.insert({{"--max-screen-error", shown(so.maxScreenError)}, {"--resident-mb", shown(double(so.residentBudgetMB))},
                  {"--upload-mb", shown(double(so.uploadBudgetMB))}, {"--stream-threads", shown(so.workers)}});
        return m;
    };
    // Options the command line alone has (no library setting) are listed with their own value.
    const std::map<std::string, std::map<std::string, std::string>> expected{
        {"fracture",
         {{"--pieces", shown(f.pieces)}, {"--seed", shown(double(f.seed))}, {"--radius", shown(f.impactRadius)},
          {"--levels", shown(f.levels)}, {"--level-pieces", shown(f.levelPieces)}, {"--density", shown(f.density)},
          {"--interior-material", shown(f.interiorMaterial)}, {"--uv-scale", shown(f.interiorUvScale)},
          {"--min-volume", shown(f.minVolume)}, {"--roughness", shown(f.roughness)},
          {"--rough-scale", shown(f.roughScale)}, {"--voxel", shown(f.voxelSize)}, {"--shard-size", shown(fp.shardSize)},
          {"--splinter-width", shown(fp.splinterWidth)}, {"--splinter-length", shown(fp.splinterLength)},
          {"--threads", "0"}}},
        {"simulate",
         {{"--frames", shown(s.frames)}, {"--fps", shown(s.fps)}, {"--substeps", shown(s.substeps)},
          {"--iterations", shown(s.solverIterations)}, {"--seed", shown(double(s.seed))},
          {"--strength", shown(s.strength)}, {"--strength-variation", shown(s.strengthVariation)},
          {"--friction", shown(s.friction)}, {"--restitution", shown(s.restitution)},
          {"--hull-vertices", shown(s.hullVertices)}, {"--margin", shown(s.margin)},
          {"--trigger-time", shown(s.triggerTime)}, {"--projectile-mass", shown(p.mass)},
          {"--projectile-speed", shown(p.speed)}, {"--projectile-radius", shown(p.radius)},
          {"--explosion-radius", shown(e.radius)}, {"--explosion-speed", shown(e.speed)},
          {"--impact-time", shown(s.impactTime)}, {"--damage-transmission", shown(s.damageTransmission)},
          {"--damage-hops", shown(s.damageHops)}, {"--damage-half-life", shown(s.damageHalfLife)},
          {"--chips-per-m2", shown(s.debris.chipsPerSquareMetre)}, {"--chips-per-bond", shown(s.debris.maxChipsPerBond)},
          {"--max-chips", shown(double(s.debris.maxChips))}, {"--chip-size", shown(s.debris.chipSize)},
          {"--spray-speed", shown(s.debris.spraySpeed)}, {"--puffs-per-m2", shown(s.debris.puffsPerSquareMetre)},
          {"--max-puffs", shown(double(s.debris.maxPuffs))}, {"--puff-size", shown(s.debris.puffSize)},
          {"--puff-life", shown(s.debris.puffLife)}, {"--threads", "0"}}},
        {"vat",
         {{"--preset", std::string(exporters::vatPresetName(v.preset))},
          {"--format", std::string(exporters::vatFormatName(v.format))}, {"--max-width", shown(v.maxWidth)},
          {"--name", v.name}}},
        {"anim",
         {{"--position-tolerance", shown(a.positionTolerance)},
          {"--rotation-tolerance", shown(a.rotationTolerance * 180.0 / M_PI)}}},
        {"city",
         {{"--seed", shown(double(c.seed))}, {"--size", shown(c.size.x) + "x" + shown(c.size.y)},
          {"--tile-size", shown(c.tileSize)}, {"--threads", "0"}}},
        {"render", streaming({{"--size", imageSize}, {"--repeat", "5"}})},
        {"view", streaming({{"--size", imageSize}, {"--frames", "0"}})},
        {"demo",
         {{"--threads", "0"}, {"--bake-texel", shown(b.texel)}, {"--bake-interior-texel", shown(b.interiorTexel)},
          {"--bake-samples", shown(b.samples)}, {"--bake-bounces", shown(b.bounces)}}},
        {"bake",
         {{"--texel", shown(b.texel)}, {"--interior-texel", shown(b.interiorTexel)}, {"--ground-texel", shown(b.groundTexel)},
          {"--samples", shown(b.samples)}, {"--sun-samples", shown(b.sunSamples)}, {"--bounces", shown(b.bounces)},
          {"--ao-radius", shown(b.aoRadius)}, {"--memory-budget", shown(b.memoryBudgetMb)}, {"--seed", shown(double(b.seed))},
          {"--threads", "0"}}},
        {"inspect", {}},
    };
    for (const auto& [command, options] : expected) EXPECT_EQ(helpDefaults(command), options) << command;
}

TEST(Cli, QuietWorksBeforeAndAfterTheCommand) {
    TempDir dir;
    for (const auto& args : {std::vector<std::string>{"-q", "city", "-o", (dir / "a").string(), "--size", "120x100"},
                             std::vector<std::string>{"city", "-o", (dir / "b").string(), "--size", "120x100", "--quiet"}}) {
        const RunResult r = test::runDawnforge(args);
        EXPECT_EQ(r.exitCode, 0) << r.err;
        EXPECT_TRUE(r.err.empty()) << r.err;
    }
    EXPECT_EQ(test::readBytes(dir / "a" / "city.glb"), test::readBytes(dir / "b" / "city.glb"));
}

TEST(Cli, BakeBadInputExits2AndWritesNothing) {
    TempDir dir;
    expectBadInput({"bake", (dir / "missing").string()}, "missing");
    std::filesystem::create_directories(dir / "empty");
    expectBadInput({"bake", (dir / "empty").string()}, "city.glb");
    expectBadInput({"bake", (dir / "empty").string(), "--texel", "0"}, "--texel");
    expectBadInput({"bake", (dir / "empty").string(), "--samples", "0"}, "--samples");
    expectBadInput({"bake", (dir / "empty").string(), "--bounces", "many"}, "--bounces");
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"empty"});
    EXPECT_TRUE(std::filesystem::is_empty(dir / "empty"));
}

TEST(Cli, UnknownOptionsAndCommandsAreBadInput) {
    expectBadInput({"inspect", "--frobnicate", "x.obj"}, "--frobnicate");
    expectBadInput({"inspect"}, "FILE");
    expectBadInput({}, "subcommand");
}

TEST(Cli, InspectReportsAnIcosphereAsJson) {
    TempDir dir;
    const Mesh sphere = makeIcosphere(1.0f, 3);
    test::writeObj(dir / "sphere.obj", sphere);
    const RunResult r = test::runDawnforge({"inspect", (dir / "sphere.obj").string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["triangles"], 1280);
    EXPECT_EQ(j["vertices"], 642);
    EXPECT_EQ(j["closed"], true);
    EXPECT_EQ(j["manifold"], true);
    EXPECT_EQ(j["self_intersecting"], false);
    EXPECT_NEAR(j["volume"].get<double>() / test::referenceVolume(sphere), 1.0, 1e-6);
    EXPECT_NEAR(j["bbox_min"][0].get<double>(), -1.0, 1e-6);
    EXPECT_NEAR(j["bbox_max"][1].get<double>(), 1.0, 1e-6);
}

TEST(Cli, InspectReportsOpenAndNonManifoldMeshes) {
    RunResult r = test::runDawnforge({"inspect", test::dataFile("open_box.obj").string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["closed"], false);
    EXPECT_TRUE(j["volume"].is_null());
    r = test::runDawnforge({"inspect", test::dataFile("fin.obj").string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["manifold"], false);
}

TEST(Cli, InspectBadFilesExit2WithOneLine) {
    TempDir dir;
    test::writeText(dir / "empty.obj", "");
    Rng rng(11);
    std::string noise(2048, '\0');
    for (char& c : noise) c = static_cast<char>(rng.below(256));
    test::writeText(dir / "noise.glb", noise);
    test::writeText(dir / "noise.obj", noise);
    expectBadInput({"inspect", (dir / "missing.obj").string()}, "missing.obj: no such file");
    expectBadInput({"inspect", (dir / "empty.obj").string()}, "empty.obj: the file is empty");
    expectBadInput({"inspect", (dir / "noise.glb").string()}, "noise.glb");
    expectBadInput({"inspect", (dir / "noise.obj").string()}, "noise.obj");
    expectBadInput({"inspect", test::dataFile("nan.obj").string()}, "non-finite");
    expectBadInput({"inspect", test::dataFile("bad_index.obj").string()}, "bad_index.obj");
    expectBadInput({"inspect", dir.path().string()}, "folder");
}

TEST(Cli, RepairWritesAValidClosedMesh) {
    TempDir dir;
    const auto out = dir / "fixed.glb";
    const RunResult r = test::runDawnforge({"inspect", test::dataFile("open_box.obj").string(), "--repair", out.string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["closed"], false);
    EXPECT_EQ(j["repair"]["result"]["closed"], true);
    EXPECT_NEAR(j["repair"]["result"]["volume"].get<double>(), 1.0, 1e-9);
    test::expectValidGltf(out);
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"fixed.glb"});
}

TEST(Cli, FailedRepairLeavesNoOutput) {
    TempDir dir;
    expectBadInput({"inspect", test::dataFile("nan.obj").string(), "--repair", (dir / "out.glb").string()}, "nan.obj");
    EXPECT_TRUE(dir.entries().empty());
}

// The whole demo, as `./run demo` runs it: its folders, the destruction's bake into VATs of
// every preset, a valid scene and three pictures. Run twice, the bytes are the same; under the
// sanitizers it runs once (the second run only repeats the first's memory paths).
TEST(Cli, DemoWritesAValidSceneDeterministically) {
    TempDir dir;
    const auto demo = [&](const char* out, bool quiet) {
        std::vector<std::string> args{"demo", "-o", (dir / out).string()};
        if (quiet) args.push_back("--quiet");
        args.insert(args.end(), std::begin(kQuickBake), std::end(kQuickBake));
        return test::runDawnforge(args);
    };
    const RunResult a = demo("a", false);
    ASSERT_EQ(a.exitCode, 0) << a.err;
    EXPECT_NE(a.out.find("fragments.glb"), std::string::npos);
    EXPECT_FALSE(std::filesystem::exists(dir / "a" / "scene.glb"));  // nothing reads it: not written
    const nlohmann::json sim = nlohmann::json::parse(test::readText(dir / "a" / "sim" / "sim.json"));
    EXPECT_GT(sim["glue"]["broken"].get<int>(), 0);
    for (const char* preset : {"native", "unreal", "unity"})
        for (const char* suffix : {"_pos.exr", "_rot.exr", "_mesh.glb", "_data.json"})
            EXPECT_TRUE(std::filesystem::exists(dir / "a" / "vat" / (std::string("building_") + preset + suffix))) << preset << suffix;
    const auto glbA = test::readBytes(dir / "a" / "fracture" / "fragments.glb");
    EXPECT_GT(glbA.size(), 1000u);
    EXPECT_EQ(glbA, test::readBytes(dir / "a" / "sim" / "fragments.glb"));  // the simulation folder's own copy
    test::expectValidGltf(dir / "a" / "fracture" / "fragments.glb");
    // The demo ends with pictures of its scene: the first camera, the promenade at night, the sunset.
    EXPECT_NE(a.out.find("render.png"), std::string::npos);
    std::map<std::string, double> mean;
    for (const char* name : {"render.png", "render_night.png", "render_sunset.png"}) {
        const Image image = readPng(dir / "a" / name);
        EXPECT_EQ(image.width, 1280) << name;
        EXPECT_EQ(image.height, 720) << name;
        double sum = 0.0;
        for (std::uint8_t v : image.rgba) sum += v;
        mean[name] = sum / double(image.rgba.size());
    }
    EXPECT_LT(mean["render_night.png"], 0.6 * mean["render.png"]);
    // report.html: the three pictures and the bake's four channels inlined, the energy, motion
    // and piece-size plots, a row per stage, every part available, nothing fetched from elsewhere.
    const std::string report = test::readText(dir / "a" / "report.html");
    EXPECT_NE(a.out.find("report.html"), std::string::npos);
    EXPECT_EQ(occurrences(report, "<img src=\"data:image/png;base64,"), 7u);
    EXPECT_EQ(occurrences(report, "<svg "), 3u);
    EXPECT_EQ(occurrences(report, "not available"), 0u) << between(report, "not available", "</p>");
    for (const char* stage : {"city", "bake", "fracture", "simulate", "vat", "render"})
        EXPECT_NE(report.find(std::string("<tr><td>") + stage + "</td>"), std::string::npos) << stage;
    // Outside the inlined images' base64 (where "http" turns up by chance: 4 letters in 4.5 MB), the
    // SVG namespace is the only URL.
    std::string text;
    for (std::size_t at = 0; at < report.size();) {
        const std::size_t data = report.find("base64,", at);
        text += report.substr(at, data == std::string::npos ? std::string::npos : data - at);
        at = data == std::string::npos ? report.size() : report.find('"', data);
    }
    EXPECT_EQ(occurrences(text, "http"), occurrences(text, "xmlns=\"http://www.w3.org/2000/svg\""));
    EXPECT_EQ(occurrences(report, "<script"), 0u);
    // The hit throws chips and dust: sim.json counts them, the VATs carry them, the report says so.
    const nlohmann::json debris = nlohmann::json::parse(test::readText(dir / "a" / "sim" / "sim.json"))["debris"];
    const std::size_t chips = debris["chips"].get<std::size_t>(), puffs = debris["dust"]["puffs"].get<std::size_t>();
    EXPECT_GT(chips, 50u);
    EXPECT_GT(puffs, 20u);
    EXPECT_TRUE(std::filesystem::exists(dir / "a" / "vat" / "building_native_dust.exr"));
    EXPECT_NE(report.find(format("{} chips of debris", chips)), std::string::npos);
    EXPECT_NE(report.find(format("{} puffs of dust", puffs)), std::string::npos);
    if (DAWNFORGE_SANITIZED) return;
    const RunResult b = demo("b", true);
    ASSERT_EQ(b.exitCode, 0) << b.err;
    EXPECT_EQ(glbA, test::readBytes(dir / "b" / "fracture" / "fragments.glb"));
    for (const char* name : {"render.png", "render_night.png", "render_sunset.png"})
        EXPECT_EQ(test::readBytes(dir / "a" / name), test::readBytes(dir / "b" / name)) << name;
    EXPECT_EQ(test::readText(dir / "a" / "scene.json"), test::readText(dir / "b" / "scene.json"));
    // The report differs run to run in its times alone: its pictures, bake, simulation and fracture are the same.
    const std::string reportB = test::readText(dir / "b" / "report.html");
    EXPECT_EQ(between(report, "<h2 id=\"pictures\">", "<h2 id=\"stages\">"), between(reportB, "<h2 id=\"pictures\">", "<h2 id=\"stages\">"));
    EXPECT_EQ(between(report, "<h2 id=\"bake\">", "</body>"), between(reportB, "<h2 id=\"bake\">", "</body>"));
    EXPECT_GT(between(report, "<h2 id=\"bake\">", "</body>").size(), 10000u);
    expectReportOpensInChromium(dir / "a" / "report.html", 7, 3);
}

TEST(Cli, DemoBadOptionsExit2) {
    TempDir dir;
    expectBadInput({"demo", "-o", (dir / "d").string(), "--bake-texel", "0"}, "--bake-texel");
    expectBadInput({"demo", "-o", (dir / "d").string(), "--bake-samples", "0"}, "--bake-samples");
    expectBadInput({"demo", "-o", (dir / "d").string(), "--building", "-3"}, "--building");
    expectBadInput({"demo", "-o", (dir / "d").string(), "--building", "many"}, "--building");
    test::writeText(dir / "file", "x");
    expectBadInput({"demo", "-o", (dir / "file").string()}, "file");
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"file"});
}

TEST(CliFracture, WritesValidFilesThatAgreeWithEachOther) {
    TempDir dir;
    const Mesh sphere = makeIcosphere(1.0f, 3);
    test::writeObj(dir / "sphere.obj", sphere);
    const RunResult r = test::runDawnforge(
        {"fracture", (dir / "sphere.obj").string(), "-o", (dir / "out").string(), "--pieces", "20", "--seed", "7"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("20 pieces"), std::string::npos) << r.out;
    test::expectValidGltf(dir / "out" / "fragments.glb");

    const nlohmann::json j = nlohmann::json::parse(test::readText(dir / "out" / "fracture.json"));
    EXPECT_EQ(j["seed"], 7);
    EXPECT_EQ(j["input"]["triangles"], 1280);
    EXPECT_EQ(j["settings"]["method"], "rvd");
    EXPECT_EQ(j["cells"]["cut"], 20);
    EXPECT_EQ(j["cells"]["by_corefinement"], 0);
    ASSERT_EQ(j["pieces"].size(), 20u);
    double total = 0.0;
    for (const auto& p : j["pieces"]) {
        for (const char* key : {"id", "name", "volume", "mass", "center_of_mass", "inertia", "triangles", "closed"})
            EXPECT_TRUE(p.contains(key)) << key;
        EXPECT_EQ(p["closed"], true);
        EXPECT_NEAR(p["mass"].get<double>(), 2400.0 * p["volume"].get<double>(), 1e-9);
        total += p["volume"].get<double>();
    }
    EXPECT_NEAR(total / j["input"]["volume"].get<double>(), 1.0, 1e-6);
    ASSERT_FALSE(j["bonds"].empty());
    for (const char* key : {"a", "b", "area", "centroid", "normal"}) EXPECT_TRUE(j["bonds"][0].contains(key)) << key;

    // The GLB's nodes: piece_NNNN, translated to the centre of mass that fracture.json states.
    const std::string glb = test::readText(dir / "out" / "fragments.glb");
    std::uint32_t length = 0;
    std::memcpy(&length, glb.data() + 12, 4);
    const nlohmann::json gltf = nlohmann::json::parse(glb.substr(20, length));
    ASSERT_EQ(gltf["nodes"].size(), 20u);
    for (std::size_t i = 0; i < 20; ++i) {
        EXPECT_EQ(gltf["nodes"][i]["name"], j["pieces"][i]["name"]);
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(gltf["nodes"][i]["translation"][k].get<double>(),
                        j["pieces"][i]["center_of_mass"][k].get<double>(), 1e-6);
    }
}

TEST(CliFracture, SameBytesOnOneAndTwoThreads) {
    TempDir dir;
    test::writeObj(dir / "torus.obj", test::makeTorus(1.0f, 0.4f, 24, 12));
    for (const char* threads : {"1", "2"})
        ASSERT_EQ(test::runDawnforge({"fracture", (dir / "torus.obj").string(), "-o", (dir / threads).string(),
                                      "--pieces", "12", "--threads", threads})
                      .exitCode,
                  0);
    EXPECT_EQ(test::readBytes(dir / "1" / "fragments.glb"), test::readBytes(dir / "2" / "fragments.glb"));
    EXPECT_EQ(test::readText(dir / "1" / "fracture.json"), test::readText(dir / "2" / "fracture.json"));
}

TEST(CliFracture, BadInputExits2AndWritesNothing) {
    TempDir dir;
    test::writeObj(dir / "sphere.obj", makeIcosphere(1.0f, 2));
    const std::string sphere = (dir / "sphere.obj").string(), out = (dir / "out").string();
    expectBadInput({"fracture", sphere, "-o", out, "--pieces", "0"}, "--pieces");
    expectBadInput({"fracture", sphere, "-o", out, "--pieces", "-5"}, "--pieces");
    expectBadInput({"fracture", sphere, "-o", out, "--pieces", "20001"}, "--force");
    expectBadInput({"fracture", sphere, "-o", out, "--impact", "1,2"}, "--impact");
    expectBadInput({"fracture", sphere, "-o", out, "--levels", "1"}, "need an impact point");
    expectBadInput({"fracture", sphere, "-o", out, "--interior-material", "16"}, "--interior-material");
    expectBadInput({"fracture", sphere, "-o", out, "--roughness", "-0.1"}, "--roughness");
    expectBadInput({"fracture", sphere, "-o", out, "--method", "fast"}, "--method");
    expectBadInput({"fracture", test::dataFile("open_box.obj").string(), "-o", out}, "not closed");
    expectBadInput({"fracture", test::dataFile("nan.obj").string(), "-o", out}, "non-finite");
    expectBadInput({"fracture", (dir / "missing.obj").string(), "-o", out}, "no such file");
    test::writeText(dir / "points.txt", "0 0 0\n0.1 oops 0\n");
    expectBadInput({"fracture", sphere, "-o", out, "--points", (dir / "points.txt").string()}, "line 2");
    EXPECT_EQ(dir.entries(), (std::vector<std::string>{"points.txt", "sphere.obj"}));
}

// Seeds at a cube's corners in a box with vertices on their bisectors: the restricted Voronoi
// diagram cannot close those cells, corefinement cuts them, and the user is told.
TEST(CliFracture, SaysHowManyCellsCorefinementCut) {
    TempDir dir;
    test::writeObj(dir / "box.obj", test::gridBox(4));
    std::string points;
    for (int k = 0; k < 8; ++k) points += format("{} {} {}\n", k & 1 ? 0.5 : -0.5, k & 2 ? 0.5 : -0.5, k & 4 ? 0.5 : -0.5);
    test::writeText(dir / "corners.txt", points);
    for (const char* method : {"rvd", "corefine"}) {
        const RunResult r = test::runDawnforge({"fracture", (dir / "box.obj").string(), "-o", (dir / method).string(),
                                                "--points", (dir / "corners.txt").string(), "--method", method});
        ASSERT_EQ(r.exitCode, 0) << r.err;
        const nlohmann::json j = nlohmann::json::parse(test::readText(dir / method / "fracture.json"));
        EXPECT_EQ(j["settings"]["method"], method);
        EXPECT_EQ(j["cells"]["cut"], 8);
        const int corefined = j["cells"]["by_corefinement"];
        if (std::string(method) == "rvd") {
            EXPECT_GT(corefined, 0);
            EXPECT_NE(r.out.find(format("{} of 8 cells cut by corefinement", corefined)), std::string::npos) << r.out;
        } else {
            EXPECT_EQ(corefined, 0);  // nothing fell back: corefinement was asked for
            EXPECT_EQ(r.out.find("cut by corefinement"), std::string::npos) << r.out;
        }
    }
}

// Fracture pieces glued back together (they touch along cut faces triangulated differently
// on each side) cannot be oriented as one surface: the repair says so; it crashed once.
TEST(Cli, RepairOfTouchingPiecesIsOneLineNotACrash) {
    TempDir dir;
    test::writeObj(dir / "block.obj", makeBox({0, 0, 0}, {2, 1, 1}));
    ASSERT_EQ(test::runDawnforge({"fracture", (dir / "block.obj").string(), "-o", (dir / "f").string(), "--pieces", "6"})
                  .exitCode,
              0);
    const RunResult r =
        test::runDawnforge({"inspect", (dir / "f" / "fragments.glb").string(), "--repair", (dir / "r.glb").string()});
    EXPECT_TRUE(r.exitCode == 0 || r.exitCode == 2) << r.exitCode << " " << r.err;
    if (r.exitCode == 2) {
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_FALSE(std::filesystem::exists(dir / "r.glb"));
    }
}

TEST(CliFracture, RepairOptionFixesAnOpenMesh) {
    TempDir dir;
    const RunResult r = test::runDawnforge(
        {"fracture", test::dataFile("open_box.obj").string(), "-o", (dir / "out").string(), "--pieces", "3", "--repair"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("filled 1 hole"), std::string::npos) << r.err;
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / "fracture.json"));
}

namespace {

// A fractured box (12 pieces) in DIR/fracture, the input of simulate.
void makeFractureFolder(const TempDir& dir) {
    test::writeObj(dir / "block.obj", makeBox({-2, 0, -1}, {2, 3, 1}));
    const RunResult r = test::runDawnforge({"fracture", (dir / "block.obj").string(), "-o", (dir / "fracture").string(),
                                            "--pieces", "12", "--density", "500"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
}

// DIR/fracture and DIR/sim: the block simulated for `frames` frames, after `extra` options.
void makeSimulationFolder(const TempDir& dir, const std::string& frames, const std::vector<std::string>& extra = {}) {
    makeFractureFolder(dir);
    std::vector<std::string> args{"simulate", (dir / "fracture").string(), "-o", (dir / "sim").string(), "--frames",
                                  frames};
    args.insert(args.end(), extra.begin(), extra.end());
    const RunResult r = test::runDawnforge(args);
    ASSERT_EQ(r.exitCode, 0) << r.err;
}

}  // namespace

TEST(CliSimulate, WritesTransformsThatMatchSimJson) {
    TempDir dir;
    makeFractureFolder(dir);
    const RunResult r = test::runDawnforge({"simulate", (dir / "fracture").string(), "-o", (dir / "sim").string(),
                                            "--frames", "40", "--fps", "24", "--projectile", "2,1.5,0",
                                            "--projectile-mass", "3000", "--projectile-radius", "0.5", "--no-debris"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(dir.entries(), (std::vector<std::string>{"block.obj", "fracture", "sim"}));
    const nlohmann::json j = nlohmann::json::parse(test::readText(dir / "sim" / "sim.json"));
    EXPECT_EQ(j["frames"], 40);
    EXPECT_EQ(j["fps"], 24.0);
    EXPECT_EQ(j["pieces"], 12);
    EXPECT_EQ(j["substeps"], 4);
    EXPECT_EQ(j["triggers"][0]["type"], "projectile");
    EXPECT_EQ(j["solver"]["sleep"], true);
    EXPECT_EQ(j["piece_names"][0], "piece_0000");
    const auto bin = test::readBytes(dir / "sim" / "transforms.bin");
    ASSERT_EQ(bin.size(), std::size_t(40 * 12 * 7 * 4));
    EXPECT_EQ(test::readBytes(dir / "sim" / "turns.bin").size(), std::size_t(40 * 12 * 4));
    // Frame 0 is the rest pose: each piece at its centre of mass, identity orientation.
    const nlohmann::json f = nlohmann::json::parse(test::readText(dir / "fracture" / "fracture.json"));
    std::vector<float> t(bin.size() / 4);
    std::memcpy(t.data(), bin.data(), bin.size());
    for (std::size_t i = 0; i < 12; ++i) {
        for (int k = 0; k < 3; ++k)
            EXPECT_FLOAT_EQ(t[i * 7 + std::size_t(k)], float(f["pieces"][i]["center_of_mass"][k].get<double>()));
        EXPECT_EQ(t[i * 7 + 6], 1.0f);
    }
    EXPECT_EQ(test::readBytes(dir / "sim" / "fragments.glb"), test::readBytes(dir / "fracture" / "fragments.glb"));
}

// Chips where bonds broke: debris.glb beside the copy of fragments.glb, named in sim.json after
// the pieces; vat and anim play them as pieces; dust in dust.bin, which vat bakes beside them.
// --no-debris and --no-dust write none and take away an earlier run's.
TEST(CliSimulate, ChipsAndDustWhereBondsBrokeThatVatAndAnimPlay) {
    TempDir dir;
    makeSimulationFolder(dir, "30", {"--collapse"});
    const std::filesystem::path sim = dir / "sim";
    nlohmann::json j = nlohmann::json::parse(test::readText(sim / "sim.json"));
    const std::size_t chips = j["debris"]["chips"].get<std::size_t>();
    ASSERT_GT(chips, 0u);
    EXPECT_EQ(j["pieces"].get<std::size_t>(), 12 + chips);
    EXPECT_EQ(j["debris"]["first_chip"], 12);
    EXPECT_EQ(j["debris"]["file"], "debris.glb");
    EXPECT_GT(j["debris"]["bonds"].get<int>(), 0);
    ASSERT_EQ(j["piece_names"].size(), 12 + chips);
    EXPECT_TRUE(j["piece_names"][12].get<std::string>().starts_with("chip_0")) << j["piece_names"][12];
    EXPECT_EQ(test::readBytes(sim / "transforms.bin").size(), 30 * (12 + chips) * 7 * 4);
    test::expectValidGltf(sim / "debris.glb");
    EXPECT_EQ(test::readBytes(sim / "fragments.glb"), test::readBytes(dir / "fracture" / "fragments.glb"));

    const std::size_t puffs = j["debris"]["dust"]["puffs"].get<std::size_t>();
    ASSERT_GT(puffs, 0u);
    EXPECT_EQ(j["debris"]["dust"]["file"], "dust.bin");
    EXPECT_EQ(test::readBytes(sim / "dust.bin").size(), 30 * puffs * 5 * 4);

    ASSERT_EQ(test::runDawnforge({"vat", sim.string(), "-o", (dir / "vat").string()}).exitCode, 0);
    const nlohmann::json vat = nlohmann::json::parse(test::readText(dir / "vat" / "vat_data.json"));
    EXPECT_EQ(vat["pieces"].get<std::size_t>(), 12 + chips);
    EXPECT_EQ(vat["dust"]["puffs"].get<std::size_t>(), puffs);
    EXPECT_EQ(vat["dust"]["file"], "vat_dust.exr");
    EXPECT_TRUE(std::filesystem::is_regular_file(dir / "vat" / "vat_dust.exr"));
    ASSERT_EQ(test::runDawnforge({"anim", sim.string(), "-o", (dir / "sim.glb").string()}).exitCode, 0);
    test::expectValidGltf(dir / "sim.glb");

    const RunResult plain = test::runDawnforge({"simulate", (dir / "fracture").string(), "-o", sim.string(), "--frames",
                                                "30", "--collapse", "--no-debris", "--no-dust"});
    ASSERT_EQ(plain.exitCode, 0) << plain.err;
    j = nlohmann::json::parse(test::readText(sim / "sim.json"));
    EXPECT_EQ(j["pieces"], 12);
    EXPECT_EQ(j["debris"]["chips"], 0);
    EXPECT_EQ(j["debris"]["dust"]["puffs"], 0);
    EXPECT_FALSE(std::filesystem::exists(sim / "debris.glb"));
    EXPECT_FALSE(std::filesystem::exists(sim / "dust.bin"));
    EXPECT_EQ(test::readBytes(sim / "transforms.bin").size(), 30 * 12 * 7 * 4);
}

// --no-sleep keeps every body awake (Rigidbody.RubbleAtRestFallsAsleep tests what that changes)
// and sim.json says so.
TEST(CliSimulate, NoSleepIsSaidInSimJson) {
    TempDir dir;
    makeFractureFolder(dir);
    ASSERT_EQ(test::runDawnforge({"simulate", (dir / "fracture").string(), "-o", (dir / "sim").string(), "--frames", "5",
                                  "--no-sleep"})
                  .exitCode,
              0);
    EXPECT_EQ(nlohmann::json::parse(test::readText(dir / "sim" / "sim.json"))["solver"]["sleep"], false);
}

TEST(CliSimulate, SameBytesOnOneAndTwoThreads) {
    TempDir dir;
    makeFractureFolder(dir);
    for (const char* threads : {"1", "2"})
        ASSERT_EQ(test::runDawnforge({"simulate", (dir / "fracture").string(), "-o", (dir / threads).string(),
                                      "--frames", "30", "--explosion", "0,1,0", "--explosion-radius", "2",
                                      "--threads", threads})
                      .exitCode,
                  0);
    EXPECT_EQ(test::readBytes(dir / "1" / "transforms.bin"), test::readBytes(dir / "2" / "transforms.bin"));
    EXPECT_EQ(test::readText(dir / "1" / "sim.json"), test::readText(dir / "2" / "sim.json"));
}

// Files whose readers crashed, corrupted the heap of, or hung the command when they ran in its
// process (tests/data/hostile/): one line naming the file and what the reader did, exit 2, no
// output, in every command that reads a user's mesh.
TEST(Cli, HostileFilesAreOneLineInEveryCommandThatReadsAMesh) {
    TempDir dir;
    makeFractureFolder(dir);
    const std::string out = (dir / "out").string();
    const std::string crash = test::dataFile("hostile/segfault_binary.ply").string(),
                      heap = test::dataFile("hostile/heap_corruption.fbx").string(),
                      hang = test::dataFile("hostile/hang_ascii.ply").string();
    expectBadInput({"inspect", crash}, crash + ": the PLY reader crashed (signal ");
    expectBadInput({"inspect", heap}, heap + ": the FBX reader crashed (signal ");
    expectBadInput({"--read-timeout", "1", "inspect", hang}, hang + ": the PLY reader gave up after 1 s (--read-timeout)");
    expectBadInput({"fracture", heap, "-o", out}, "the FBX reader crashed");
    expectBadInput({"fracture", hang, "-o", out, "--read-timeout", "1"}, "the PLY reader gave up after 1 s");
    expectBadInput({"simulate", (dir / "fracture").string(), "-o", out, "--collider", crash}, "the PLY reader crashed");
    expectBadInput({"pivots", heap, "-o", out}, "the FBX reader crashed");
    expectBadInput({"--read-timeout", "0", "inspect", crash}, "--read-timeout");
    expectBadInput({"--read-memory", "-1", "inspect", crash}, "--read-memory");
    EXPECT_EQ(dir.entries(), (std::vector<std::string>{"block.obj", "fracture"}));
}

TEST(CliSimulate, BadInputExits2AndWritesNothing) {
    TempDir dir;
    makeFractureFolder(dir);
    const std::string fracture = (dir / "fracture").string(), out = (dir / "out").string();
    expectBadInput({"simulate", (dir / "missing").string(), "-o", out}, "no such folder");
    expectBadInput({"simulate", (dir / "block.obj").string(), "-o", out}, "no such folder");
    expectBadInput({"simulate", fracture, "-o", out, "--frames", "0"}, "--frames");
    expectBadInput({"simulate", fracture, "-o", out, "--fps", "0"}, "--fps");
    expectBadInput({"simulate", fracture, "-o", out, "--projectile", "1,2"}, "--projectile");
    expectBadInput({"simulate", fracture, "-o", out, "--projectile", ",,"}, "--projectile: expected X,Y,Z");
    expectBadInput({"simulate", fracture, "-o", out, "--projectile", "1,2,nan"}, "three numbers");
    expectBadInput({"simulate", fracture, "-o", out, "--strength", "-1"}, "--strength");
    // An inconsistent folder: fracture.json lists a piece fragments.glb does not have.
    std::filesystem::create_directories(dir / "broken");
    std::filesystem::copy_file(dir / "fracture" / "fragments.glb", dir / "broken" / "fragments.glb");
    nlohmann::json j = nlohmann::json::parse(test::readText(dir / "fracture" / "fracture.json"));
    j["pieces"].push_back(j["pieces"][0]);
    test::writeText(dir / "broken" / "fracture.json", j.dump());
    expectBadInput({"simulate", (dir / "broken").string(), "-o", out}, "do not belong together");
    test::writeText(dir / "broken" / "fracture.json", "{\"format\": \"dawnforge.fracture\", \"version\": 1");
    expectBadInput({"simulate", (dir / "broken").string(), "-o", out}, "not valid JSON");
    std::filesystem::remove(dir / "broken" / "fracture.json");
    expectBadInput({"simulate", (dir / "broken").string(), "-o", out}, "fracture.json");
    EXPECT_EQ(dir.entries(), (std::vector<std::string>{"block.obj", "broken", "fracture"}));
}

TEST(CliVat, WritesTexturesMeshAndDataForEveryPreset) {
    TempDir dir;
    makeSimulationFolder(dir, "20", {"--collapse", "--no-debris"});
    for (const char* preset : {"native", "unreal", "unity"}) {
        const RunResult r = test::runDawnforge({"vat", (dir / "sim").string(), "-o", (dir / "vat").string(), "--preset",
                                                preset, "--name", preset, "--max-width", "5"});
        ASSERT_EQ(r.exitCode, 0) << r.err;
        const nlohmann::json j = nlohmann::json::parse(test::readText(dir / "vat" / (std::string(preset) + "_data.json")));
        EXPECT_EQ(j["W"], 5);
        EXPECT_EQ(j["R"], 3);  // 12 pieces at width 5
        EXPECT_EQ(j["height"], 60);
        EXPECT_EQ(j["frames"], 20);
        EXPECT_LT(j["max_vertex_error"].get<double>(), 1e-3);
        test::expectValidGltf(dir / "vat" / (std::string(preset) + "_mesh.glb"));
    }
    const RunResult half = test::runDawnforge({"vat", (dir / "sim").string(), "-o", (dir / "half").string(), "--half"});
    ASSERT_EQ(half.exitCode, 0) << half.err;
    const nlohmann::json j = nlohmann::json::parse(test::readText(dir / "half" / "vat_data.json"));
    EXPECT_EQ(j["precision"], "half");
    EXPECT_GT(j["max_vertex_error"].get<double>(), 0.0);
    for (const char* preset : {"unreal", "unity"}) {
        const RunResult ldr = test::runDawnforge({"vat", (dir / "sim").string(), "-o", (dir / "ldr").string(), "--preset",
                                                  preset, "--name", preset, "--format", "ldr"});
        ASSERT_EQ(ldr.exitCode, 0) << ldr.err;
        EXPECT_TRUE(test::contains(ldr.out, "RGBA8 (Non-HDR)")) << ldr.out;
        const nlohmann::json l = nlohmann::json::parse(test::readText(dir / "ldr" / (std::string(preset) + "_data.json")));
        EXPECT_EQ(l["texture_format"], "ldr");
        EXPECT_EQ(l["precision"], "8-bit");
        EXPECT_GT(l["max_rotation_error"].get<double>(), 0.0);
        for (const char* suffix : {"_pos.png", "_pos2.png", "_rot.png"})
            EXPECT_TRUE(std::filesystem::is_regular_file(dir / "ldr" / (std::string(preset) + suffix))) << suffix;
        test::expectValidGltf(dir / "ldr" / (std::string(preset) + "_mesh.glb"));
    }
    std::size_t written = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir / "ldr")) written += entry.path().extension() != ".tmp";
    EXPECT_EQ(written, 10u) << "five files per preset (three PNGs, the mesh, the data), no EXR, nothing left over";
}

TEST(CliVat, BadInputExits2AndWritesNothing) {
    TempDir dir;
    makeSimulationFolder(dir, "1000");
    const std::string sim = (dir / "sim").string(), out = (dir / "out").string();
    // 12 pieces at width 1 take 12 rows per frame: 1000 frames need 12,000 rows; 682 fit.
    expectBadInput({"vat", sim, "-o", out, "--max-width", "1"}, "at most 682 frames fit");
    expectBadInput({"vat", sim, "-o", out, "--max-width", "0"}, "--max-width");
    expectBadInput({"vat", sim, "-o", out, "--preset", "blender"}, "blender");
    expectBadInput({"vat", sim, "-o", out, "--preset", "unity", "--full-precision-uvs"}, "for the unreal preset");
    expectBadInput({"vat", sim, "-o", out, "--format", "png"}, "expected hdr or ldr");
    expectBadInput({"vat", sim, "-o", out, "--format", "ldr"}, "unity and unreal presets");
    expectBadInput({"vat", sim, "-o", out, "--format", "ldr", "--preset", "unity", "--half"}, "--half is for the hdr");
    expectBadInput({"vat", (dir / "fracture").string(), "-o", out}, "sim.json");
    // A simulation that does not match its mesh: transforms.bin cut short.
    auto bytes = test::readBytes(dir / "sim" / "transforms.bin");
    bytes.resize(bytes.size() - 28);
    std::filesystem::create_directories(dir / "short");
    for (const char* f : {"sim.json", "fragments.glb"}) std::filesystem::copy_file(dir / "sim" / f, dir / "short" / f);
    test::writeText(dir / "short" / "transforms.bin", std::string(bytes.begin(), bytes.end()));
    expectBadInput({"vat", (dir / "short").string(), "-o", out}, "transforms.bin");
    EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

TEST(CliAnim, WritesANodePerPieceAndAValidAnimation) {
    TempDir dir;
    makeSimulationFolder(dir, "20", {"--collapse"});
    const RunResult r = test::runDawnforge({"anim", (dir / "sim").string(), "-o", (dir / "sim.glb").string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(test::contains(r.out, "worst error at a frame")) << r.out;
    test::expectValidGltf(dir / "sim.glb");
    const auto glb = test::readBytes(dir / "sim.glb");
    std::uint32_t length = 0;
    std::memcpy(&length, glb.data() + 12, 4);
    const nlohmann::json j = nlohmann::json::parse(std::string(reinterpret_cast<const char*>(glb.data()) + 20, length));
    const nlohmann::json sim = nlohmann::json::parse(test::readText(dir / "sim" / "sim.json"));
    ASSERT_EQ(j["nodes"].size(), sim["piece_names"].size());
    for (std::size_t i = 0; i < j["nodes"].size(); ++i) EXPECT_EQ(j["nodes"][i]["name"], sim["piece_names"][i]);
    ASSERT_EQ(j["animations"].size(), 1u);
    EXPECT_EQ(j["animations"][0]["channels"].size(), 2 * sim["piece_names"].size());
    // The same simulation gives the same bytes.
    ASSERT_EQ(test::runDawnforge({"anim", (dir / "sim").string(), "-o", (dir / "again.glb").string()}).exitCode, 0);
    EXPECT_EQ(test::readBytes(dir / "again.glb"), glb);
}

TEST(CliAnim, BadInputExits2AndWritesNothing) {
    TempDir dir;
    makeSimulationFolder(dir, "5");
    const std::string sim = (dir / "sim").string(), out = (dir / "out.glb").string();
    expectBadInput({"anim", sim, "-o", (dir / "out.gltf").string()}, "must be a .glb file");
    expectBadInput({"anim", sim, "-o", out, "--rotation-tolerance", "20"}, "--rotation-tolerance");
    expectBadInput({"anim", sim, "-o", out, "--position-tolerance", "-1"}, "--position-tolerance");
    expectBadInput({"anim", (dir / "fracture").string(), "-o", out}, "sim.json");
    expectBadInput({"anim", sim, "-o", (dir / "missing" / "out.glb").string()}, "missing");
    EXPECT_FALSE(std::filesystem::exists(dir / "out.glb"));
    EXPECT_FALSE(std::filesystem::exists(dir / "out.gltf"));
}

// Assimp's glTF 2.0 test scene: 12 mesh nodes, 6 of them children of others. The expected
// elements come from the file's own JSON, read here: depth first from the scene's roots, each
// mesh node's parent its nearest mesh ancestor (a root its own).
TEST(CliPivots, PaintsARealHierarchyInBothPresets) {
    const std::filesystem::path gltf = "/usr/share/assimp/models/glTF2/textureTransform/TextureTransformTest.gltf";
    const nlohmann::json file = nlohmann::json::parse(test::readText(gltf));
    std::vector<std::pair<std::string, int>> want;  // name, parent
    const std::function<void(int, int)> visit = [&](int node, int parentElement) {
        const nlohmann::json& n = file["nodes"][std::size_t(node)];
        if (n.contains("mesh")) {
            const int self = int(want.size());
            want.emplace_back(n.value("name", ""), parentElement < 0 ? self : parentElement);
            parentElement = self;
        }
        for (const auto& c : n.value("children", nlohmann::json::array())) visit(c.get<int>(), parentElement);
    };
    for (const auto& root : file["scenes"][file.value("scene", 0)]["nodes"]) visit(root.get<int>(), -1);
    ASSERT_EQ(want.size(), 12u);

    TempDir dir;
    for (const char* preset : {"unreal", "native"}) {
        const std::filesystem::path out = dir / preset;
        const RunResult r = test::runDawnforge({"--quiet", "pivots", gltf.string(), "-o", out.string(), "--preset", preset,
                                                "--name", "t"});
        ASSERT_EQ(r.exitCode, 0) << r.err;
        const nlohmann::json json = nlohmann::json::parse(test::readText(out / "t_pivots.json"));
        ASSERT_EQ(json["elements"].size(), want.size());
        for (std::size_t i = 0; i < want.size(); ++i) {
            EXPECT_EQ(json["elements"][i]["name"], want[i].first);
            EXPECT_EQ(json["elements"][i]["parent"], want[i].second) << want[i].first;
        }
        EXPECT_EQ(json["width"], 4);
        EXPECT_EQ(json["height"], 3);
        EXPECT_TRUE(std::filesystem::exists(out / (std::string("t_axes.") + (preset[0] == 'u' ? "png" : "exr"))));
        test::expectValidGltf(out / "t.glb");
    }
}

TEST(CliPivots, BadInputExits2AndWritesNothing) {
    TempDir dir;
    const std::string out = (dir / "out").string();
    expectBadInput({"pivots", "/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf", "-o", out},
                   "no node hierarchy");
    expectBadInput({"pivots", test::dataFile("cube_quads.obj").string(), "-o", out}, "no node hierarchy");
    expectBadInput({"pivots", (dir / "missing.glb").string(), "-o", out}, "no such file");
    expectBadInput({"pivots", "/usr/share/assimp/models/glTF2/textureTransform/TextureTransformTest.gltf", "-o", out,
                    "--preset", "unity"},
                   "unknown preset 'unity'");
    EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

TEST(CliCity, WritesAValidGlbAndAReportThatAgree) {
    TempDir dir;
    const RunResult r = test::runDawnforge({"--quiet", "city", "-o", (dir / "c").string(), "--size", "300x240", "--seed", "4"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("buildings"), std::string::npos);
    test::expectValidGltf(dir / "c" / "city.glb");
    const nlohmann::json report = nlohmann::json::parse(test::readText(dir / "c" / "city.json"));
    EXPECT_EQ(report["seed"], 4);
    EXPECT_EQ(report["size"][0], 300.0);
    EXPECT_GT(report["counts"]["buildings"].get<int>(), 5);
    EXPECT_GT(report["counts"]["rooms"].get<int>(), report["counts"]["buildings"].get<int>());
    // Every building node of the GLB is in the report, with both LODs.
    const auto nodes = loadMeshNodes(dir / "c" / "city.glb");
    std::size_t lod0 = 0;
    for (const MeshNode& n : nodes) {
        lod0 += n.name.ends_with("_lod0");
        for (std::uint8_t id : n.mesh.materialIds) ASSERT_LT(id, 16);
    }
    EXPECT_EQ(lod0, report["buildings"].size());
    // Every tree and lamp of the report stands in the GLB where the report says (a trunk's or a
    // lamp's node origin is its foot: glTF (x, height, -y)).
    std::map<std::string, glm::vec3> origins;
    for (const MeshNode& n : nodes) origins[n.name] = glm::vec3(n.world[3]);
    for (const char* kind : {"trees", "lamps"}) {
        ASSERT_GT(report[kind].size(), 10u) << kind;
        for (const auto& e : report[kind]) {
            const auto it = origins.find(e["name"].get<std::string>());
            ASSERT_NE(it, origins.end()) << e["name"];
            EXPECT_NEAR(it->second.x, e["foot"][0].get<double>(), 1e-3);
            EXPECT_NEAR(it->second.z, -e["foot"][1].get<double>(), 1e-3);
        }
    }
    // Each species with its Pivot Painter 2 files for Unreal.
    for (const auto& species : report["tree_species"]) {
        const std::string name = species["name"].get<std::string>();
        const nlohmann::json pp = nlohmann::json::parse(test::readText(dir / "c" / "trees" / (name + "_pivots.json")));
        EXPECT_EQ(pp["preset"], "unreal");
        EXPECT_EQ(pp["elements"].size(), species["elements"].size());
        EXPECT_TRUE(std::filesystem::exists(dir / "c" / "trees" / (name + "_pivots.exr"))) << name;
        EXPECT_TRUE(std::filesystem::exists(dir / "c" / "trees" / (name + "_axes.png"))) << name;
    }
}

TEST(CliCity, SameBytesOnOneAndTwoThreadsAndATileMatchesTheCity) {
    TempDir dir;
    const std::vector<std::string> common{"--quiet", "city", "--size", "300x240", "--tile-size", "150"};
    auto runWith = [&](const std::string& out, std::vector<std::string> extra) {
        std::vector<std::string> args = common;
        args.insert(args.end(), {"-o", (dir / out).string()});
        args.insert(args.end(), extra.begin(), extra.end());
        const RunResult r = test::runDawnforge(args);
        EXPECT_EQ(r.exitCode, 0) << r.err;
    };
    runWith("one", {"--threads", "1"});
    runWith("two", {"--threads", "2"});
    runWith("tile", {"--tile", "1,0"});
    EXPECT_EQ(test::readBytes(dir / "one" / "city.glb"), test::readBytes(dir / "two" / "city.glb"));
    EXPECT_EQ(test::readBytes(dir / "one" / "city.json"), test::readBytes(dir / "two" / "city.json"));
    // The tile's meshes are the whole city's meshes of the same names.
    std::map<std::string, Mesh> whole;
    for (MeshNode& n : loadMeshNodes(dir / "one" / "city.glb")) whole[n.name] = std::move(n.mesh);
    std::size_t compared = 0;
    for (const MeshNode& n : loadMeshNodes(dir / "tile" / "city.glb")) {
        ASSERT_TRUE(whole.count(n.name)) << n.name;
        const Mesh& w = whole[n.name];
        EXPECT_EQ(n.mesh.positions, w.positions) << n.name;
        EXPECT_EQ(n.mesh.indices, w.indices) << n.name;
        EXPECT_EQ(n.mesh.uv1, w.uv1) << n.name;
        ++compared;
    }
    EXPECT_GT(compared, 3u);
}

// `dawnforge bake` as a user runs it: the same bytes on 1 and 2 threads, a summary, and a
// render that refuses a bake made from another city.glb with one line.
TEST(CliBake, SameBytesOnAnyThreadCountAndTheRendererRefusesAnotherCitysBake) {
    TempDir dir;
    const std::vector<std::string> quick{"--texel", "0.5", "--interior-texel", "1", "--ground-texel", "2", "--samples", "8",
                                         "--sun-samples", "4", "--bounces", "1"};
    for (const char* name : {"one", "two"}) {
        ASSERT_EQ(test::runDawnforge({"-q", "city", "-o", (dir / name).string(), "--size", "120x100"}).exitCode, 0);
        std::vector<std::string> args{"bake", (dir / name).string(), "--threads", name[0] == 'o' ? "1" : "2"};
        args.insert(args.end(), quick.begin(), quick.end());
        const RunResult r = test::runDawnforge(args);
        ASSERT_EQ(r.exitCode, 0) << r.err;
        EXPECT_NE(r.out.find("Mrays/s"), std::string::npos) << r.out;
    }
    std::size_t files = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir / "one" / "bake")) {
        EXPECT_EQ(test::readBytes(e.path()), test::readBytes(dir / "two" / "bake" / e.path().filename())) << e.path().filename();
        ++files;
    }
    EXPECT_GT(files, 10u);
    // Another city under the same bake: the renderer says so and exits 2.
    ASSERT_EQ(test::runDawnforge({"-q", "city", "-o", (dir / "other").string(), "--size", "120x100", "--seed", "2"}).exitCode, 0);
    std::filesystem::copy_file(dir / "other" / "city.glb", dir / "two" / "city.glb", std::filesystem::copy_options::overwrite_existing);
    test::writeText(dir / "scene.json", R"({"format": "dawnforge.scene", "version": 1, "city": "two"})");
    expectBadInput({"render", (dir / "scene.json").string(), "-o", (dir / "x.png").string()}, "another city.glb");
    EXPECT_FALSE(std::filesystem::exists(dir / "x.png"));
}

TEST(CliCity, RecipesFromTheExamplesWork) {
    TempDir dir;
    for (const char* name : {"downtown", "coastal_town"}) {
        const std::string recipe = test::dataFile("../../examples/recipes/").string() + name + ".json";
        const RunResult r = test::runDawnforge({"--quiet", "city", "-o", (dir / name).string(), "--size", "260x220", "--recipe", recipe});
        ASSERT_EQ(r.exitCode, 0) << name << ": " << r.err;
        test::expectValidGltf(dir / name / "city.glb");
    }
    // The two recipes make different towns: downtown is taller.
    auto meanFloors = [&](const char* name) {
        const nlohmann::json j = nlohmann::json::parse(test::readText(dir / name / "city.json"));
        return j["counts"]["floors"].get<double>() / j["counts"]["buildings"].get<double>();
    };
    EXPECT_GT(meanFloors("downtown"), 2.0 * meanFloors("coastal_town"));
}

TEST(CliCity, BadOptionsAndRecipesExit2AndWriteNothing) {
    TempDir dir;
    const std::string out = (dir / "out").string();
    expectBadInput({"city", "-o", out, "--size", "-100x200"}, "city size");
    expectBadInput({"city", "-o", out, "--size", "banana"}, "--size");
    expectBadInput({"city", "-o", out, "--size", "0x0"}, "city size");
    expectBadInput({"city", "-o", out, "--tile", "9,9"}, "tile 9,9 is outside the city");
    expectBadInput({"city", "-o", out, "--tile", "a,b"}, "--tile");
    expectBadInput({"city", "-o", out, "--tile-size", "0"}, "tile size");
    expectBadInput({"city", "-o", out, "--recipe", (dir / "missing.json").string()}, "missing.json");
    test::writeText(dir / "unknown.json", R"({"buildings": {"max_flors": 3}})");
    expectBadInput({"city", "-o", out, "--recipe", (dir / "unknown.json").string()}, "buildings.max_flors");
    test::writeText(dir / "zero.json", R"({"buildings": {"storey_height": 0}})");
    expectBadInput({"city", "-o", out, "--recipe", (dir / "zero.json").string()}, "storey_height");
    test::writeText(dir / "broken.json", "{ \"streets\": ");
    expectBadInput({"city", "-o", out, "--recipe", (dir / "broken.json").string()}, "broken.json");
    // Malformed tree, lamp and terrain recipes.
    test::writeText(dir / "trees.json", R"({"dressing": {"tree_spacing": 1.5}})");
    expectBadInput({"city", "-o", out, "--recipe", (dir / "trees.json").string()}, "dressing.tree_spacing must be 0 (none) or at least 4");
    test::writeText(dir / "lamps.json", R"({"dressing": {"lamp_height": "tall"}})");
    expectBadInput({"city", "-o", out, "--recipe", (dir / "lamps.json").string()}, "dressing.lamp_height must be a number");
    test::writeText(dir / "land.json", R"({"terrain": {"margin": -5}})");
    expectBadInput({"city", "-o", out, "--recipe", (dir / "land.json").string()}, "terrain.margin");
    EXPECT_EQ(dir.entries(), (std::vector<std::string>{"broken.json", "lamps.json", "land.json", "trees.json", "unknown.json",
                                                       "zero.json"}));
}

namespace {

// A small city, a VAT of two boxes and a scene.json naming both, with a camera.
struct RenderFixture {
    TempDir dir;
    std::filesystem::path scene = dir / "scene.json";
    RenderFixture() {
        const RunResult city = test::runDawnforge({"--quiet", "city", "-o", (dir / "city").string(), "--size", "160x160"});
        EXPECT_EQ(city.exitCode, 0) << city.err;
        writeBoxesVat(dir / "vat", "boxes", 2);
        writeScene(R"("city": "city", "time_of_day": 12, "time": 0.5,
                      "ocean": {"level": -0.8, "grid": [64, 48]},
                      "destruction": [{"vat": "vat", "name": "boxes", "position": [80, 0, -80], "start_time": 0}],
                      "cameras": [{"name": "high", "position": [200, 90, 60], "target": [80, 0, -80]},
                                  {"name": "low", "position": [40, 5, -20], "target": [80, 5, -80], "fov_degrees": 70}])");
    }
    void writeScene(const std::string& body) const {
        test::writeText(scene, R"({"format": "dawnforge.scene", "version": 1, )" + body + "}");
    }
    // `pieces` boxes falling for 10 frames.
    static void writeBoxesVat(const std::filesystem::path& dir, const std::string& name, int pieces) {
        std::vector<Mesh> meshes;
        std::vector<float> transforms;
        for (int j = 0; j < pieces; ++j) meshes.push_back(makeBox({-1, -1, -1}, {1, 1, 1}, 3));
        for (int k = 0; k < 10; ++k)
            for (int j = 0; j < pieces; ++j) {
                const float piece[7] = {3.0f * float(j), 5.0f - 0.2f * float(k), 0, 0, 0, 0, 1};
                transforms.insert(transforms.end(), piece, piece + 7);
            }
        VatSettings settings;
        settings.name = name;
        writeVat(encodeVat({meshes, transforms, 10, 30.0}, settings), settings, dir);
    }
    RunResult render(std::vector<std::string> extra) const {
        std::vector<std::string> args{"render", scene.string(), "-o", (dir / "out.png").string(), "--size", "128x96"};
        args.insert(args.end(), extra.begin(), extra.end());
        return test::runDawnforge(args);
    }
};

}  // namespace

TEST(CliRender, WritesThePictureAndItsPassTimes) {
    RenderFixture f;
    const RunResult r = f.render({"--stats", "--repeat", "1"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json stats = nlohmann::json::parse(r.out);
    EXPECT_EQ(stats["size"][0], 128);
    std::vector<std::string> passes;
    for (const auto& p : stats["passes"]) {
        passes.push_back(p["name"]);
        EXPECT_GE(p["cpu_ms"].get<double>(), 0.0);
    }
    EXPECT_EQ(passes,
              (std::vector<std::string>{"shadow", "probes", "opaque", "destruction", "sky", "ocean", "dust", "exposure", "flares", "tonemap", "readback"}));
    EXPECT_FALSE(stats.contains("probes")) << "probes are off by default";
    EXPECT_EQ(stats["ocean_vertices"], 64 * 48);
    EXPECT_GT(stats["triangles"].get<int>(), 1000);
    const Image image = readPng(f.dir / "out.png");
    ASSERT_EQ(image.width, 128);
    ASSERT_EQ(image.height, 96);
    std::set<std::uint32_t> colours;
    for (std::size_t p = 0; p < image.rgba.size(); p += 4)
        colours.insert(std::uint32_t(image.rgba[p]) << 16 | std::uint32_t(image.rgba[p + 1]) << 8 | image.rgba[p + 2]);
    EXPECT_GT(colours.size(), 500u) << "a picture, not a flat colour";
}

TEST(CliRender, SameSceneSameBytesOnAnyThreadCount) {
    RenderFixture f;
    // The probes read the bake's proxies: a ground slab and one block are enough for them.
    std::filesystem::create_directories(f.dir / "city" / "bake");
    test::writeText(f.dir / "city" / "bake" / "proxies.json", R"({"format": "dawnforge.proxies", "version": 1, "boxes": [
        {"name": "g", "part": 0, "kind": "ground", "centre": [80, -0.05, -80], "u": [1, 0, 0], "w": [0, 0, 1],
         "half_size": [120, 0.05, 120], "colours": [[0.3, 0.4, 0.2], [0.3, 0.4, 0.2], [0.3, 0.4, 0.2], [0.3, 0.4, 0.2], [0.3, 0.4, 0.2], [0.3, 0.4, 0.2]]},
        {"name": "b", "part": 0, "kind": "building", "centre": [50, 6, -35], "u": [1, 0, 0], "w": [0, 0, 1],
         "half_size": [4, 6, 4], "colours": [[0.8, 0.5, 0.3], [0.8, 0.5, 0.3], [0.2, 0.2, 0.2], [0.8, 0.5, 0.3], [0.8, 0.5, 0.3], [0.8, 0.5, 0.3]]}]})");
    std::map<std::string, std::vector<unsigned char>> images;
    for (const std::string probes : {"off", "mid"})
        for (const char* threads : {"1", "3"}) {
            setenv("LP_NUM_THREADS", threads, 1);
            const RunResult r = f.render({"--camera", "low", "--probes", probes});
            ASSERT_EQ(r.exitCode, 0) << r.err;
            images[probes + threads] = test::readBytes(f.dir / "out.png");
        }
    unsetenv("LP_NUM_THREADS");
    EXPECT_EQ(images["off1"], images["off3"]);
    EXPECT_EQ(images["mid1"], images["mid3"]);
    EXPECT_NE(images["off1"], images["mid1"]) << "the probes light the unbaked city";
}

TEST(CliRender, TimeOfDayCameraAndFrameChangeThePicture) {
    RenderFixture f;
    const auto mean = [&](std::vector<std::string> extra) {
        const RunResult r = f.render(extra);
        EXPECT_EQ(r.exitCode, 0) << r.err;
        const Image image = readPng(f.dir / "out.png");
        double sum = 0.0;
        for (std::uint8_t v : image.rgba) sum += v;
        return std::pair{sum / double(image.rgba.size()), test::readBytes(f.dir / "out.png")};
    };
    const auto noon = mean({"--time-of-day", "12"}), night = mean({"--time-of-day", "23"});
    EXPECT_LT(night.first, 0.6 * noon.first);
    EXPECT_NE(mean({"--camera", "low"}).second, noon.second);
    EXPECT_NE(mean({"--camera", "low", "--frame", "9"}).second, mean({"--camera", "low", "--frame", "0"}).second);
}

// Trees sway in the vertex shader: with wind, frames differ; without, they are the same bytes.
// The camera looks down on a street tree from 30 m, so no building hides it.
TEST(CliRender, TreesSwayInTheWindAndStandStillWithout) {
    RenderFixture f;
    const nlohmann::json city = nlohmann::json::parse(test::readText(f.dir / "city" / "city.json"));
    ASSERT_FALSE(city["trees"].empty());
    const double x = city["trees"][0]["foot"][0].get<double>(), z = -city["trees"][0]["foot"][1].get<double>();
    const auto frame = [&](double speed, int frame) {
        f.writeScene(dawnforge::format(R"("city": "city", "time_of_day": 12, "wind": {{"speed": {}}},
                               "cameras": [{{"name": "tree", "position": [{}, 30, {}], "target": [{}, 4, {}]}}])",
                            speed, x + 1.0, z + 1.0, x, z));
        const RunResult r = f.render({"--frame", std::to_string(frame)});
        EXPECT_EQ(r.exitCode, 0) << r.err;
        return test::readBytes(f.dir / "out.png");
    };
    const auto still = frame(0.0, 0);
    EXPECT_EQ(still, frame(0.0, 45));
    const auto windy = frame(15.0, 0);
    EXPECT_NE(windy, still);
    EXPECT_NE(frame(15.0, 45), windy);
}

TEST(CliRender, BadScenesExit2WithOneLine) {
    RenderFixture f;
    const auto out = (f.dir / "out.png").string();
    expectBadInput({"render", (f.dir / "none.json").string(), "-o", out}, "none.json");
    expectBadInput({"view", (f.dir / "none.json").string()}, "none.json");  // refused before any window opens
    expectBadInput({"render", f.scene.string(), "-o", (f.dir / "out.jpg").string()}, ".png");
    expectBadInput({"render", f.scene.string(), "-o", out, "--size", "12x"}, "--size");
    expectBadInput({"render", f.scene.string(), "-o", out, "--camera", "drone"}, "drone");
    expectBadInput({"render", f.scene.string(), "-o", out, "--time-of-day", "25"}, "--time-of-day");
    expectBadInput({"render", f.scene.string(), "-o", out, "--probes", "ultra"}, "--probes");
    expectBadInput({"render", f.scene.string(), "-o", out, "--probes", "mid"}, "dawnforge bake");  // the city has no bake
    f.writeScene(R"("city": "city", "ocean": {"heigth": 2})");
    expectBadInput({"render", f.scene.string(), "-o", out}, "ocean.heigth");
    f.writeScene(R"("city": "town")");
    expectBadInput({"render", f.scene.string(), "-o", out}, "town");
    f.writeScene(R"("destruction": [{"vat": "missing", "name": "boxes"}])");
    expectBadInput({"render", f.scene.string(), "-o", out}, "missing");
    // A VAT whose mesh has three pieces where its textures have two.
    RenderFixture::writeBoxesVat(f.dir / "other", "boxes", 3);
    std::filesystem::copy_file(f.dir / "other" / "boxes_mesh.glb", f.dir / "vat" / "boxes_mesh.glb",
                               std::filesystem::copy_options::overwrite_existing);
    f.writeScene(R"("destruction": [{"vat": "vat", "name": "boxes"}])");
    expectBadInput({"render", f.scene.string(), "-o", out}, "boxes_mesh.glb");
    // A VAT for an engine, not for the runtime.
    VatSettings unity;
    unity.preset = VatPreset::Unity;
    unity.name = "crate";
    {
        std::vector<Mesh> meshes{makeBox({-1, -1, -1}, {1, 1, 1}, 3)};
        const std::vector<float> transforms{0, 0, 0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1};
        writeVat(encodeVat({meshes, transforms, 2, 30.0}, unity), unity, f.dir / "vat");
    }
    f.writeScene(R"("destruction": [{"vat": "vat", "name": "crate"}])");
    expectBadInput({"render", f.scene.string(), "-o", out}, "native");
    EXPECT_FALSE(std::filesystem::exists(out)) << "nothing written on bad input";
}

TEST(CliView, OpensAWindowAndDrawsFrames) {
    // A window needs a display: the X virtual framebuffer that ./run installs.
    if (!std::filesystem::exists("/usr/bin/xvfb-run")) GTEST_SKIP() << "xvfb-run is not installed (./run installs it)";
    RenderFixture f;
    // Under AddressSanitizer, the X and GLX client libraries keep allocations until exit that
    // are not ours (and are reported from unloaded modules): leak checking is off for this
    // one child; every other sanitizer check stays on.
    const char* asan = std::getenv("ASAN_OPTIONS");
    const std::string saved = asan ? asan : "";
    setenv("ASAN_OPTIONS", (saved.empty() ? std::string("detect_leaks=0") : saved + ":detect_leaks=0").c_str(), 1);
    const RunResult r = test::run("/usr/bin/xvfb-run", {"-a", "-s", "-screen 0 640x480x24", DAWNFORGE_EXE, "view",
                                                        f.scene.string(), "--size", "320x240", "--frames", "3"});
    if (asan) setenv("ASAN_OPTIONS", saved.c_str(), 1);
    else unsetenv("ASAN_OPTIONS");
    ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("showed 3 frames"), std::string::npos) << r.out;
}
