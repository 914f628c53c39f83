// Fracture figures (issue: Voronoi fracture). Fixed inputs: a 20,480-triangle unit
// icosphere (makeIcosphere(1, 5)) into 200 and 1,000 pieces, seed 1, by the restricted Voronoi
// diagram (the default) and by one corefinement per cell; wall time, all cores.
//   build/bin/sim_bench --benchmark_filter=Fracture
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/sim/fracture.hpp>

#include <benchmark/benchmark.h>

namespace {

void BM_FractureIcosphere(benchmark::State& state) {
    const dawnforge::Mesh sphere = dawnforge::makeIcosphere(1.0f, 5);
    dawnforge::sim::FractureSettings settings;
    settings.pieces = static_cast<int>(state.range(0));
    settings.method = state.range(1) ? dawnforge::sim::FractureMethod::Corefine : dawnforge::sim::FractureMethod::Rvd;
    state.SetLabel(dawnforge::sim::fractureMethodName(settings.method));
    double volumeError = 0.0;
    for (auto _ : state) {
        const dawnforge::sim::FractureResult r = dawnforge::sim::fractureMesh(sphere, settings);
        double total = 0.0;
        for (const auto& p : r.pieces) total += p.mass.volume;
        volumeError = std::abs(total - r.inputVolume) / r.inputVolume;
        benchmark::DoNotOptimize(r.pieces.data());
    }
    state.counters["triangles"] = static_cast<double>(sphere.triangleCount());
    state.counters["volume_rel_error"] = volumeError;
}
BENCHMARK(BM_FractureIcosphere)->Args({200, 0})->Args({1000, 0})->Args({200, 1})->Args({1000, 1})->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

void BM_FractureSeeds(benchmark::State& state) {
    const dawnforge::Mesh sphere = dawnforge::makeIcosphere(1.0f, 5);
    dawnforge::sim::FractureSettings settings;
    settings.pieces = 200;
    for (auto _ : state) benchmark::DoNotOptimize(dawnforge::sim::sampleFractureSeeds(sphere, settings));
}
BENCHMARK(BM_FractureSeeds)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
