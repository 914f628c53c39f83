// End-to-end tests of the dawnforge executable, as a user runs it.
#include "test_support.hpp"

#include <dawnforge/core/primitives.hpp>
#include <dawnforge/core/seed.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstring>

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

TEST(CliFracture, WritesValidFilesThatAgreeWithEachOther) {
    TempDir dir;
    const Mesh sphere = makeIcosphere(1.0f, 3);
    test::writeObj(dir / "sphere.obj", sphere);
    const RunResult r = test::runDawnforge(
        {"fracture", (dir / "sphere.obj").string(), "-o", (dir / "out").string(), "--pieces", "20", "--seed", "7"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("20 pieces"), std::string::npos) << r.out;
    const RunResult v = test::validateGltf(dir / "out" / "fragments.glb");
    EXPECT_EQ(v.exitCode, 0) << v.out;

    const nlohmann::json j = nlohmann::json::parse(test::readText(dir / "out" / "fracture.json"));
    EXPECT_EQ(j["seed"], 7);
    EXPECT_EQ(j["input"]["triangles"], 1280);
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
    expectBadInput({"fracture", sphere, "-o", out, "--levels", "1"}, "--impact");
    expectBadInput({"fracture", sphere, "-o", out, "--interior-material", "16"}, "--interior-material");
    expectBadInput({"fracture", sphere, "-o", out, "--roughness", "-0.1"}, "--roughness");
    expectBadInput({"fracture", test::dataFile("open_box.obj").string(), "-o", out}, "not closed");
    expectBadInput({"fracture", test::dataFile("nan.obj").string(), "-o", out}, "non-finite");
    expectBadInput({"fracture", (dir / "missing.obj").string(), "-o", out}, "no such file");
    test::writeText(dir / "points.txt", "0 0 0\n0.1 oops 0\n");
    expectBadInput({"fracture", sphere, "-o", out, "--points", (dir / "points.txt").string()}, "line 2");
    EXPECT_EQ(dir.entries(), (std::vector<std::string>{"points.txt", "sphere.obj"}));
}

TEST(CliFracture, RepairOptionFixesAnOpenMesh) {
    TempDir dir;
    const RunResult r = test::runDawnforge(
        {"fracture", test::dataFile("open_box.obj").string(), "-o", (dir / "out").string(), "--pieces", "3", "--repair"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("filled 1 holes"), std::string::npos) << r.err;
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / "fracture.json"));
}
