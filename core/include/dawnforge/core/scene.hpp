#pragma once
// A scene: meshes and a node hierarchy, as the exporters write it (one glTF node per node).
#include <dawnforge/core/mesh.hpp>

#include <glm/gtc/quaternion.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace dawnforge {

struct Node {
    std::string name;
    glm::vec3 translation{0.0f};
    glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};  // glm order (w, x, y, z); files use (x, y, z, w)
    glm::vec3 scale{1.0f};
    std::int32_t mesh = -1;                       // index into Scene::meshes, or -1
    std::vector<std::uint32_t> children;          // indices into Scene::nodes
    std::string extrasJson;                       // a JSON object for glTF "extras", or empty
};

// A node's motion: keys at times in seconds (increasing), each list interpolated linearly
// (rotations by slerp, as glTF's LINEAR). An empty list leaves that property still.
struct NodeTrack {
    std::uint32_t node = 0;  // index into Scene::nodes
    std::vector<float> translationTimes;
    std::vector<glm::vec3> translations;
    std::vector<float> rotationTimes;
    std::vector<glm::quat> rotations;
};

struct Animation {
    std::string name;
    std::vector<NodeTrack> tracks;
};

// Per-feature properties, one table (glTF: EXT_structural_metadata's property table; a mesh
// with a featureId is that row, EXT_mesh_features). Each property fills one of its columns.
struct FeatureProperty {
    std::string name;
    std::vector<std::uint32_t> uints;  // UINT32, or
    std::vector<float> floats;         // FLOAT32, or
    std::vector<std::string> strings;  // STRING (UTF-8)
};

struct FeatureTable {
    std::string className;  // empty: the scene has no features
    std::size_t count = 0;  // rows
    std::vector<FeatureProperty> properties;
};

struct Scene {
    std::vector<Mesh> meshes;
    std::vector<Node> nodes;
    std::vector<std::uint32_t> roots;  // nodes without a parent, in order
    std::vector<Animation> animations;
    std::string extrasJson;            // a JSON object for the scene's "extras", or empty
    FeatureTable features;

    // Adds a mesh and a root node that shows it; returns the node's index.
    std::uint32_t addMeshNode(Mesh mesh, glm::vec3 translation = glm::vec3(0.0f));
};

}  // namespace dawnforge
