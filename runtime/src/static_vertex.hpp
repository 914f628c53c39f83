#pragma once
// The vertex layout of every static mesh the renderer draws (buildings, ground, VAT pieces,
// tree species), private to the renderer.
#include "gl.hpp"

#include <dawnforge/core/mesh.hpp>

#include <glm/glm.hpp>

#include <cstdint>

namespace dawnforge::runtime {

// 64 bytes per vertex.
struct StaticVertex {
    glm::vec3 position;
    glm::vec3 normal;
    glm::vec2 uv0, uv1, uv2;
    std::uint8_t material;
    std::uint8_t pad[3];
    glm::vec3 light;  // baked lightmap: (u, v, layer) in the lightmap array; layer < 0: none
};

// Vertex i of `m` moved by `world` (normals by `normalMatrix`), with no baked light.
StaticVertex staticVertex(const Mesh& m, std::size_t i, const glm::mat4& world, const glm::mat3& normalMatrix);
// Attributes 0-5 and 9 of `vao` from binding 0 in the StaticVertex layout.
void vertexLayout(GLuint vao);
// [lo, hi] grown around the eight corners of the box [boxMin, boxMax] placed by `model`.
void growPlacedBox(glm::dvec3 boxMin, glm::dvec3 boxMax, const glm::mat4& model, glm::dvec3& lo, glm::dvec3& hi);
// vertexLayout, the vertex and index buffers, and per-instance attributes 6 (uvec4: the atlas
// blocks) and 7 (uint: the building id) from binding 1 at the given offsets.
void instancedLayout(GLuint vao, GLuint vertices, GLuint indices, GLuint instances, GLsizei instanceStride,
                     GLuint blocksOffset, GLuint buildingOffset);

}  // namespace dawnforge::runtime
