// What reading a user's file in a child process costs (issue: untrusted files): loadMesh with
// ReadIn::child against ReadIn::thisProcess, on three real inputs, in one run so the ratio is
// fair on a machine whose speed varies.
//   build/bin/import_bench
// - CGAL's armadillo (OFF, 52,000 triangles; Debian libcgal-demo's data.tar.gz, unpacked once),
// - Assimp's spider.fbx (Debian assimp-testmodels),
// - the demo's city.glb (default recipe, seed 1, 320 x 280 m), written once to a temporary folder.
// Each reading runs in a fresh, small process forked for it, as a command's first reading does:
// a process that has already read the file keeps its heap warm and its pages mapped, which
// would flatter the in-process path, and a large parent makes fork and copy-on-write dearer.
// Wall time of the fresh process, reading included, fork and exit excluded from neither side.
#include <dawnforge/core/import.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/procgen/city.hpp>

#include <benchmark/benchmark.h>

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace {

using namespace dawnforge;
namespace fs = std::filesystem;

const fs::path& workDir() {
    static const fs::path dir = [] {
        const fs::path d = fs::temp_directory_path() / "dawnforge_import_bench";
        fs::create_directories(d);
        return d;
    }();
    return dir;
}

fs::path armadillo() {
    const fs::path file = workDir() / "data/meshes/armadillo.off";
    if (!fs::exists(file)) {
        const std::string command = "tar xzf /usr/share/doc/libcgal-dev/data.tar.gz -C '" + workDir().string() +
                                    "' data/meshes/armadillo.off";
        if (std::system(command.c_str()) != 0) return {};
    }
    return file;
}

// Runs `work` in a forked process and waits for it; false if it failed.
template <typename Work>
bool inFreshProcess(const Work& work) {
    const pid_t pid = ::fork();
    if (pid == 0) {
        try {
            work();
        } catch (...) {
            ::_exit(1);
        }
        ::_exit(0);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    return pid > 0 && WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

fs::path demoCity() {
    const fs::path file = workDir() / "city.glb";
    if (!fs::exists(file))  // made in another process, so that this one stays small
        inFreshProcess([&] {
            procgen::CitySettings settings;
            settings.size = {320.0, 280.0};
            settings.tileSize = 160.0;
            settings.recipe.coast.water = 0.3;
            procgen::City city = procgen::generateCity(settings);
            exporters::writeGlb(procgen::takeCityScene(city), file);
        });
    return file;
}

fs::path input(int which) {
    switch (which) {
        case 0: return armadillo();
        case 1: return "/usr/share/assimp/models/FBX/spider.fbx";
        default: return demoCity();
    }
}

// Arg 0: which input (armadillo, spider, city); arg 1: 1 = in a child, 0 = in this process.
void BM_LoadMesh(benchmark::State& state) {
    const fs::path file = input(int(state.range(0)));
    if (file.empty() || !fs::exists(file)) {
        state.SkipWithError("input missing (./run installs libcgal-demo and assimp-testmodels)");
        return;
    }
    const ReadIn where = state.range(1) ? ReadIn::child : ReadIn::thisProcess;
    for (auto _ : state) {
        const auto start = std::chrono::steady_clock::now();
        if (!inFreshProcess([&] { loadMesh(file, where); })) {
            state.SkipWithError("the file did not load");
            return;
        }
        state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    state.SetLabel(file.filename().string() + (state.range(1) ? " child" : " this process"));
}
BENCHMARK(BM_LoadMesh)
    ->ArgsProduct({{0, 1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->MinTime(2.0);

}  // namespace
