// Runtime figures (issue: runtime renderer). Fixed input: the demo's district (default
// recipe, seed 1, 320 x 280 m, a third sea) with the ocean, seen from the demo's harbour
// camera at 17:30, rendered headless (EGL; llvmpipe unless a GPU driver is there).
//   build/bin/render_bench                    (frames at 720p and 1080p, start-up pieces)
// The whole demo scene, with its breaking tower, is measured by the CLI:
//   build/bin/dawnforge render out/demo/scene.json -o frame.png --stats
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/procgen/city.hpp>
#include <dawnforge/runtime/atlas.hpp>
#include <dawnforge/runtime/context.hpp>
#include <dawnforge/runtime/interior.hpp>
#include <dawnforge/runtime/ocean.hpp>
#include <dawnforge/runtime/renderer.hpp>

#include <benchmark/benchmark.h>

#include <filesystem>
#include <memory>

namespace {

using namespace dawnforge;
using namespace dawnforge::runtime;

// The demo district, written once into a temporary folder.
const SceneFile& district() {
    static const SceneFile scene = [] {
        const auto dir = std::filesystem::temp_directory_path() / "dawnforge_render_bench";
        std::filesystem::create_directories(dir / "city");
        procgen::CitySettings settings;
        settings.size = {320.0, 280.0};
        settings.tileSize = 160.0;
        settings.recipe.coast.water = 0.3;
        procgen::City city = procgen::generateCity(settings);
        exporters::writeGlb(procgen::takeCityScene(city), dir / "city" / "city.glb");
        SceneFile s;
        s.cityDir = dir / "city";
        s.ocean = OceanSettings{};
        return s;
    }();
    return scene;
}

GlContext& context() {
    static const std::unique_ptr<GlContext> c = GlContext::headless();
    return *c;
}

FrameSettings harbour() {
    FrameSettings f;
    f.camera.position = {235.0, 22.0, 3.5};
    f.camera.forward = glm::normalize(glm::dvec3(150.0, 12.0, -91.5) - f.camera.position);
    f.camera.fovYDegrees = 55.0;
    f.timeOfDay = 17.5;
    f.time = 2.4;
    return f;
}

void frames(benchmark::State& state, glm::ivec2 size) {
    context();
    RendererOptions options;
    options.size = size;
    Renderer renderer(district(), options);
    const FrameSettings frame = harbour();
    renderer.render(frame);  // warm-up: shader compilation, first uploads
    FrameStats last;
    for (auto _ : state) last = renderer.render(frame);
    // The split: one more frame with a glFinish after each pass.
    renderer.setSynchronisedPasses(true);
    const FrameStats split = renderer.render(frame);
    for (const PassTime& p : split.passes) state.counters[p.name + "_ms"] = p.cpuMs;
    state.counters["triangles"] = double(last.triangles);
    state.counters["ocean_vertices"] = double(last.oceanVertices);
    state.SetLabel(context().description());
}

void BM_Frame720p(benchmark::State& state) { frames(state, {1280, 720}); }
BENCHMARK(BM_Frame720p)->Unit(benchmark::kMillisecond)->Iterations(10)->UseRealTime();

void BM_Frame1080p(benchmark::State& state) { frames(state, {1920, 1080}); }
BENCHMARK(BM_Frame1080p)->Unit(benchmark::kMillisecond)->Iterations(10)->UseRealTime();

// Start-up work on the CPU.
void BM_GenerateAtlas(benchmark::State& state) {
    for (auto _ : state) benchmark::DoNotOptimize(generateAtlas());
}
BENCHMARK(BM_GenerateAtlas)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_GenerateInteriors(benchmark::State& state) {
    for (auto _ : state) benchmark::DoNotOptimize(generateInteriors(128, 8));  // what the renderer makes
}
BENCHMARK(BM_GenerateInteriors)->Unit(benchmark::kMillisecond)->UseRealTime();

// Per frame on the CPU: placing the ocean grid's rows.
void BM_ProjectOceanGrid(benchmark::State& state) {
    OceanCamera camera;
    const FrameSettings f = harbour();
    camera.position = f.camera.position;
    camera.forward = f.camera.forward;
    camera.fovYRadians = glm::radians(55.0);
    camera.aspect = 16.0 / 9.0;
    camera.nearPlane = 0.5;
    camera.farPlane = 4000.0;
    for (auto _ : state) benchmark::DoNotOptimize(projectOceanGrid(camera, -0.8, 192, 160));
}
BENCHMARK(BM_ProjectOceanGrid)->Unit(benchmark::kMicrosecond);

}  // namespace
