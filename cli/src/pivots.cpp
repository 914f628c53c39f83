#include "commands.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/exporters/pivot_painter.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>

namespace dawnforge::cli {

namespace {

struct PivotsOptions {
    std::filesystem::path input;
    std::filesystem::path outputDir;
    exporters::PivotPreset preset = exporters::PivotPreset::Unreal;
    std::string name;
};

int runPivots(const PivotsOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    const std::vector<MeshNode> nodes = loadMeshNodes(o.input);
    const exporters::PivotPainter painter = exporters::buildPivotPainter(nodes, o.preset, o.input.string());
    const std::string name = o.name.empty() ? o.input.stem().string() : o.name;
    exporters::writePivotPainter(painter, o.outputDir, name);

    const auto roots = std::count_if(painter.elements.begin(), painter.elements.end(),
                                     [](const exporters::PivotElement& e) { return e.depth == 0; });
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("painted %zu elements (%td root(s), %d levels) into %d×%d texels (%s preset) in %.2f s\n",
                painter.elements.size(), roots, painter.levels, painter.width, painter.height,
                std::string(exporters::pivotPresetName(o.preset)).c_str(), seconds);
    if (o.preset == exporters::PivotPreset::Unreal && painter.levels > 4)
        std::fprintf(stderr, "warning: %d levels; Unreal's PivotPainter2FoliageShader animates the first 4\n", painter.levels);
    std::printf("  wrote %s/%s{.glb,_pivots.exr,_axes.%s,_pivots.json} (TEXCOORD_1 addresses each element's texel)\n",
                o.outputDir.string().c_str(), name.c_str(), o.preset == exporters::PivotPreset::Native ? "exr" : "png");
    return 0;
}

}  // namespace

Command addPivots(CLI::App& app, CommonOptions&) {
    auto o = std::make_shared<PivotsOptions>();
    CLI::App* cmd = app.add_subcommand(
        "pivots", "Pivot Painter 2 textures of a node hierarchy (each mesh node an element, its mesh ancestor its "
                  "parent): DIR/<name>_pivots.exr, _axes.png (.exr for native), <name>.glb, _pivots.json");
    cmd->add_option("MESH", o->input, "A file with a node hierarchy (glTF, GLB, FBX, ...)")->required();
    cmd->add_option("-o,--output", o->outputDir, "Output folder")->required();
    addChoiceOption(*cmd, "--preset", o->preset, exporters::parsePivotPreset, "preset", "unreal or native",
                    "unreal (Epic's Pivot Painter 2: centimetres, Z up, half-float pivots) or native (metres, +Y up, float)",
                    "unreal");
    cmd->add_option("--name", o->name, "File name prefix (default: the input's name)");
    return {cmd, [o] { return runPivots(*o); }};
}

}  // namespace dawnforge::cli
