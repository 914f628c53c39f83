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
    {"city", "Generate a city district: DIR/city.glb, DIR/city.json (not built yet)"},
    {"simulate", "Simulate fractured pieces with Bullet: DIR/sim.json, DIR/transforms.bin (not built yet)"},
    {"vat", "Bake a simulation into vertex animation textures (EXR) (not built yet)"},
    {"bake", "Bake lightmaps and overlook depth next to a city (not built yet)"},
    {"render", "Render a scene headless to PNG (not built yet)"},
    {"view", "Show a scene in a window (not built yet)"},
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

    cli::DemoOptions demo;
    CLI::App* demoCmd = app.add_subcommand("demo", "Run the whole pipeline on built-in defaults");
    demoCmd->add_option("-o,--output", demo.outputDir, "Output folder")->required();
    demoCmd->add_option("--floors", demo.floors, "Floors of the demo tower")
        ->check(CLI::Range(1, 200))
        ->capture_default_str();

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
        if (fractureCmd->parsed()) return cli::runFracture(fracture, common);
        if (demoCmd->parsed()) return cli::runDemo(demo, common);
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
