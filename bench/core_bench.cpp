// Core figures: mesh inspection (welding, topology, CGAL self-intersection and volume)
// and GLB encoding, on icospheres of fixed size.
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/core/validate.hpp>
#include <dawnforge/exporters/gltf.hpp>

#include <benchmark/benchmark.h>

namespace {

void BM_InspectIcosphere(benchmark::State& state) {
    const dawnforge::Mesh sphere = dawnforge::makeIcosphere(1.0f, static_cast<int>(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(dawnforge::inspectMesh(sphere));
    state.counters["triangles"] = static_cast<double>(sphere.triangleCount());
}
BENCHMARK(BM_InspectIcosphere)->Arg(4)->Arg(5)->Arg(6)->Unit(benchmark::kMillisecond);

void BM_EncodeGlb(benchmark::State& state) {
    dawnforge::Scene scene;
    scene.addMeshNode(dawnforge::makeIcosphere(1.0f, static_cast<int>(state.range(0))));
    for (auto _ : state) benchmark::DoNotOptimize(dawnforge::exporters::encodeGlb(scene));
    state.counters["triangles"] = static_cast<double>(scene.meshes[0].triangleCount());
}
BENCHMARK(BM_EncodeGlb)->Arg(5)->Arg(7)->Unit(benchmark::kMillisecond);

}  // namespace
