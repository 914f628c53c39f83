#include <dawnforge/core/scene.hpp>

namespace dawnforge {

std::uint32_t Scene::addMeshNode(Mesh mesh, glm::vec3 translation) {
    Node node;
    node.name = mesh.name;
    node.translation = translation;
    node.mesh = static_cast<std::int32_t>(meshes.size());
    meshes.push_back(std::move(mesh));
    const auto index = static_cast<std::uint32_t>(nodes.size());
    nodes.push_back(std::move(node));
    roots.push_back(index);
    return index;
}

}  // namespace dawnforge
