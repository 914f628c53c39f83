#pragma once
// The files around `dawnforge simulate` (ARCHITECTURE.md, File formats): reading a
// fracture folder (fracture.json + fragments.glb) and writing / reading a simulation
// folder (sim.json + transforms.bin, with a copy of fragments.glb so the folder stands
// on its own).
#include <dawnforge/core/scene.hpp>
#include <dawnforge/sim/rigidbody.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace dawnforge::sim {

struct FractureFolder {
    std::vector<RigidPiece> pieces;  // in fracture.json order; meshes from fragments.glb
    std::vector<Bond> bonds;         // with their own strength where fracture.json gives one
    std::uint64_t seed = 0;
    std::string input;               // input.file as given to fracture (a city folder for a building)
    int building = -1;               // input.building: the city building it is, or -1
};

// Reads DIR/fracture.json and DIR/fragments.glb and checks that they agree (same pieces,
// same names in order, node translation = centre of mass). Throws InputError naming the
// file and the problem.
FractureFolder loadFracture(const std::filesystem::path& dir);

// sim.json: format, version, frames, fps, pieces, substeps, gravity, seed, triggers,
// ground, glue, solver settings, energy summary, debris, piece names (the pieces', then the
// chips') and the transforms layout.
std::string simulationJson(const SimulationResult& result, const SimulationSettings& settings,
                           std::span<const RigidPiece> pieces, std::string_view fractureDir);

// Writes DIR/transforms.bin (little-endian float32, frame-major, 7 floats per piece per
// frame), DIR/turns.bin (float32, frames × pieces), DIR/dust.bin when there is dust
// (float32, frames × puffs × 5) and DIR/sim.json, each atomically.
// The copy of fragments.glb is the caller's to write.
void writeSimulation(const std::filesystem::path& dir, const SimulationResult& result,
                     const SimulationSettings& settings, std::span<const RigidPiece> pieces,
                     std::string_view fractureDir);

struct SimulationFolder {
    int frames = 0;
    double fps = 0.0;
    std::vector<std::string> names;  // per piece
    std::vector<float> transforms;   // frames × pieces × 7
    std::vector<float> turns;        // frames × pieces, or empty when turns.bin is absent
    std::vector<Mesh> meshes;        // per piece, from fragments.glb then debris.glb: relative to the pivot, world axes
    std::size_t chips = 0;           // the last `chips` pieces are debris (sim.json's debris.chips)
    std::vector<float> dust;         // frames × dustPuffs × (x y z size opacity), from dust.bin
    std::size_t dustPuffs = 0;
};

// The chips of a simulation with debris as a scene to write as DIR/debris.glb: one node per
// chip at its rest pivot, named as in sim.json, like fragments.glb's pieces.
Scene debrisScene(const SimulationResult& result);

// Reads DIR/sim.json, DIR/transforms.bin, DIR/turns.bin if present, DIR/fragments.glb and
// DIR/debris.glb when sim.json counts chips, DIR/dust.bin when it counts puffs,
// and checks them against each other (size,
// finite values, unit quaternions). Throws InputError naming the file and the problem.
SimulationFolder loadSimulation(const std::filesystem::path& dir);

}  // namespace dawnforge::sim
