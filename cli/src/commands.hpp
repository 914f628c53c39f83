#pragma once
// The commands of the dawnforge executable: each parses nothing and computes nothing of
// its own; it wires the stages of the libraries together (ARCHITECTURE.md, cli/).
#include <filesystem>
#include <cstdint>
#include <string>
#include <vector>

namespace dawnforge::cli {

struct CommonOptions {
    bool quiet = false;  // no progress on stderr
};

struct InspectOptions {
    std::filesystem::path file;
    std::filesystem::path repairOutput;  // empty: no repair
};
int runInspect(const InspectOptions& options, const CommonOptions& common);

struct FractureOptions {
    std::filesystem::path file;
    std::filesystem::path outputDir;
    std::filesystem::path pointsFile;  // empty: sample seeds
    int pieces = 50;
    std::uint64_t seed = 1;
    std::vector<double> impact;        // empty, or x, y, z
    double radius = 1.0;
    double density = 2400.0;
    int interiorMaterial = 15;
    double uvScale = 1.0;
    double minVolume = 0.0;
    int levels = 0;
    int levelPieces = 8;
    bool force = false;
    bool repair = false;
    double roughness = 0.0;
    double roughScale = 0.0;
    double voxelSize = 0.0;
};
int runFracture(const FractureOptions& options, const CommonOptions& common);

struct DemoOptions {
    std::filesystem::path outputDir;
    int floors = 8;
};
int runDemo(const DemoOptions& options, const CommonOptions& common);

}  // namespace dawnforge::cli
