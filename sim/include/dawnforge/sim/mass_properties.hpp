#pragma once
// Mass properties of a closed triangle mesh of uniform density, exact for the polyhedron
// (divergence theorem). Method: D. Eberly, "Polyhedral Mass Properties (Revisited)", 2002.
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <span>

namespace dawnforge::sim {

struct MassProperties {
    double volume = 0.0;             // m^3, signed (negative when the mesh is inside out)
    double mass = 0.0;               // kg: volume × density
    glm::dvec3 centerOfMass{0.0};    // m
    glm::dmat3 inertia{0.0};         // kg·m^2, about the centre of mass, in world axes
};

// `positions` and `indices` (three per triangle) describe a closed, outward-oriented mesh.
MassProperties computeMassProperties(std::span<const glm::dvec3> positions, std::span<const std::uint32_t> indices,
                                     double density);

}  // namespace dawnforge::sim
