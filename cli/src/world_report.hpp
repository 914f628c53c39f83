#pragma once
// DIR/report.html of a world (`world build`): its stages from the jobs' records and logs, the
// first baked tile's first building, the first destroyed building's simulation and pieces.
#include <dawnforge/world/build.hpp>

#include <filesystem>

namespace dawnforge::cli {

// Writes WORLD_DIR/report.html and returns its path; throws only when it cannot write.
std::filesystem::path writeWorldReport(const std::filesystem::path& worldDir, const world::BuildReport& build);

}  // namespace dawnforge::cli
