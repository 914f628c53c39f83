#pragma once
// What a scene file puts on the GPU (private to the renderer): the city (city_gpu.hpp) or a
// world's streamed tiles (streaming.hpp), the atlas and interior textures, the destruction
// VATs, the ocean grid, the shadow map and the overlook depth.
//
// Camera-relative rendering: everything is drawn in render space, runtime coordinates less
// `renderOrigin()`. A city scene keeps the origin at 0; a world moves it with the camera in
// steps of kOriginStep metres, so coordinates on the GPU stay small wherever the camera is.
#include "city_gpu.hpp"
#include "gl.hpp"
#include "piece_boxes.hpp"
#include "streaming.hpp"

#include <dawnforge/runtime/lightmaps.hpp>
#include <dawnforge/runtime/ocean.hpp>
#include <dawnforge/runtime/renderer.hpp>
#include <dawnforge/runtime/scene_file.hpp>

#include <glm/glm.hpp>

#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

namespace dawnforge::runtime {

class SceneGpu {
public:
    static constexpr double kOriginStep = 1024.0;

    void load(const SceneFile& scene, int shadowMapSize, const StreamingOptions& streaming);

    bool world() const { return world_ != nullptr; }
    const TileStreamer* streamer() const { return world_.get(); }
    glm::dvec3 boundsMin() const { return boundsMin_; }
    glm::dvec3 boundsMax() const { return boundsMax_; }
    // The render origin for a camera at `camera` (0 for a city), and the frame's streaming.
    glm::dvec3 beginFrame(glm::dvec3 camera, const SelectionCamera& selection, const SelectionCamera* prefetch,
                          StreamingStats& stats);
    glm::dvec3 renderOrigin() const { return origin_; }
    void setCamera(glm::dvec3 position, glm::dvec3 forward, double fovY, double aspect, double nearPlane, double farPlane);
    glm::mat4 lightViewProj(glm::dvec3 sunDirection);
    // Shadow-map depth units per metre along the light (its depth range is 3 × the shadow radius).
    double shadowDepthPerMetre() const { return 1.0 / (3.0 * shadowRadius()); }
    double shadowRadius() const;
    glm::vec4 overlookArea() const;
    glm::vec4 overlookDepthRange() const { return overlookDepth_; }
    double overlookMs() const { return overlookMs_; }
    bool baked() const { return baked_; }
    void bindShared();
    // The street lamps of the city, or of the world's tiles drawn this frame, in render space.
    std::vector<StreetLamp> lamps(const std::vector<StreetLamp>& cityLamps);

    // A world's probe proxies: those of the full-detail tiles drawn now, in render space, when
    // they differ from the last call's (other tiles, or the render origin moved); else nothing.
    std::optional<std::vector<ProbeBox>> worldProbeBoxes();
    // The destruction pieces drawn at scene time `time`, as boxes for the probes' capture (render space).
    std::vector<ProbeBox> pieceBoxes(double time) const;
    std::size_t pieceCount() const;
    // The buildings replaced by their destruction at scene time `time`.
    std::vector<int> goneBuildings(double time) const;

    // Each returns the number of draw calls it made.
    std::size_t drawShadow(double time);
    std::size_t drawOpaque(glm::dvec3 camera, const glm::mat4& viewProj, double lodDistance, double time, FrameStats& stats);
    std::size_t drawDestruction(double time, FrameStats& stats);
    std::size_t drawOcean(FrameStats& stats);  // from the camera given to setCamera()
    // The destructions' dust (scene_dust.cpp), blended into the framebuffer bound now, which
    // must not hold `depth` (the scene's depth, read for the soft fade); `lens` as flares.hpp's.
    std::size_t drawDust(double time, GLuint depth, glm::vec4 lens, FrameStats& stats);

private:
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
        glm::dvec3 place{0.0};       // where it stands, runtime coordinates
        double yawDegrees = 0.0;
        glm::mat4 model{1.0f};       // runtime coordinates (the probes' boxes)
        glm::uvec4 blocks{0u};
        VatPieceBoxes boxes;
        gl::Texture dust;            // _dust.exr when there is dust
        glm::vec4 dustLayout{0.0f};  // W, R, frames, puffs
    };

    void loadCity(const SceneFile& scene);
    void loadOverlook(const OverlookDepth& overlook);
    void loadVat(const DestructionInstance& instance);
    void checkReplaced(const SceneFile& scene) const;
    void loadOcean(const OceanSettings& settings);
    void renderOverlook();
    std::size_t drawVats(double time, bool depth, FrameStats* stats);
    glm::vec3 offsetOf(glm::dvec3 frame) const { return glm::vec3(frame - origin_); }
    // The VAT's frame at scene time `time` and its placement, as vat.vert and dust.vert read them.
    void setPlayback(const Vat& v, double time) const;

    CityPrograms programs_;
    IndirectDraws indirect_;
    std::optional<CityGpu> city_;
    std::unique_ptr<TileStreamer> world_;
    std::vector<TileStreamer::Drawn> drawn_;  // this frame's streamed content
    std::vector<int> probeNodes_;               // the tiles whose proxies the probes hold
    glm::dvec3 probeOrigin_{0.0};
    glm::dvec3 origin_{0.0};
    gl::Program vat_, vatDepth_, ocean_, dust_;
    gl::VertexArray emptyVao_;  // the dust's draws make their vertices from gl_VertexID
    gl::Texture atlas_, rooms_, roomMiddle_;
    gl::Buffer atlasMeans_;  // AtlasMeans (atlas.glsl): each block's mean colour, by code
    gl::Texture noLightmaps_;    // a 1×1 black layer for what has no bake (never read: layer -1)
    bool baked_ = false, bakedOverlook_ = false;
    int roomStyles_ = 1;
    gl::Buffer materialsUbo_;
    std::vector<Vat> vats_;
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
