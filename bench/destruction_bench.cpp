// Destruction figures (issue: rigid-body destruction baked into VATs). Fixed input: the
// demo's tower shape (8 storeys, 12 × 10 m, density 300 kg/m^3) fractured into 500 pieces
// (seed 1), hit by a 20 t ball at 40 m/s 0.2 s in; 240 frames at 30 fps, 4 substeps.
//   build/bin/destruction_bench
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/exporters/vat.hpp>
#include <dawnforge/sim/fracture.hpp>
#include <dawnforge/sim/rigidbody.hpp>

#include <benchmark/benchmark.h>

#include <filesystem>

namespace {

using namespace dawnforge;

struct Fixture {
    sim::FractureResult fracture;
    std::vector<sim::RigidPiece> pieces;
    std::vector<Mesh> meshes;
    sim::SimulationSettings settings;
};

const Fixture& fixture() {
    static const Fixture f = [] {
        Fixture out;
        sim::FractureSettings fs;
        fs.pieces = 500;
        fs.density = 300.0;
        out.fracture = sim::fractureMesh(makeTower(8, 3.2f, 12.0f, 10.0f), fs);
        out.pieces = sim::rigidPieces(out.fracture);
        for (const sim::RigidPiece& p : out.pieces) out.meshes.push_back(p.mesh);
        out.settings.frames = 240;
        out.settings.fps = 30.0;
        out.settings.substeps = 4;
        sim::Projectile ball;
        ball.target = {6.0, 12.8, 2.0};
        ball.radius = 1.5;
        out.settings.projectile = ball;
        return out;
    }();
    return f;
}

const sim::SimulationResult& simulation() {
    static const sim::SimulationResult r = sim::simulate(fixture().pieces, fixture().fracture.bonds, fixture().settings);
    return r;
}

void BM_Simulate500Pieces240Frames(benchmark::State& state) {
    const Fixture& f = fixture();
    sim::SimulationResult r;
    for (auto _ : state) r = sim::simulate(f.pieces, f.fracture.bonds, f.settings);
    state.counters["pieces"] = double(r.pieces);
    state.counters["bonds"] = double(r.bonds);
    state.counters["broken"] = double(r.brokenBonds);
}
BENCHMARK(BM_Simulate500Pieces240Frames)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);

// Encoding and writing the four files (EXRs, mesh, data) of one preset.
void BM_WriteVat500Pieces240Frames(benchmark::State& state) {
    const Fixture& f = fixture();
    const sim::SimulationResult& r = simulation();
    exporters::VatSettings settings;
    settings.preset = static_cast<exporters::VatPreset>(state.range(0));
    settings.half = state.range(1) != 0;
    const auto dir = std::filesystem::temp_directory_path() / "dawnforge_vat_bench";
    exporters::Vat vat;
    for (auto _ : state) {
        vat = exporters::encodeVat({f.meshes, r.transforms, r.frames, r.fps}, settings);
        exporters::writeVat(vat, settings, dir);
    }
    std::filesystem::remove_all(dir);
    state.counters["max_vertex_error_mm"] = 1000.0 * vat.maxVertexError;
}
BENCHMARK(BM_WriteVat500Pieces240Frames)
    ->Args({int(exporters::VatPreset::Native), 0})
    ->Args({int(exporters::VatPreset::Unreal), 0})
    ->Args({int(exporters::VatPreset::Unity), 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
