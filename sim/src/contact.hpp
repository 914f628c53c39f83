#pragma once
// Where fracture pieces touch: the overlap of their cut faces, measured triangle by triangle
// on each cut plane. A bond's area, centroid and normal come from what two pieces really
// share, whatever made them: a cell cut into islands, a piece fractured again into smaller
// ones next to pieces that were not, noisy (rough) cut surfaces.
#include <glm/vec3.hpp>

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace dawnforge::sim::detail {

struct CutFace {
    std::uint32_t piece = 0;
    std::pair<std::int64_t, std::int64_t> plane;  // the two cells whose bisector it lies on (low, high)
    glm::dvec3 a, b, c;                           // counter-clockwise seen from outside the piece
};

struct Contact {
    std::uint32_t a = 0, b = 0;  // pieces, a < b
    double area = 0.0;
    glm::dvec3 centroid{0.0};
    glm::dvec3 normal{0.0};      // unit, from a to b
};

// Every pair of pieces whose cut faces on one plane overlap (facing each other) by more than
// `minArea`, in the order of (a, b). Faces are compared in the plane's projection: triangles
// with the same corners share their whole area; others share the area of their clipped
// intersection, lifted back to 3D. Deterministic: sums run in a fixed order.
std::vector<Contact> contacts(std::span<const CutFace> faces, double minArea);

}  // namespace dawnforge::sim::detail
