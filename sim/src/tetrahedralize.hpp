#pragma once
// TetGen 1.5, kept to this one translation unit: a constrained tetrahedralisation of a
// closed triangle surface (plain arrays in and out).
#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace dawnforge::sim::detail {

struct Tetrahedra {
    std::vector<glm::dvec3> points;
    std::vector<std::array<std::uint32_t, 4>> tets;
};

// Throws InputError if TetGen refuses the surface (it is open or self-intersecting).
Tetrahedra tetrahedralize(std::span<const glm::dvec3> points, std::span<const std::array<std::uint32_t, 3>> triangles);

}  // namespace dawnforge::sim::detail
