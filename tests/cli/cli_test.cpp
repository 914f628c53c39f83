// End-to-end tests of the dawnforge executable, as a user runs it.
#include "test_support.hpp"

#include <dawnforge/core/primitives.hpp>
#include <dawnforge/core/seed.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

using namespace dawnforge;
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

}  // namespace

TEST(Cli, HelpListsEveryCommandOfTheArchitecture) {
    const RunResult r = test::runDawnforge({"--help"});
    EXPECT_EQ(r.exitCode, 0);
    for (const char* cmd : {"inspect", "city", "fracture", "simulate", "vat", "bake", "render", "view", "demo"}) {
        EXPECT_NE(r.out.find(std::string("\n  ") + cmd + " "), std::string::npos) << cmd;
        EXPECT_EQ(test::runDawnforge({cmd, "--help"}).exitCode, 0) << cmd;
    }
}

TEST(Cli, CommandsNotBuiltYetSaySoAndExit2) {
    for (const char* cmd : {"city", "simulate", "vat", "bake", "render", "view"})
        expectBadInput({cmd, "-o", "x"}, "not built yet");
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
    const RunResult v = test::validateGltf(out);
    EXPECT_EQ(v.exitCode, 0) << v.out;
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"fixed.glb"});
}

TEST(Cli, FailedRepairLeavesNoOutput) {
    TempDir dir;
    expectBadInput({"inspect", test::dataFile("nan.obj").string(), "--repair", (dir / "out.glb").string()}, "nan.obj");
    EXPECT_TRUE(dir.entries().empty());
}

TEST(Cli, DemoWritesAValidSceneDeterministically) {
    TempDir dir;
    const RunResult a = test::runDawnforge({"demo", "-o", (dir / "a").string()});
    ASSERT_EQ(a.exitCode, 0) << a.err;
    EXPECT_NE(a.out.find("scene.glb"), std::string::npos);
    const RunResult b = test::runDawnforge({"--quiet", "demo", "-o", (dir / "b").string()});
    ASSERT_EQ(b.exitCode, 0) << b.err;
    const auto glbA = test::readBytes(dir / "a" / "scene.glb");
    EXPECT_GT(glbA.size(), 1000u);
    EXPECT_EQ(glbA, test::readBytes(dir / "b" / "scene.glb"));
    const RunResult v = test::validateGltf(dir / "a" / "scene.glb");
    EXPECT_EQ(v.exitCode, 0) << v.out;
}

TEST(Cli, DemoBadOptionsExit2) {
    TempDir dir;
    expectBadInput({"demo", "-o", (dir / "d").string(), "--floors", "0"}, "--floors");
    expectBadInput({"demo", "-o", (dir / "d").string(), "--floors", "-3"}, "--floors");
    expectBadInput({"demo", "-o", (dir / "d").string(), "--floors", "many"}, "--floors");
    test::writeText(dir / "file", "x");
    expectBadInput({"demo", "-o", (dir / "file").string()}, "file");
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"file"});
}
