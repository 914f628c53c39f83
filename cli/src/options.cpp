#include "options.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>

#include <cmath>
#include <optional>
#include <regex>

namespace dawnforge::cli {

void addThreadsOption(CLI::App& command, CommonOptions& common) {
    command.add_option("--threads", common.threads, "Worker threads (0: all cores); output does not depend on it")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
}

namespace {

// The whole of `text` as a finite number, or nothing.
std::optional<double> finiteNumber(const std::string& text) {
    try {
        std::size_t used = 0;
        const double v = std::stod(text, &used);
        if (used == text.size() && std::isfinite(v)) return v;
    } catch (const std::exception&) {
    }
    return std::nullopt;
}

}  // namespace

glm::dvec2 parseSize(const std::string& text, const char* option, const char* unit) {
    static const std::regex kSize(R"(\s*([-+0-9.eE]+)\s*[xX]\s*([-+0-9.eE]+)\s*)");
    std::smatch m;
    if (std::regex_match(text, m, kSize)) {
        const std::optional<double> w = finiteNumber(m[1].str()), h = finiteNumber(m[2].str());
        if (w && h) return {*w, *h};
    }
    throw InputError(format("{}: expected W x H in {}, e.g. 500x400 (got \"{}\")", option, unit, text));
}

glm::dvec3 parsePoint(const std::string& text, const char* option) {
    static const std::regex kPoint(R"(\s*([^,\s]+)\s*,\s*([^,\s]+)\s*,\s*([^,\s]+)\s*)");
    std::smatch m;
    if (std::regex_match(text, m, kPoint)) {
        const std::optional<double> x = finiteNumber(m[1].str()), y = finiteNumber(m[2].str()), z = finiteNumber(m[3].str());
        if (x && y && z) return {*x, *y, *z};
    }
    throw InputError(format("{}: expected X,Y,Z, three numbers separated by commas, e.g. 6,12.8,2 (got \"{}\")", option, text));
}

std::string sizeText(glm::dvec2 size) { return format("{}x{}", size.x, size.y); }

CLI::Option* addPointOption(CLI::App& command, const std::string& name, std::optional<glm::dvec3>& target,
                            const std::string& description) {
    const std::string option = name.substr(0, name.find(','));
    return command
        .add_option_function<std::string>(
            name, [&target, option](const std::string& text) { target = parsePoint(text, option.c_str()); }, description)
        ->type_name("X,Y,Z");
}

StderrProgress progressFor(const char* label, const CommonOptions& common) {
    return StderrProgress(label, !common.quiet && stderrIsTerminal());
}

Mesh repairFile(const Mesh& mesh, const std::filesystem::path& file, RepairReport* report) {
    try {
        return repairMesh(mesh, report);
    } catch (const InputError& e) {
        throw InputError(format("{}: {}", file.string(), e.what()));
    }
}

}  // namespace dawnforge::cli
