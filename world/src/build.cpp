// buildWorld and runJob (build.hpp): which jobs are left, a backend to run them, the records
// that say what finished, then the manifest.
#include <dawnforge/world/build.hpp>

#include "backend.hpp"
#include "jobs.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>

namespace dawnforge::world {

namespace fs = std::filesystem;

namespace {

void checkSettings(const WorldPlan& plan, const BuildSettings& s) {
    if (s.backend != "local" && s.backend != "slurm")
        throw InputError(format("--backend: \"{}\" is not a backend (local or slurm)", s.backend));
    for (const std::string& stage : s.stages)
        if (std::find_if(std::begin(kStages), std::end(kStages), [&](const char* k) { return stage == k; }) == std::end(kStages))
            throw InputError(format("--stages: \"{}\" is not a stage (city, bake, hlod, destroy)", stage));
    for (glm::ivec2 t : s.only)
        if (t.x < 0 || t.y < 0 || t.x >= plan.tileCount.x || t.y >= plan.tileCount.y)
            throw InputError(format("--only: tile {},{} is not in this world, which has {} x {} tiles (0,0 to {},{})", t.x, t.y,
                                    plan.tileCount.x, plan.tileCount.y, plan.tileCount.x - 1, plan.tileCount.y - 1));
    if (s.jobs < 0 || s.jobs > 1024) throw InputError(format("--jobs: must be 0 to 1024 (got {})", s.jobs));
}

// The tiles a job of `stage` works on.
std::vector<glm::ivec2> jobTiles(const WorldPlan& plan, const std::string& stage, int task) {
    if (stage == "city" || stage == "bake") return {plan.tiles[std::size_t(task)].index};
    if (stage == "destroy") return {plan.destroy[std::size_t(task)].tile};
    int k = 0;
    for (const HlodNode& n : plan.hlod)
        if (format("hlod{}", n.level) == stage && k++ == task) return n.tiles;
    return {};
}

bool selected(const std::vector<glm::ivec2>& only, const std::vector<glm::ivec2>& tiles) {
    if (only.empty()) return true;
    return std::any_of(tiles.begin(), tiles.end(), [&](glm::ivec2 t) { return std::find(only.begin(), only.end(), t) != only.end(); });
}

std::string jobLabel(const std::string& stage, const std::string& name) {
    if (stage == "city" || stage == "bake") return "tile " + name;
    if (stage == "destroy") return name;
    return "hlod node " + name;
}

// What jobs killed part-way left: temporary files (".tmp-"), partial folders (".partial-") and
// a bake's swapped-out folder ("bake.old-"). A build of the same folder must not be running.
void removeStaleTemporaries(const fs::path& worldDir) {
    std::vector<fs::path> stale;
    for (const char* top : {"tiles", "hlod", "destroy", "jobs"}) {
        std::error_code ec;
        if (!fs::is_directory(worldDir / top, ec)) continue;
        for (auto it = fs::recursive_directory_iterator(worldDir / top); it != fs::recursive_directory_iterator(); ++it) {
            const std::string name = it->path().filename().string();
            if (name.find(".tmp-") != std::string::npos || name.find(".partial-") != std::string::npos || name.starts_with("bake.old-")) {
                stale.push_back(it->path());
                it.disable_recursion_pending();
            }
        }
    }
    for (const fs::path& p : stale) fs::remove_all(p);
}

int defaultWorkers() { return int(std::max(1u, std::thread::hardware_concurrency())); }

}  // namespace

BuildReport buildWorld(const fs::path& worldDirIn, const BuildSettings& settings, const BuildProgress& progress) {
    const auto start = std::chrono::steady_clock::now();
    const fs::path worldDir = fs::absolute(worldDirIn).lexically_normal();
    const WorldPlan plan = readPlan(worldDir);
    checkSettings(plan, settings);
    removeStaleTemporaries(worldDir);
    const int workers = settings.jobs > 0 ? settings.jobs : defaultWorkers();
    const int threads = settings.threadsPerJob > 0 ? settings.threadsPerJob : std::max(1, defaultWorkers() / workers);

    BuildReport report;
    std::vector<StageJobs> todo;
    std::vector<std::vector<int>> selectedTasks;
    for (const std::string& stage : expandStages(plan, settings.stages)) {
        StageReport sr{stage, 0, 0, 0, {}};
        StageJobs jobs{stage, {}, threads, settings.memoryMb};
        std::vector<int> all;
        const std::size_t count = stageJobs(plan, stage).size();
        for (int task = 0; task < int(count); ++task) {
            if (!selected(settings.only, jobTiles(plan, stage, task))) continue;
            all.push_back(task);
            ++sr.jobs;
            if (jobFinished(worldDir, stage, task)) ++sr.skipped;
            else jobs.tasks.push_back(task);
        }
        sr.ran = jobs.tasks.size();
        report.stages.push_back(sr);
        todo.push_back(std::move(jobs));
        selectedTasks.push_back(std::move(all));
    }
    // Progress counts the records on disk, whichever backend runs the jobs.
    std::vector<std::size_t> shown(todo.size(), std::size_t(-1));
    const auto poll = [&] {
        if (!progress) return;
        for (std::size_t s = 0; s < todo.size(); ++s) {
            std::size_t done = report.stages[s].skipped;
            for (int task : todo[s].tasks) done += fs::exists(recordPath(worldDir, todo[s].stage, task)) ? 1 : 0;
            if (done != shown[s]) progress(todo[s].stage, done, report.stages[s].jobs), shown[s] = done;
        }
    };
    BackendContext ctx{settings.executable, worldDir, workers, settings.partition, poll};
    poll();
    if (settings.backend == "local") runLocal(todo, ctx);
    else runSlurm(todo, ctx);
    poll();

    bool failed = false;
    for (std::size_t s = 0; s < todo.size(); ++s) {
        const std::vector<std::string> names = stageJobs(plan, todo[s].stage);
        for (int task : todo[s].tasks)
            if (!jobFinished(worldDir, todo[s].stage, task)) {
                report.stages[s].failed.push_back(jobLabel(todo[s].stage, names[std::size_t(task)]));
                failed = true;
            }
    }
    if (!failed) {
        writeTileset(worldDir, plan);
        report.manifest = true;
    }
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

void runJob(const fs::path& worldDirIn, const std::string& stage, int task, const fs::path& executable) {
    const auto start = std::chrono::steady_clock::now();
    const fs::path worldDir = fs::absolute(worldDirIn).lexically_normal();
    const WorldPlan plan = readPlan(worldDir);
    const std::vector<std::string> names = stageJobs(plan, stage);
    std::error_code ec;
    fs::remove(recordPath(worldDir, stage, task), ec);  // a failure leaves no record of an older run
    const std::vector<std::string> outputs = runStageJob(worldDir, plan, stage, task, executable);
    writeRecord(worldDir, stage, task, names[std::size_t(task)], outputs);
    rusage self{}, children{};
    ::getrusage(RUSAGE_SELF, &self);
    ::getrusage(RUSAGE_CHILDREN, &children);
    const double cpu = double(self.ru_utime.tv_sec + self.ru_stime.tv_sec) + 1e-6 * double(self.ru_utime.tv_usec + self.ru_stime.tv_usec);
    std::printf("job %s %s: %.2f s wall, %.2f s CPU, peak memory %.0f MB (children %.0f MB)\n", stage.c_str(),
                names[std::size_t(task)].c_str(), std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                cpu, double(self.ru_maxrss) / 1024.0, double(children.ru_maxrss) / 1024.0);
}

}  // namespace dawnforge::world
