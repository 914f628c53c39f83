// Lens flares (runtime/src/flares.hpp, flare.vert): visibility from this frame's depth buffer,
// every element placed on the axis through the screen centre, one draw for any number of
// lights. Each scene is drawn by two renderers, with and without flares, and what the flare
// pass added is the difference of their HDR images (the flare pass is the only one that differs).
#include "flares.hpp"
#include "golden.hpp"
#include "render_support.hpp"
#include "test_support.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/core/scene.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/runtime/renderer.hpp>
#include <dawnforge/runtime/sky.hpp>

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include <fstream>
#include <memory>

using namespace dawnforge;
using namespace dawnforge::runtime;
using dawnforge::test::TempDir;

namespace {

constexpr glm::ivec2 kSize{320, 180};
constexpr double kNight = 22.0, kFov = 50.0;
const glm::dvec3 kEye{0, 2, 12};
const glm::dvec3 kLamp{-5, 4.5, -8};  // 20 m in front of kEye; its line of sight crosses z = 0 at x = -3
const glm::dvec3 kLampColour{1.0, 0.8, 0.55};

// A wall in the plane z = 0 from x0 to x1 (1 cm thick, so its front edge is its outline), and
// a backdrop 30 m away, behind the lamp.
std::vector<Mesh> wallAndBackdrop(float x0, float x1) {
    return {makeBox({x0, -2, -0.01f}, {x1, 12, 0}, 2), makeBox({-80, -2, -32}, {80, 40, -30}, 3)};
}

// A city folder: city.glb holding `meshes`, city.json holding the lamps (plan metres: a
// runtime point (x, h, z) is the plan point (x, -z) at height h).
std::filesystem::path writeCity(const std::filesystem::path& dir, std::vector<Mesh> meshes,
                                const std::vector<glm::dvec3>& lamps) {
    std::filesystem::create_directories(dir);
    Scene scene;
    for (Mesh& m : meshes) scene.addMeshNode(std::move(m));
    exporters::writeGlb(scene, dir / "city.glb");
    nlohmann::json list = nlohmann::json::array();
    for (std::size_t i = 0; i < lamps.size(); ++i) {
        const glm::dvec3& p = lamps[i];
        list.push_back({{"id", i}, {"tile", {0, 0}}, {"foot", {p.x, -p.z}}, {"light", {p.x, -p.z, p.y}},
                        {"colour", {kLampColour.x, kLampColour.y, kLampColour.z}}});
    }
    std::ofstream(dir / "city.json") << nlohmann::json{{"lamps", list}}.dump();
    return dir;
}

std::unique_ptr<Renderer> renderer(const std::filesystem::path& city, bool flares, glm::ivec2 size = kSize) {
    test::llvmpipeContext();
    SceneFile scene;
    scene.cityDir = city;
    scene.lensFlares = flares;
    RendererOptions options;
    options.size = size;
    options.shadowMapSize = 512;
    return std::make_unique<Renderer>(scene, options);
}

FrameSettings lookingAt(glm::dvec3 eye, glm::dvec3 target, double hours = kNight) {
    return test::lookingAt(eye, target, hours, kFov);
}

// A scene drawn with and without flares.
struct FlarePair {
    std::unique_ptr<Renderer> on, off;
    explicit FlarePair(const std::filesystem::path& city) : on(renderer(city, true)), off(renderer(city, false)) {}
    // What the flare pass added to the HDR image of `frame` (row 0 at the top).
    std::vector<glm::vec3> added(const FrameSettings& frame) {
        on->render(frame);
        off->render(frame);
        std::vector<glm::vec3> a = on->readHdrPixels();
        const std::vector<glm::vec3> b = off->readHdrPixels();
        for (std::size_t i = 0; i < a.size(); ++i) a[i] -= b[i];
        return a;
    }
};

double luminance(glm::vec3 c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

double energy(const std::vector<glm::vec3>& added) {
    double sum = 0.0;
    for (const glm::vec3& c : added) sum += luminance(c);
    return sum;
}

// Where `p` lands in the kSize image of `frame`, as normalised device coordinates.
glm::dvec2 ndcOf(const FrameSettings& frame, glm::dvec3 p) {
    const glm::dmat4 proj = glm::perspective(glm::radians(kFov), double(kSize.x) / double(kSize.y), 0.5, 4000.0);
    const glm::dmat4 view = glm::lookAt(frame.camera.position, frame.camera.position + frame.camera.forward, glm::dvec3(0, 1, 0));
    const glm::dvec4 clip = proj * view * glm::dvec4(p, 1.0);
    return glm::dvec2(clip) / clip.w;
}

// The mean added luminance of the 3 × 3 pixels around `ndc`.
double addedAt(const std::vector<glm::vec3>& added, glm::dvec2 ndc) {
    const int x = int((ndc.x * 0.5 + 0.5) * kSize.x), y = kSize.y - 1 - int((ndc.y * 0.5 + 0.5) * kSize.y);
    double sum = 0.0;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) sum += luminance(added[std::size_t((y + dy) * kSize.x + x + dx)]);
    return sum / 9.0;
}

}  // namespace

