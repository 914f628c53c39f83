#include "folders.hpp"

#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/mesh.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/read_file.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/exporters/pivot_painter.hpp>
#include <dawnforge/sim/fracture_io.hpp>
#include <dawnforge/sim/rigidbody_io.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace dawnforge::cli {

procgen::CityPlan writeCityFolder(const procgen::CitySettings& settings, const std::filesystem::path& dir,
                                  const CommonOptions& common) {
    const auto start = std::chrono::steady_clock::now();
    procgen::City city;
    {
        StderrProgress progress = progressFor("city", common);
        city = procgen::generateCity(settings, progress.callback());
    }
    const std::string report = procgen::cityReportJson(city);
    const procgen::CityCounts counts = procgen::countCity(city);
    const std::size_t blocks = city.plan.blocks.size();
    const std::vector<procgen::TreeSpecies> species = city.dressing.species;
    const Scene scene = procgen::takeCityScene(city);
    ensureOutputDirectory(dir);
    exporters::writeGlb(scene, dir / "city.glb", {.images = exporters::MaterialImages::kEmbedded});
    writeFileAtomically(dir / "city.json", report);
    // Each tree species with its Pivot Painter 2 textures, for Unreal's wind shaders.
    for (const procgen::TreeSpecies& s : species)
        exporters::writePivotPainter(
            exporters::buildPivotPainter(procgen::speciesNodes(s), exporters::PivotPreset::Unreal, s.name), dir / "trees",
            s.name);

    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("generated %s%.0f x %.0f m, seed %llu: %zu blocks, %zu buildings, %zu rooms in %.2f s\n",
                settings.tile ? format("tile {},{} of ", settings.tile->x, settings.tile->y).c_str() : "",
                settings.size.x, settings.size.y, static_cast<unsigned long long>(settings.seed), blocks, counts.buildings,
                counts.rooms, seconds);
    std::printf("  triangles: LOD0 %zu, LOD1 %zu; %zu trees, %zu street lamps\n", counts.trianglesLod0,
                counts.trianglesLod1, counts.trees, counts.lamps);
    std::printf("  wrote %s, %s and %s (tree species with Pivot Painter 2 textures)\n", (dir / "city.glb").string().c_str(),
                (dir / "city.json").string().c_str(), (dir / "trees").string().c_str());
    return std::move(city.plan);
}

void writeFractureFolder(const sim::FractureResult& result, const sim::FractureSettings& settings,
                         const std::string& input, const std::filesystem::path& dir, int building) {
    ensureOutputDirectory(dir);
    exporters::writeGlb(sim::fractureScene(result), dir / "fragments.glb", {.images = exporters::MaterialImages::kEmbedded});
    writeFileAtomically(dir / "fracture.json", sim::fractureJson(result, settings, input, building));
}

void writeSimulationFolder(const sim::SimulationResult& result, const sim::SimulationSettings& settings,
                           std::span<const sim::RigidPiece> pieces, const std::filesystem::path& fractureDir,
                           const std::filesystem::path& dir) {
    const std::vector<std::byte> fragments = readBinaryFile(fractureDir / "fragments.glb");
    ensureOutputDirectory(dir);
    if (!result.chips.empty())
        exporters::writeGlb(sim::debrisScene(result), dir / "debris.glb", {.images = exporters::MaterialImages::kEmbedded});
    else std::filesystem::remove(dir / "debris.glb");  // an earlier run's, which sim.json no longer counts
    sim::writeSimulation(dir, result, settings, pieces, fractureDir.string());
    writeFileAtomically(dir / "fragments.glb", fragments);
}

void placeInCity(procgen::CityBuilding building, sim::SimulationSettings& settings) {
    double lowest = building.bounds.min.y;
    for (Mesh& ground : building.ground) {
        lowest = std::min(lowest, computeBounds(ground.positions).min.y);
        settings.colliders.push_back(std::move(ground));
    }
    for (Mesh& shell : building.neighbours) settings.colliders.push_back(std::move(shell));
    if (!settings.groundHeight) settings.groundHeight = lowest - 0.05;
    settings.support = sim::Support{building.bounds.min.y, {building.bounds.min.x, building.bounds.min.z},
                                    {building.bounds.max.x, building.bounds.max.z}};
}

}  // namespace dawnforge::cli
