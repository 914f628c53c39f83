#include "commands.hpp"
#include "folders.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/read_file.hpp>
#include <dawnforge/procgen/city.hpp>

#include <memory>
#include <regex>

namespace dawnforge::cli {

namespace {

struct CityOptions {
    std::filesystem::path outputDir;
    std::filesystem::path recipeFile;
    procgen::CitySettings settings;
};

glm::ivec2 parseTile(const std::string& text) {
    static const std::regex kTile(R"(\s*(-?[0-9]+)\s*,\s*(-?[0-9]+)\s*)");
    std::smatch m;
    if (!std::regex_match(text, m, kTile) || m[1].length() > 6 || m[2].length() > 6)
        throw InputError(format("--tile: expected I,J (tile column and row, from 0), e.g. 1,0 (got \"{}\")", text));
    return {std::stoi(m[1].str()), std::stoi(m[2].str())};
}

int runCity(CityOptions& options, const CommonOptions& common) {
    if (!options.recipeFile.empty())
        options.settings.recipe = procgen::parseRecipe(readTextFile(options.recipeFile), options.recipeFile.string());
    writeCityFolder(options.settings, options.outputDir, common);
    return 0;
}

}  // namespace

Command addCity(CLI::App& app, CommonOptions& common) {
    auto o = std::make_shared<CityOptions>();
    procgen::CitySettings& s = o->settings;
    CLI::App* cmd =
        app.add_subcommand("city", "Generate a city district with buildings and interiors: DIR/city.glb, DIR/city.json");
    cmd->add_option("-o,--output", o->outputDir, "Output folder")->required();
    cmd->add_option("--seed", s.seed, "Random seed")->capture_default_str();
    cmd->add_option_function<std::string>(
           "--size", [&s](const std::string& text) { s.size = parseSize(text, "--size", "metres"); },
           "District size WxD in metres (x east, y north)")
        ->default_str(sizeText(s.size));
    cmd->add_option_function<std::string>(
        "--tile", [&s](const std::string& text) { s.tile = parseTile(text); },
        "Generate only tile I,J (identical to that tile of the whole district)");
    cmd->add_option("--tile-size", s.tileSize, "Tile size in metres")->capture_default_str();
    cmd->add_option("--recipe", o->recipeFile,
                    "JSON recipe: any parameter of streets, coast, lots, buildings, interiors, roofs (examples/recipes/)");
    addThreadsOption(*cmd, common);
    return {cmd, [o, &common] { return runCity(*o, common); }};
}

}  // namespace dawnforge::cli
