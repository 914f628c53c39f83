#pragma once
// Mesh import into core Meshes: OBJ (tinyobjloader), glTF 2.0 / GLB (tinygltf), OFF (CGAL's
// reader) and every other format Assimp reads (FBX, Collada, STL, PLY, 3DS, ...), in metres,
// +Y up.
#include <dawnforge/core/mesh.hpp>

#include <glm/mat4x4.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace dawnforge {

// Where a file's reader runs. A user's file goes to a child process (isolate.hpp): a reader
// that crashes, hangs or corrupts its heap there costs one error line, not the process. A
// file that dawnforge wrote itself (a city's, a world's tiles) may be read in this process,
// which costs no fork, from any thread.
enum class ReadIn { child, thisProcess };

// Reads a whole file as one mesh in world space (node transforms applied, OBJ groups
// merged, polygons triangulated, points and lines skipped). Chooses the reader by
// extension: .obj, .gltf, .glb, .off, or any extension Assimp knows. FBX and Collada units and up
// axes are converted to metres and +Y up; STL, PLY, OFF and OBJ coordinates are taken as
// metres as they are. Only glTF carries material IDs (_MATERIAL_ID, or an older file's
// binary COLOR_0); other formats leave
// materialIds empty. Throws InputError naming the file if it is missing, empty,
// unparsable, glTF 1.0 or Draco-compressed, has no triangles, a non-finite coordinate or
// an index out of range; a ReaderFailure if the reader crashed or ran past its limits.
Mesh loadMesh(const std::filesystem::path& file, ReadIn where = ReadIn::child);

// A node that shows a mesh: its name, its world transform (with the file's unit and axis
// conversion), its mesh in the node's own coordinates (all primitives merged) and its parent:
// the nearest ancestor that shows a mesh, as an index into the same list (-1: none).
struct MeshNode {
    std::string name;
    glm::mat4 world{1.0f};
    Mesh mesh;
    int parent = -1;
};

// Every node of a file that shows a mesh, in hierarchy order (depth first from the
// default scene's roots, so a parent comes before its children); an OBJ or OFF file is one
// node named after the file. Each node's mesh
// gets the checks of loadMesh.
std::vector<MeshNode> loadMeshNodes(const std::filesystem::path& file, ReadIn where = ReadIn::child);

}  // namespace dawnforge
