#include "commands.hpp"

#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/validate.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/sim/fracture.hpp>
#include <dawnforge/sim/fracture_io.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace dawnforge::cli {

namespace {

constexpr int kMaxPiecesWithoutForce = 20000;

// Seed points: one "x y z" per line; blank lines and lines starting with # are skipped.
std::vector<glm::dvec3> readPoints(const std::filesystem::path& file) {
    std::ifstream in(file);
    if (!in) throw InputError(format("{}: cannot read the points file", file.string()));
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

}  // namespace

int runFracture(const FractureOptions& options, const CommonOptions& common) {
    const auto start = std::chrono::steady_clock::now();
    sim::FractureSettings settings;
    settings.pieces = options.pieces;
    settings.seed = options.seed;
    if (!options.impact.empty()) settings.impact = glm::dvec3(options.impact[0], options.impact[1], options.impact[2]);
    settings.impactRadius = options.radius;
    settings.density = options.density;
    settings.interiorMaterial = static_cast<std::uint8_t>(options.interiorMaterial);
    settings.interiorUvScale = options.uvScale;
    settings.minVolume = options.minVolume;
    settings.levels = options.levels;
    settings.levelPieces = options.levelPieces;
    settings.roughness = options.roughness;
    settings.roughScale = options.roughScale;
    settings.voxelSize = options.voxelSize;
    if (!options.pointsFile.empty()) settings.points = readPoints(options.pointsFile);
    const std::size_t requested = settings.points.empty() ? std::size_t(settings.pieces) : settings.points.size();
    if (requested > std::size_t(kMaxPiecesWithoutForce) && !options.force)
        throw InputError(format("{} pieces is above the limit of {}; add --force if you mean it", requested,
                                kMaxPiecesWithoutForce));
    if (settings.levels > 0 && !settings.impact) throw InputError("--levels needs --impact (pieces near it are re-fractured)");

    Mesh mesh = loadMesh(options.file);
    if (options.repair) {
        RepairReport report;
        mesh = repairMesh(mesh, &report);
        for (const std::string& action : report.actions)
            std::fprintf(stderr, "dawnforge fracture: repaired %s: %s\n", options.file.string().c_str(), action.c_str());
    }
    sim::FractureResult result;
    {
        StderrProgress progress("fracture", !common.quiet && stderrIsTerminal());
        try {
            result = sim::fractureMesh(mesh, settings, progress.callback());
        } catch (const InputError& e) {
            throw InputError(format("{}: {}", options.file.string(), e.what()));
        }
    }
    ensureOutputDirectory(options.outputDir);
    exporters::writeGlb(sim::fractureScene(result), options.outputDir / "fragments.glb");
    writeFileAtomically(options.outputDir / "fracture.json", sim::fractureJson(result, settings, options.file.string()));

    double total = 0.0;
    for (const sim::FracturePiece& p : result.pieces) total += p.mass.volume;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("fractured %s into %zu pieces with %zu bonds in %.2f s\n", options.file.string().c_str(),
                result.pieces.size(), result.bonds.size(), seconds);
    std::printf("  volume %.6g m^3, pieces add up to %.6g (relative error %.1e)%s\n", result.inputVolume, total,
                std::abs(total - result.inputVolume) / result.inputVolume,
                result.merged ? format(", {} slivers merged", result.merged).c_str() : "");
    std::printf("  wrote %s and %s\n", (options.outputDir / "fragments.glb").string().c_str(),
                (options.outputDir / "fracture.json").string().c_str());
    return 0;
}

}  // namespace dawnforge::cli
