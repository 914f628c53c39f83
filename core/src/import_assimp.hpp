#pragma once
// Mesh import through Assimp: FBX, Collada, STL, PLY, 3DS and the other formats it
// reads. Private to core (docs/STYLE.md 2): no Assimp type leaves import_assimp.cpp.
#include <dawnforge/core/import.hpp>

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace dawnforge::detail {

// Whether Assimp has an importer for files ending in `extension` (".fbx", lower case).
bool assimpReadsExtension(std::string_view extension);

// Every node of the file that shows a mesh, in hierarchy order (depth first), with world
// transforms that bring the file's units and axes to metres, +Y up, right-handed.
// Throws InputError naming `name` (the file as the user gave it) if Assimp cannot read it.
std::vector<MeshNode> loadAssimpNodes(const std::filesystem::path& file, const std::string& name);

}  // namespace dawnforge::detail
