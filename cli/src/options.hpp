#pragma once
// What every command's options share: the common flags, the one --threads option, the one
// W x H parser, X,Y,Z points, options that name one of a few choices, and progress on stderr.
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/progress.hpp>
#include <dawnforge/core/validate.hpp>

#include <CLI/CLI.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <filesystem>
#include <optional>
#include <string>

namespace dawnforge::cli {

struct CommonOptions {
    bool quiet = false;  // no progress on stderr
    int threads = 0;     // 0: all cores
};

// The --threads option of a command that runs parallel work.
void addThreadsOption(CLI::App& command, CommonOptions& common);

// "W x H" (e.g. "1280x720"): two finite numbers separated by x or X. Throws InputError
// naming `option` and `unit` otherwise.
glm::dvec2 parseSize(const std::string& text, const char* option, const char* unit);
std::string sizeText(glm::dvec2 size);  // "500x500", the form parseSize reads

// "X,Y,Z": three finite numbers separated by commas. Throws InputError naming `option` otherwise.
glm::dvec3 parsePoint(const std::string& text, const char* option);

// An option naming one of a few choices: `parse` turns a name into the value (or nullopt), and
// an unknown name is refused as "unknown WHAT 'NAME' (expected CHOICES)". Help shows `shown`.
template <typename T, typename Parse>
CLI::Option* addChoiceOption(CLI::App& command, const std::string& name, T& target, Parse parse, const char* what,
                             const char* choices, const std::string& description, const std::string& shown) {
    return command
        .add_option_function<std::string>(
            name,
            [&target, parse, what, choices](const std::string& text) {
                const std::optional<T> value = parse(text);
                if (!value) throw InputError(format("unknown {} '{}' (expected {})", what, text, choices));
                target = *value;
            },
            description)
        ->default_str(shown);
}

// An "X,Y,Z" option (parsePoint) that sets `target` when given.
CLI::Option* addPointOption(CLI::App& command, const std::string& name, std::optional<glm::dvec3>& target,
                            const std::string& description);

// Progress on stderr for `label`, shown when stderr is a terminal and --quiet is not given.
StderrProgress progressFor(const char* label, const CommonOptions& common);

// repairMesh() on the mesh of `file`, its errors naming the file.
Mesh repairFile(const Mesh& mesh, const std::filesystem::path& file, RepairReport* report);

}  // namespace dawnforge::cli
