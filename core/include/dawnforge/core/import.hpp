#pragma once
// Mesh import: OBJ (tinyobjloader) and glTF/GLB (tinygltf) into one core Mesh.
#include <dawnforge/core/mesh.hpp>

#include <filesystem>

namespace dawnforge {

// Reads a whole file as one mesh in world space (glTF node transforms applied,
// OBJ groups merged, polygons triangulated). Chooses the reader by extension
// (.obj, .gltf, .glb). Throws InputError naming the file if it is missing, empty,
// unparsable, has no triangles, a non-finite coordinate or an index out of range.
Mesh loadMesh(const std::filesystem::path& file);

}  // namespace dawnforge
