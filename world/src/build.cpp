// buildWorld and runJob (build.hpp): which jobs are left, a backend to run them, the records
// that say what finished, then the manifest.
#include <dawnforge/world/build.hpp>

#include "backend.hpp"
#include "jobs.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <chrono>
#include <cstring>
#include <map>
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
    return hlodStageNodes(plan, stage)[std::size_t(task)]->tiles;
}

bool overOnly(const std::vector<glm::ivec2>& only, const std::vector<glm::ivec2>& tiles) {
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

// Jobs at once on this machine: one per core, but no more than the memory holds bakes of the
// plan's budget (each with half a gigabyte more for the rest of the job).
int localWorkers(const WorldPlan& plan, const BuildSettings& s) {
    if (s.jobs > 0) return s.jobs;
    const double memoryMb = double(::sysconf(_SC_PHYS_PAGES)) * double(::sysconf(_SC_PAGESIZE)) / 1048576.0;
    const int byMemory = int(memoryMb / (plan.settings.bake.memoryBudgetMb + 512.0));
    return std::max(1, std::min(defaultWorkers(), byMemory));
}

// Only one build of a folder at a time: the lock is held by the build and, through the file
// descriptor they inherit, by its local jobs, so a build killed while its jobs still run is not
// followed by another that would race them.
class BuildLock {
public:
    explicit BuildLock(const fs::path& worldDir) {
        const fs::path file = worldDir / ".build.lock";
        fd_ = ::open(file.c_str(), O_RDWR | O_CREAT, 0644);
        if (fd_ < 0) throw InputError(format("{}: cannot open the build lock: {}", file.string(), std::strerror(errno)));
        if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
            ::close(fd_);
            throw InputError(format("{}: another world build, or jobs of a killed one, still run in this folder: "
                                    "wait for them to end (or stop them), then build again", worldDir.string()));
        }
    }
    ~BuildLock() { ::close(fd_); }
    BuildLock(const BuildLock&) = delete;
    BuildLock& operator=(const BuildLock&) = delete;

private:
    int fd_ = -1;
};

// Which jobs of each stage run: those not finished, and those whose inputs run in this build.
// Under --only, the city and bake jobs of those tiles, and the HLOD and destroy jobs over them
// whose inputs are all finished or run too (the others wait: "left").
struct Schedule {
    std::vector<StageReport> reports;
    std::vector<StageJobs> jobs;
    std::map<std::pair<std::string, int>, bool> runs;
};

Schedule schedule(const fs::path& worldDir, const WorldPlan& plan, const std::string& hash, const BuildSettings& s, int threads) {
    Schedule out;
    const int memoryMb = s.memoryMb > 0 ? s.memoryMb : int(plan.settings.bake.memoryBudgetMb) + 512;
    for (const std::string& stage : expandStages(plan, s.stages)) {
        StageReport report{stage, 0, 0, 0, 0, {}};
        StageJobs jobs{stage, {}, threads, memoryMb};
        for (int task = 0; task < int(stageJobs(plan, stage).size()); ++task) {
            if (!overOnly(s.only, jobTiles(plan, stage, task))) continue;
            ++report.jobs;
            bool inputRuns = false, inputMissing = false;
            for (const auto& input : jobInputs(plan, stage, task)) {
                const bool runs = out.runs.contains(input) && out.runs[input];
                inputRuns = inputRuns || runs;
                inputMissing = inputMissing || (!runs && !jobFinished(worldDir, input.first, input.second,
                                                                      jobStamp(worldDir, plan, hash, input.first, input.second)));
            }
            const bool finished = !inputRuns && jobFinished(worldDir, stage, task, jobStamp(worldDir, plan, hash, stage, task));
            const bool waits = !finished && !s.only.empty() && inputMissing && stage != "city" && stage != "bake";
            out.runs[{stage, task}] = !finished && !waits;
            if (finished) ++report.skipped;
            else if (waits) ++report.left;
            else jobs.tasks.push_back(task);
        }
        report.ran = jobs.tasks.size();
        out.reports.push_back(report);
        out.jobs.push_back(std::move(jobs));
    }
    return out;
}

}  // namespace

