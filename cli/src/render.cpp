// dawnforge render / view: load a scene file, draw it headless to a PNG or in a window.
#include "commands.hpp"

#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/exporters/image.hpp>
#include <dawnforge/runtime/context.hpp>
#include <dawnforge/runtime/probe_placement.hpp>
#include <dawnforge/runtime/renderer.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

namespace dawnforge::cli {

namespace {

// --size in pixels: "W x H", each a whole number from 16 to 16384.
glm::ivec2 imageSize(const std::string& text) {
    const glm::dvec2 size = parseSize(text, "--size", "pixels");
    const bool whole = size.x == std::floor(size.x) && size.y == std::floor(size.y);
    if (!whole || size.x < 16 || size.y < 16 || size.x > 16384 || size.y > 16384)
        throw InputError(format("--size: expected W x H in pixels, each 16 to 16384, e.g. 1280x720 (got \"{}\")", text));
    return glm::ivec2(size);
}

CLI::Option* addImageSizeOption(CLI::App& cmd, glm::ivec2& size, const char* description) {
    return cmd.add_option_function<std::string>("--size", [&size](const std::string& text) { size = imageSize(text); },
                                                description)
        ->default_str(sizeText(glm::dvec2(size)));
}

runtime::ViewCamera chooseCamera(const runtime::SceneFile& scene, const runtime::Renderer& renderer, const std::string& name) {
    if (!name.empty()) {
        if (const runtime::SceneCamera* c = runtime::findCamera(scene, name)) return runtime::Renderer::cameraOf(*c);
        std::string names;
        for (const runtime::SceneCamera& c : scene.cameras) names += (names.empty() ? "" : ", ") + c.name;
        throw InputError(format("{}: no camera named \"{}\" (the scene has: {})", scene.file.string(), name,
                                names.empty() ? "none" : names));
    }
    if (!scene.cameras.empty()) return runtime::Renderer::cameraOf(scene.cameras.front());
    return renderer.overviewCamera();
}

std::unique_ptr<runtime::GlContext> headlessContext() {
    try {
        return runtime::GlContext::headless();
    } catch (const std::runtime_error& e) {
        throw std::runtime_error(format("no headless OpenGL 4.5 context: {}", e.what()));
    }
}

// What `render` and `view` change in the scene they read.
struct SceneOverrides {
    std::optional<std::string> probePreset;
    bool showProbes = false;
    std::optional<double> exposure;  // pins it
    void apply(runtime::SceneFile& scene) const {
        if (probePreset) scene.probes.preset = *probePreset;
        if (showProbes) scene.probes.show = true;
        if (exposure) scene.exposure.fixed = *exposure;
    }
};

void addSceneOverrides(CLI::App& cmd, SceneOverrides& o) {
    cmd.add_option("--probes", o.probePreset,
                   "Irradiance probes: off, low, mid or high (default: the scene's \"probes\"; any but off needs the city's bake)")
        ->check(CLI::IsMember({"off", "low", "mid", "high"}));
    cmd.add_flag("--show-probes", o.showProbes, "Draw each probe as a small sphere lit by it (the probes' debug view)");
    cmd.add_option("--exposure", o.exposure,
                   "Pin the exposure: the HDR colour's multiplier before the tone curve (default: the scene's \"exposure\", "
                   "automatic unless it has \"fixed\")")
        ->check(CLI::PositiveNumber);
}

// How a world scene streams; ignored for a city.
void addStreamingOptions(CLI::App& cmd, runtime::StreamingOptions& o) {
    cmd.add_option("--max-screen-error", o.maxScreenError,
                   "World: a tile refines into its children when its error on screen is larger (pixels)")
        ->check(CLI::Range(0.5, 1000.0))->capture_default_str();
    cmd.add_option("--resident-mb", o.residentBudgetMB, "World: GPU memory the streamed tiles may hold (MB)")
        ->check(CLI::Range(16, 1 << 20))->capture_default_str();
    cmd.add_option("--upload-mb", o.uploadBudgetMB, "World: bytes uploaded per frame at most (MB)")
        ->check(CLI::Range(1, 1 << 20))->capture_default_str();
    cmd.add_option("--stream-threads", o.workers, "World: threads that read and parse tiles")
        ->check(CLI::Range(1, 16))->capture_default_str();
}

struct RenderOptions {
    std::filesystem::path sceneFile;
    std::filesystem::path output;
    std::string camera;                // empty: the scene's first camera, or an overview
    std::optional<double> timeOfDay;   // hours; default: the scene's
    std::optional<int> frame;          // time = frame / fps; default: the scene's time
    bool stats = false;
    int repeat = 5;                    // --stats: timed frames after one warm-up; the median is reported
    SceneOverrides overrides;          // of the scene's probes and exposure
    runtime::RendererOptions renderer;
};

int runRender(const RenderOptions& options, const CommonOptions& common) {
    const glm::ivec2 size = options.renderer.size;
    std::string extension = options.output.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (extension != ".png")
        throw InputError(format("{}: the output must be a .png file", options.output.string()));
    if (options.timeOfDay && !(*options.timeOfDay >= 0.0 && *options.timeOfDay <= 24.0))
        throw InputError(format("--time-of-day: expected hours from 0 to 24 (got {})", *options.timeOfDay));
    runtime::SceneFile scene = runtime::loadSceneFile(options.sceneFile);
    options.overrides.apply(scene);
    if (options.output.has_parent_path()) ensureOutputDirectory(options.output.parent_path());

    const auto context = headlessContext();
    runtime::RendererOptions ro = options.renderer;
    ro.streaming.wait = true;  // one picture: its camera's selection, resident (deterministic)
    runtime::Renderer renderer(scene, ro);
    runtime::FrameSettings frame;
    frame.camera = chooseCamera(scene, renderer, options.camera);
    frame.time = options.frame ? double(*options.frame) / scene.fps : scene.time;
    frame.timeOfDay = options.timeOfDay ? std::fmod(*options.timeOfDay, 24.0) : scene.timeOfDay;

    // With --stats, the first frame's passes are finished one by one too, so that the probes'
    // capture time holds only the capture (llvmpipe runs the shadow pass at the next flush).
    renderer.setSynchronisedPasses(options.stats);
    runtime::FrameStats stats = renderer.render(frame);
    exporters::Image image = renderer.readPixels(&stats);
    const runtime::ProbeStats firstProbes = stats.probes;  // the frame that captured them
    const runtime::StreamingStats firstStreaming = stats.streaming;  // the frame that loaded the tiles
    if (options.stats) {
        // The first frame pays for shader compilation and first uploads: time the next ones,
        // pipelined for the frame time, then with a glFinish after each pass for the split.
        const auto median = [&](bool synchronised) {
            renderer.setSynchronisedPasses(synchronised);
            std::vector<runtime::FrameStats> timed;
            for (int i = 0; i < options.repeat; ++i) {
                timed.push_back(renderer.render(frame));
                image = renderer.readPixels(&timed.back());
            }
            std::sort(timed.begin(), timed.end(), [](const auto& a, const auto& b) { return a.frameMs < b.frameMs; });
            return timed[timed.size() / 2];
        };
        const double frameMs = median(false).frameMs;
        stats = median(true);
        stats.frameMs = frameMs;
        stats.probes = firstProbes;
        stats.streaming = firstStreaming;
    }
    exporters::writePng(image, options.output);
    if (options.stats)
        std::fputs(runtime::frameStatsJson(stats, size, context->description(), renderer.loadSeconds(), renderer.overlookMs())
                       .c_str(),
                   stdout);
    else if (!common.quiet)
        std::printf("wrote %s: %dx%d, %.1f ms per frame (%zu draw calls, %zu triangles)\n", options.output.string().c_str(),
                    size.x, size.y, stats.frameMs, stats.drawCalls, stats.triangles);
    if (firstStreaming.on && !common.quiet && !options.stats)
        std::printf("  streamed %d of %d tiles and HLOD nodes (%.1f MB) before drawing: %.0f ms\n", firstStreaming.drawn,
                    firstStreaming.nodes, firstStreaming.residentMB, firstStreaming.waitMs);
    return 0;
}

struct ViewOptions {
    std::filesystem::path sceneFile;
    std::string camera;
    SceneOverrides overrides;
    int frames = 0;  // > 0: close after this many frames (smoke tests, timing the window path)
    runtime::RendererOptions renderer;
};

int runView(const ViewOptions& options, const CommonOptions& common) {
    runtime::SceneFile scene = runtime::loadSceneFile(options.sceneFile);
    options.overrides.apply(scene);
    const auto window =
        runtime::GlContext::window(options.renderer.size, "dawnforge view: " + options.sceneFile.string());
    runtime::RendererOptions ro = options.renderer;
    ro.size = window->framebufferSize();
    // The preset's probes per second, spread over frames at about 30 per second.
    if (const auto preset = runtime::probePreset(scene.probes.preset)) ro.probeBudget = int(std::ceil(preset->probesPerSecond / 30.0));
    runtime::Renderer renderer(scene, ro);
    runtime::FrameSettings frame;
    frame.camera = chooseCamera(scene, renderer, options.camera);
    frame.timeOfDay = scene.timeOfDay;
    double yaw = std::atan2(frame.camera.forward.x, -frame.camera.forward.z);
    double pitch = std::asin(std::clamp(glm::normalize(frame.camera.forward).y, -1.0, 1.0));
    const auto start = std::chrono::steady_clock::now();
    auto last = start, restartAt = start;
    int drawn = 0;
    glm::dvec3 velocity(0.0);
    for (;;) {
        const runtime::WindowInput in = window->poll();
        if (in.closeRequested || (options.frames > 0 && drawn >= options.frames)) break;
        const auto now = std::chrono::steady_clock::now();
        const double dt = std::chrono::duration<double>(now - last).count();
        last = now;
        if (in.cameraKey >= 0 && std::size_t(in.cameraKey) < scene.cameras.size()) {
            frame.camera = runtime::Renderer::cameraOf(scene.cameras[std::size_t(in.cameraKey)]);
            yaw = std::atan2(frame.camera.forward.x, -frame.camera.forward.z);
            pitch = std::asin(std::clamp(frame.camera.forward.y, -1.0, 1.0));
        }
        if (in.restart) restartAt = now;
        // Fly camera: drag to look, WASD/QE to move.
        yaw += in.mouseDelta.x * 0.004;
        pitch = std::clamp(pitch - in.mouseDelta.y * 0.004, -1.55, 1.55);
        const glm::dvec3 forward(std::cos(pitch) * std::sin(yaw), std::sin(pitch), -std::cos(pitch) * std::cos(yaw));
        const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0, 1, 0)));
        const double speed = (in.fast ? 60.0 : 15.0) * dt;
        frame.camera.forward = forward;
        const glm::dvec3 step = (right * in.move.x + glm::dvec3(0, 1, 0) * in.move.y + forward * in.move.z) * speed;
        frame.camera.position += step;
        // A world prefetches where the camera is heading (smoothed over about half a second).
        if (dt > 0.0) velocity = glm::mix(velocity, step / dt, std::min(1.0, 2.0 * dt));
        frame.cameraVelocity = velocity;
        frame.timeOfDay = std::fmod(frame.timeOfDay + in.timeOfDayDelta + 24.0, 24.0);
        frame.time = scene.time + std::chrono::duration<double>(now - restartAt).count();
        frame.adaptSeconds = drawn == 0 ? 0.0 : dt;  // the first frame's exposure converges
        const glm::ivec2 fb = window->framebufferSize();
        renderer.resize(fb);
        renderer.render(frame);
        renderer.present(fb);
        window->swapBuffers();
        ++drawn;
    }
    if (!common.quiet)
        std::printf("showed %d frames in %.1f s (%s)\n", drawn,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                    window->description().c_str());
    return 0;
}

}  // namespace

