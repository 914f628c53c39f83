#include "commands.hpp"

#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/progress.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/procgen/city.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>

namespace dawnforge::cli {

namespace {

glm::dvec2 parseSize(const std::string& text) {
    static const std::regex kSize(R"(\s*([-+0-9.eE]+)\s*[xX]\s*([-+0-9.eE]+)\s*)");
    std::smatch m;
    double w = NAN, d = NAN;
    if (std::regex_match(text, m, kSize)) {
        try {
            std::size_t used1 = 0, used2 = 0;
            w = std::stod(m[1].str(), &used1);
            d = std::stod(m[2].str(), &used2);
            if (used1 != m[1].str().size() || used2 != m[2].str().size()) w = NAN;
        } catch (const std::exception&) {
            w = NAN;
        }
    }
    if (!std::isfinite(w) || !std::isfinite(d))
        throw InputError(format("--size: expected W x D in metres, e.g. 500x400 (got \"{}\")", text));
    return {w, d};
}

glm::ivec2 parseTile(const std::string& text) {
    static const std::regex kTile(R"(\s*(-?[0-9]+)\s*,\s*(-?[0-9]+)\s*)");
    std::smatch m;
    if (!std::regex_match(text, m, kTile) || m[1].length() > 6 || m[2].length() > 6)
        throw InputError(format("--tile: expected I,J (tile column and row, from 0), e.g. 1,0 (got \"{}\")", text));
    return {std::stoi(m[1].str()), std::stoi(m[2].str())};
}

procgen::CityRecipe readRecipe(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in || std::filesystem::is_directory(file)) throw InputError(format("{}: cannot read the recipe", file.string()));
    std::stringstream text;
    text << in.rdbuf();
    return procgen::parseRecipe(text.str(), file.string());
}

}  // namespace

procgen::CityPlan writeCityFolder(const procgen::CitySettings& settings, const std::filesystem::path& outputDir,
                                  const CommonOptions& common) {
    const auto start = std::chrono::steady_clock::now();
    procgen::City city;
    {
        StderrProgress progress("city", !common.quiet && stderrIsTerminal());
        city = procgen::generateCity(settings, progress.callback());
    }
    const std::string report = procgen::cityReportJson(city);
    const procgen::CityCounts counts = procgen::countCity(city);
    const std::size_t blocks = city.plan.blocks.size();
    const Scene scene = procgen::takeCityScene(city);
    ensureOutputDirectory(outputDir);
    exporters::writeGlb(scene, outputDir / "city.glb");
    writeFileAtomically(outputDir / "city.json", report);

    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("generated %s%.0f x %.0f m, seed %llu: %zu blocks, %zu buildings, %zu rooms in %.2f s\n",
                settings.tile ? format("tile {},{} of ", settings.tile->x, settings.tile->y).c_str() : "",
                settings.size.x, settings.size.y, static_cast<unsigned long long>(settings.seed), blocks, counts.buildings,
                counts.rooms, seconds);
    std::printf("  triangles: LOD0 %zu, LOD1 %zu\n", counts.trianglesLod0, counts.trianglesLod1);
    std::printf("  wrote %s and %s\n", (outputDir / "city.glb").string().c_str(), (outputDir / "city.json").string().c_str());
    return std::move(city.plan);
}

int runCity(const CityOptions& options, const CommonOptions& common) {
    procgen::CitySettings settings;
    if (!options.recipeFile.empty()) settings.recipe = readRecipe(options.recipeFile);
    settings.seed = options.seed;
    settings.size = parseSize(options.size);
    settings.tileSize = options.tileSize;
    if (!options.tile.empty()) settings.tile = parseTile(options.tile);
    writeCityFolder(settings, options.outputDir, common);
    return 0;
}

}  // namespace dawnforge::cli
