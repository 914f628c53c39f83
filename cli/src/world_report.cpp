// A world's report.html: what each stage's jobs made (their records, jobs/STAGE/K.json), how
// long they took (the last line of each log, logs/STAGE_K.log: "job ...: S s wall, ..."), and
// the parts of the page that a world has (no pictures: world build renders none).
#include "world_report.hpp"

#include "report.hpp"

#include <dawnforge/core/format.hpp>
#include <dawnforge/core/read_file.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <regex>

namespace dawnforge::cli {

namespace {

namespace fs = std::filesystem;

// The entries of `dir` whose names match `name`, sorted; none when it cannot be read.
std::vector<fs::path> entriesOf(const fs::path& dir, const std::regex& name) {
    std::vector<fs::path> out;
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
        if (std::regex_match(it->path().filename().string(), name)) out.push_back(it->path());
    std::sort(out.begin(), out.end());
    return out;
}

// Every file the stage's finished jobs list in their records, relative to the world's folder.
std::vector<fs::path> recordedFiles(const fs::path& worldDir, const std::string& stage) {
    std::vector<fs::path> files;
    for (const fs::path& record : entriesOf(worldDir / "jobs" / stage, std::regex(R"([0-9]+\.json)"))) {
        try {
            const nlohmann::json j = nlohmann::json::parse(readTextFile(record));
            for (const nlohmann::json& f : j.at("files")) files.push_back(f.at("path").get<std::string>());
        } catch (const std::exception&) {
            continue;  // a damaged record: the build redoes its job; the report leaves it out
        }
    }
    std::sort(files.begin(), files.end());
    return files;
}

// The wall seconds of the stage's jobs, added up from their logs' last "job ..." lines.
double loggedSeconds(const fs::path& worldDir, const std::string& stage) {
    static const std::regex kLine(R"(job \S+ [^\n]*: ([0-9.]+) s wall)");
    double total = 0.0;
    for (const fs::path& log : entriesOf(worldDir / "logs", std::regex(stage + R"(_[0-9]+\.log)"))) {
        try {
            const std::string text = readTextFile(log);
            double last = 0.0;
            for (std::sregex_iterator it(text.begin(), text.end(), kLine), end; it != end; ++it) last = std::stod((*it)[1].str());
            total += last;
        } catch (const std::exception&) {
            continue;
        }
    }
    return total;
}

ReportStage stageOf(const fs::path& worldDir, const world::StageReport& s) {
    ReportStage stage;
    stage.name = s.stage;
    stage.made = format("{} jobs: {} run now, {} already done, {} failed", s.jobs, s.ran, s.skipped, s.failed.size());
    if (s.left > 0) stage.made += format(", {} left", s.left);
    stage.outputs = recordedFiles(worldDir, s.stage);
    stage.seconds = loggedSeconds(worldDir, s.stage);
    return stage;
}

}  // namespace

fs::path writeWorldReport(const fs::path& worldDir, const world::BuildReport& build) {
    ReportInputs report;
    const fs::path dir = worldDir.lexically_normal();  // "w/" names w too
    report.title = "dawnforge world: " + (dir.has_filename() ? dir.filename() : dir.parent_path().filename()).string();
    for (const world::StageReport& s : build.stages) report.stages.push_back(stageOf(worldDir, s));
    for (const fs::path& tile : entriesOf(worldDir / "tiles", std::regex(R"([0-9]+_[0-9]+)")))
        if (fs::exists(tile / "bake" / "bake.json")) {
            report.bakeDir = tile / "bake";
            break;
        }
    for (const fs::path& building : entriesOf(worldDir / "destroy", std::regex(R"(building_[0-9]+)")))
        if (fs::exists(building / "sim" / "sim.json")) {
            report.fractureDir = building / "fracture";
            report.simDir = building / "sim";
            break;
        }
    return writeReport(report, worldDir);
}

}  // namespace dawnforge::cli
