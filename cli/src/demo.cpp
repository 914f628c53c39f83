// dawnforge demo: the whole pipeline on built-in defaults (district, its bake, the tower's
// destruction, the scene and a picture), each stage written with the same writers as its own command.
#include "commands.hpp"
#include "folders.hpp"
#include "report.hpp"

#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/read_file.hpp>
#include <dawnforge/exporters/image.hpp>
#include <dawnforge/exporters/vat.hpp>
#include <dawnforge/runtime/context.hpp>
#include <dawnforge/runtime/renderer.hpp>
#include <dawnforge/runtime/sky.hpp>
#include <dawnforge/runtime/scene_file.hpp>
#include <dawnforge/procgen/city_building.hpp>
#include <dawnforge/procgen/plan.hpp>
#include <dawnforge/sim/fracture.hpp>
#include <dawnforge/sim/fracture_parts.hpp>
#include <dawnforge/sim/rigidbody.hpp>

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>
#include <type_traits>

namespace dawnforge::cli {

namespace {

struct DemoOptions {
    std::filesystem::path outputDir;
    std::optional<int> building;  // the building to knock down; default the tallest near the water
    bake::BakeSettings bake;      // the district's baked lighting
};

constexpr double kStartTime = 1.0;  // scene time at which the building's destruction takes over
constexpr double kSunsetHours = 17.7; // the sunset picture: the sun low in the west, above the horizon

// A small coastal district on the default recipe: a third of it sea.
procgen::CityPlan demoCity(const DemoOptions& options, const CommonOptions& common) {
    procgen::CitySettings city;
    city.size = {320.0, 280.0};
    city.tileSize = 160.0;
    city.recipe.coast.water = 0.3;
    return writeCityFolder(city, options.outputDir / "city", common);
}

// The building on the quay: of the buildings of at least four storeys (three if none has
// four), the one whose footprint's centre is nearest the coastline.
int quayBuilding(const std::filesystem::path& cityDir, const procgen::CityPlan& plan) {
    const nlohmann::json city = nlohmann::json::parse(readTextFile(cityDir / "city.json"));
    int best = -1;
    double bestScore = std::numeric_limits<double>::max();
    for (const nlohmann::json& b : city["buildings"]) {
        glm::dvec2 centre(0.0);
        for (const nlohmann::json& p : b["footprint"]) centre += glm::dvec2(p[0].get<double>(), p[1].get<double>());
        centre /= double(b["footprint"].size());
        const int floors = b["floors"].get<int>();
        const double score = std::abs(centre.y - procgen::coastY(plan, centre.x)) + (floors >= 4 ? 0.0 : floors >= 3 ? 1e4 : 1e6);
        if (score < bestScore) bestScore = score, best = b["id"].get<int>();
    }
    if (best < 0) throw InputError("demo: the district has no building to knock down");
    return best;
}

// Where the ball hits: mid-height on the building's side facing the sea (+z, plan south).
glm::dvec3 impactPoint(const procgen::CityBuilding& building) {
    const Bounds& b = building.bounds;
    return {0.5 * (b.min.x + b.max.x), b.min.y + 0.45 * (b.max.y - b.min.y), b.max.z};
}

// The building, part by part by material, smaller pieces around the impact.
sim::FractureResult fractureBuilding(const DemoOptions& options, const procgen::CityBuilding& building) {
    std::vector<sim::FracturePart> parts;
    for (const procgen::CityBuildingPart& part : building.parts)
        parts.push_back({procgen::partKindName(part.kind), part.material, part.mesh});
    sim::PartsFractureSettings fracture;
    fracture.common.pieces = 120;
    fracture.shardSize = 0.8;  // about three shards a pane: the whole district is seen
    fracture.common.impact = impactPoint(building);
    fracture.common.impactRadius = 5.0;
    const sim::FractureResult pieces = sim::fractureParts(parts, fracture);
    const std::filesystem::path cityDir = options.outputDir / "city";
    writeFractureFolder(pieces, fracture.common, cityDir.string(), options.outputDir / "fracture", building.id);
    std::printf("wrote %s: %s in %zu pieces with %zu bonds\n",
                (options.outputDir / "fracture" / "fragments.glb").string().c_str(), building.name.c_str(),
                pieces.pieces.size(), pieces.bonds.size());
    return pieces;
}

// Knock it down: a 20 t ball at 40 m/s from the sea into its wall, 0.2 s in; 8 s at 30 fps,
// among its neighbours and on the city's ground.
sim::SimulationResult simulateBuilding(const DemoOptions& options, const procgen::CityBuilding& building,
                                       const sim::FractureResult& pieces, std::span<const sim::RigidPiece> rigid,
                                       const CommonOptions& common) {
    sim::SimulationSettings sim;
    sim.frames = 240;
    placeInCity(building, sim);
    sim::Projectile ball;
    ball.target = impactPoint(building);
    ball.direction = glm::dvec3(0.0, 0.0, -1.0);
    ball.radius = 1.5;
    sim.projectile = ball;
    sim.debris.chips = true;
    sim.debris.dust = true;
    sim::SimulationResult motion;
    {
        StderrProgress progress = progressFor("simulate", common);
        motion = sim::simulate(rigid, pieces.bonds, sim, progress.callback());
    }
    writeSimulationFolder(motion, sim, rigid, options.outputDir / "fracture", options.outputDir / "sim");
    std::printf("wrote %s: %d frames, %zu of %zu bonds broke, %zu chips and %zu puffs of dust\n",
                (options.outputDir / "sim" / "sim.json").string().c_str(), motion.frames, motion.brokenBonds, motion.bonds,
                motion.chips.size(), motion.dustPuffs);
    return motion;
}

// Bake it for our runtime and for the Labs shaders in Unreal and Unity.
void bakeVats(const DemoOptions& options, std::span<const sim::RigidPiece> rigid, const sim::SimulationResult& motion) {
    std::vector<Mesh> meshes;
    for (const sim::RigidPiece& p : rigid) meshes.push_back(p.mesh);
    for (const sim::RigidPiece& p : motion.chips) meshes.push_back(p.mesh);
    const exporters::VatAnimation animation{meshes, motion.transforms, motion.frames, motion.fps, motion.turns, motion.dust,
                                            motion.dustPuffs};
    for (exporters::VatPreset preset :
         {exporters::VatPreset::Native, exporters::VatPreset::Unreal, exporters::VatPreset::Unity}) {
        exporters::VatSettings vat;
        vat.preset = preset;
        vat.name = "building_" + std::string(exporters::vatPresetName(preset));
        exporters::writeVat(exporters::encodeVat(animation, vat), vat, options.outputDir / "vat");
    }
    std::printf("wrote %s: building_{native,unreal,unity}_{pos.exr,rot.exr,mesh.glb,data.json}\n",
                (options.outputDir / "vat").string().c_str());
}

// The district with the building replaced by its destruction from kStartTime on (the VAT is
// in world space: no offset), the sea, cameras, at half past five in the afternoon, 2.2 s
// after the swap: the building is coming down.
runtime::SceneFile demoScene(const std::filesystem::path& dir, const procgen::CityBuilding& building) {
    runtime::SceneFile scene;
    scene.cityDir = dir / "city";
    scene.timeOfDay = 17.5;
    scene.time = kStartTime + 2.2;
    scene.fps = 30.0;
    scene.ocean = runtime::OceanSettings{};
    runtime::DestructionInstance destruction;
    destruction.vatDir = dir / "vat";
    destruction.name = "building_native";
    destruction.startTime = kStartTime;
    destruction.replaces = building.id;
    scene.destruction.push_back(destruction);
    const glm::dvec3 c = 0.5 * (building.bounds.min + building.bounds.max);
    const double x = c.x, z = building.bounds.max.z;
    scene.cameras.push_back({"harbour", glm::dvec3(x + 45.0, 20.0, z + 60.0), glm::dvec3(x - 5.0, 8.0, c.z), 55.0});
    scene.cameras.push_back({"overview", glm::dvec3(x + 200.0, 190.0, z + 160.0), glm::dvec3(x, 0.0, z - 90.0), 50.0});
    scene.cameras.push_back({"street", glm::dvec3(x - 40.0, 2.0, z + 6.0), glm::dvec3(x, 10.0, c.z), 65.0});
    // Along the promenade towards the building, past its street lamps (the night picture).
    scene.cameras.push_back({"promenade", glm::dvec3(x - 70.0, 3.5, z + 12.0), glm::dvec3(x + 10.0, 5.0, z + 4.0), 60.0});
    // From the harbour towards the setting sun, which stands a third of the way up the picture.
    const glm::dvec3 sun = runtime::lightingAt(kSunsetHours).sunDirection;
    const glm::dvec3 level = glm::normalize(glm::dvec3(sun.x, 0.0, sun.z));
    const glm::dvec3 eye(x + 30.0, 5.0, z + 45.0);
    const glm::dvec3 look = glm::normalize(level + glm::dvec3(0.0, std::tan(std::asin(sun.y)) - 0.12, 0.0));
    scene.cameras.push_back({"sunset", eye, eye + 100.0 * look, 60.0});
    return scene;
}

// Writes scene.json and three pictures of it: render.png from its first camera at the scene's
// time of day, render_night.png along the promenade at 22:00 (lit windows, street lamps,
// their light on the ground and their flares) and render_sunset.png from the harbour into the setting sun (its flare).
void renderDemo(const DemoOptions& options, const procgen::CityBuilding& building) {
    const auto sceneFile = options.outputDir / "scene.json";
    writeFileAtomically(sceneFile, runtime::sceneFileJson(demoScene(options.outputDir, building), options.outputDir));
    std::printf("wrote %s\n", sceneFile.string().c_str());
    const runtime::SceneFile view = runtime::loadSceneFile(sceneFile);
    const auto context = runtime::GlContext::headless();
    runtime::Renderer renderer(view, runtime::RendererOptions{});
    const struct {
        const char* file;
        const char* camera;
        double hours;
    } pictures[] = {{"render.png", view.cameras.front().name.c_str(), view.timeOfDay},
                    {"render_night.png", "promenade", 22.0},
                    {"render_sunset.png", "sunset", kSunsetHours}};
    for (const auto& p : pictures) {
        runtime::FrameSettings frame;
        frame.camera = runtime::Renderer::cameraOf(*runtime::findCamera(view, p.camera));
        frame.time = view.time;
        frame.timeOfDay = p.hours;
        runtime::FrameStats stats = renderer.render(frame);
        const exporters::Image image = renderer.readPixels(&stats);
        const auto picture = options.outputDir / p.file;
        exporters::writePng(image, picture);
        std::printf("wrote %s: %dx%d from \"%s\" at %.1f h, %.2f s into the scene (%s); %.0f ms\n", picture.string().c_str(),
                    image.width, image.height, p.camera, frame.timeOfDay, frame.time, context->description().c_str(),
                    stats.frameMs);
    }
    std::printf("next: dawnforge render %s -o frame.png --stats, or dawnforge view %s\n", sceneFile.string().c_str(),
                sceneFile.string().c_str());
}

// Runs one stage and records it, with its wall time, for the report.
template <typename Stage>
auto timed(std::vector<ReportStage>& stages, ReportStage stage, Stage&& run) {
    const auto start = std::chrono::steady_clock::now();
    const auto record = [&] {
        stage.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        stages.push_back(std::move(stage));
    };
    if constexpr (std::is_void_v<decltype(run())>) {
        run();
        record();
    } else {
        auto result = run();
        record();
        return result;
    }
}

// DIR/report.html: the pictures, the stages, the bake of the knocked-down building, its
// simulation and its pieces.
void writeDemoReport(const DemoOptions& options, int building, std::vector<ReportStage> stages) {
    const std::filesystem::path& dir = options.outputDir;
    ReportInputs report;
    report.title = "dawnforge demo: " + dir.filename().string();
    report.pictures = {{"the harbour at 17:30, the building coming down", dir / "render.png"},
                       {"the promenade at 22:00", dir / "render_night.png"},
                       {"into the sun at 17:42", dir / "render_sunset.png"}};
    report.stages = std::move(stages);
    report.bakeDir = dir / "city" / "bake";
    report.bakeBuilding = building;
    report.fractureDir = dir / "fracture";
    report.simDir = dir / "sim";
    std::printf("wrote %s\n", writeReport(report, dir).string().c_str());
}

int runDemo(const DemoOptions& options, const CommonOptions& common) {
    ensureOutputDirectory(options.outputDir);
    const std::filesystem::path cityDir = options.outputDir / "city";
    std::vector<ReportStage> stages;
    const procgen::CityPlan plan = timed(stages, {"city", "a 320 × 280 m district", {"city/city.glb", "city/city.json", "city/trees"}},
                                         [&] { return demoCity(options, common); });
    timed(stages, {"bake", "the district's lighting: a lightmap per building and ground tile", {"city/bake"}},
          [&] { bakeCityFolder(cityDir, options.bake, common); });
    const int id = options.building ? *options.building : quayBuilding(cityDir, plan);
    const procgen::CityBuilding building = procgen::loadCityBuilding(cityDir, id);
    const sim::FractureResult pieces = timed(stages, {"fracture", "", {"fracture"}}, [&] { return fractureBuilding(options, building); });
    stages.back().made = format("{} in {} pieces with {} bonds", building.name, pieces.pieces.size(), pieces.bonds.size());
    const std::vector<sim::RigidPiece> rigid = sim::rigidPieces(pieces);
    const sim::SimulationResult motion =
        timed(stages, {"simulate", "", {"sim"}}, [&] { return simulateBuilding(options, building, pieces, rigid, common); });
    stages.back().made = format("{} frames at {} fps; {} of {} bonds broke; {} chips and {} puffs of dust", motion.frames,
                                motion.fps, motion.brokenBonds, motion.bonds, motion.chips.size(), motion.dustPuffs);
    timed(stages, {"vat", "VATs of the destruction in three presets: native, unreal, unity", {"vat"}},
          [&] { bakeVats(options, rigid, motion); });
    timed(stages, {"render", "scene.json and three 1280 × 720 pictures", {"scene.json", "render.png", "render_night.png", "render_sunset.png"}},
          [&] { renderDemo(options, building); });
    writeDemoReport(options, id, std::move(stages));
    return 0;
}

}  // namespace

Command addDemo(CLI::App& app, CommonOptions& common) {
    auto o = std::make_shared<DemoOptions>();
    CLI::App* cmd = app.add_subcommand("demo", "Run the whole pipeline on built-in defaults");
    cmd->add_option("-o,--output", o->outputDir, "Output folder")->required();
    cmd->add_option("--building", o->building,
                    "The building of the district to knock down (its id); default the tallest one nearest the water")
        ->check(CLI::NonNegativeNumber);
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
