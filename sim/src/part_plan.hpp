// How a building's parts share a fracture (part_plan.cpp).
#pragma once

#include <dawnforge/sim/fracture.hpp>
#include <dawnforge/sim/fracture_parts.hpp>

#include <span>
#include <vector>

namespace dawnforge::sim::detail {

// Each part's own settings: its cells (Voronoi parts share `pieces` by weighted volume, and a
// thin one gets at least one cell per (2s)² of one face and a slender one one per 2s of its
// length, s the mean cell's size, so that a trim band round a building is not one 46 m ring;
// shards and splinters by the area of one face of the plate), density, seed and grain.
// `result.parts` holds each part's style and volume (describeParts); each part's cell count goes
// into it too.
std::vector<FractureSettings> planParts(std::span<const FracturePart> parts, const PartsFractureSettings& settings,
                                        FractureResult& result);

}  // namespace dawnforge::sim::detail