TEST(Flares, ALampBehindAWallAddsNothing) {
    TempDir dir;
    FlarePair pair(writeCity(dir / "city", wallAndBackdrop(-20, 2), {kLamp}));
    const FrameSettings frame = lookingAt(kEye, {0, 2, 0});
    const std::vector<glm::vec3> added = pair.added(frame);
    // Every instance of the hidden light is degenerate: not one pixel changes.
    for (const glm::vec3& c : added) ASSERT_EQ(c, glm::vec3(0.0f));
    EXPECT_EQ(pair.on->readPixels().rgba, pair.off->readPixels().rgba);
}

TEST(Flares, ALampHalfBehindAnEdgeIsDimmedAboutHalf) {
    TempDir dir;
    const FrameSettings frame = lookingAt(kEye, {0, 2, 0});
    // The wall's edge at x = -3 lies on the line of sight to the lamp; at x = -8 it is clear of it.
    FlarePair half(writeCity(dir / "half", wallAndBackdrop(-20, -3), {kLamp}));
    FlarePair clear(writeCity(dir / "clear", wallAndBackdrop(-20, -8), {kLamp}));
    const double ratio = energy(half.added(frame)) / energy(clear.added(frame));
    // The 32 samples are symmetric about the light, so an edge through it hides 16 of them;
    // which pixel column the edge falls in can move a column of samples (4 of 32) either way.
    EXPECT_GT(ratio, 0.35);
    EXPECT_LT(ratio, 0.65);
    EXPECT_NEAR(ratio, 0.5, 0.13) << "ratio " << ratio;
    RecordProperty("ratio", std::to_string(ratio));
}

TEST(Flares, ALampInViewDrawsEveryElementInTheFirstFrame) {
    TempDir dir;
    FlarePair pair(writeCity(dir / "city", wallAndBackdrop(-20, -8), {kLamp}));
    const FrameSettings frame = lookingAt(kEye, {0, 2, 0});
    // The renderers' first frame: no query from an earlier frame is needed to show the flare.
    const std::vector<glm::vec3> added = pair.added(frame);
    const glm::dvec2 light = ndcOf(frame, kLamp);
    for (const FlareElement& e : flareElements()) {
        glm::dvec2 at = light * double(e.axis);
        if (e.shape == FlareShape::Halo) at.y += 2.0 * 0.82 * e.size;  // on the ring (flare.frag)
        EXPECT_GT(addedAt(added, at), 1e-3) << "element at axis " << e.axis << " is missing";
    }
    // The next frame looks from where the wall hides the lamp: nothing is added at once, and
    // looking back shows the whole flare again at once.
    const double first = energy(added);
    EXPECT_EQ(energy(pair.added(lookingAt({-14, 2, 12}, {-14, 2, 0}))), 0.0);
    EXPECT_DOUBLE_EQ(energy(pair.added(frame)), first);
}

TEST(Flares, OneDrawForOneLampOrFifty) {
    TempDir dir;
    std::vector<glm::dvec3> fifty;
    for (int i = 0; i < 50; ++i) fifty.push_back({-12.0 + 0.5 * i, 3.0 + 0.1 * (i % 7), -8.0 - 0.2 * (i % 5)});
    std::vector<double> energies;
    for (const auto& [name, lamps] : {std::pair{"one", std::vector<glm::dvec3>{kLamp}}, std::pair{"fifty", fifty}}) {
        FlarePair pair(writeCity(dir / name, wallAndBackdrop(-20, -18), lamps));
        const FrameSettings frame = lookingAt(kEye, {0, 2, 0});
        energies.push_back(energy(pair.added(frame)));
        const FrameStats on = pair.on->render(frame), off = pair.off->render(frame);
        EXPECT_EQ(on.drawCalls - off.drawCalls, 1u) << name << " lamps";
        EXPECT_TRUE(std::any_of(on.passes.begin(), on.passes.end(), [](const PassTime& p) { return p.name == "flares"; }));
    }
    EXPECT_GT(energies[1], 10.0 * energies[0]);  // the fifty are all drawn
}

