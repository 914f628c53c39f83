// Destroying a building of the demo district (issue: destroy the city's own buildings).
// Fixed input: the demo's district (default recipe, seed 1, 320 x 280 m, a third sea),
// building 27 (five storeys, 164 parts: 75 panes, a door), fractured by material into about
// 300 pieces (80 Voronoi cells, glass in 1 m shards, smaller cells within 5 m of the impact),
// simulated in its city (13 neighbours, the ground) for 240 frames at 30 fps with a 20 t ball
// at 40 m/s into its sea side, baked into a native VAT.
//   build/bin/building_bench
#include <dawnforge/core/materials.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/exporters/vat.hpp>
#include <dawnforge/procgen/city.hpp>
#include <dawnforge/procgen/city_building.hpp>
#include <dawnforge/sim/fracture_parts.hpp>
#include <dawnforge/sim/rigidbody.hpp>

#include <benchmark/benchmark.h>

#include <filesystem>

namespace {

using namespace dawnforge;

constexpr int kBuilding = 27;

const procgen::CityBuilding& building() {
    static const procgen::CityBuilding b = [] {
        const auto dir = std::filesystem::temp_directory_path() / "dawnforge_building_bench";
        std::filesystem::create_directories(dir);
        procgen::CitySettings settings;
        settings.size = {320.0, 280.0};
        settings.tileSize = 160.0;
        settings.recipe.coast.water = 0.3;
        procgen::City city = procgen::generateCity(settings);
        const std::string report = procgen::cityReportJson(city);
        exporters::writeGlb(procgen::takeCityScene(city), dir / "city.glb");
        FILE* f = std::fopen((dir / "city.json").string().c_str(), "wb");
        std::fwrite(report.data(), 1, report.size(), f);
        std::fclose(f);
        return procgen::loadCityBuilding(dir, kBuilding);
    }();
    return b;
}

glm::dvec3 impact() {
    const Bounds& b = building().bounds;
    return {0.5 * (b.min.x + b.max.x), b.min.y + 0.45 * (b.max.y - b.min.y), b.max.z};
}

sim::FractureResult fracture() {
    std::vector<sim::FracturePart> parts;
    for (const procgen::CityBuildingPart& p : building().parts) parts.push_back({procgen::partKindName(p.kind), p.material, p.mesh});
    sim::PartsFractureSettings s;
    s.common.pieces = 80;
    s.common.impact = impact();
    s.common.impactRadius = 5.0;
    s.shardSize = 1.0;
    return sim::fractureParts(parts, s);
}

const sim::FractureResult& pieces() {
    static const sim::FractureResult r = fracture();
    return r;
}

sim::SimulationSettings settings() {
    sim::SimulationSettings s;
    s.frames = 240;
    double lowest = building().bounds.min.y;
    for (const Mesh& g : building().ground) lowest = std::min(lowest, computeBounds(g.positions).min.y);
    s.colliders = building().ground;
    s.colliders.insert(s.colliders.end(), building().neighbours.begin(), building().neighbours.end());
    s.groundHeight = lowest - 0.05;
    const Bounds& b = building().bounds;
    s.support = sim::Support{b.min.y, {b.min.x, b.min.z}, {b.max.x, b.max.z}};
    sim::Projectile ball;
    ball.target = impact();
    ball.direction = {0.0, 0.0, -1.0};
    ball.radius = 1.5;
    s.projectile = ball;
    return s;
}

void BM_FractureFiveStoreyBuilding(benchmark::State& state) {
    building();
    sim::FractureResult r;
    for (auto _ : state) r = fracture();
    state.counters["pieces"] = double(r.pieces.size());
    state.counters["bonds"] = double(r.bonds.size());
    std::array<int, kMaterialCount> per{};
    for (const sim::FracturePiece& p : r.pieces) ++per[p.material];
    for (int m = 0; m < kMaterialCount; ++m)
        if (per[std::size_t(m)]) state.counters[materialName(std::uint8_t(m))] = per[std::size_t(m)];
}
BENCHMARK(BM_FractureFiveStoreyBuilding)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

void BM_SimulateItInItsCity240Frames(benchmark::State& state) {
    const std::vector<sim::RigidPiece> rigid = sim::rigidPieces(pieces());
    const sim::SimulationSettings s = settings();
    sim::SimulationResult r;
    for (auto _ : state) r = sim::simulate(rigid, pieces().bonds, s);
    state.counters["pieces"] = double(r.pieces);
    state.counters["broken"] = double(r.brokenBonds);
}
BENCHMARK(BM_SimulateItInItsCity240Frames)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);

void BM_BakeItsVat(benchmark::State& state) {
    const std::vector<sim::RigidPiece> rigid = sim::rigidPieces(pieces());
    static const sim::SimulationResult motion = sim::simulate(rigid, pieces().bonds, settings());
    std::vector<Mesh> meshes;
    for (const sim::RigidPiece& p : rigid) meshes.push_back(p.mesh);
    const auto dir = std::filesystem::temp_directory_path() / "dawnforge_building_bench" / "vat";
    exporters::VatSettings vat;
    for (auto _ : state)
        exporters::writeVat(exporters::encodeVat({meshes, motion.transforms, motion.frames, motion.fps, motion.turns}, vat),
                            vat, dir);
}
BENCHMARK(BM_BakeItsVat)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

}  // namespace
