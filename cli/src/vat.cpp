#include "commands.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/exporters/vat.hpp>
#include <dawnforge/sim/rigidbody_io.hpp>

#include <chrono>
#include <cstdio>

namespace dawnforge::cli {

int runVat(const VatOptions& options, const CommonOptions&) {
    const auto start = std::chrono::steady_clock::now();
    VatSettings settings;
    const auto preset = parseVatPreset(options.preset);
    if (!preset) throw InputError(format("unknown preset '{}' (expected native, unreal or unity)", options.preset));
    settings.preset = *preset;
    settings.half = options.half;
    settings.maxWidth = options.maxWidth;
    settings.name = options.name;

    const SimulationFolder sim = loadSimulation(options.simDir);
    // The VAT is laid out before anything is read further, so a texture that cannot fit
    // is reported first.
    vatLayout(sim.names.size(), sim.frames, settings.maxWidth);
    std::vector<MeshNode> nodes = loadMeshNodes(sim.fragments);
    if (nodes.size() != sim.names.size())
        throw InputError(format("{}: has {} pieces but the simulation has {}", sim.fragments.string(), nodes.size(),
                                sim.names.size()));
    std::vector<Mesh> pieces;
    for (std::size_t j = 0; j < nodes.size(); ++j) {
        if (nodes[j].name != sim.names[j])
            throw InputError(format("{}: node {} is '{}' but the simulation names piece {} '{}'", sim.fragments.string(),
                                    j, nodes[j].name, j, sim.names[j]));
        const glm::vec3 pivot(nodes[j].world[3]);
        const glm::vec3 rest(sim.transforms[j * 7], sim.transforms[j * 7 + 1], sim.transforms[j * 7 + 2]);
        if (glm::length(pivot - rest) > 1e-3f * std::max(1.0f, glm::length(rest)))
            throw InputError(format("{}: piece '{}' sits at ({}, {}, {}) but the simulation starts it at ({}, {}, {})",
                                    sim.fragments.string(), nodes[j].name, pivot.x, pivot.y, pivot.z, rest.x, rest.y,
                                    rest.z));
        Mesh mesh = std::move(nodes[j].mesh);
        for (glm::vec3& p : mesh.positions) p = glm::mat3(nodes[j].world) * p;  // relative to the pivot, world axes
        pieces.push_back(std::move(mesh));
    }
    VatAnimation animation;
    animation.pieces = pieces;
    animation.transforms = sim.transforms;
    animation.frames = sim.frames;
    animation.fps = sim.fps;
    animation.turns = sim.turns;
    const Vat vat = encodeVat(animation, settings);
    writeVat(vat, settings, options.outputDir);

    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("baked %zu pieces × %d frames into %d×%d %s textures (%s preset, %d rows per frame) in %.2f s\n",
                vat.layout.pieces, vat.layout.frames, vat.layout.width, vat.layout.height,
                settings.half ? "RGBA16F" : "RGBA32F", std::string(vatPresetName(settings.preset)).c_str(),
                vat.layout.rowsPerFrame, seconds);
    std::printf("  worst error from the precision: position %.3g m, rotation %.3g rad, any vertex %.3g m\n",
                vat.maxPositionError, vat.maxRotationError, vat.maxVertexError);
    std::printf("  wrote %s/%s_{pos.exr,rot.exr,mesh.glb,data.json}\n", options.outputDir.string().c_str(),
                settings.name.c_str());
    return 0;
}

}  // namespace dawnforge::cli
