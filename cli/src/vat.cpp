#include "commands.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/exporters/vat.hpp>
#include <dawnforge/sim/rigidbody_io.hpp>

#include <chrono>
#include <cstdio>
#include <memory>

namespace dawnforge::cli {

namespace {

struct VatOptions {
    std::filesystem::path simDir;
    std::filesystem::path outputDir;
    exporters::VatSettings settings;
};

int runVat(const VatOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    const exporters::VatSettings& settings = options.settings;
    const sim::SimulationFolder sim = sim::loadSimulation(options.simDir);
    exporters::VatAnimation animation;
    animation.pieces = sim.meshes;
    animation.transforms = sim.transforms;
    animation.frames = sim.frames;
    animation.fps = sim.fps;
    animation.turns = sim.turns;
    animation.dust = sim.dust;
    animation.dustPuffs = sim.dustPuffs;
    const exporters::Vat vat = exporters::encodeVat(animation, settings);
    exporters::writeVat(vat, settings, options.outputDir);

    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const bool ldr = settings.format == exporters::VatFormat::Ldr;
    std::printf("baked %zu pieces × %d frames into %d×%d %s textures (%s preset, %d rows per frame) in %.2f s\n",
                vat.layout.pieces, vat.layout.frames, vat.layout.width, vat.layout.height,
                ldr ? "RGBA8 (Non-HDR)" : settings.half ? "RGBA16F" : "RGBA32F",
                std::string(exporters::vatPresetName(settings.preset)).c_str(), vat.layout.rowsPerFrame, seconds);
    std::printf("  worst error from the precision: position %.3g m, rotation %.3g rad, any vertex %.3g m\n",
                vat.maxPositionError, vat.maxRotationError, vat.maxVertexError);
    if (sim.dustPuffs > 0)
        std::printf("  dust: %zu puffs%s\n", sim.dustPuffs,
                    vat.dust.empty() ? ", not carried by the ldr format" : format(" into {}×{} texels", vat.dustLayout.width,
                                                                                  vat.dustLayout.height).c_str());
    std::printf("  wrote %s/%s_{%s%s,mesh.glb,data.json}\n", options.outputDir.string().c_str(), settings.name.c_str(),
                !ldr ? "pos.exr,rot.exr" : vat.position2.empty() ? "pos.png,rot.png" : "pos.png,pos2.png,rot.png",
                vat.dust.empty() ? "" : ",dust.exr");
    return 0;
}

}  // namespace

Command addVat(CLI::App& app, CommonOptions&) {
    auto o = std::make_shared<VatOptions>();
    exporters::VatSettings& s = o->settings;
    CLI::App* cmd = app.add_subcommand(
        "vat", "Bake a simulation into vertex animation textures (SideFX Labs VAT 3.0 rigid layout): "
               "DIR/<name>_pos.exr, _rot.exr (or with --format ldr _pos.png, _pos2.png, _rot.png), _mesh.glb, _data.json");
    cmd->add_option("SIM_DIR", o->simDir, "Folder written by 'dawnforge simulate'")->required();
    cmd->add_option("-o,--output", o->outputDir, "Output folder")->required();
    addChoiceOption(*cmd, "--preset", s.preset, exporters::parseVatPreset, "preset", "native, unreal or unity",
                    "native (metres, +Y up), unreal (Z-up centimetres) or unity",
                    std::string(exporters::vatPresetName(s.preset)));
    addChoiceOption(*cmd, "--format", s.format, exporters::parseVatFormat, "format", "hdr or ldr",
                    "hdr (OpenEXR float) or ldr (the Labs Non-HDR form: 8-bit PNGs _pos, _pos2, _rot, for mobile; unity "
                    "and unreal presets)",
                    std::string(exporters::vatFormatName(s.format)));
    cmd->add_flag("--half", s.half, "hdr: RGBA16F textures instead of RGBA32F");
    cmd->add_flag("--single-position-texture", s.singlePositionTexture,
                  "ldr: positions in one 8-bit texture (to 1/510 of the bounds) instead of two (to 1/51,000)");
    cmd->add_option("--max-width", s.maxWidth, "Texture width limit; more pieces take several rows per frame")
        ->check(CLI::Range(1, exporters::kVatMaxTextureSize))->capture_default_str();
    cmd->add_option("--name", s.name, "File name prefix")->capture_default_str();
    cmd->add_flag("--full-precision-uvs", s.fullPrecisionUvs,
                  "unreal: exact pivots in 32-bit UVs (turn on Unreal's 'Use Full Precision UVs') instead of the Labs "
                  "'Very High' form, which costs up to 1/4096 of a pivot's distance from the origin");
    return {cmd, [o] { return runVat(*o); }};
}

}  // namespace dawnforge::cli
