#pragma once
// One city mesh on the GPU (private to the renderer): a scene's city, a world's tile or an HLOD
// node. Built in two halves so a world can stream: `buildCityCpu` (any thread) turns the file's
// nodes and bake into vertex, index and instance arrays, lightmap layers and tree species;
// `CityGpu::upload` (the GL thread) moves them to the GPU a budget of bytes at a time. Its
// vertices are in its own frame; every draw adds `offset` (the frame's place relative to the
// render origin), so coordinates stay small wherever the city is (camera-relative rendering).
#include "frustum.hpp"
#include "gl.hpp"
#include "static_vertex.hpp"
#include "trees.hpp"

#include <dawnforge/core/import.hpp>
#include <dawnforge/runtime/lightmaps.hpp>
#include <dawnforge/runtime/renderer.hpp>
#include <dawnforge/runtime/scene_file.hpp>

#include <glm/glm.hpp>

#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <vector>

namespace dawnforge::runtime {

// Per-instance data: the material → atlas block mapping (16 codes, one byte each) and the
// building id. Every building is one instance of the same multi-draw, each with its own mapping.
struct InstanceData {
    glm::uvec4 blocks;
    std::uint32_t building;
};

// The default mapping of an instance: every material in its own block, brick and plaster in
// one of their four half-size variants chosen from the instance id.
glm::uvec4 instanceBlocks(std::uint32_t id);

struct DrawRange {
    std::uint32_t count = 0, firstIndex = 0;
    std::int32_t baseVertex = 0;
};

struct CityBuilding {
    DrawRange lod0, lod1;
    glm::vec3 min{0.0f}, max{0.0f};
    std::uint32_t instance = 0;
    std::uint32_t id = 0;                                      // the city's building id
    double until = std::numeric_limits<double>::infinity();  // scene time a destruction replaces it
};

struct CityStatic {
    DrawRange range;
    glm::vec3 min{0.0f}, max{0.0f};
    std::uint32_t instance = 0;
};

struct CityCpu {
    std::vector<StaticVertex> vertices;
    std::vector<std::uint32_t> indices;
    std::vector<InstanceData> instances;
    std::vector<CityBuilding> buildings;
    std::vector<CityStatic> statics;
    TreeCpu trees;
    std::optional<BakedCity> baked;
    std::vector<std::uint8_t> lightmapMip1;  // the lightmaps' level 1, layer after layer
    // In the city's frame: everything but the far land (land_*) / everything.
    glm::dvec3 boundsMin{std::numeric_limits<double>::max()}, boundsMax{-std::numeric_limits<double>::max()};
    glm::dvec3 fullMin{std::numeric_limits<double>::max()}, fullMax{-std::numeric_limits<double>::max()};
    std::size_t bytes() const;  // what it takes on the GPU
};

// `vertexBaked`: the mesh carries its bake in TEXCOORD_1 = (sky, sun bounce) and TEXCOORD_2 =
// (AO, lamps), decoded (an HLOD node's): its vertices get the layer −2, which surface.frag reads
// as such, and no interior mapping. `until`: building id → the scene time a destruction replaces it.
CityCpu buildCityCpu(std::vector<MeshNode> nodes, std::optional<BakedCity> baked, bool vertexBaked,
                     const std::map<std::uint32_t, double>& until);
// A city folder's city.glb and its bake (InputError for a broken one).
CityCpu loadCityCpu(const std::filesystem::path& cityDir, const std::map<std::uint32_t, double>& until);

// The programs every city draws with, made once.
struct CityPrograms {
    gl::Program surface, depth;
    TreePrograms trees;
    void make();
};

// The indirect buffer of the multi-draws, grown as needed.
class IndirectDraws {
public:
    struct Command {
        std::uint32_t count, instanceCount, firstIndex;
        std::int32_t baseVertex;
        std::uint32_t baseInstance;
    };
    void draw(GLuint vao, const std::vector<Command>& commands);

private:
    gl::Buffer buffer_;
    std::size_t capacity_ = 0;
};

struct CityDraw {
    glm::vec3 offset{0.0f};        // the city's frame relative to the render origin
    glm::dvec3 camera{0.0};        // in the city's frame
    glm::mat4 viewProj{1.0f};      // render space (culling adds the offset)
    double lodDistance = 90.0;
    double time = 0.0;
};

// What one call of CityGpu::upload did: bytes copied to the GPU, and its cost against the
// budget (the copies and the storage it allocated).
struct UploadStep {
    std::size_t copied = 0, cost = 0;
};

class CityGpu {
public:
    CityGpu() = default;
    explicit CityGpu(CityCpu cpu) : cpu_(std::move(cpu)) {}
    // Allocates and copies to the GPU until the budget is spent (the first call at least
    // allocates its vertex storage, so each call makes progress). `done()` once everything is
    // there; the CPU copy is then released.
    UploadStep upload(std::size_t budget);
    bool done() const { return done_; }
    std::size_t bytes() const { return bytes_; }
    bool baked() const { return baked_; }
    bool empty() const { return buildings_.empty() && statics_.empty() && trees_.treeCount() == 0; }
    const std::optional<OverlookDepth>& overlook() const { return overlook_; }
    glm::dvec3 boundsMin() const { return boundsMin_; }
    glm::dvec3 boundsMax() const { return boundsMax_; }
    glm::dvec3 fullMin() const { return fullMin_; }
    glm::dvec3 fullMax() const { return fullMax_; }
    bool hasBuilding(std::uint32_t id) const;

    // Depth of the ground and every building's LOD1 shell standing at `time`, and the trees (swaying).
    std::size_t drawDepth(const CityPrograms& p, IndirectDraws& indirect, const glm::mat4& viewProj, glm::vec3 offset,
                          double time, const WindSettings* wind);
    // The ground, the buildings (culled, LOD by distance, nearest first) and the trees; with
    // `stats` null, their depth alone (the opaque pass's pre-pass).
    std::size_t drawOpaque(const CityPrograms& p, IndirectDraws& indirect, const CityDraw& d, const WindSettings& wind,
                           int roomStyles, FrameStats* stats);

private:
    void finishUpload();

    CityCpu cpu_;
    std::size_t vertexBytesDone_ = 0, indexBytesDone_ = 0;
    int levelsDone_ = 0, layersDone_ = 0, rowsDone_ = 0;
    bool started_ = false, treesDone_ = false, done_ = false, baked_ = false;
    std::size_t bytes_ = 0;
    std::vector<CityBuilding> buildings_;
    std::vector<CityStatic> statics_;
    gl::Buffer vertices_, indices_, instances_;
    gl::VertexArray vao_;
    gl::Texture lightmaps_;
    TreeGpu trees_;
    std::optional<OverlookDepth> overlook_;
    glm::dvec3 boundsMin_{0.0}, boundsMax_{0.0}, fullMin_{0.0}, fullMax_{0.0};
};

}  // namespace dawnforge::runtime
