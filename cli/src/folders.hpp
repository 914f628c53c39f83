#pragma once
// The output folders of the pipeline's stages, written the same way by their commands and
// by the demo (ARCHITECTURE.md, File formats).
#include "options.hpp"

#include <dawnforge/bake/bake.hpp>
#include <dawnforge/procgen/city.hpp>
#include <dawnforge/procgen/city_building.hpp>
#include <dawnforge/sim/fracture.hpp>
#include <dawnforge/sim/rigidbody.hpp>

#include <filesystem>
#include <span>
#include <string>

namespace dawnforge::cli {

// Generates a district and writes DIR/city.glb and DIR/city.json, with progress and a
// summary; returns the district's plan (streets, coast, blocks, lots).
procgen::CityPlan writeCityFolder(const procgen::CitySettings& settings, const std::filesystem::path& dir,
                                  const CommonOptions& common);

// Bakes CITY_DIR/bake/ with progress and a summary; a budget error names the options that fix it.
void bakeCityFolder(const std::filesystem::path& cityDir, const bake::BakeSettings& settings, const CommonOptions& common);

// DIR/fragments.glb and DIR/fracture.json; `input` names the mesh in fracture.json (the city
// folder when `building` >= 0 names the building).
void writeFractureFolder(const sim::FractureResult& result, const sim::FractureSettings& settings,
                         const std::string& input, const std::filesystem::path& dir, int building = -1);

// DIR/sim.json, transforms.bin, turns.bin, a copy of FRACTURE_DIR/fragments.glb, so that
// the folder stands on its own, and debris.glb when there are chips.
void writeSimulationFolder(const sim::SimulationResult& result, const sim::SimulationSettings& settings,
                           std::span<const sim::RigidPiece> pieces, const std::filesystem::path& fractureDir,
                           const std::filesystem::path& dir);

// A city building's simulation in its city: the ground meshes (streets, kerbs, the sea floor)
// and the neighbours' shells become static colliders, the building stands on a support at its
// base over its footprint's bounds, and the ground plane goes 5 cm under the lowest ground
// point as a backstop (unless the settings give its height). `simulate` of a building's
// fracture and the demo both use it.
void placeInCity(procgen::CityBuilding building, sim::SimulationSettings& settings);

}  // namespace dawnforge::cli
