// dawnforge: the command line. Argument parsing (CLI11) and error reporting only:
// bad input -> one line on stderr, exit 2; an internal failure -> exit 1.
#include "commands.hpp"

#include <dawnforge/core/error.hpp>

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>

#include <cstdio>
#include <optional>
#include <string>
#include <vector>

namespace {

struct PlannedCommand {
    const char* name;
    const char* summary;
};

// Commands of ARCHITECTURE.md that later work builds; they are listed so --help shows
// the whole tool, and they say plainly that they are not built yet.
constexpr PlannedCommand kPlanned[] = {
    {"bake", "Bake lightmaps and overlook depth next to a city (not built yet)"},
};

}  // namespace

int main(int argc, char** argv) {
    using namespace dawnforge;
    CLI::App app{"dawnforge: city generation, Voronoi fracture, rigid-body destruction baked into VATs, "
                 "and a mobile-style renderer.",
                 "dawnforge"};
    app.require_subcommand(1);
    app.set_version_flag("--version", std::string(DAWNFORGE_VERSION));
    cli::CommonOptions common;
    app.add_flag("-q,--quiet", common.quiet, "No progress on stderr");
    int threads = 0;

    cli::InspectOptions inspect;
    CLI::App* inspectCmd = app.add_subcommand(
        "inspect", "Report on a mesh (OBJ, glTF, GLB) as JSON on stdout: triangles, vertices, closed, manifold, "
                   "self_intersecting, volume, bbox_min, bbox_max, ...");
    inspectCmd->add_option("FILE", inspect.file, "Mesh file (.obj, .gltf, .glb)")->required();
    inspectCmd->add_option("--repair", inspect.repairOutput,
                           "Also write a repaired copy (GLB): duplicate points merged, degenerate triangles "
                           "removed, orientation made consistent, borders stitched, holes filled");

    cli::FractureOptions fracture;
    CLI::App* fractureCmd = app.add_subcommand(
        "fracture", "Fracture a closed mesh into Voronoi pieces: DIR/fragments.glb, DIR/fracture.json");
    fractureCmd->add_option("FILE", fracture.file, "Closed mesh (.obj, .gltf, .glb)")->required();
    fractureCmd->add_option("-o,--output", fracture.outputDir, "Output folder")->required();
    fractureCmd->add_option("--pieces", fracture.pieces, "Number of Voronoi cells (seeds), exact for uniform sampling")
        ->check(CLI::PositiveNumber)->capture_default_str();
    fractureCmd->add_option("--seed", fracture.seed, "Random seed")->capture_default_str();
    fractureCmd->add_option("--impact", fracture.impact, "Cluster smaller pieces around this point X,Y,Z (m)")
        ->delimiter(',')->expected(3);
    fractureCmd->add_option("--radius", fracture.radius, "Impact radius (m)")
        ->check(CLI::PositiveNumber)->capture_default_str();
    fractureCmd->add_option("--points", fracture.pointsFile, "Seed points file, one 'x y z' per line (instead of --pieces)");
    fractureCmd->add_option("--density", fracture.density, "Density (kg/m^3)")
        ->check(CLI::PositiveNumber)->capture_default_str();
    fractureCmd->add_option("--interior-material", fracture.interiorMaterial, "Material ID of cut faces (0-15)")
        ->check(CLI::Range(0, 15))->capture_default_str();
    fractureCmd->add_option("--uv-scale", fracture.uvScale, "Metres per UV unit on cut faces")
        ->check(CLI::PositiveNumber)->capture_default_str();
    fractureCmd->add_option("--min-volume", fracture.minVolume, "Merge pieces below this volume (m^3) into their largest neighbour")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    fractureCmd->add_option("--levels", fracture.levels, "Fracture pieces within --radius of --impact again, this many times")
        ->check(CLI::Range(0, 4))->capture_default_str();
    fractureCmd->add_option("--level-pieces", fracture.levelPieces, "Pieces per re-fractured piece")
        ->check(CLI::Range(2, 1000))->capture_default_str();
    fractureCmd->add_option("--roughness", fracture.roughness,
                            "Noisy cut surfaces of this amplitude (m), meshed from OpenVDB level sets; 0: exact planar cuts")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    fractureCmd->add_option("--rough-scale", fracture.roughScale, "Noise wavelength (m); default four times --roughness")
        ->check(CLI::NonNegativeNumber);
    fractureCmd->add_option("--voxel", fracture.voxelSize, "Level-set voxel size (m) for --roughness; default automatic")
        ->check(CLI::NonNegativeNumber);
    fractureCmd->add_flag("--force", fracture.force, "Allow more than 20,000 pieces");
    fractureCmd->add_flag("--repair", fracture.repair, "Repair an open or inconsistent mesh first (and say so on stderr)");
    fractureCmd->add_option("--threads", threads, "Worker threads (0: all cores); output does not depend on it")
        ->check(CLI::NonNegativeNumber)->capture_default_str();

    cli::SimulateOptions sim;
    CLI::App* simulateCmd = app.add_subcommand(
        "simulate", "Simulate fractured pieces with Bullet: DIR/sim.json, DIR/transforms.bin, DIR/turns.bin (+ a copy of fragments.glb)");
    simulateCmd->add_option("FRACTURE_DIR", sim.fractureDir, "Folder written by 'dawnforge fracture'")->required();
    simulateCmd->add_option("-o,--output", sim.outputDir, "Output folder")->required();
    simulateCmd->add_option("--frames", sim.frames, "Frames to write; frame 0 is the rest pose")
        ->check(CLI::Range(1, 100000))->capture_default_str();
    simulateCmd->add_option("--fps", sim.fps, "Frames per second")->check(CLI::PositiveNumber)->capture_default_str();
    simulateCmd->add_option("--substeps", sim.substeps, "Fixed simulation steps per frame")
        ->check(CLI::Range(1, 100))->capture_default_str();
    simulateCmd->add_option("--iterations", sim.iterations, "Constraint solver iterations per step")
        ->check(CLI::Range(1, 1000))->capture_default_str();
    simulateCmd->add_option("--seed", sim.seed, "Random seed (varies each bond's strength)")->capture_default_str();
    simulateCmd->add_option("--strength", sim.strength,
                            "Glue strength (Pa): a bond breaks when its stress (axial + bending) above what it carries at rest exceeds this; 0: no glue")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    simulateCmd->add_option("--strength-variation", sim.strengthVariation, "Relative spread of bond strengths, from the seed")
        ->check(CLI::Range(0.0, 0.99))->capture_default_str();
    simulateCmd->add_option("--trigger-time", sim.triggerTime, "When the projectile, explosion or collapse happens (s)")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    simulateCmd->add_option("--projectile", sim.projectile, "Throw a ball at this point X,Y,Z (m)")
        ->delimiter(',')->expected(3);
    simulateCmd->add_option("--projectile-dir", sim.projectileDirection, "Direction of travel DX,DY,DZ (default -1,0,0)")
        ->delimiter(',')->expected(3);
    simulateCmd->add_option("--projectile-mass", sim.projectileMass, "kg")->check(CLI::PositiveNumber)->capture_default_str();
    simulateCmd->add_option("--projectile-speed", sim.projectileSpeed, "m/s")->check(CLI::NonNegativeNumber)->capture_default_str();
    simulateCmd->add_option("--projectile-radius", sim.projectileRadius, "m")->check(CLI::PositiveNumber)->capture_default_str();
    simulateCmd->add_option("--explosion", sim.explosion, "Push pieces away from this point X,Y,Z (m)")
        ->delimiter(',')->expected(3);
    simulateCmd->add_option("--explosion-radius", sim.explosionRadius, "m")->check(CLI::PositiveNumber)->capture_default_str();
    simulateCmd->add_option("--explosion-impulse", sim.explosionImpulse, "N·s at the centre, falling off as (1 - d/r)^2")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    simulateCmd->add_flag("--collapse", sim.collapse, "Every bond breaks at the trigger time (gravity collapse)");
    simulateCmd->add_flag("--no-ground", sim.noGround, "No ground plane");
    simulateCmd->add_option("--ground-height", sim.groundHeight, "Ground plane height (m); default the lowest point of the pieces");
    simulateCmd->add_option("--collider", sim.colliders, "Static collider mesh (.obj, .gltf, .glb), world space; repeatable");
    simulateCmd->add_option("--friction", sim.friction, "Friction coefficient of pieces, ground and colliders")->check(CLI::NonNegativeNumber)->capture_default_str();
    simulateCmd->add_option("--restitution", sim.restitution, "Bounciness (0: none, 1: elastic)")->check(CLI::Range(0.0, 1.0))->capture_default_str();
    simulateCmd->add_option("--hull-vertices", sim.hullVertices, "Collision hull vertex budget per piece")
        ->check(CLI::Range(4, 1000))->capture_default_str();
    simulateCmd->add_option("--margin", sim.margin, "Collision margin (m)")->check(CLI::PositiveNumber)->capture_default_str();
    simulateCmd->add_option("--threads", threads, "Worker threads (0: all cores); output does not depend on it")
        ->check(CLI::NonNegativeNumber)->capture_default_str();

    cli::VatOptions vat;
    CLI::App* vatCmd = app.add_subcommand(
        "vat", "Bake a simulation into vertex animation textures (SideFX Labs VAT 3.0 rigid layout): "
               "DIR/<name>_pos.exr, _rot.exr, _mesh.glb, _data.json");
    vatCmd->add_option("SIM_DIR", vat.simDir, "Folder written by 'dawnforge simulate'")->required();
    vatCmd->add_option("-o,--output", vat.outputDir, "Output folder")->required();
    vatCmd->add_option("--preset", vat.preset, "native (metres, +Y up), unreal (Z-up centimetres) or unity")
        ->capture_default_str();
    vatCmd->add_flag("--half", vat.half, "RGBA16F textures instead of RGBA32F");
    vatCmd->add_option("--max-width", vat.maxWidth, "Texture width limit; more pieces take several rows per frame")
        ->check(CLI::Range(1, 8192))->capture_default_str();
    vatCmd->add_option("--name", vat.name, "File name prefix")->capture_default_str();

    cli::CityOptions city;
    CLI::App* cityCmd = app.add_subcommand(
        "city", "Generate a city district with buildings and interiors: DIR/city.glb, DIR/city.json");
    cityCmd->add_option("-o,--output", city.outputDir, "Output folder")->required();
    cityCmd->add_option("--seed", city.seed, "Random seed")->capture_default_str();
    cityCmd->add_option("--size", city.size, "District size WxD in metres (x east, y north)")->capture_default_str();
    cityCmd->add_option("--tile", city.tile, "Generate only tile I,J (identical to that tile of the whole district)");
    cityCmd->add_option("--tile-size", city.tileSize, "Tile size in metres")->capture_default_str();
    cityCmd->add_option("--recipe", city.recipeFile,
                        "JSON recipe: any parameter of streets, coast, lots, buildings, interiors, roofs "
                        "(examples/recipes/)");
    cityCmd->add_option("--threads", threads, "Worker threads (0: all cores); output does not depend on it")
        ->check(CLI::NonNegativeNumber)->capture_default_str();

    cli::DemoOptions demo;
    CLI::App* demoCmd = app.add_subcommand("demo", "Run the whole pipeline on built-in defaults");
    demoCmd->add_option("-o,--output", demo.outputDir, "Output folder")->required();
    demoCmd->add_option("--floors", demo.floors, "Floors of the demo tower")
        ->check(CLI::Range(1, 200))
        ->capture_default_str();

    cli::RenderOptions render;
    CLI::App* renderCmd = app.add_subcommand(
        "render", "Render a scene file headless (EGL) to a PNG: the city, destruction VATs, the ocean, sky and sun");
    renderCmd->add_option("SCENE", render.sceneFile, "Scene file (scene.json)")->required();
    renderCmd->add_option("-o,--output", render.output, "PNG file to write")->required();
    renderCmd->add_option("--size", render.size, "Image size WxH")->capture_default_str();
    renderCmd->add_option("--camera", render.camera, "Named camera of the scene (default: its first, or an overview)");
    renderCmd->add_option("--time-of-day", render.timeOfDay, "Hours, 0 to 24 (default: the scene's)");
    renderCmd->add_option("--frame", render.frame, "Frame number: scene time = frame / fps (default: the scene's time)")
        ->check(CLI::NonNegativeNumber);
    renderCmd->add_flag("--stats", render.stats, "Print per-pass GPU and CPU times as JSON on stdout");
    renderCmd->add_option("--repeat", render.repeat, "With --stats: timed frames after a warm-up (median reported)")
        ->check(CLI::Range(1, 1000))->capture_default_str();

    cli::ViewOptions view;
    CLI::App* viewCmd = app.add_subcommand(
        "view", "Show a scene file in a window: drag to look, WASD/QE to fly (shift: faster), 1-9 cameras, "
                "[ ] time of day, R restart the destruction, Esc quit");
    viewCmd->add_option("SCENE", view.sceneFile, "Scene file (scene.json)")->required();
    viewCmd->add_option("--size", view.size, "Window size WxH")->capture_default_str();
    viewCmd->add_option("--camera", view.camera, "Named camera to start from");
    viewCmd->add_option("--frames", view.frames, "Close after this many frames (0: when the window is closed)")
        ->check(CLI::NonNegativeNumber)->capture_default_str();

    std::vector<CLI::App*> planned;
    for (const PlannedCommand& p : kPlanned) {
        CLI::App* cmd = app.add_subcommand(p.name, p.summary);
        cmd->allow_extras();
        planned.push_back(cmd);
    }

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::string where = "dawnforge";
        for (const CLI::App* sub : app.get_subcommands()) where += " " + sub->get_name();
        std::fprintf(stderr, "%s: %s (see '%s --help')\n", where.c_str(), e.what(), where.c_str());
        return static_cast<int>(ExitCode::BadInput);
    }

    try {
        if (inspectCmd->parsed()) return cli::runInspect(inspect, common);
        std::optional<tbb::global_control> threadLimit;
        if (threads > 0) threadLimit.emplace(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        if (cityCmd->parsed()) return cli::runCity(city, common);
        if (fractureCmd->parsed()) return cli::runFracture(fracture, common);
        if (simulateCmd->parsed()) return cli::runSimulate(sim, common);
        if (vatCmd->parsed()) return cli::runVat(vat, common);
        if (demoCmd->parsed()) return cli::runDemo(demo, common);
        if (renderCmd->parsed()) return cli::runRender(render, common);
        if (viewCmd->parsed()) return cli::runView(view, common);
        for (CLI::App* cmd : planned)
            if (cmd->parsed()) {
                std::fprintf(stderr, "dawnforge %s: not built yet\n", cmd->get_name().c_str());
                return static_cast<int>(ExitCode::BadInput);
            }
    } catch (const InputError& e) {
        std::fprintf(stderr, "dawnforge: error: %s\n", e.what());
        return static_cast<int>(ExitCode::BadInput);
    } catch (const Cancelled&) {
        std::fprintf(stderr, "dawnforge: cancelled\n");
        return static_cast<int>(ExitCode::Internal);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "dawnforge: internal error: %s\n", e.what());
        return static_cast<int>(ExitCode::Internal);
    }
    return static_cast<int>(ExitCode::Internal);
}
