#pragma once
// The commands of the dawnforge executable: each parses nothing and computes nothing of
// its own; it wires the stages of the libraries together (ARCHITECTURE.md, cli/).
#include <dawnforge/procgen/city.hpp>

#include <filesystem>
#include <cstdint>
#include <optional>
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

struct SimulateOptions {
    std::filesystem::path fractureDir;
    std::filesystem::path outputDir;
    int frames = 120;
    double fps = 30.0;
    int substeps = 4;
    int iterations = 10;
    std::uint64_t seed = 1;
    double strength = 1e6;
    double strengthVariation = 0.2;
    double triggerTime = 0.2;
    double friction = 0.6;
    double restitution = 0.1;
    int hullVertices = 48;
    double margin = 0.01;
    bool noGround = false;
    std::optional<double> groundHeight;
    std::vector<double> projectile;           // empty, or the target x, y, z
    std::vector<double> projectileDirection;  // empty, or x, y, z
    double projectileMass = 20000.0;
    double projectileSpeed = 40.0;
    double projectileRadius = 1.0;
    std::vector<double> explosion;            // empty, or the centre x, y, z
    double explosionRadius = 5.0;
    double explosionImpulse = 5e5;
    bool collapse = false;
    std::vector<std::filesystem::path> colliders;
};
int runSimulate(const SimulateOptions& options, const CommonOptions& common);

struct VatOptions {
    std::filesystem::path simDir;
    std::filesystem::path outputDir;
    std::string preset = "native";
    bool half = false;
    int maxWidth = 1024;
    std::string name = "vat";
};
int runVat(const VatOptions& options, const CommonOptions& common);

struct CityOptions {
    std::filesystem::path outputDir;
    std::uint64_t seed = 1;
    std::string size = "500x500";
    std::string tile;           // "I,J", or empty for the whole city
    double tileSize = 250.0;
    std::filesystem::path recipeFile;
};
int runCity(const CityOptions& options, const CommonOptions& common);
// Generates a district and writes DIR/city.glb and DIR/city.json, with progress and a
// summary; returns the district's plan (streets, coast, blocks, lots).
procgen::CityPlan writeCityFolder(const procgen::CitySettings& settings, const std::filesystem::path& outputDir,
                                  const CommonOptions& common);

struct RenderOptions {
    std::filesystem::path sceneFile;
    std::filesystem::path output;
    std::string size = "1280x720";
    std::string camera;                // empty: the scene's first camera, or an overview
    std::optional<double> timeOfDay;   // hours; default: the scene's
    std::optional<int> frame;          // time = frame / fps; default: the scene's time
    bool stats = false;
    int repeat = 5;                    // --stats: timed frames after one warm-up; the median is reported
};
int runRender(const RenderOptions& options, const CommonOptions& common);

struct ViewOptions {
    std::filesystem::path sceneFile;
    std::string size = "1280x720";
    std::string camera;
    int frames = 0;  // > 0: close after this many frames (smoke tests, timing the window path)
};
int runView(const ViewOptions& options, const CommonOptions& common);

struct DemoOptions {
    std::filesystem::path outputDir;
    int floors = 8;
};
int runDemo(const DemoOptions& options, const CommonOptions& common);

}  // namespace dawnforge::cli