TEST(Flares, TheSunFlaresByDayAndHidesBehindAWall) {
    TempDir dir;
    const double hours = 17.0;
    const glm::dvec3 sun = lightingAt(hours).sunDirection;
    const FrameSettings frame = lookingAt(kEye, kEye + sun, hours);
    FlarePair open(writeCity(dir / "open", {makeBox({-80, -3, -80}, {80, -2, 80}, 13)}, {kLamp}));
    EXPECT_GT(energy(open.added(frame)), 1.0);
    const glm::vec3 wall = glm::vec3(kEye + 10.0 * sun);
    FlarePair hidden(writeCity(dir / "hidden", {makeBox(wall - 5.0f, wall + 5.0f, 2)}, {kLamp}));
    EXPECT_EQ(energy(hidden.added(frame)), 0.0);  // by day the lamps make no flare either
}

TEST(Flares, NightStreetGolden) {
    // A street of two facades and four lamp posts, at night. The standard tolerance of
    // golden.hpp (0.5 % of pixels over 8 per channel, mean under 1.0): the flare is smooth
    // and its positions are exact, so llvmpipe gives the same bytes from run to run.
    TempDir dir;
    std::vector<Mesh> meshes{makeBox({-40, -1, -60}, {40, 0, 20}, 13), makeBox({-16, 0, -60}, {-8, 14, 10}, 2),
                             makeBox({8, 0, -60}, {16, 20, 10}, 4)};
    std::vector<glm::dvec3> lamps;
    for (int i = 0; i < 4; ++i) {
        const float x = i % 2 ? 6.5f : -6.5f, z = -4.0f - 14.0f * float(i);
        meshes.push_back(makeBox({x - 0.08f, 0, z - 0.08f}, {x + 0.08f, 5.7f, z + 0.08f}, 3));
        lamps.push_back({x, 6.0, z});
    }
    const auto r = renderer(writeCity(dir / "city", meshes, lamps), true, {160, 90});
    r->render(lookingAt({-2, 1.7, 14}, {1, 4, -20}));
    test::expectGolden("flares_night_street", r->readPixels());
}

TEST(Flares, MalformedLampsAreRefusedNamingCityJson) {
    const std::vector<StreetLamp> lamps = parseStreetLamps(
        R"({"lamps": [{"id": 0, "tile": [0, 0], "foot": [3, 4], "light": [3, 4, 6], "colour": [1, 0.5, 0.25]}]})", "c/city.json");
    ASSERT_EQ(lamps.size(), 1u);
    EXPECT_EQ(lamps[0].position, glm::dvec3(3, 6, -4));
    EXPECT_EQ(lamps[0].colour, glm::dvec3(1, 0.5, 0.25));
    EXPECT_TRUE(parseStreetLamps(R"({"buildings": []})", "c/city.json").empty());
    for (const char* bad : {R"({"lamps": {}})", R"({"lamps": [3]})", R"({"lamps": [{"colour": [1, 1, 1]}]})",
                            R"({"lamps": [{"light": [1, 2], "colour": [1, 1, 1]}]})",
                            R"({"lamps": [{"light": [1, 2, 3], "colour": [1, 2, 1]}]})",
                            R"({"lamps": [{"light": [1, 2, 3], "colour": [1, 1, 1], "tile": "a"}]})"}) {
        const std::string message = test::inputErrorOf([&] { parseStreetLamps(bad, "c/city.json"); });
        EXPECT_EQ(message.rfind("c/city.json: ", 0), 0u) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
    // Through the renderer: the scene's city.json is named.
    TempDir dir;
    const auto city = writeCity(dir / "city", wallAndBackdrop(-20, -8), {});
    std::ofstream(city / "city.json") << R"({"lamps": [{"light": [0, 0, "high"], "colour": [1, 1, 1]}]})";
    const std::string message = test::inputErrorOf([&] { renderer(city, true); });
    EXPECT_NE(message.find("city.json: \"lamps[0].light\""), std::string::npos) << message;
    EXPECT_NO_THROW(renderer(city, false));  // without flares the lamps are not read
}