Command addRender(CLI::App& app, CommonOptions& common) {
    auto o = std::make_shared<RenderOptions>();
    CLI::App* cmd = app.add_subcommand(
        "render", "Render a scene file headless (EGL) to a PNG: the city, destruction VATs, the ocean, sky and sun");
    cmd->add_option("SCENE", o->sceneFile, "Scene file (scene.json)")->required();
    cmd->add_option("-o,--output", o->output, "PNG file to write")->required();
    addImageSizeOption(*cmd, o->renderer.size, "Image size WxH");
    cmd->add_option("--camera", o->camera, "Named camera of the scene (default: its first, or an overview)");
    cmd->add_option("--time-of-day", o->timeOfDay, "Hours, 0 to 24 (default: the scene's)");
    cmd->add_option("--frame", o->frame, "Frame number: scene time = frame / fps (default: the scene's time)")
        ->check(CLI::NonNegativeNumber);
    addSceneOverrides(*cmd, o->overrides);
    addStreamingOptions(*cmd, o->renderer.streaming);
    cmd->add_flag("--stats", o->stats, "Print per-pass GPU and CPU times as JSON on stdout");
    cmd->add_option("--repeat", o->repeat, "With --stats: timed frames after a warm-up (median reported)")
        ->check(CLI::Range(1, 1000))->capture_default_str();
    return {cmd, [o, &common] { return runRender(*o, common); }};
}

Command addView(CLI::App& app, CommonOptions& common) {
    auto o = std::make_shared<ViewOptions>();
    CLI::App* cmd = app.add_subcommand(
        "view", "Show a scene file in a window: drag to look, WASD/QE to fly (shift: faster), 1-9 cameras, "
                "[ ] time of day, R restart the destruction, Esc quit");
    cmd->add_option("SCENE", o->sceneFile, "Scene file (scene.json)")->required();
    addImageSizeOption(*cmd, o->renderer.size, "Window size WxH");
    cmd->add_option("--camera", o->camera, "Named camera to start from");
    addSceneOverrides(*cmd, o->overrides);
    addStreamingOptions(*cmd, o->renderer.streaming);
    cmd->add_option("--frames", o->frames, "Close after this many frames (0: when the window is closed)")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    return {cmd, [o, &common] { return runView(*o, common); }};
}

}  // namespace dawnforge::cli
