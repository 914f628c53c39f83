#pragma once
// How `world build` runs its jobs (ARCHITECTURE.md, the world's backends). A job is one
// process: `dawnforge world job DIR --stage STAGE --task K --threads C`, run with that argv
// (never through a shell, so a folder's name can hold anything). Its stdout and stderr go to
// DIR/logs/STAGE_K.log. It writes its outputs under temporary names, renames them, and then
// its record DIR/jobs/STAGE/K.json: the caller reads the records to know what finished,
// whichever backend ran the job; a backend only runs processes and waits.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace dawnforge::world {

// One stage's tasks that are still to do. Stages run in the order given: a task of a later
// stage starts only once every task of the earlier stages has ended (finished or failed).
struct StageJobs {
    std::string stage;        // "city", "bake", "hlod1", "hlod2", ..., "destroy"
    std::vector<int> tasks;   // task indices, ascending
    int cpus = 1;             // cores per task (the job's --threads)
    int memoryMb = 4096;      // memory per task (Slurm --mem)
};

struct BackendContext {
    std::filesystem::path executable;  // the dawnforge executable (absolute)
    std::filesystem::path worldDir;    // absolute
    int workers = 1;                   // local: jobs at once
    std::string partition;             // slurm: --partition, empty for the default
    // Called about once a second while jobs run (progress); never from another thread.
    std::function<void()> poll = [] {};
};

// The argv of task `task` of `stage`, the executable first.
std::vector<std::string> jobArguments(const BackendContext& ctx, const std::string& stage, int task, int cpus);
// DIR/logs/STAGE_K.log
std::filesystem::path jobLog(const std::filesystem::path& worldDir, const std::string& stage, int task);

// Runs every task on this machine, `workers` processes at a time; returns when all ended.
// Throws InputError when a process cannot be started at all.
void runLocal(const std::vector<StageJobs>& stages, const BackendContext& ctx);

// Submits one Slurm job array per stage (`sbatch --array`, each array depending on the one
// before with afterany), waits until none is queued or running, and returns. Throws InputError
// with one line when sbatch is missing or no controller answers.
void runSlurm(const std::vector<StageJobs>& stages, const BackendContext& ctx);

}  // namespace dawnforge::world
