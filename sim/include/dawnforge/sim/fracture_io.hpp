#pragma once
// The files of `dawnforge fracture` (ARCHITECTURE.md, File formats): the scene that
// becomes fragments.glb (one node per piece, named piece_NNNN, translated to its centre
// of mass, mesh relative to it) and the text of fracture.json.
#include <dawnforge/core/scene.hpp>
#include <dawnforge/sim/fracture.hpp>

#include <string>
#include <string_view>

namespace dawnforge::sim {

Scene fractureScene(const FractureResult& result);

// fracture.json: input (file, triangles, volume), seed, settings, and per piece id, name,
// volume, mass, center_of_mass, inertia (about the centre of mass), triangles, closed;
// plus bonds between touching pieces: a, b, area, centroid, normal. A building's fracture
// (fractureParts; `building` >= 0, `inputFile` its city folder) adds input.building, the
// parts, each piece's part and material, and each bond's strength.
std::string fractureJson(const FractureResult& result, const FractureSettings& settings, std::string_view inputFile,
                         int building = -1);

}  // namespace dawnforge::sim
