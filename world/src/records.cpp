// Job records: DIR/jobs/STAGE/K.json (jobs.hpp).
#include "jobs.hpp"

#include <dawnforge/bake/bake_folder.hpp>
#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/read_file.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>

namespace dawnforge::world {

namespace fs = std::filesystem;

namespace {

// Every file of `outputs` (a folder stands for the files under it), sorted.
std::vector<std::string> filesOf(const fs::path& worldDir, const std::vector<std::string>& outputs) {
    std::vector<std::string> files;
    for (const std::string& out : outputs) {
        const fs::path p = worldDir / out;
        if (!fs::is_directory(p)) {
            files.push_back(out);
            continue;
        }
        for (const fs::directory_entry& e : fs::recursive_directory_iterator(p))
            if (e.is_regular_file()) files.push_back(fs::relative(e.path(), worldDir).generic_string());
    }
    std::sort(files.begin(), files.end());
    return files;
}

}  // namespace

fs::path recordPath(const fs::path& worldDir, const std::string& stage, int task) {
    return worldDir / "jobs" / stage / format("{}.json", task);
}

std::string planHash(const fs::path& worldDir) {
    return bake::hashText(bake::hashFileBytes(readBinaryFile(worldDir / "plan.json")));
}

std::vector<std::pair<std::string, int>> jobInputs(const WorldPlan& plan, const std::string& stage, int task) {
    std::vector<std::pair<std::string, int>> inputs;
    if (stage == "destroy") inputs.emplace_back("city", tileTask(plan, plan.destroy[std::size_t(task)].tile));
    const std::vector<const HlodNode*> level = hlodStageNodes(plan, stage);
    if (level.empty()) return inputs;
    const HlodNode& node = *level[std::size_t(task)];
    if (node.level == 1)
        for (glm::ivec2 t : node.tiles) inputs.emplace_back("city", tileTask(plan, t)), inputs.emplace_back("bake", tileTask(plan, t));
    const std::vector<const HlodNode*> below = hlodStageNodes(plan, hlodStage(node.level - 1));
    for (std::size_t k = 0; k < below.size(); ++k)
        if (below[k]->index / 2 == node.index) inputs.emplace_back(hlodStage(node.level - 1), int(k));
    return inputs;
}

Stamp jobStamp(const fs::path& worldDir, const WorldPlan& plan, const std::string& hash, const std::string& stage, int task) {
    Stamp stamp{hash, ""};
    std::error_code ec;
    for (const auto& [s, k] : jobInputs(plan, stage, task)) {
        const fs::path record = recordPath(worldDir, s, k);
        stamp.inputs += fs::is_regular_file(record, ec) ? bake::hashText(bake::hashFileBytes(readBinaryFile(record))) : "-";
        stamp.inputs += " ";
    }
    return stamp;
}

void writeRecord(const fs::path& worldDir, const std::string& stage, int task, const std::string& job,
                 const std::vector<std::string>& outputs, const Stamp& stamp) {
    nlohmann::ordered_json files = nlohmann::ordered_json::array();
    for (const std::string& f : filesOf(worldDir, outputs)) {
        const std::vector<std::byte> bytes = readBinaryFile(worldDir / f);
        files.push_back({{"path", f}, {"bytes", bytes.size()}, {"hash", bake::hashText(bake::hashFileBytes(bytes))}});
    }
    const nlohmann::ordered_json j{{"stage", stage}, {"task", task},       {"job", job},
                                   {"plan", stamp.plan}, {"inputs", stamp.inputs}, {"files", std::move(files)}};
    ensureOutputDirectory(recordPath(worldDir, stage, task).parent_path());
    writeFileAtomically(recordPath(worldDir, stage, task), j.dump(1) + "\n");
}

bool jobFinished(const fs::path& worldDir, const std::string& stage, int task, const Stamp& stamp) {
    const fs::path record = recordPath(worldDir, stage, task);
    std::error_code ec;
    if (!fs::is_regular_file(record, ec)) return false;
    try {
        const nlohmann::json j = nlohmann::json::parse(readTextFile(record));
        if (j.at("plan").get<std::string>() != stamp.plan || j.at("inputs").get<std::string>() != stamp.inputs) return false;
        for (const nlohmann::json& f : j.at("files")) {
            const fs::path p = worldDir / f.at("path").get<std::string>();
            if (!fs::is_regular_file(p, ec) || fs::file_size(p, ec) != f.at("bytes").get<std::uintmax_t>()) return false;
        }
        return true;
    } catch (const std::exception&) {
        return false;  // a damaged record: the job runs again
    }
}

}  // namespace dawnforge::world
