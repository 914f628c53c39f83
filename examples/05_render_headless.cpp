// Example 5: draw a city with the runtime, headless, into a PNG: no window, no display.
//
//   build/bin/example_05_render_headless CITY_DIR OUT.png [HOURS]
//
// CITY_DIR holds a city.glb, as `dawnforge city` or example_04_generate_city writes it;
// HOURS is the time of day (default 17.5, a low sun). `dawnforge render` does the same from
// a scene.json.
//
// The runtime needs an OpenGL 4.5 core context. GlContext::headless() makes one through EGL
// without any window: on Mesa's software rasteriser (llvmpipe) when there is no GPU, which
// is how the tests render, or on an NVIDIA GPU (DAWNFORGE_EGL_DEVICE=0).
#include <dawnforge/core/error.hpp>
#include <dawnforge/exporters/image.hpp>
#include <dawnforge/runtime/context.hpp>
#include <dawnforge/runtime/renderer.hpp>
#include <dawnforge/runtime/scene_file.hpp>

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

int main(int argc, char** argv) {
    if (argc != 3 && argc != 4) {
        std::fprintf(stderr, "usage: %s CITY_DIR OUT.png [HOURS]\n", argv[0]);
        return 2;
    }
    using namespace dawnforge;

    // What to draw, built in code: the struct a scene.json is read into
    // (runtime::loadSceneFile(path) gives the same from a file). Here: the city and the sea.
    runtime::SceneFile scene;
    scene.cityDir = argv[1];
    scene.ocean = runtime::OceanSettings{};  // default sea level and projected grid
    scene.timeOfDay = argc == 4 ? std::strtod(argv[3], nullptr) : 17.5;

    try {
        // The context first: the renderer uploads meshes and compiles shaders as it loads.
        // Throws std::runtime_error with the reason when no context can be made.
        const auto context = runtime::GlContext::headless();

        // Loads the city (both LODs, the atlas, the interiors) and the ocean onto the GPU.
        // Throws InputError when city.glb is missing or is not a city.
        runtime::RendererOptions options;
        options.size = {640, 360};
        runtime::Renderer renderer(scene, options);

        // One frame: a camera that frames the whole city, at the scene's time of day.
        runtime::FrameSettings frame;
        frame.camera = renderer.overviewCamera();
        frame.timeOfDay = scene.timeOfDay;
        const runtime::FrameStats stats = renderer.render(frame);

        // The pixels back on the CPU (row 0 at the top), then a PNG written atomically.
        const exporters::Image image = renderer.readPixels();
        exporters::writePng(image, argv[2]);
        std::printf("wrote %s: %dx%d on %s, %zu draw calls, %zu triangles\n", argv[2], image.width, image.height,
                    context->description().c_str(), stats.drawCalls, stats.triangles);
    } catch (const InputError& e) {  // bad input: the city folder, the output name
        std::fprintf(stderr, "%s\n", e.what());
        return 2;
    } catch (const std::runtime_error& e) {  // no OpenGL 4.5 context on this machine
        std::fprintf(stderr, "no headless OpenGL context: %s\n", e.what());
        return 1;
    }
    return 0;
}
