#pragma once
// Where the parts of an assembly touch, before any fracture: triangles of different parts
// that lie on one plane, face each other and overlap. Each group of such triangles (joined
// through overlaps) gets a plane key of its own, so that the pieces cut from the parts keep
// these faces as contact faces (pieces.hpp) and bond across parts. Plain data, no CGAL.
#include "pieces.hpp"

#include <dawnforge/core/mesh.hpp>

#include <span>
#include <vector>

namespace dawnforge::sim::detail {

// The plane key of contact group `id` (distinct from cut planes, whose cells are >= 0, and
// from kSurface).
inline PlaneKey contactKey(std::int64_t id) { return {-2 - id, -2 - id}; }
inline bool isContactKey(const PlaneKey& key) { return key.first <= -2; }

struct PartContacts {
    std::vector<std::vector<PlaneKey>> planes;  // per part, per triangle: a contact key, or kSurface
    std::size_t groups = 0;                     // contact groups found
};

// Triangles of two parts touch when their planes are within `distance` (m) of each other,
// their normals opposite within about 0.06 degrees, and their overlap seen along the normal
// exceeds `minArea` (m^2). Deterministic: groups are numbered by their first triangle.
PartContacts partContacts(std::span<const Mesh* const> parts, double distance = 1e-4, double minArea = 1e-8);

}  // namespace dawnforge::sim::detail
