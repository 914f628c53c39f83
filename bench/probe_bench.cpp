// Irradiance probe throughput (issue 14) over a camera path through a baked scene:
//   ./run demo && build/bin/probe_bench out/demo/scene.json [CAMERA [PRESET [FACE_SIZE [MULTI_BOUNCE]]]]
// defaults: the camera "street", preset "mid", 64 px faces, multi-bounce on. The camera walks
// 60 m along its view (level), 1.5 m and 1° of turn per frame, at 1280 × 720; every frame
// captures all the new probes its lighting area wants (no budget). Prints the probes
// captured, the capture time (finished with glFinish) and probes per second, with the
// frame's pass times of the last frame.
#include <dawnforge/runtime/context.hpp>
#include <dawnforge/runtime/renderer.hpp>
#include <dawnforge/runtime/scene_file.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

using namespace dawnforge::runtime;

int main(int argc, char** argv) try {
    if (argc < 2) {
        std::fprintf(stderr, "usage: probe_bench SCENE.json [CAMERA [PRESET [FACE_SIZE [MULTI_BOUNCE 0|1]]]]\n");
        return 2;
    }
    SceneFile scene = loadSceneFile(argv[1]);
    const std::string camera = argc > 2 ? argv[2] : "street";
    scene.probes.preset = argc > 3 ? argv[3] : "mid";
    scene.probes.faceSize = argc > 4 ? std::atoi(argv[4]) : 64;
    scene.probes.multiBounce = argc > 5 ? std::atoi(argv[5]) != 0 : true;
    const SceneCamera* start = findCamera(scene, camera);
    if (!start) {
        std::fprintf(stderr, "probe_bench: no camera \"%s\" in %s\n", camera.c_str(), argv[1]);
        return 2;
    }
    const auto context = GlContext::headless();
    Renderer renderer(scene, RendererOptions{});
    renderer.setSynchronisedPasses(true);  // the shadow pass is finished before the capture's clock starts
    FrameSettings frame;
    frame.camera = Renderer::cameraOf(*start);
    frame.timeOfDay = scene.timeOfDay;
    double yaw = std::atan2(frame.camera.forward.x, -frame.camera.forward.z);
    int captured = 0;
    double captureMs = 0.0;
    FrameStats stats;
    for (int i = 0; i < 40; ++i) {
        stats = renderer.render(frame);
        captured += stats.probes.captured;
        captureMs += stats.probes.captureMs;
        yaw += 0.0174533;
        frame.camera.forward = {std::sin(yaw), frame.camera.forward.y, -std::cos(yaw)};
        frame.camera.position += 1.5 * glm::normalize(glm::dvec3(frame.camera.forward.x, 0.0, frame.camera.forward.z));
    }
    std::printf("{\"device\": \"%s\", \"preset\": \"%s\", \"face_size\": %d, \"multi_bounce\": %s, \"frames\": 40, "
                "\"captured\": %d, \"capture_ms\": %.1f, \"probes_per_second\": %.1f, \"held\": %d}\n",
                context->description().c_str(), scene.probes.preset.c_str(), scene.probes.faceSize,
                scene.probes.multiBounce ? "true" : "false", captured, captureMs,
                captureMs > 0.0 ? 1000.0 * captured / captureMs : 0.0, stats.probes.held);
    for (const PassTime& p : stats.passes) std::printf("  %-12s cpu %.1f ms\n", p.name.c_str(), p.cpuMs);
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "probe_bench: %s\n", e.what());
    return 2;
}
