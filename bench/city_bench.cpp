// City figures (issue: procedural city blocks with buildings and interiors). Fixed input:
// the default recipe, seed 1, a 1000 x 1000 m district (1 km^2) with interiors.
//   build/bin/city_bench                       (plan, generation, GLB encoding, whole command)
// Peak memory of the whole command: /usr/bin/time -v build/bin/dawnforge city -o out --size 1000x1000
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/procgen/city.hpp>

#include <benchmark/benchmark.h>

namespace {

using namespace dawnforge;
using namespace dawnforge::procgen;

CitySettings district() {
    CitySettings s;
    s.size = {1000.0, 1000.0};
    s.seed = 1;
    return s;
}

void recordCounts(benchmark::State& state, const City& city) {
    const CityCounts counts = countCity(city);
    state.counters["buildings"] = static_cast<double>(counts.buildings);
    state.counters["rooms"] = static_cast<double>(counts.rooms);
    state.counters["tris_lod0"] = static_cast<double>(counts.trianglesLod0);
    state.counters["tris_lod1"] = static_cast<double>(counts.trianglesLod1);
}

void BM_Plan1km(benchmark::State& state) {
    const CitySettings s = district();
    for (auto _ : state) {
        const CityPlan plan = planCity(s.recipe, s.seed, s.size);
        state.counters["blocks"] = static_cast<double>(plan.blocks.size());
        state.counters["lots"] = static_cast<double>(plan.lots.size());
    }
}
BENCHMARK(BM_Plan1km)->Unit(benchmark::kMillisecond);

void BM_Generate1km(benchmark::State& state) {
    for (auto _ : state) {
        const City city = generateCity(district());
        recordCounts(state, city);
    }
}
BENCHMARK(BM_Generate1km)->Unit(benchmark::kMillisecond)->Iterations(2);

// What `dawnforge city` does after generation: report, scene, GLB bytes in memory.
void BM_GenerateAndEncode1km(benchmark::State& state) {
    for (auto _ : state) {
        City city = generateCity(district());
        recordCounts(state, city);
        const std::string report = cityReportJson(city);
        const std::vector<std::byte> glb = exporters::encodeGlb(takeCityScene(city));
        state.counters["glb_MB"] = static_cast<double>(glb.size()) / 1e6;
        benchmark::DoNotOptimize(report.data());
    }
}
BENCHMARK(BM_GenerateAndEncode1km)->Unit(benchmark::kMillisecond)->Iterations(2);

}  // namespace
