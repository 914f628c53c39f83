// A world streamed by the renderer (ARCHITECTURE.md 7, Streaming): a 2 × 2 world of 128 m tiles
// with a quick bake and one HLOD node, built by `dawnforge world build` as a user builds it.
// Goldens of a street and an aerial view, the streamed picture against every tile at full
// detail, the same street 20 km from the origin, eviction under a budget, prefetching, the
// stats, and what a missing tile does.
#include "golden.hpp"
#include "render_support.hpp"
#include "test_support.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/runtime/renderer.hpp>

#include "streaming.hpp"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <thread>

namespace dawnforge {
namespace {

namespace fs = std::filesystem;
using runtime::Renderer;
using runtime::RendererOptions;
using runtime::SceneFile;

const fs::path& smallWorld() { return test::streamWorld(); }

SceneFile worldScene(const fs::path& world) {
    SceneFile s;
    s.file = world / "scene.json";
    s.worldDir = world;
    return s;
}

RendererOptions options(glm::ivec2 size, double maxError = 16.0) {
    RendererOptions o;
    o.size = size;
    o.streaming.maxScreenError = maxError;
    o.streaming.wait = true;
    return o;
}

// Major street 3 runs north along plan x ≈ 124..135 across the border at y = 128.
const glm::dvec3 kStreetEye{124.0, 1.7, -90.0}, kStreetTarget{129.0, 1.7, -200.0};
const glm::dvec3 kAerialEye{128.0, 260.0, 220.0}, kAerialTarget{128.0, 0.0, -128.0};

double meanDifference(const exporters::Image& a, const exporters::Image& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.rgba.size(); ++i) sum += std::abs(int(a.rgba[i]) - int(b.rgba[i]));
    return sum / double(a.rgba.size());
}

double shareDifferingBy(const exporters::Image& a, const exporters::Image& b, int threshold) {
    std::size_t n = 0;
    for (std::size_t p = 0; p < a.rgba.size(); p += 4)
        for (int c = 0; c < 3; ++c)
            if (std::abs(int(a.rgba[p + std::size_t(c)]) - int(b.rgba[p + std::size_t(c)])) > threshold) {
                ++n;
                break;
            }
    return double(n) / double(a.rgba.size() / 4);
}

exporters::Image draw(Renderer& r, glm::dvec3 eye, glm::dvec3 target, runtime::FrameStats* stats = nullptr) {
    const runtime::FrameStats s = r.render(test::lookingAt(eye, target));
    if (stats) *stats = s;
    return r.readPixels();
}

TEST(Streaming, StreetAndAerialGoldens) {
    test::llvmpipeContext();
    Renderer r(worldScene(smallWorld()), options({160, 120}));
    runtime::FrameStats street, aerial;
    test::expectGolden("stream_street", draw(r, kStreetEye, kStreetTarget, &street));
    test::expectGolden("stream_aerial", draw(r, kAerialEye, kAerialTarget, &aerial));
    // At street level the tiles draw at full detail (LOD0 buildings near); from the air, the HLOD.
    EXPECT_GT(street.lod0Buildings, 0u);
    EXPECT_EQ(aerial.lod0Buildings + aerial.lod1Buildings, 0u);
    EXPECT_EQ(aerial.streaming.drawn, 1);
    EXPECT_TRUE(street.streaming.complete && aerial.streaming.complete);
}

// Against the same view with every tile at full detail (a screen error of 0.01 px refines
// everything): the HLOD costs little of the picture.
TEST(Streaming, TheStreamedPictureIsCloseToFullDetail) {
    test::llvmpipeContext();
    const glm::ivec2 size{320, 180};
    // 250 m out: the HLOD's 2.2 m is 6 px at 180 px high, under the default 16.
    const glm::dvec3 eye{128.0, 120.0, 230.0};
    SceneFile scene = worldScene(smallWorld());
    scene.exposure.fixed = 1.0;  // the same exposure for both: the pictures differ only by what is drawn
    Renderer streamed(scene, options(size));
    Renderer full(scene, options(size, 0.01));
    runtime::FrameStats s, f;
    const exporters::Image a = draw(streamed, eye, kAerialTarget, &s), b = draw(full, eye, kAerialTarget, &f);
    EXPECT_EQ(s.streaming.drawn, 1);
    EXPECT_EQ(f.streaming.drawn, 4);
    EXPECT_LT(s.triangles * 2, f.triangles);
    const double mean = meanDifference(a, b), share = shareDifferingBy(a, b, 24);
    // Measured: mean 2.1/255, 4.6 % of pixels by more than 24 (edges of simplified roofs, cards for trees).
    EXPECT_LT(mean, 4.0);
    EXPECT_LT(share, 0.10);
    EXPECT_GT(mean, 0.0);  // they are different meshes
    std::printf("streamed vs full detail: mean %.2f/255, %.1f %% of pixels by more than 24\n", mean, 100.0 * share);
}

// Where the HLOD hands over to the tiles (its error on screen just under 16 px), the swap
// changes the picture by what the error allows and no more: the pop.
TEST(Streaming, TheHandOverFromHlodToTilesPopsLittle) {
    test::llvmpipeContext();
    const glm::ivec2 size{320, 180};
    const runtime::Tileset tiles = runtime::readTileset(smallWorld());
    const runtime::TileNode& hlod = tiles.nodes[std::size_t(tiles.nodes.front().children.front())];
    ASSERT_TRUE(hlod.hlod);
    // South of the world, 30 m up, looking at its centre; back off until the HLOD is just coarse enough.
    const auto camera = [&](double back) {
        runtime::SelectionCamera c;
        c.position = {128.0, 30.0, back};
        c.screenHeight = double(size.y);
        c.fovYRadians = glm::radians(50.0);
        return c;
    };
    double back = 1.0;
    while (runtime::screenSpaceError(hlod, camera(back)) > 15.9) back *= 1.01;
    const glm::dvec3 eye = camera(back).position;
    Renderer streamed(worldScene(smallWorld()), options(size));
    Renderer full(worldScene(smallWorld()), options(size, 0.01));
    runtime::FrameStats s, f;
    const exporters::Image a = draw(streamed, eye, kAerialTarget, &s), b = draw(full, eye, kAerialTarget, &f);
    ASSERT_EQ(s.streaming.drawn, 1);  // the HLOD
    ASSERT_GT(f.streaming.drawn, 1);  // the tiles
    const double mean = meanDifference(a, b), share = shareDifferingBy(a, b, 24);
    // Measured: at 27 m, mean 4.4/255 and 10.5 % of pixels by more than 24 (16 px of error is 9 % of 180 px).
    EXPECT_LT(mean, 8.0);
    EXPECT_LT(share, 0.15);
    std::printf("hand-over at %.0f m: mean %.2f/255, %.1f %% of pixels by more than 24\n", back, mean, 100.0 * share);
}

// The same street drawn 20 km from the origin (the tileset's root moved by 20,480 m east and
// north, the camera with it): camera-relative rendering gives the same picture.
TEST(Streaming, AStreetTwentyKilometresAwayDrawsTheSame) {
    test::llvmpipeContext();
    test::TempDir dir;
    const fs::path far = dir / "far";
    fs::create_directories(far);
    for (const char* sub : {"tiles", "hlod"}) fs::create_directory_symlink(smallWorld() / sub, far / sub);
    nlohmann::json t = nlohmann::json::parse(test::readText(smallWorld() / "tileset.json"));
    const double shift = 20480.0;
    t["root"]["transform"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, shift, shift, 0, 1};
    test::writeText(far / "tileset.json", t.dump());
    const glm::dvec3 move{shift, 0.0, -shift};  // plan (x, y) → runtime (x, −y)
    Renderer near(worldScene(smallWorld()), options({320, 180}));
    Renderer away(worldScene(far), options({320, 180}));
    const exporters::Image a = draw(near, kStreetEye, kStreetTarget), b = draw(away, kStreetEye + move, kStreetTarget + move);
    EXPECT_EQ(shareDifferingBy(a, b, 2), 0.0);
    EXPECT_LT(meanDifference(a, b), 0.01);
}

// A budget that holds about two tiles: walking from corner to corner of the world evicts what
// is behind, a return loads it again, and the picture is the same.
TEST(Streaming, EvictsUnderTheBudgetAndReloadsTheSamePicture) {
    test::llvmpipeContext();
    RendererOptions o = options({160, 120});
    o.streaming.residentBudgetMB = 64;
    o.streaming.keepFrames = 1;
    Renderer r(worldScene(smallWorld()), o);
    // At each corner of the world, looking out of it along the diagonal.
    const std::vector<std::pair<glm::dvec3, glm::dvec3>> corners{{{20, 1.7, -20}, {-1, 0, 1}},
                                                                  {{236, 1.7, -236}, {1, 0, -1}},
                                                                  {{236, 1.7, -20}, {1, 0, 1}},
                                                                  {{20, 1.7, -236}, {-1, 0, -1}}};
    runtime::FrameStats s;
    const exporters::Image before = draw(r, corners[0].first, corners[0].first + corners[0].second, &s);
    int evictions = 0;
    double peak = s.streaming.residentMB;
    for (const auto& [eye, look] : corners) {
        draw(r, eye, eye + look, &s);
        evictions += s.streaming.evictions;
        peak = std::max(peak, s.streaming.residentMB);
    }
    EXPECT_GT(evictions, 0);
    EXPECT_LE(peak, 64.0 + 45.0);  // the budget, and at most the tile that came in on top of it
    const exporters::Image after = draw(r, corners[0].first, corners[0].first + corners[0].second, &s);
    EXPECT_GT(s.streaming.loads, 0);  // it had left
    EXPECT_EQ(meanDifference(before, after), 0.0);
}

// While tiles load the frame never waits and never shows a hole: no pixel shows the sky where
// the converged picture has something (a hole would), and the last frame is the converged one.
TEST(Streaming, LoadingFramesStandInWithTheParentAndConverge) {
    test::llvmpipeContext();
    RendererOptions o = options({160, 120});
    o.streaming.wait = false;
    o.streaming.uploadBudgetMB = 2;  // tiles take several frames each
    Renderer r(worldScene(smallWorld()), o);
    Renderer reference(worldScene(smallWorld()), options({160, 120}));
    const exporters::Image converged = draw(reference, kStreetEye, kStreetTarget);
    runtime::FrameStats s;
    const exporters::Image empty = draw(r, kStreetEye, kStreetTarget, &s);  // nothing resident yet: the sky
    ASSERT_EQ(s.streaming.drawn, 0);
    int incomplete = 0, partial = 0;
    exporters::Image last;
    for (int frame = 0; frame < 1000; ++frame) {
        last = draw(r, kStreetEye, kStreetTarget, &s);
        EXPECT_EQ(s.streaming.waitMs, 0.0);
        // The budget, and at most one piece that does not split (a tile's trees).
        EXPECT_LE(double(s.streaming.uploadBytes), 3.0 * 1024 * 1024) << "frame " << frame;
        if (s.streaming.complete) break;
        ++incomplete;
        if (s.streaming.drawn == 0) continue;
        ++partial;
        std::size_t holes = 0, covered = 0;
        for (std::size_t p = 0; p < last.rgba.size(); p += 4) {
            const auto same = [&](const exporters::Image& a, const exporters::Image& b) {
                return std::equal(a.rgba.begin() + std::ptrdiff_t(p), a.rgba.begin() + std::ptrdiff_t(p + 3), b.rgba.begin() + std::ptrdiff_t(p));
            };
            if (same(converged, empty)) continue;  // sky in the finished picture too
            ++covered;
            holes += same(last, empty);
        }
        EXPECT_LT(double(holes), 0.002 * double(covered)) << "frame " << frame << ": " << holes << " pixels of sky";
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    EXPECT_TRUE(s.streaming.complete);
    EXPECT_GT(partial, 3);  // frames drew the HLOD while the tiles came
    EXPECT_EQ(meanDifference(last, converged), 0.0);
}

// A camera moving fast asks for the tiles where it will be in a second.
TEST(Streaming, AMovingCameraPrefetchesAhead) {
    test::llvmpipeContext();
    const auto settle = [](glm::dvec3 velocity) {
        RendererOptions o = options({160, 120});
        o.streaming.wait = false;
        Renderer r(worldScene(smallWorld()), o);
        runtime::FrameSettings f = test::lookingAt({40, 1.7, -40}, {20, 1.7, -60});  // tile 0_0, looking at its corner
        f.cameraVelocity = velocity;
        runtime::FrameStats s;
        for (int k = 0; k < 300; ++k) {
            s = r.render(f);
            if (s.streaming.complete && s.streaming.loading == 0) break;
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        return s.streaming.resident;
    };
    const int still = settle(glm::dvec3(0.0)), moving = settle({150.0, 0.0, -150.0});  // towards tile 1_1
    EXPECT_GT(moving, still);
}

TEST(Streaming, StatsSayWhatStreamed) {
    test::llvmpipeContext();
    Renderer r(worldScene(smallWorld()), options({160, 120}));
    runtime::FrameStats s;
    draw(r, kStreetEye, kStreetTarget, &s);
    const runtime::StreamingStats& st = s.streaming;
    EXPECT_TRUE(st.on);
    EXPECT_EQ(st.nodes, 6);  // the root, the HLOD node, four tiles
    EXPECT_GT(st.loads, 0);
    EXPECT_GE(st.resident, st.drawn);
    EXPECT_GT(st.residentMB, 1.0);
    EXPECT_GT(st.uploadBytes, 0u);
    EXPECT_GT(st.waitMs, 0.0);
    EXPECT_TRUE(st.waited);
    const nlohmann::json j = nlohmann::json::parse(runtime::frameStatsJson(s, {160, 120}, "llvmpipe", 0.0, 0.0));
    for (const char* key : {"nodes", "wanted", "resident", "drawn", "loading", "loads", "evictions", "failed", "resident_mb",
                            "upload_mb", "upload_ms", "wait_ms", "complete"})
        EXPECT_TRUE(j["streaming"].contains(key)) << key;
    // The next frame of the same view loads nothing and waits for nothing.
    draw(r, kStreetEye, kStreetTarget, &s);
    EXPECT_EQ(s.streaming.loads, 0);
    EXPECT_EQ(s.streaming.waitMs, 0.0);
}

// A manifest naming a tile that is not there: one warning, the HLOD drawn in its place.
TEST(Streaming, AMissingTileIsDrawnAsItsParent) {
    test::llvmpipeContext();
    test::TempDir dir;
    const fs::path w = dir / "w";
    fs::create_directories(w / "tiles");
    fs::create_directory_symlink(smallWorld() / "hlod", w / "hlod");
    for (const char* tile : {"0_0", "1_0", "1_1"}) fs::create_directory_symlink(smallWorld() / "tiles" / tile, w / "tiles" / tile);
    fs::create_directories(w / "tiles" / "0_1");
    test::writeText(w / "tiles" / "0_1" / "city.glb", "not a glb");  // broken
    fs::copy_file(smallWorld() / "tileset.json", w / "tileset.json");
    Renderer r(worldScene(w), options({160, 120}));
    runtime::FrameStats s;
    testing::internal::CaptureStderr();
    draw(r, kStreetEye, kStreetTarget, &s);
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_EQ(test::lineCount(err), 1u) << err;
    EXPECT_TRUE(test::contains(err, "tiles/0_1/city.glb")) << err;
    EXPECT_TRUE(test::contains(err, "its parent is drawn in its place")) << err;
    EXPECT_EQ(s.streaming.failed, 1);
    EXPECT_TRUE(s.streaming.complete);
    EXPECT_EQ(s.streaming.drawn, 1);  // the HLOD, for all four
    EXPECT_EQ(s.lod0Buildings + s.lod1Buildings, 0u);
}

// A tileset whose content is a plain GLB, not a tile's city folder (as other tools write them):
// drawn as it is.
TEST(Streaming, AnyGlbContentIsDrawnAsItIs) {
    test::llvmpipeContext();
    test::TempDir dir;
    const fs::path w = dir / "w";
    fs::create_directories(w);
    fs::copy_file(smallWorld() / "hlod" / "1_0_0.glb", w / "mesh.glb");
    nlohmann::json t = nlohmann::json::parse(test::readText(smallWorld() / "tileset.json"));
    nlohmann::json node = t["root"]["children"][0];
    node.erase("children");
    node.erase("extras");  // not marked as an HLOD node: its vertices' bake goes unread
    node["content"]["uri"] = "mesh.glb";
    t["root"]["children"] = nlohmann::json::array({node});
    test::writeText(w / "tileset.json", t.dump());
    Renderer r(worldScene(w), options({160, 120}));
    runtime::FrameStats s;
    testing::internal::CaptureStderr();
    draw(r, kAerialEye, kAerialTarget, &s);
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
    EXPECT_EQ(s.streaming.drawn, 1);
    EXPECT_EQ(s.streaming.failed, 0);
    EXPECT_GT(s.triangles, 10000u);
}

// What a destruction may replace in a world: the buildings its plan gives its tiles.
TEST(Streaming, TheWorldsBuildingsComeFromItsPlan) {
    const std::optional<std::set<std::uint32_t>> ids = runtime::worldBuildings(smallWorld());
    ASSERT_TRUE(ids.has_value());
    EXPECT_EQ(ids->size(), 62u);  // `world plan` said so
    EXPECT_FALSE(runtime::worldBuildings(smallWorld() / "tiles").has_value());  // no plan.json there
    test::TempDir dir;
    test::writeText(dir / "plan.json", R"({"tiles": [{"buildings": ["seven"]}]})");
    EXPECT_TRUE(test::contains(test::inputErrorOf([&] { runtime::worldBuildings(dir.path()); }), "not a world plan"));
}

// Probes in a world: captured from the proxies of the tiles drawn now, in render space. The
// world is baked, so they light what the bake does not: the trees.
TEST(Streaming, ProbesLightAWorldFromItsTilesProxies) {
    test::llvmpipeContext();
    SceneFile scene = worldScene(smallWorld());
    scene.probes.preset = "mid";
    scene.probes.show = true;
    Renderer withProbes(scene, options({160, 120}));
    Renderer without(worldScene(smallWorld()), options({160, 120}));
    runtime::FrameStats s;
    const exporters::Image a = draw(withProbes, kStreetEye, kStreetTarget, &s), b = draw(without, kStreetEye, kStreetTarget);
    EXPECT_EQ(s.probePreset, "mid");
    EXPECT_GT(s.probes.captured, 20);
    EXPECT_EQ(s.probes.injected, s.probes.wanted);
    EXPECT_GT(shareDifferingBy(a, b, 8), 0.01);  // the spheres of the debug view, and the trees
    // Every probe stands outside the boxes it was captured from, within the tiles' square.
    for (const runtime::CapturedProbe& p : withProbes.capturedProbes()) {
        EXPECT_GE(p.position.x, -1.0);
        EXPECT_LE(p.position.x, 257.0);
        EXPECT_LE(p.position.z, 1.0);
        EXPECT_GE(p.position.z, -257.0);
    }
    // Elsewhere in the world, other tiles: the probes start again from their proxies.
    draw(withProbes, {200, 1.7, -230}, {230, 1.7, -250}, &s);
    EXPECT_GT(s.probes.captured, 0);
}

}  // namespace
}  // namespace dawnforge
