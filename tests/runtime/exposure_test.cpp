// Auto exposure (exposure.comp; ARCHITECTURE.md 7, Exposure) on a generated, baked district:
// a street at noon and rooms by day, lit a hundred times less, both land in one band of
// display luminance; `view`'s adaptation moves in steps towards the target; a pinned exposure
// is kept as given.
#include "render_support.hpp"
#include "test_support.hpp"

#include <dawnforge/bake/bake.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/scene.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/procgen/city.hpp>
#include <dawnforge/runtime/renderer.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <map>
#include <string>
#include <vector>
#include <filesystem>

using namespace dawnforge;
using namespace dawnforge::runtime;
using dawnforge::test::TempDir;

namespace {

// The band a readable picture's mean display luminance lies in (8-bit sRGB values / 255,
// Rec. 709 weights): the ACES curve puts the key (0.18) at about 0.53.
constexpr double kReadableLow = 0.25, kReadableHigh = 0.7;

double meanDisplayLuminance(const exporters::Image& image) {
    double sum = 0.0;
    for (std::size_t p = 0; p < image.rgba.size(); p += 4)
        sum += 0.2126 * image.rgba[p] + 0.7152 * image.rgba[p + 1] + 0.0722 * image.rgba[p + 2];
    return sum / (255.0 * double(image.rgba.size() / 4));
}

// A small generated district baked coarsely, shared by the suite.
class Exposure : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        test::llvmpipeContext();
        dir_ = new TempDir();
        procgen::CitySettings settings;
        settings.size = {120.0, 100.0};
        procgen::City city = procgen::generateCity(settings);
        report_ = nlohmann::json::parse(procgen::cityReportJson(city));
        std::filesystem::create_directories(cityDir());
        test::writeText(cityDir() / "city.json", report_.dump());
        exporters::writeGlb(procgen::takeCityScene(city), cityDir() / "city.glb");
        bake::BakeSettings bake;
        bake.texel = 0.5;
        bake.interiorTexel = 0.75;
        bake.groundTexel = 2.0;
        bake.samples = 16;
        bake.sunSamples = 4;
        bake.bounces = 1;
        bake::bakeCity(cityDir(), bake);
    }
    static void TearDownTestSuite() {
        delete dir_;
        dir_ = nullptr;
    }
    static std::filesystem::path cityDir() { return dir_->path() / "city"; }
    static SceneFile scene() {
        SceneFile s;
        s.cityDir = cityDir();
        s.lensFlares = false;
        return s;
    }
    // Inside each building, 1.6 m above its floor, looking from near the middle of its footprint
    // towards a corner: the rooms of the ground floor, lit through their windows.
    static std::vector<FrameSettings> roomViews(double hours) {
        std::map<std::string, double> floorOf;
        for (const MeshNode& n : loadMeshNodes(cityDir() / "city.glb", ReadIn::thisProcess))
            if (n.name.ends_with("_lod0")) floorOf[n.name.substr(0, n.name.size() - 5)] = computeBounds(n.mesh.positions).min.y;
        std::vector<FrameSettings> views;
        for (const nlohmann::json& b : report_["buildings"]) {
            glm::dvec2 centre(0.0);
            for (const nlohmann::json& p : b["footprint"]) centre += glm::dvec2(p[0].get<double>(), p[1].get<double>());
            centre /= double(b["footprint"].size());
            const glm::dvec2 corner(b["footprint"][0][0].get<double>(), b["footprint"][0][1].get<double>());
            const glm::dvec2 eye = centre + 0.3 * (centre - corner), at = corner + 0.1 * (centre - corner);
            const double y = floorOf.at(b["name"].get<std::string>()) + 1.6;
            views.push_back(test::lookingAt({eye.x, y, -eye.y}, {at.x, y - 0.2, -at.y}, hours, 70.0));
        }
        return views;
    }
    static TempDir* dir_;
    static nlohmann::json report_;
};
TempDir* Exposure::dir_ = nullptr;
nlohmann::json Exposure::report_;

RendererOptions small() {
    RendererOptions o;
    o.size = {128, 96};
    o.shadowMapSize = 1024;
    return o;
}

