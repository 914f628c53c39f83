#pragma once
// The core mesh: plain indexed triangles with optional per-vertex attributes
// (docs/STYLE.md 3). Units are metres, +Y up, counter-clockwise front faces (as glTF).
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <glm/mat4x4.hpp>

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace dawnforge {

// 16 material IDs (materials.hpp). Files written before _MATERIAL_ID carried them in COLOR_0
// as binary RGBA, id = R + 2G + 4B + 8A; the glTF reader still decodes those.
inline constexpr int kMaterialIdCount = 16;
glm::u8vec4 materialIdToColor(std::uint8_t id);  // each channel 0 or 255
std::uint8_t colorToMaterialId(glm::vec4 rgba);  // channels in [0,1], thresholded at 0.5

struct Mesh {
    std::string name;
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> indices;     // three per triangle
    std::vector<glm::vec3> normals;         // empty, or one per vertex
    std::vector<glm::vec2> uv0;             // surface UVs (metres for generated content)
    std::vector<glm::vec2> uv1;             // second set (VAT lookup, lightmap)
    std::vector<glm::vec2> uv2;             // third set (VAT pivot)
    std::vector<glm::vec2> uv3;             // fourth set (VAT pivot)
    std::vector<std::uint8_t> materialIds;  // empty, or one per vertex, 0..15
    std::vector<std::uint32_t> pieceIds;    // empty, or one per vertex
    std::int32_t featureId = -1;            // ≥ 0: every vertex is that row of the scene's FeatureTable

    std::size_t vertexCount() const { return positions.size(); }
    std::size_t triangleCount() const { return indices.size() / 3; }
};

struct Bounds {
    glm::dvec3 min{0.0};
    glm::dvec3 max{0.0};
};
Bounds computeBounds(std::span<const glm::vec3> positions);  // zero bounds when empty

// Throws InputError naming `source` if the mesh cannot be used: no triangles, a
// non-finite coordinate, an index out of range, an attribute of the wrong length,
// a material ID above 15.
void validateMeshData(const Mesh& mesh, std::string_view source);

// Appends `src` to `dst`, transforming positions and normals. Attributes present in only
// one of the two are filled with zeros (material 0, piece 0) for the other's vertices.
void appendMesh(Mesh& dst, const Mesh& src, const glm::mat4& transform = glm::mat4(1.0f));

// Reverses the winding of every triangle and negates normals.
void flipOrientation(Mesh& mesh);

// For each vertex, the index of the first vertex with exactly the same position
// (vertex welding by position, as topology needs it for meshes split at UV seams).
std::vector<std::uint32_t> weldByPosition(std::span<const glm::vec3> positions);

}  // namespace dawnforge
