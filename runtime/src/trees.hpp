#pragma once
// The city's trees on the GPU (private to the renderer). Every "tree_NNNNN" node hierarchy of
// city.glb is one tree; trees whose elements show the same meshes are one species, drawn in one
// instanced draw: its elements merged into one mesh whose TEXCOORD_1 points at each element's
// texel of its Pivot Painter 2 textures (native preset, exporters/pivot_painter.hpp), and each
// tree one instance (its trunk's transform). wind.glsl bends every element about its pivot,
// parents after children, from those textures alone: no per-element work on the CPU.
#include "gl.hpp"
#include "static_vertex.hpp"

#include <dawnforge/core/import.hpp>
#include <dawnforge/exporters/pivot_painter.hpp>
#include <dawnforge/runtime/renderer.hpp>
#include <dawnforge/runtime/scene_file.hpp>

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace dawnforge::runtime {

// Texture units the wind reads (wind.glsl).
inline constexpr GLuint kPivotUnit = 9, kAxisUnit = 10;
inline constexpr GLuint kLeafUnit = 16;  // the leaf picture (leaves.hpp): surface.frag and depth.frag with TREE

struct PivotTextures {
    gl::Texture pivots, axes;  // RGBA32F: pivot (m) and parent index; X axis and extent (m)
};
PivotTextures uploadPivotTextures(const exporters::PivotPainter& painter);

struct TreeInstance {
    glm::mat4 model;
    glm::uvec4 blocks;
    std::uint32_t building;
    std::uint32_t pad[3];
};

// The trees of a city file, ready to upload (made on any thread).
struct TreeCpu {
    struct Species {
        exporters::PivotPainter painter;  // its textures; the mesh is in `vertices`
        std::uint32_t firstIndex = 0, indexCount = 0, baseVertex = 0, firstInstance = 0, instances = 0;
    };
    std::vector<Species> species;
    std::vector<StaticVertex> vertices;
    std::vector<std::uint32_t> indices;
    std::vector<TreeInstance> instances;
    std::vector<glm::vec3> boxMin, boxMax;  // per instance, the tree's box placed (its frame)
    std::size_t trees = 0;
    std::size_t bytes() const;
};

// Takes the tree nodes out of `nodes` and grows [lo, hi] around the trees, which wear the
// atlas blocks `blocks` (instance data, as the buildings').
TreeCpu prepareTrees(std::vector<MeshNode>& nodes, glm::uvec4 blocks, glm::dvec3& lo, glm::dvec3& hi);

struct TreePrograms {
    gl::Program surface, depth;
    gl::Texture leaves;  // the leaf cards' picture, shared by every tree
    void make();
};

class TreeGpu {
public:
    void upload(const TreeCpu& cpu);
    std::size_t treeCount() const { return treeCount_; }
    // One draw per species of the trees whose box is in the frustum of `viewProj` (render space);
    // `depth` selects the depth-only program (shadow map), which `viewProj` then projects with;
    // `offset`: the trees' frame relative to the render origin.
    std::size_t draw(const TreePrograms& programs, const WindSettings& wind, double time, const glm::mat4& viewProj, bool depth,
                     glm::vec3 offset, FrameStats* stats);

private:
    struct Species {
        PivotTextures textures;
        std::uint32_t firstIndex = 0, indexCount = 0, baseVertex = 0, firstInstance = 0, instances = 0;
    };
    std::vector<Species> species_;
    gl::Buffer vertices_, indices_, instances_;  // instances_: this draw's visible trees
    gl::VertexArray vao_;
    std::vector<TreeInstance> all_;
    std::vector<glm::vec3> boxMin_, boxMax_;
    std::vector<TreeInstance> visible_;
    std::size_t treeCount_ = 0;
};

}  // namespace dawnforge::runtime
