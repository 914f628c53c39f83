#include "commands.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/exporters/animation.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/sim/rigidbody_io.hpp>

#include <chrono>
#include <cstdio>
#include <memory>
#include <numbers>

namespace dawnforge::cli {

namespace {

struct AnimOptions {
    std::filesystem::path simDir;
    std::filesystem::path output;
    double rotationToleranceDegrees = 0.05;
    exporters::AnimationSettings settings;
};

int runAnim(AnimOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    if (options.output.extension() != ".glb")
        throw InputError(format("anim: the output '{}' must be a .glb file", options.output.string()));
    options.settings.rotationTolerance = options.rotationToleranceDegrees * std::numbers::pi / 180.0;
    const sim::SimulationFolder sim = sim::loadSimulation(options.simDir);
    const exporters::PieceAnimation anim = exporters::animatePieces(
        {sim.meshes, sim.names, sim.transforms, sim.frames, sim.fps}, options.settings);
    exporters::writeGlb(anim.scene, options.output);

    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double poses = double(sim.frames) * double(sim.meshes.size());
    std::printf("animated %zu pieces × %d frames at %g fps: %zu translation and %zu rotation keys (%.1f %% and %.1f %% "
                "of the frames) in %.2f s\n",
                sim.meshes.size(), sim.frames, sim.fps, anim.translationKeys, anim.rotationKeys,
                100.0 * double(anim.translationKeys) / poses, 100.0 * double(anim.rotationKeys) / poses, seconds);
    std::printf("  worst error at a frame: position %.3g m, rotation %.3g°\n", anim.maxPositionError,
                anim.maxRotationError * 180.0 / std::numbers::pi);
    std::printf("  wrote %s (%ju bytes)\n", options.output.string().c_str(),
                std::uintmax_t(std::filesystem::file_size(options.output)));
    return 0;
}

}  // namespace

Command addAnim(CLI::App& app, CommonOptions&) {
    auto o = std::make_shared<AnimOptions>();
    CLI::App* cmd = app.add_subcommand(
        "anim", "Write a simulation as a glTF animation (one node per piece, named as in sim.json's piece_names; "
                "linear translation and rotation keys) for Blender, three.js and engines without the Labs shaders");
    cmd->add_option("SIM_DIR", o->simDir, "Folder written by 'dawnforge simulate'")->required();
    cmd->add_option("-o,--output", o->output, "Output file (.glb)")->required();
    cmd->add_option("--position-tolerance", o->settings.positionTolerance,
                    "Drop a key where linear interpolation stays within this distance (m) of every frame")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    cmd->add_option("--rotation-tolerance", o->rotationToleranceDegrees,
                    "Drop a key where slerp stays within this angle (degrees) of every frame")
        ->check(CLI::Range(0.0, 10.0))
        ->capture_default_str();
    return {cmd, [o] { return runAnim(*o); }};
}

}  // namespace dawnforge::cli
