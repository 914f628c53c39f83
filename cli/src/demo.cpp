#include "commands.hpp"

#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/core/validate.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/sim/fracture.hpp>
#include <dawnforge/sim/fracture_io.hpp>
#include <dawnforge/sim/rigidbody.hpp>
#include <dawnforge/sim/rigidbody_io.hpp>
#include <dawnforge/exporters/vat.hpp>
#include <dawnforge/core/progress.hpp>
#include <dawnforge/exporters/image.hpp>
#include <dawnforge/runtime/context.hpp>
#include <dawnforge/runtime/renderer.hpp>
#include <dawnforge/runtime/scene_file.hpp>

#include <cstdio>
#include <dawnforge/core/format.hpp>

namespace dawnforge::cli {


namespace {

// The district, the tower standing on the middle of the quay (the 15 m strip between the
// coastline and the water) at x = 160 m and breaking, the sea, cameras.
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

}  // namespace

int runDemo(const DemoOptions& options, const CommonOptions& common) {
    ensureOutputDirectory(options.outputDir);

    // A small coastal district on the default recipe: a third of it sea.
    procgen::CitySettings city;
    city.size = {320.0, 280.0};
    city.tileSize = 160.0;
    city.recipe.coast.water = 0.3;
    const procgen::CityPlan plan = writeCityFolder(city, options.outputDir / "city", common);

    Scene scene;
    Mesh ground = makeBox({-40, -0.5f, -40}, {40, 0, 40}, 1);
    ground.name = "ground";
    scene.addMeshNode(std::move(ground));
    scene.addMeshNode(makeTower(options.floors, 3.2f, 12.0f, 10.0f), {0, 0, 0});
    Mesh sphere = makeIcosphere(4.0f, 3);
    sphere.materialIds.assign(sphere.vertexCount(), 4);
    scene.addMeshNode(std::move(sphere), {20, 4, 10});
    scene.extrasJson = format(R"({{"generator":"dawnforge demo","floors":{}}})", options.floors);

    const auto file = options.outputDir / "scene.glb";
    exporters::writeGlb(scene, file);

    std::size_t triangles = 0;
    for (const Mesh& m : scene.meshes) triangles += m.triangleCount();
    std::printf("wrote %s: %zu meshes, %zu triangles\n", file.string().c_str(), scene.meshes.size(), triangles);
    for (const Mesh& m : scene.meshes) {
        const MeshReport r = inspectMesh(m);
        std::printf("  %-8s %6zu triangles, closed %s, manifold %s, volume %.3f m^3\n", m.name.c_str(), r.triangles,
                    r.closed ? "yes" : "no", r.manifold ? "yes" : "no", r.volume.value_or(0.0));
    }

    // Break the tower: 40 Voronoi pieces, smaller near a corner at mid-height.
    sim::FractureSettings fracture;
    fracture.pieces = 40;
    fracture.impact = glm::dvec3(6.0, 0.5 * 3.2 * options.floors, 5.0);
    fracture.impactRadius = 6.0;
    fracture.density = 300.0;  // a building is mostly air: about 300 kg/m^3 on average
    const sim::FractureResult pieces = sim::fractureMesh(scene.meshes[1], fracture);
    const auto fractureDir = options.outputDir / "fracture";
    ensureOutputDirectory(fractureDir);
    const std::vector<std::byte> fragments = exporters::encodeGlb(sim::fractureScene(pieces));  // also copied into sim/
    writeFileAtomically(fractureDir / "fragments.glb", fragments);
    writeFileAtomically(fractureDir / "fracture.json", sim::fractureJson(pieces, fracture, "built-in tower"));
    std::printf("wrote %s: the tower in %zu pieces with %zu bonds\n", (fractureDir / "fragments.glb").string().c_str(),
                pieces.pieces.size(), pieces.bonds.size());

    // Knock it down: a 20 t ball at 40 m/s into the +x wall at mid-height, 0.2 s in; 8 s at 30 fps.
    const std::vector<sim::RigidPiece> rigid = sim::rigidPieces(pieces);
    sim::SimulationSettings sim;
    sim.frames = 240;
    sim.strength = 3e5;  // weak masonry: it stands on its own (tested) and falls when hit
    sim::Projectile ball;
    ball.target = glm::dvec3(6.0, 0.5 * 3.2 * options.floors, 2.0);
    ball.radius = 1.5;
    sim.projectile = ball;
    sim::SimulationResult motion;
    {
        StderrProgress progress("simulate", !common.quiet && stderrIsTerminal());
        motion = sim::simulate(rigid, pieces.bonds, sim, progress.callback());
    }
    const auto simDir = options.outputDir / "sim";
    sim::writeSimulation(simDir, motion, sim, rigid, fractureDir.string());
    writeFileAtomically(simDir / "fragments.glb", fragments);
    std::printf("wrote %s: %d frames, %zu of %zu bonds broke\n", (simDir / "sim.json").string().c_str(), motion.frames,
                motion.brokenBonds, motion.bonds);

    // Bake it for our runtime and for the Labs shaders in Unreal and Unity.
    std::vector<Mesh> meshes;
    for (const sim::RigidPiece& p : rigid) meshes.push_back(p.mesh);
    exporters::VatAnimation animation{meshes, motion.transforms, motion.frames, motion.fps, motion.turns};
    for (exporters::VatPreset preset : {exporters::VatPreset::Native, exporters::VatPreset::Unreal, exporters::VatPreset::Unity}) {
        exporters::VatSettings vat;
        vat.preset = preset;
        vat.name = "tower_" + std::string(exporters::vatPresetName(preset));
        exporters::writeVat(exporters::encodeVat(animation, vat), vat, options.outputDir / "vat");
    }
    std::printf("wrote %s: tower_{native,unreal,unity}_{pos.exr,rot.exr,mesh.glb,data.json}\n",
                (options.outputDir / "vat").string().c_str());

    // The scene: the district, the tower standing on the quay and breaking, the sea, at
    // half past five in the afternoon; then a picture of it.
    const auto sceneFile = options.outputDir / "scene.json";
    writeFileAtomically(sceneFile, runtime::sceneFileJson(demoScene(options.outputDir, plan), options.outputDir));
    std::printf("wrote %s\n", sceneFile.string().c_str());
    const runtime::SceneFile view = runtime::loadSceneFile(sceneFile);
    const auto context = runtime::GlContext::headless();
    runtime::RendererOptions ro;
    runtime::Renderer renderer(view, ro);
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
    std::printf("not built yet: bake\n");
    return 0;
}

}  // namespace dawnforge::cli
