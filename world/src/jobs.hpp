#pragma once
// The jobs of `world build`, one per tile, HLOD node or destroyed building (jobs.cpp), and
// their records (records.cpp).
#include <dawnforge/world/plan.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace dawnforge::world {

// What one stage has to do: its jobs' names, in task order ("0_1", "1_0_0", "building_00042").
std::vector<std::string> stageJobs(const WorldPlan& plan, const std::string& stage);
// The stages `world build` runs for the stage names given ("hlod" becomes hlod1..hlodK).
std::vector<std::string> expandStages(const WorldPlan& plan, const std::vector<std::string>& stages);

// Runs one job; returns the paths it made, relative to the world folder (files or folders).
std::vector<std::string> runStageJob(const std::filesystem::path& worldDir, const WorldPlan& plan, const std::string& stage,
                                     int task, const std::filesystem::path& executable);

// DIR/jobs/STAGE/K.json: the job's outputs, each file with its size and hash, written last.
std::filesystem::path recordPath(const std::filesystem::path& worldDir, const std::string& stage, int task);
void writeRecord(const std::filesystem::path& worldDir, const std::string& stage, int task, const std::string& job,
                 const std::vector<std::string>& outputs);
// Whether the record is there and every file it lists is there with its size.
bool jobFinished(const std::filesystem::path& worldDir, const std::string& stage, int task);

// DIR/tileset.json (tileset.cpp).
void writeTileset(const std::filesystem::path& worldDir, const WorldPlan& plan);

}  // namespace dawnforge::world