// Along the first street of the city, 1.7 m up.
FrameSettings streetView(const nlohmann::json& report, double hours) {
    const nlohmann::json& line = report["streets"][0]["polyline"];
    const glm::dvec2 a(line[0][0].get<double>(), line[0][1].get<double>());
    const glm::dvec2 b(line[1][0].get<double>(), line[1][1].get<double>());
    return test::lookingAt({a.x, 1.7, -a.y}, {b.x, 1.5, -b.y}, hours, 60.0);
}

}  // namespace

TEST_F(Exposure, RoomsByDayAndStreetsAtNoonAreBothReadable) {
    Renderer renderer(scene(), small());
    FrameStats street = renderer.render(streetView(report_, 12.0));
    const double streetLuminance = meanDisplayLuminance(renderer.readPixels());
    EXPECT_GT(streetLuminance, kReadableLow);
    EXPECT_LT(streetLuminance, kReadableHigh);
    int rooms = 0;
    for (const FrameSettings& view : roomViews(12.0)) {
        const FrameStats room = renderer.render(view);
        const double l = meanDisplayLuminance(renderer.readPixels());
        EXPECT_GT(l, kReadableLow) << "room " << rooms << ": scene luminance " << room.sceneLuminance << ", exposure " << room.exposure;
        EXPECT_LT(l, kReadableHigh) << "room " << rooms;
        // A room is lit through its windows: far less than the street, which the exposure makes up.
        EXPECT_LT(room.sceneLuminance, 0.1 * street.sceneLuminance) << "room " << rooms;
        EXPECT_GT(room.exposure, 10.0 * street.exposure) << "room " << rooms;
        ++rooms;
    }
    EXPECT_GE(rooms, 3);
}

TEST_F(Exposure, AFixedExposureLeavesRoomsDark) {
    SceneFile pinned = scene();
    pinned.exposure.fixed = 0.9;  // the street's exposure before auto exposure
    Renderer renderer(pinned, small());
    for (const FrameSettings& view : roomViews(12.0)) {
        const FrameStats stats = renderer.render(view);
        EXPECT_FLOAT_EQ(float(stats.exposure), 0.9f);
        EXPECT_LT(meanDisplayLuminance(renderer.readPixels()), 0.1);
    }
}

TEST_F(Exposure, NightStaysDarkerThanDay) {
    Renderer renderer(scene(), small());
    renderer.render(streetView(report_, 12.0));
    const double day = meanDisplayLuminance(renderer.readPixels());
    const FrameStats stats = renderer.render(streetView(report_, 22.0));
    const double night = meanDisplayLuminance(renderer.readPixels());
    EXPECT_GT(night, 0.04) << "readable: exposure " << stats.exposure;
    EXPECT_LT(night, 0.8 * day);
}

TEST_F(Exposure, ViewAdaptsStepByStepAndRenderConvergesDeterministically) {
    Renderer renderer(scene(), small());
    const FrameSettings street = streetView(report_, 12.0);
    FrameSettings room = roomViews(12.0).front();
    const FrameStats start = renderer.render(street);
    const exporters::Image first = renderer.readPixels();
    const FrameStats converged = renderer.render(room);  // adaptSeconds 0: converges at once
    room.adaptSeconds = 1.0 / 30.0;
    renderer.render(street);
    double last = start.exposure;
    for (int i = 0; i < 90; ++i) {  // three seconds at 30 fps from the street's exposure
        const double e = renderer.render(room).exposure;
        EXPECT_GT(e, last) << "frame " << i;
        EXPECT_LE(e, converged.exposure * 1.0001) << "frame " << i;
        if (i == 0) {
            EXPECT_LT(e, 0.5 * converged.exposure) << "the first step is small";
        }
        last = e;
    }
    EXPECT_NEAR(std::log2(last), std::log2(converged.exposure), 0.1) << "1.5 per second: 99 % of the way in 3 s";
    renderer.render(street);
    EXPECT_EQ(renderer.readPixels().rgba, first.rgba) << "the same frame twice is the same picture";
}
