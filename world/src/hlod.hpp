#pragma once
// HLOD meshes of a world's quadtree (ARCHITECTURE.md, the world's hlod stage). A level-1 node
// merges the content of its (up to) four tiles, a level-L node the meshes of its four level
// L-1 children; each merged mesh is simplified with meshoptimizer (meshopt_simplify, open
// borders locked so that neighbouring nodes still meet), and its geometric error is the
// simplifier's own error, in metres, plus the largest of its children's. Where meshopt_simplify
// stops short of the ratio (flat-shaded shells and ground lock most of their vertices: from
// level 2 up), a second pass clusters the vertices, on one octree for every material, to the
// ratio; it does not lock open borders, but its error bounds how far an open border's point moves.
//
// Vertex attributes of an HLOD mesh: POSITION, NORMAL, TEXCOORD_0 (metres, atlas tiling, as
// the city's), _MATERIAL_ID (material id), and the bake folded in: TEXCOORD_1 = (sky, sun bounce)
// and TEXCOORD_2 = (ao, lamps), the decoded channels of the bake (bake_folder.hpp:
// value = range * (stored / 255)^2 with ranges 2, 2, 1, 4), sampled at the vertex's lightmap
// UV; a vertex with no bake gets sky 1, sun bounce 1, ao 1, lamps 0.
#include <dawnforge/core/mesh.hpp>

#include <filesystem>
#include <vector>

namespace dawnforge::world {

struct HlodSettings {
    double ratio = 0.25;        // target index count, as a fraction of the merged mesh's
    double maxError = 0.05;     // meshopt's relative error limit (of the mesh's extent)
};

struct HlodMesh {
    Mesh mesh;
    double error = 0.0;         // metres: meshopt's error in world units, plus the second pass's
                                // where it ran (the farthest a point on an open edge, or the plane
                                // of a triangle, is from where the triangle's corner went)
};

// What a tile gives its level-1 HLOD node, in the frame of the tile's city.glb (positions as
// loadMeshNodes' world matrices place them): every building's LOD1 shell, the ground tile with
// its kerbs and the far land beyond the world's edge, and each tree as two crossed vertical cards (its crown's
// width and height, material `ground` like the leaves) with its trunk; lamps are dropped.
// When TILE_DIR/bake/ is there (bake::readBake), the bake is folded in as described above.
// Throws InputError when city.glb is missing or unreadable.
Mesh tileHlodSource(const std::filesystem::path& tileDir);

// Merges `children` (all in one frame) and simplifies the result to about `settings.ratio`
// of its triangles (at most 5 % above; the second pass stops at or a little under it).
// Degenerate triangles are dropped; an empty input gives an empty mesh with error 0.
HlodMesh simplifyHlod(const std::vector<Mesh>& children, const HlodSettings& settings = {});

}  // namespace dawnforge::world