BuildReport buildWorld(const fs::path& worldDirIn, const BuildSettings& settings, const BuildProgress& progress) {
    const auto start = std::chrono::steady_clock::now();
    const fs::path worldDir = fs::absolute(worldDirIn).lexically_normal();
    const WorldPlan plan = readPlan(worldDir);
    checkSettings(plan, settings);
    const BuildLock lock(worldDir);
    removeStaleTemporaries(worldDir);
    const std::string hash = planHash(worldDir);
    const int workers = settings.backend == "local" ? localWorkers(plan, settings) : 1;
    const int threads = settings.threadsPerJob > 0 ? settings.threadsPerJob
                        : settings.backend == "local" ? std::max(1, defaultWorkers() / workers) : 1;
    Schedule plan_ = schedule(worldDir, plan, hash, settings, threads);
    BuildReport report;
    report.stages = plan_.reports;

    // Progress counts the records on disk, whichever backend runs the jobs.
    std::vector<std::size_t> shown(plan_.jobs.size(), std::size_t(-1));
    const auto poll = [&] {
        if (!progress) return;
        for (std::size_t s = 0; s < plan_.jobs.size(); ++s) {
            std::size_t done = report.stages[s].skipped;
            for (int task : plan_.jobs[s].tasks) done += fs::exists(recordPath(worldDir, plan_.jobs[s].stage, task)) ? 1 : 0;
            if (done != shown[s]) progress(plan_.jobs[s].stage, done, report.stages[s].jobs), shown[s] = done;
        }
    };
    // Records of jobs about to run go first, so that neither progress nor a later build counts them.
    for (const StageJobs& stage : plan_.jobs)
        for (int task : stage.tasks) fs::remove(recordPath(worldDir, stage.stage, task));
    BackendContext ctx{settings.executable, worldDir, workers, settings.partition, poll};
    poll();
    if (settings.backend == "local") runLocal(plan_.jobs, ctx);
    else runSlurm(plan_.jobs, ctx);
    poll();

    bool complete = true;
    for (std::size_t s = 0; s < plan_.jobs.size(); ++s) {
        const std::string& stage = plan_.jobs[s].stage;
        const std::vector<std::string> names = stageJobs(plan, stage);
        for (int task : plan_.jobs[s].tasks)
            if (!jobFinished(worldDir, stage, task, jobStamp(worldDir, plan, hash, stage, task)))
                report.stages[s].failed.push_back(jobLabel(stage, names[std::size_t(task)]));
        complete = complete && report.stages[s].failed.empty();
    }
    if (complete) {
        writeTileset(worldDir, plan, [&](const std::string& stage, int task) {
            return jobFinished(worldDir, stage, task, jobStamp(worldDir, plan, hash, stage, task));
        });
        report.manifest = true;
    }
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

void runJob(const fs::path& worldDirIn, const std::string& stage, int task, int threads, const fs::path& executable) {
    const auto start = std::chrono::steady_clock::now();
    const fs::path worldDir = fs::absolute(worldDirIn).lexically_normal();
    const WorldPlan plan = readPlan(worldDir);
    const std::vector<std::string> names = stageJobs(plan, stage);
    if (names.empty()) {
        const std::vector<std::string> all = expandStages(plan, {std::begin(kStages), std::end(kStages)});
        std::string list;
        for (const std::string& a : all) list += (list.empty() ? "" : ", ") + a;
        throw InputError(format("--stage: this world has no jobs of stage \"{}\" (its stages: {})", stage, list));
    }
    if (task < 0 || std::size_t(task) >= names.size())
        throw InputError(format("--task {}: stage \"{}\" has {} jobs (0 to {})", task, stage, names.size(), names.size() - 1));
    // A job of a local build ends with it (the build's own process ended: nobody will read the
    // result, and a rerun must not race it).
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() == 1) throw InputError("the world build that started this job has ended");
    // The stamp of the inputs as this job finds them: its record says what it was made from.
    const Stamp stamp = jobStamp(worldDir, plan, planHash(worldDir), stage, task);
    std::error_code ec;
    fs::remove(recordPath(worldDir, stage, task), ec);  // a failure leaves no record of an older run
    const std::vector<std::string> outputs = runStageJob(worldDir, plan, stage, task, threads, executable);
    writeRecord(worldDir, stage, task, names[std::size_t(task)], outputs, stamp);
    rusage self{}, children{};
    ::getrusage(RUSAGE_SELF, &self);
    ::getrusage(RUSAGE_CHILDREN, &children);
    const auto seconds = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
    std::printf("job %s %s: %.2f s wall, %.2f s CPU (children %.2f s), peak memory %.0f MB (children %.0f MB)\n", stage.c_str(),
                names[std::size_t(task)].c_str(), std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                seconds(self.ru_utime) + seconds(self.ru_stime), seconds(children.ru_utime) + seconds(children.ru_stime),
                double(self.ru_maxrss) / 1024.0, double(children.ru_maxrss) / 1024.0);
}

}  // namespace dawnforge::world
