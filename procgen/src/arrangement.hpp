#pragma once
// Plain-data front of the CGAL code the city plan needs (docs/STYLE.md 2): the faces of a
// segment arrangement. Every CGAL type stays in arrangement.cpp.
#include <dawnforge/procgen/geometry2d.hpp>

#include <span>
#include <vector>

namespace dawnforge::procgen {

// One segment of the street graph; `weight` travels with it into the faces (the plan uses
// half the street's width).
struct ArrangementSegment {
    glm::dvec2 a{0.0};
    glm::dvec2 b{0.0};
    double weight = 0.0;
};

// A bounded face of the arrangement: its outer boundary (counter-clockwise) and, per edge i
// (polygon[i] -> polygon[i+1]), the largest weight of the segments that edge lies on.
struct ArrangementFace {
    Polygon2 polygon;
    std::vector<double> edgeWeight;
    bool hasHoles = false;
};

// The bounded faces of the arrangement of `segments`, computed exactly (the only rounding
// is of the output vertices to double). Dangling edges (edges with the same face on both
// sides) are removed first, so a face's boundary is a simple polygon. Deterministic: the
// face order depends only on the input.
std::vector<ArrangementFace> arrangementFaces(std::span<const ArrangementSegment> segments);

}  // namespace dawnforge::procgen
