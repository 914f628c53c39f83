#pragma once
// Closed primitive meshes for defaults, demos and tests (outward, counter-clockwise).
#include <dawnforge/core/mesh.hpp>

namespace dawnforge {

// An axis-aligned box with 24 vertices (flat normals, UVs in metres), material `materialId`.
Mesh makeBox(glm::vec3 min, glm::vec3 max, std::uint8_t materialId = 0);

// A geodesic sphere: an icosahedron subdivided `subdivisions` times and projected on the
// sphere; 20·4^s triangles sharing their vertices (smooth normals).
Mesh makeIcosphere(float radius, int subdivisions);

// A closed tower of `floors` storeys on the ground (y = 0), footprint width × depth centred
// on the origin. Each storey's walls are separate quads alternating between two material
// IDs (wall, window band); the mesh is closed and manifold once welded by position.
Mesh makeTower(int floors, float storeyHeight, float width, float depth, std::uint8_t wallMaterial = 2,
               std::uint8_t bandMaterial = 3);

}  // namespace dawnforge
