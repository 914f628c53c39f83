#include "commands.hpp"
#include "folders.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/read_file.hpp>
#include <dawnforge/core/materials.hpp>
#include <dawnforge/core/validate.hpp>
#include <dawnforge/procgen/city_building.hpp>
#include <dawnforge/sim/fracture.hpp>
#include <dawnforge/sim/fracture_parts.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

namespace dawnforge::cli {

namespace {

constexpr int kMaxPiecesWithoutForce = 20000;

// What only the command line has; everything else is the library's FractureSettings.
struct FractureOptions {
    std::filesystem::path file;
    std::filesystem::path outputDir;
    std::filesystem::path pointsFile;  // empty: sample seeds
    bool force = false;
    bool repair = false;
    sim::FractureSettings settings;
    // A building of a city folder (FILE is then the folder): broken part by part.
    std::optional<int> building;
    sim::PartsFractureSettings parts;       // its `common` is `settings` when run
    std::vector<std::string> strengths;     // "MATERIAL=PA"
    CLI::App* app = nullptr;                // to tell which options were given
};

// "MATERIAL=PA" (a material name of core/materials.hpp, glue strength in pascals) into the table.
void applyStrengths(const std::vector<std::string>& specs, std::array<sim::MaterialBreak, kMaterialCount>& table) {
    for (const std::string& spec : specs) {
        const std::size_t eq = spec.find('=');
        const std::string name = spec.substr(0, eq);
        int id = -1;
        for (int m = 0; m < kMaterialCount; ++m)
            if (name == materialName(std::uint8_t(m))) id = m;
        if (eq == std::string::npos || id < 0)
            throw InputError(format("--strength {}: expected MATERIAL=PA with MATERIAL one of asphalt, paving, brick, "
                                    "concrete, plaster, glass, metal, trim, roof_tiles, roof_flat, wood, interior_wall, "
                                    "floor, ground, sand, rubble", spec));
        char* end = nullptr;
        const double pa = std::strtod(spec.c_str() + eq + 1, &end);
        if (end == spec.c_str() + eq + 1 || *end != '\0' || !std::isfinite(pa) || pa < 0.0)
            throw InputError(format("--strength {}: the strength must be a number of pascals, not negative", spec));
        table[std::size_t(id)].strength = pa;
    }
}

// Seed points: one "x y z" per line; blank lines and lines starting with # are skipped.
std::vector<glm::dvec3> readPoints(const std::filesystem::path& file) {
    std::istringstream in(readTextFile(file));
    std::vector<glm::dvec3> points;
    std::string line;
    for (std::size_t lineNo = 1; std::getline(in, line); ++lineNo) {
        const std::size_t first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#') continue;
        std::istringstream s(line);
        glm::dvec3 p;
        std::string rest;
        if (!(s >> p.x >> p.y >> p.z) || (s >> rest))
            throw InputError(format("{}: line {}: expected three numbers 'x y z'", file.string(), lineNo));
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw InputError(format("{}: line {}: the point is not finite", file.string(), lineNo));
        points.push_back(p);
    }
    if (points.empty()) throw InputError(format("{}: no points in the file", file.string()));
    return points;
}

Mesh loadInput(const FractureOptions& options) {
    Mesh mesh = loadMesh(options.file);
    if (!options.repair) return mesh;
    RepairReport report;
    mesh = repairFile(mesh, options.file, &report);
    for (const std::string& action : report.actions)
        std::fprintf(stderr, "dawnforge fracture: repaired %s: %s\n", options.file.string().c_str(), action.c_str());
    return mesh;
}

// How the cells were cut, when some could not be cut the chosen way.
std::string fallbackNote(const sim::FractureResult& result) {
    if (result.fallbackCells == 0) return "";
    return format(", {} of {} cells cut by corefinement (the restricted Voronoi diagram could not close them)",
                  result.fallbackCells, result.cells);
}

void printSummary(const FractureOptions& options, const sim::FractureResult& result, double seconds) {
    double total = 0.0;
    for (const sim::FracturePiece& p : result.pieces) total += p.mass.volume;
    std::printf("fractured %s into %zu pieces with %zu bonds in %.2f s\n", options.file.string().c_str(),
                result.pieces.size(), result.bonds.size(), seconds);
    std::printf("  volume %.6g m^3, pieces add up to %.6g (relative error %.1e)%s%s\n", result.inputVolume, total,
                std::abs(total - result.inputVolume) / result.inputVolume,
                result.merged ? format(", {} slivers merged", result.merged).c_str() : "", fallbackNote(result).c_str());
    std::printf("  wrote %s and %s\n", (options.outputDir / "fragments.glb").string().c_str(),
                (options.outputDir / "fracture.json").string().c_str());
}

// Options that mean nothing for a building's parts are refused rather than ignored.
void checkBuildingOptions(const FractureOptions& options) {
    for (const char* name : {"--points", "--density", "--roughness", "--rough-scale", "--voxel", "--repair"})
        if (options.app->count(name) > 0)
            throw InputError(format("{} does not apply with --building (a building's parts are closed, weigh what their "
                                    "materials weigh and are cut with planar faces)", name));
}

void printBuildingSummary(const FractureOptions& options, const sim::FractureResult& result, double seconds) {
    double total = 0.0;
    for (const sim::FracturePiece& p : result.pieces) total += p.mass.volume;
    std::printf("fractured building %d of %s (%zu parts) into %zu pieces with %zu bonds in %.2f s\n", *options.building,
                options.file.string().c_str(), result.parts.size(), result.pieces.size(), result.bonds.size(), seconds);
    std::array<std::size_t, kMaterialCount> perMaterial{};
    for (const sim::FracturePiece& p : result.pieces) ++perMaterial[p.material];
    std::printf("  pieces per material:");
    for (int m = 0; m < kMaterialCount; ++m)
        if (perMaterial[std::size_t(m)]) std::printf(" %s %zu", materialName(std::uint8_t(m)), perMaterial[std::size_t(m)]);
    std::printf("\n  volume %.6g m^3, pieces add up to %.6g (relative error %.1e)%s\n", result.inputVolume, total,
                std::abs(total - result.inputVolume) / result.inputVolume, fallbackNote(result).c_str());
    std::printf("  wrote %s and %s\n", (options.outputDir / "fragments.glb").string().c_str(),
                (options.outputDir / "fracture.json").string().c_str());
}

int runBuildingFracture(FractureOptions& options, const CommonOptions& common) {
    const auto start = std::chrono::steady_clock::now();
    checkBuildingOptions(options);
    options.parts.common = options.settings;
    applyStrengths(options.strengths, options.parts.materials);
    procgen::CityBuilding building = procgen::loadCityBuilding(options.file, *options.building);
    std::vector<sim::FracturePart> parts;
    for (procgen::CityBuildingPart& part : building.parts)
        parts.push_back({procgen::partKindName(part.kind), part.material, std::move(part.mesh)});
    sim::FractureResult result;
    {
        StderrProgress progress = progressFor("fracture", common);
        try {
            result = sim::fractureParts(parts, options.parts, progress.callback());
        } catch (const InputError& e) {
            throw InputError(format("{}: building {}: {}", options.file.string(), *options.building, e.what()));
        }
    }
    if (result.pieces.size() > std::size_t(kMaxPiecesWithoutForce) && !options.force)
        throw InputError(format("{} pieces is above the limit of {}; add --force if you mean it", result.pieces.size(),
                                kMaxPiecesWithoutForce));
    writeFractureFolder(result, options.settings, options.file.string(), options.outputDir, *options.building);
    printBuildingSummary(options, result, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return 0;
}

int runFracture(FractureOptions& options, const CommonOptions& common) {
    if (options.building) return runBuildingFracture(options, common);
    for (const char* name : {"--shard-size", "--splinter-width", "--splinter-length", "--strength"})
        if (options.app->count(name) > 0) throw InputError(format("{} needs --building (it is for a city's building)", name));
    const auto start = std::chrono::steady_clock::now();
    sim::FractureSettings& settings = options.settings;
    if (!options.pointsFile.empty()) settings.points = readPoints(options.pointsFile);
    const std::size_t requested = settings.points.empty() ? std::size_t(settings.pieces) : settings.points.size();
    if (requested > std::size_t(kMaxPiecesWithoutForce) && !options.force)
        throw InputError(format("{} pieces is above the limit of {}; add --force if you mean it", requested,
                                kMaxPiecesWithoutForce));
    const Mesh mesh = loadInput(options);
    sim::FractureResult result;
    {
        StderrProgress progress = progressFor("fracture", common);
        try {
            result = sim::fractureMesh(mesh, settings, progress.callback());
        } catch (const RepairableMeshError& e) {
            throw InputError(format("{}: {}{}", options.file.string(), e.what(),
                                    options.repair ? "" : "; add --repair to repair it first"));
        } catch (const InputError& e) {
            throw InputError(format("{}: {}", options.file.string(), e.what()));
        }
    }
    for (const std::string& note : result.notes)
        std::fprintf(stderr, "dawnforge fracture: %s: %s\n", options.file.string().c_str(), note.c_str());
    writeFractureFolder(result, settings, options.file.string(), options.outputDir);
    printSummary(options, result, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return 0;
}

void addSeedOptions(CLI::App& cmd, FractureOptions& o) {
    sim::FractureSettings& s = o.settings;
    cmd.add_option("--pieces", s.pieces, "Number of Voronoi cells (seeds), exact for uniform sampling; with --building, shared by the parts by volume, thin and slender parts getting more")
        ->check(CLI::PositiveNumber)->capture_default_str();
    cmd.add_option("--seed", s.seed, "Random seed")->capture_default_str();
    addPointOption(cmd, "--impact", s.impact, "Cluster smaller pieces around this point X,Y,Z (m)");
    cmd.add_option("--radius", s.impactRadius, "Impact radius (m)")->check(CLI::PositiveNumber)->capture_default_str();
    cmd.add_option("--points", o.pointsFile, "Seed points file, one 'x y z' per line (instead of --pieces)");
    cmd.add_option("--levels", s.levels, "Fracture pieces within --radius of --impact again, this many times")
        ->check(CLI::Range(0, 4))->capture_default_str();
    cmd.add_option("--level-pieces", s.levelPieces, "Pieces per re-fractured piece")
        ->check(CLI::Range(2, 1000))->capture_default_str();
}

void addPieceOptions(CLI::App& cmd, sim::FractureSettings& s) {
    cmd.add_option("--density", s.density, "Density (kg/m^3)")->check(CLI::PositiveNumber)->capture_default_str();
    cmd.add_option_function<int>(
           "--interior-material", [&s](int id) { s.interiorMaterial = std::uint8_t(id); },
           "Material ID of cut faces (0-15)")
        ->check(CLI::Range(0, 15))->default_str(std::to_string(s.interiorMaterial));
    cmd.add_option("--uv-scale", s.interiorUvScale, "Metres per UV unit on cut faces")
        ->check(CLI::PositiveNumber)->capture_default_str();
    cmd.add_option("--min-volume", s.minVolume, "Merge pieces below this volume (m^3) into their largest neighbour")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    cmd.add_option("--roughness", s.roughness,
                   "Noisy cut surfaces of this amplitude (m), meshed from OpenVDB level sets; 0: exact planar cuts")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    cmd.add_option("--rough-scale", s.roughScale, "Noise wavelength (m); 0: four times --roughness")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    cmd.add_option("--voxel", s.voxelSize, "Level-set voxel size (m) for --roughness; 0: automatic")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    const std::map<std::string, sim::FractureMethod> methods{{"rvd", sim::FractureMethod::Rvd},
                                                             {"corefine", sim::FractureMethod::Corefine}};
    cmd.add_option("--method", s.method,
                   "How cells cut the mesh: rvd (the restricted Voronoi diagram, in one pass; a cell it cannot close "
                   "falls back to corefine) or corefine (one CGAL corefinement per cell, slower)")
        ->transform(CLI::CheckedTransformer(methods, CLI::ignore_case))
        ->default_str("rvd");
}

void addBuildingOptions(CLI::App& cmd, FractureOptions& o) {
    sim::PartsFractureSettings& p = o.parts;
    cmd.add_option("--building", o.building,
                   "Fracture this building of the city folder FILE (its id in city.json), part by part by material")
        ->check(CLI::NonNegativeNumber);
    cmd.add_option("--shard-size", p.shardSize, "With --building: glass breaks into shards about this wide (m)")
        ->check(CLI::PositiveNumber)->capture_default_str();
    cmd.add_option("--splinter-width", p.splinterWidth, "With --building: wood splinters about this wide (m)")
        ->check(CLI::PositiveNumber)->capture_default_str();
    cmd.add_option("--splinter-length", p.splinterLength, "With --building: and this long along the grain (m)")
        ->check(CLI::PositiveNumber)->capture_default_str();
    cmd.add_option("--strength", o.strengths,
                   "With --building: MATERIAL=PA, the glue strength of a material's bonds (repeatable; a bond takes "
                   "the weaker of its two pieces'; defaults: concrete 3e6, brick and plaster 1.5e6, wood 9e5, glass 1.5e5)");
}

}  // namespace

Command addFracture(CLI::App& app, CommonOptions& common) {
    auto options = std::make_shared<FractureOptions>();
    CLI::App* cmd =
        app.add_subcommand("fracture", "Fracture a closed mesh into Voronoi pieces: DIR/fragments.glb, DIR/fracture.json");
    options->app = cmd;
    cmd->add_option("FILE", options->file, "Closed mesh (or, with --building, a city folder): glTF/GLB, OBJ, FBX, STL, PLY, OFF, DAE, 3DS, ... (metres, +Y up after import)")->required();
    cmd->add_option("-o,--output", options->outputDir, "Output folder")->required();
    addSeedOptions(*cmd, *options);
    addPieceOptions(*cmd, options->settings);
    addBuildingOptions(*cmd, *options);
    cmd->add_flag("--force", options->force, "Allow more than 20,000 pieces");
    cmd->add_flag("--repair", options->repair, "Repair an open or inconsistent mesh first (and say so on stderr)");
    addThreadsOption(*cmd, common);
    return {cmd, [options, &common] { return runFracture(*options, common); }};
}

}  // namespace dawnforge::cli
