#pragma once
// The jobs of `world build`, one per tile, HLOD node or destroyed building (jobs.cpp), and
// their records (records.cpp).
#include <dawnforge/world/plan.hpp>

#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace dawnforge::world {

// What one stage has to do: its jobs' names, in task order ("0_1", "1_0_0", "building_00042").
std::vector<std::string> stageJobs(const WorldPlan& plan, const std::string& stage);
// The stages `world build` runs for the stage names given ("hlod" becomes hlod1..hlodK).
std::vector<std::string> expandStages(const WorldPlan& plan, const std::vector<std::string>& stages);

// Runs one job; returns the paths it made, relative to the world folder (files or folders).
std::vector<std::string> runStageJob(const std::filesystem::path& worldDir, const WorldPlan& plan, const std::string& stage,
                                     int task, int threads, const std::filesystem::path& executable);

// What a job's record must agree with to count as finished: the plan (a hash of plan.json)
// and the records of the jobs whose outputs it read (an HLOD node its tiles' city and bake,
// or its children; a destroyed building its tile's city), so that a job reruns when the plan
// changed or an input was made again.
struct Stamp {
    std::string plan, inputs;
};
std::string planHash(const std::filesystem::path& worldDir);
Stamp jobStamp(const std::filesystem::path& worldDir, const WorldPlan& plan, const std::string& planHash,
               const std::string& stage, int task);
// The jobs whose outputs a job reads, as (stage, task).
std::vector<std::pair<std::string, int>> jobInputs(const WorldPlan& plan, const std::string& stage, int task);

// DIR/jobs/STAGE/K.json: the job's stamp and outputs, each file with its size and hash,
// written last.
std::filesystem::path recordPath(const std::filesystem::path& worldDir, const std::string& stage, int task);
void writeRecord(const std::filesystem::path& worldDir, const std::string& stage, int task, const std::string& job,
                 const std::vector<std::string>& outputs, const Stamp& stamp);
// Whether the record is there with this stamp and every file it lists is there with its size.
bool jobFinished(const std::filesystem::path& worldDir, const std::string& stage, int task, const Stamp& stamp);

// DIR/tileset.json (tileset.cpp): the tiles and HLOD nodes whose jobs `finished` says are done.
void writeTileset(const std::filesystem::path& worldDir, const WorldPlan& plan,
                  const std::function<bool(const std::string& stage, int task)>& finished);

}  // namespace dawnforge::world
