#pragma once
// What a scene file puts on the GPU (private to the renderer): the city's meshes in one
// vertex/index buffer with per-building instance data, the atlas and interior textures,
// the destruction VATs, the ocean grid, the shadow map and the overlook depth.
#include "gl.hpp"
#include "piece_boxes.hpp"
#include "static_vertex.hpp"
#include "trees.hpp"

#include <dawnforge/runtime/lightmaps.hpp>
#include <dawnforge/runtime/ocean.hpp>
#include <dawnforge/runtime/renderer.hpp>
#include <dawnforge/runtime/scene_file.hpp>

#include <glm/glm.hpp>

#include <cstdint>
#include <limits>
#include <vector>

namespace dawnforge::runtime {

// Per-instance data: the material → atlas block mapping (16 codes, one byte each) and the
// building id. Every building is one instance of the same multi-draw, each with its own mapping.
struct InstanceData {
    glm::uvec4 blocks;
    std::uint32_t building;
};

struct DrawRange {
    std::uint32_t count = 0, firstIndex = 0;
    std::int32_t baseVertex = 0;
};

class SceneGpu {
public:
    void load(const SceneFile& scene, int shadowMapSize);

    glm::dvec3 boundsMin() const { return boundsMin_; }
    glm::dvec3 boundsMax() const { return boundsMax_; }
    void setCamera(glm::dvec3 position, glm::dvec3 forward, double fovY, double aspect, double nearPlane, double farPlane);
    glm::mat4 lightViewProj(glm::dvec3 sunDirection);
    // Shadow-map depth units per metre along the light (its depth range is 3 × the scene's radius).
    double shadowDepthPerMetre() const { return 1.0 / (3.0 * sceneRadius()); }
    double sceneRadius() const { return std::max(0.5 * glm::length(boundsMax_ - boundsMin_), 1.0); }
    glm::vec4 overlookArea() const { return overlookArea_; }
    glm::vec4 overlookDepthRange() const { return overlookDepth_; }
    double overlookMs() const { return overlookMs_; }
    bool baked() const { return baked_; }
    void bindShared();

    // The destruction pieces drawn at scene time `time`, as boxes for the probes' capture.
    std::vector<ProbeBox> pieceBoxes(double time) const;
    std::size_t pieceCount() const;
    // The buildings replaced by their destruction at scene time `time`.
    std::vector<int> goneBuildings(double time) const;

    // Each returns the number of draw calls it made.
    std::size_t drawShadow(double time);
    std::size_t drawOpaque(glm::dvec3 camera, const glm::mat4& viewProj, double lodDistance, double time, FrameStats& stats);
    std::size_t drawDestruction(double time, FrameStats& stats);
    std::size_t drawOcean(FrameStats& stats);  // from the camera given to setCamera()

private:
    struct Building {
        DrawRange lod0, lod1;
        glm::vec3 min{0.0f}, max{0.0f};
        std::uint32_t instance = 0;
        std::uint32_t id = 0;                                      // the city's building id
        double until = std::numeric_limits<double>::infinity();  // scene time a destruction replaces it
    };
    struct Static {
        DrawRange range;
        std::uint32_t instance = 0;
    };
    struct Vat {
        std::string name;
        gl::VertexArray vao;
        gl::Buffer vertices, indices;
        std::uint32_t indexCount = 0;
        gl::Texture position, rotation;
        glm::vec4 layout{0.0f};  // W, R, height, frames
        double fps = 30.0, startTime = 0.0;
        bool replacing = false;      // replaces a building: not drawn before startTime
        std::uint32_t building = 0xfffeu;  // the instance id the shaders see (the building's when replacing)
        glm::mat4 model{1.0f};
        glm::uvec4 blocks{0u};
        VatPieceBoxes boxes;
    };
    struct Command {
        std::uint32_t count, instanceCount, firstIndex;
        std::int32_t baseVertex;
        std::uint32_t baseInstance;
    };

    void loadCity(const std::filesystem::path& cityDir);
    void loadLightmaps(const LightmapArray& lightmaps);
    void loadOverlook(const OverlookDepth& overlook);
    void loadVat(const DestructionInstance& instance);
    void replaceBuilding(const DestructionInstance& instance);
    void loadOcean(const OceanSettings& settings);
    void renderOverlook();
    std::size_t drawStatic(const std::vector<Command>& commands);
    std::size_t drawShells(GLuint fbo, int size, const glm::mat4& viewProj, double time);
    std::size_t drawVats(double time, bool depth, FrameStats* stats);

    // City geometry.
    std::vector<Building> buildings_;
    std::vector<Static> statics_;
    gl::Buffer vertices_, indices_, instances_, indirect_;
    std::size_t indirectCapacity_ = 0;
    gl::VertexArray vao_;
    gl::Program surface_, surfaceDepth_, vat_, vatDepth_, ocean_;
    gl::Texture atlas_, rooms_, roomMiddle_;
    gl::Texture lightmaps_;      // baked lighting (lightmaps.hpp); a 1×1 black layer without a bake
    bool baked_ = false, bakedOverlook_ = false;
    int roomStyles_ = 1;
    gl::Buffer materialsUbo_;
    std::vector<Vat> vats_;
    TreeGpu trees_;
    WindSettings wind_;
    glm::dvec3 boundsMin_{-1.0}, boundsMax_{1.0};

    // Shadow map and overlook depth.
    gl::Texture shadowMap_, overlook_;
    gl::Framebuffer shadowFbo_, overlookFbo_;
    int shadowSize_ = 2048;
    glm::mat4 lightViewProj_{1.0f};
    glm::vec4 overlookArea_{0.0f, 0.0f, 1.0f, 1.0f};
    glm::vec4 overlookDepth_{0.0f};
    double overlookMs_ = 0.0;

    // Ocean.
    bool hasOcean_ = false;
    OceanSettings oceanSettings_;
    WaveSet waves_;
    gl::VertexArray oceanVao_;
    gl::Buffer oceanVertices_, oceanIndices_, oceanRows_, oceanUbo_;
    gl::Texture waveNoise_;
    std::uint32_t oceanIndexCount_ = 0;
    OceanCamera camera_{};
};

}  // namespace dawnforge::runtime
