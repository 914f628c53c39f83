// Bake figures (issue: baked lighting). Fixed input: the demo's district (default recipe,
// seed 1, 320 x 280 m, a third sea: 88 buildings with interiors), written once to a temporary
// folder.
//   build/bin/bake_bench --benchmark_filter=RawRays     Embree's incoherent closest-hit rate on
//                                                       the district's ray scene (the ceiling)
//   build/bin/bake_bench --benchmark_filter=Bake        the whole bake at default settings, with
//                                                       its own rays/s against that ceiling, its
//                                                       CPU seconds (fair on a shared machine) and
//                                                       the process's peak memory
// Wall time, every core (TBB and Embree share them).
#include <dawnforge/bake/bake.hpp>
#include <dawnforge/bake/ray_scene.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/materials.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/procgen/city.hpp>

#include <benchmark/benchmark.h>

#include <sys/resource.h>

#include <filesystem>
#include <fstream>

namespace {

using namespace dawnforge;

const std::filesystem::path& district() {
    static const std::filesystem::path dir = [] {
        const auto d = std::filesystem::temp_directory_path() / "dawnforge_bake_bench" / "city";
        std::filesystem::create_directories(d);
        procgen::CitySettings settings;
        settings.size = {320.0, 280.0};
        settings.tileSize = 160.0;
        settings.recipe.coast.water = 0.3;
        procgen::City city = procgen::generateCity(settings);
        const std::string report = procgen::cityReportJson(city);
        exporters::writeGlb(procgen::takeCityScene(city), d / "city.glb");
        std::ofstream(d / "city.json") << report;
        return d;
    }();
    return dir;
}

// The bake's ray scene: every LOD0 mesh and the ground, window glass left out.
struct DistrictScene {
    std::vector<Mesh> meshes;
    std::vector<std::vector<std::uint32_t>> opaque;
    std::vector<bake::RayGeometry> geometries;
    std::unique_ptr<bake::RayScene> scene;
};

const DistrictScene& districtScene() {
    static const DistrictScene s = [] {
        DistrictScene d;
        for (MeshNode& node : loadMeshNodes(district() / "city.glb", ReadIn::thisProcess)) {
            if (node.name.ends_with("_lod1")) continue;
            Mesh m = std::move(node.mesh);
            for (glm::vec3& p : m.positions) p = glm::vec3(node.world * glm::vec4(p, 1.0f));
            std::vector<std::uint32_t> idx;
            for (std::size_t t = 0; t < m.triangleCount(); ++t)
                if (m.materialIds.empty() || m.materialIds[m.indices[3 * t]] != kGlass)
                    idx.insert(idx.end(), {m.indices[3 * t], m.indices[3 * t + 1], m.indices[3 * t + 2]});
            d.meshes.push_back(std::move(m));
            d.opaque.push_back(std::move(idx));
        }
        for (std::size_t i = 0; i < d.meshes.size(); ++i) d.geometries.push_back({d.meshes[i].positions, d.opaque[i], 1u});
        d.scene = std::make_unique<bake::RayScene>(d.geometries);
        return d;
    }();
    return s;
}

void RawRays(benchmark::State& state) {
    const DistrictScene& d = districtScene();
    bake::RayThroughput t;
    for (auto _ : state) t = bake::measureRayThroughput(*d.scene, d.geometries, 4'000'000, 1, std::size_t(state.range(0)));
    state.counters["Mrays_per_s"] = t.raysPerSecond / 1e6;
    state.counters["Mrays_per_cpu_s"] = t.raysPerCpuSecond / 1e6;
    state.counters["hit_fraction"] = t.hitFraction;
    state.counters["triangles"] = double(d.scene->triangleCount());
}
BENCHMARK(RawRays)->Arg(1)->Arg(64)->Arg(256)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

void Bake(benchmark::State& state) {
    const std::filesystem::path& city = district();
    bake::BakeReport r;
    double cpu = 0.0;
    for (auto _ : state) {
        const double cpu0 = bake::processCpuSeconds();
        r = bake::bakeCity(city, bake::BakeSettings{});
        cpu = bake::processCpuSeconds() - cpu0;
    }
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    state.counters["Mrays_per_s"] = double(r.lighting.rays) / r.lighting.raySeconds / 1e6;
    state.counters["cpu_s"] = cpu;
    state.counters["bake_s"] = r.seconds;
    state.counters["peak_MB"] = double(usage.ru_maxrss) / 1024.0;
    state.counters["rays_M"] = double(r.lighting.rays) / 1e6;
    state.counters["texels_M"] = double(r.texels) / 1e6;
    state.counters["ray_s"] = r.lighting.raySeconds;
}
BENCHMARK(Bake)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace
