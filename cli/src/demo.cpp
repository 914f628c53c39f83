// dawnforge demo: the whole pipeline on built-in defaults (district, its bake, the tower's
// destruction, the scene and a picture), each stage written with the same writers as its own command.
#include "commands.hpp"
#include "folders.hpp"

#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/exporters/image.hpp>
#include <dawnforge/exporters/vat.hpp>
#include <dawnforge/runtime/context.hpp>
#include <dawnforge/runtime/renderer.hpp>
#include <dawnforge/runtime/scene_file.hpp>
#include <dawnforge/sim/fracture.hpp>
#include <dawnforge/sim/rigidbody.hpp>

#include <cstdio>
#include <memory>

namespace dawnforge::cli {

namespace {

struct DemoOptions {
    std::filesystem::path outputDir;
    int floors = 8;
    bake::BakeSettings bake;  // the district's baked lighting
};

constexpr double kStorey = 3.2;  // storey height of the tower (m)

// A small coastal district on the default recipe: a third of it sea.
procgen::CityPlan demoCity(const DemoOptions& options, const CommonOptions& common) {
    procgen::CitySettings city;
    city.size = {320.0, 280.0};
    city.tileSize = 160.0;
    city.recipe.coast.water = 0.3;
    return writeCityFolder(city, options.outputDir / "city", common);
}

// The tower in 40 Voronoi pieces, smaller near a corner at mid-height.
sim::FractureResult fractureTower(const DemoOptions& options) {
    sim::FractureSettings fracture;
    fracture.pieces = 40;
    fracture.impact = glm::dvec3(6.0, 0.5 * kStorey * options.floors, 5.0);
    fracture.impactRadius = 6.0;
    fracture.density = 300.0;  // a building is mostly air: about 300 kg/m^3 on average
    const sim::FractureResult pieces = sim::fractureMesh(makeTower(options.floors, float(kStorey), 12.0f, 10.0f), fracture);
    writeFractureFolder(pieces, fracture, "built-in tower", options.outputDir / "fracture");
    std::printf("wrote %s: the tower in %zu pieces with %zu bonds\n",
                (options.outputDir / "fracture" / "fragments.glb").string().c_str(), pieces.pieces.size(),
                pieces.bonds.size());
    return pieces;
}

// Knock it down: a 20 t ball at 40 m/s into the +x wall at mid-height, 0.2 s in; 8 s at 30 fps.
sim::SimulationResult simulateTower(const DemoOptions& options, const sim::FractureResult& pieces,
                                    std::span<const sim::RigidPiece> rigid, const CommonOptions& common) {
    sim::SimulationSettings sim;
    sim.frames = 240;
    sim.strength = 3e5;  // weak masonry: it stands on its own (tested) and falls when hit
    sim::Projectile ball;
    ball.target = glm::dvec3(6.0, 0.5 * kStorey * options.floors, 2.0);
    ball.radius = 1.5;
    sim.projectile = ball;
    sim::SimulationResult motion;
    {
        StderrProgress progress = progressFor("simulate", common);
        motion = sim::simulate(rigid, pieces.bonds, sim, progress.callback());
    }
    writeSimulationFolder(motion, sim, rigid, options.outputDir / "fracture", options.outputDir / "sim");
    std::printf("wrote %s: %d frames, %zu of %zu bonds broke\n", (options.outputDir / "sim" / "sim.json").string().c_str(),
                motion.frames, motion.brokenBonds, motion.bonds);
    return motion;
}

// Bake it for our runtime and for the Labs shaders in Unreal and Unity.
void bakeTowerVats(const DemoOptions& options, std::span<const sim::RigidPiece> rigid,
                   const sim::SimulationResult& motion) {
    std::vector<Mesh> meshes;
    for (const sim::RigidPiece& p : rigid) meshes.push_back(p.mesh);
    const exporters::VatAnimation animation{meshes, motion.transforms, motion.frames, motion.fps, motion.turns};
    for (exporters::VatPreset preset :
         {exporters::VatPreset::Native, exporters::VatPreset::Unreal, exporters::VatPreset::Unity}) {
        exporters::VatSettings vat;
        vat.preset = preset;
        vat.name = "tower_" + std::string(exporters::vatPresetName(preset));
        exporters::writeVat(exporters::encodeVat(animation, vat), vat, options.outputDir / "vat");
    }
    std::printf("wrote %s: tower_{native,unreal,unity}_{pos.exr,rot.exr,mesh.glb,data.json}\n",
                (options.outputDir / "vat").string().c_str());
}

// The district, the tower standing on the middle of the quay (the 15 m strip between the
// coastline and the water) at x = 160 m and breaking, the sea, cameras, at half past five
// in the afternoon.
runtime::SceneFile demoScene(const std::filesystem::path& dir, const procgen::CityPlan& plan) {
    runtime::SceneFile scene;
    scene.cityDir = dir / "city";
    scene.timeOfDay = 17.5;
    scene.time = 2.4;  // the ball hits at 0.2 s: the tower is coming down
    scene.fps = 30.0;
    scene.ocean = runtime::OceanSettings{};
    const double x = 160.0, z = -(procgen::coastY(plan, x) - 7.5);  // plan y north → glTF z = −y
    scene.destruction.push_back({dir / "vat", "tower_native", glm::dvec3(x, 0.0, z), 0.0, 0.0});
    scene.cameras.push_back({"harbour", glm::dvec3(x + 75.0, 22.0, z + 70.0), glm::dvec3(x - 10.0, 12.0, z - 25.0), 55.0});
    scene.cameras.push_back({"overview", glm::dvec3(x + 200.0, 190.0, z + 160.0), glm::dvec3(x, 0.0, z - 90.0), 50.0});
    scene.cameras.push_back({"street", glm::dvec3(x - 40.0, 2.0, z + 2.0), glm::dvec3(x, 12.0, z), 65.0});
    return scene;
}

// Writes scene.json and a picture of it from its first camera.
void renderDemo(const DemoOptions& options, const procgen::CityPlan& plan) {
    const auto sceneFile = options.outputDir / "scene.json";
    writeFileAtomically(sceneFile, runtime::sceneFileJson(demoScene(options.outputDir, plan), options.outputDir));
    std::printf("wrote %s\n", sceneFile.string().c_str());
    const runtime::SceneFile view = runtime::loadSceneFile(sceneFile);
    const auto context = runtime::GlContext::headless();
    runtime::Renderer renderer(view, runtime::RendererOptions{});
    runtime::FrameSettings frame;
    frame.camera = runtime::Renderer::cameraOf(view.cameras.front());
    frame.time = view.time;
    frame.timeOfDay = view.timeOfDay;
    runtime::FrameStats stats = renderer.render(frame);
    const exporters::Image image = renderer.readPixels(&stats);
    const auto picture = options.outputDir / "render.png";
    exporters::writePng(image, picture);
    std::printf("wrote %s: %dx%d at %.1f h, %.2f s into the scene (%s); %.0f ms for the first frame\n",
                picture.string().c_str(), image.width, image.height, frame.timeOfDay, frame.time,
                context->description().c_str(), stats.frameMs);
    std::printf("next: dawnforge render %s -o frame.png --stats, or dawnforge view %s\n", sceneFile.string().c_str(),
                sceneFile.string().c_str());
}

int runDemo(const DemoOptions& options, const CommonOptions& common) {
    ensureOutputDirectory(options.outputDir);
    const procgen::CityPlan plan = demoCity(options, common);
    bakeCityFolder(options.outputDir / "city", options.bake, common);
    const sim::FractureResult pieces = fractureTower(options);
    const std::vector<sim::RigidPiece> rigid = sim::rigidPieces(pieces);
    const sim::SimulationResult motion = simulateTower(options, pieces, rigid, common);
    bakeTowerVats(options, rigid, motion);
    renderDemo(options, plan);
    return 0;
}

}  // namespace

Command addDemo(CLI::App& app, CommonOptions& common) {
    auto o = std::make_shared<DemoOptions>();
    CLI::App* cmd = app.add_subcommand("demo", "Run the whole pipeline on built-in defaults");
    cmd->add_option("-o,--output", o->outputDir, "Output folder")->required();
    cmd->add_option("--floors", o->floors, "Floors of the demo tower")->check(CLI::Range(1, 200))->capture_default_str();
    cmd->add_option("--bake-texel", o->bake.texel, "Lightmap texel of the district's bake (m; see dawnforge bake --texel)")
        ->check(CLI::Range(0.01, 10.0))->capture_default_str();
    cmd->add_option("--bake-interior-texel", o->bake.interiorTexel, "Lightmap texel in rooms (m)")
        ->check(CLI::Range(0.01, 10.0))->capture_default_str();
    cmd->add_option("--bake-samples", o->bake.samples, "Hemisphere rays per texel per pass of the bake")
        ->check(CLI::Range(1, 65536))->capture_default_str();
    cmd->add_option("--bake-bounces", o->bake.bounces, "Bounces of the bake")->check(CLI::Range(0, 16))->capture_default_str();
    addThreadsOption(*cmd, common);
    return {cmd, [o, &common] { return runDemo(*o, common); }};
}

}  // namespace dawnforge::cli
