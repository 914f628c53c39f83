#pragma once
// `world build`: one job per tile (or HLOD node, or destroyed building) per stage, run by a
// backend (this machine, or Slurm job arrays), then the 3D Tiles manifest (ARCHITECTURE.md,
// section 9). Every job writes under temporary names, renames, then writes its record
// DIR/jobs/STAGE/K.json (what it made, with sizes and hashes): a build run again skips the
// jobs whose record and outputs are there and redoes the others, so an interrupted build
// ends with the same bytes as one that never was.
#include <dawnforge/world/plan.hpp>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace dawnforge::world {

struct BuildSettings {
    std::string backend = "local";   // "local" or "slurm"
    int jobs = 0;                    // local: jobs at once (0: one per core)
    int threadsPerJob = 0;           // cores per job (0: the cores / jobs, at least 1)
    std::vector<std::string> stages{"city", "bake", "hlod", "destroy"};
    std::vector<glm::ivec2> only;    // tiles to build (empty: all); HLOD nodes and destroyed buildings over them
    std::string partition;           // slurm: --partition (empty: the default)
    int memoryMb = 0;                // slurm: --mem per job (0: the plan's bake budget + 512 MB)
    std::filesystem::path executable;  // the dawnforge executable that runs the jobs
};

struct StageReport {
    std::string stage;
    std::size_t jobs = 0, skipped = 0, left = 0, ran = 0;  // left: --only, and their inputs are not built
    std::vector<std::string> failed;  // the failed jobs' names ("tile 1_0", "hlod 1_0_0", "building 00042")
};

struct BuildReport {
    std::vector<StageReport> stages;
    bool manifest = false;           // tileset.json written (only when no job failed)
    double seconds = 0.0;
};

// Progress: called with the stage and its jobs finished of total (recorded on disk).
using BuildProgress = std::function<void(const std::string& stage, std::size_t done, std::size_t total)>;

// Throws InputError for a folder without plan.json, an unknown stage or backend, a tile not in
// the plan, or a backend that cannot run (no Slurm controller).
BuildReport buildWorld(const std::filesystem::path& worldDir, const BuildSettings& settings,
                       const BuildProgress& progress = {});

// Runs task `task` of `stage` (a job's process: `dawnforge world job`). Throws InputError for a
// stage or task that is not in the plan, and whatever the stage throws. `executable` runs the
// destroy stage's commands, with `threads` (0: all cores).
void runJob(const std::filesystem::path& worldDir, const std::string& stage, int task, int threads,
            const std::filesystem::path& executable);

}  // namespace dawnforge::world
