#pragma once
// Roofs on any simple footprint: flat with a parapet, hip and gable from CGAL's 2D straight
// skeleton (CGAL 5.5 has no skeleton extrusion: a skeleton vertex's height is its offset
// time times the pitch), and shed.
#include <dawnforge/core/mesh.hpp>
#include <dawnforge/procgen/geometry2d.hpp>

#include <cstdint>

namespace dawnforge::procgen {

enum class RoofType { Flat, Hip, Gable, Shed };
const char* roofTypeName(RoofType type);  // "flat", "hip", "gable", "shed"

struct RoofSettings {
    RoofType type = RoofType::Flat;
    double pitch = 0.6;          // rise per metre of run (hip, gable, shed)
    double parapetHeight = 0.9;  // flat
    double parapetWidth = 0.3;   // flat
    double slabThickness = 0.25; // flat: the roof slab under the parapet
    std::size_t frontEdge = 0;   // gable: the ridge runs parallel to this edge; shed: the high side
    std::uint8_t roofMaterial = 8;   // pitched roof faces
    std::uint8_t flatMaterial = 9;   // flat roof surface
    std::uint8_t wallMaterial = 2;   // gable ends, shed sides, parapet
    std::uint8_t trimMaterial = 7;   // parapet coping
};

struct Roof {
    Mesh mesh;          // closed (watertight, outward normals), flat normals, uv0 in metres, materialIds
    double height = 0;  // top of the roof above `baseHeight`
};

// The roof over `footprint` (counter-clockwise), standing on the plane y = baseHeight.
Roof buildRoof(std::span<const glm::dvec2> footprint, double baseHeight, const RoofSettings& settings);

}  // namespace dawnforge::procgen
