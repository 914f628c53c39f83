#include "commands.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/exporters/vat.hpp>
#include <dawnforge/sim/rigidbody_io.hpp>

#include <chrono>
#include <cstdio>

namespace dawnforge::cli {

int runVat(const VatOptions& options, const CommonOptions&) {
    const auto start = std::chrono::steady_clock::now();
    exporters::VatSettings settings;
    const auto preset = exporters::parseVatPreset(options.preset);
    if (!preset) throw InputError(format("unknown preset '{}' (expected native, unreal or unity)", options.preset));
    settings.preset = *preset;
    settings.half = options.half;
    settings.maxWidth = options.maxWidth;
    settings.name = options.name;

    const sim::SimulationFolder sim = sim::loadSimulation(options.simDir);
    exporters::VatAnimation animation;
    animation.pieces = sim.meshes;
    animation.transforms = sim.transforms;
    animation.frames = sim.frames;
    animation.fps = sim.fps;
    animation.turns = sim.turns;
    const exporters::Vat vat = exporters::encodeVat(animation, settings);
    exporters::writeVat(vat, settings, options.outputDir);

    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("baked %zu pieces × %d frames into %d×%d %s textures (%s preset, %d rows per frame) in %.2f s\n",
                vat.layout.pieces, vat.layout.frames, vat.layout.width, vat.layout.height,
                settings.half ? "RGBA16F" : "RGBA32F", std::string(exporters::vatPresetName(settings.preset)).c_str(),
                vat.layout.rowsPerFrame, seconds);
    std::printf("  worst error from the precision: position %.3g m, rotation %.3g rad, any vertex %.3g m\n",
                vat.maxPositionError, vat.maxRotationError, vat.maxVertexError);
    std::printf("  wrote %s/%s_{pos.exr,rot.exr,mesh.glb,data.json}\n", options.outputDir.string().c_str(),
                settings.name.c_str());
    return 0;
}

}  // namespace dawnforge::cli
