#pragma once
// Mesh import: OBJ (tinyobjloader) and glTF/GLB (tinygltf) into one core Mesh.
#include <dawnforge/core/mesh.hpp>

#include <glm/mat4x4.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace dawnforge {

// Reads a whole file as one mesh in world space (glTF node transforms applied,
// OBJ groups merged, polygons triangulated). Chooses the reader by extension
// (.obj, .gltf, .glb). Throws InputError naming the file if it is missing, empty,
// unparsable, has no triangles, a non-finite coordinate or an index out of range.
Mesh loadMesh(const std::filesystem::path& file);

// A glTF node that shows a mesh: its name, its world transform and its mesh in the
// node's own coordinates (all primitives merged).
struct MeshNode {
    std::string name;
    glm::mat4 world{1.0f};
    Mesh mesh;
};

// Every node of a glTF/GLB file that shows a mesh, in hierarchy order (depth first from
// the default scene's roots). Each node's mesh gets the checks of loadMesh.
std::vector<MeshNode> loadMeshNodes(const std::filesystem::path& file);

}  // namespace dawnforge
