#pragma once
// The renderer: loads what a scene file names (the city, destruction VATs, the ocean) onto
// the GPU and draws frames through a fixed frame graph of passes, each timed with GL timer
// queries:
//   overlook (once, at load)  top-down orthographic depth of the terrain and buildings (for the ocean)
//   shadow                    directional shadow map from the sun (LOD1 shells, VAT pieces)
//   probes                    irradiance probes around the player: placed, captured from the bake's
//                             proxy boxes, lit, projected and injected (probes.hpp; off by default)
//   opaque                    buildings (atlas tiling, interior mapping on glass) and ground
//   destruction               VAT playback of each destruction instance
//   sky                       sky and sun where nothing was drawn
//   ocean                     projected-grid Gerstner water, blended, depth writes on
//   exposure                  the frame's log-average luminance and exposure (compute; ExposureSettings)
//   flares                    lens flares of the sun and the street lamps: one instanced draw, added to
//                             the HDR colour; visibility from the depth texture in the vertex shader
//   tonemap                   HDR × exposure → 8-bit sRGB (ACES fit)
//   readback                  pixels back to the CPU (headless only)
// A GL context (GlContext) must be current on the calling thread for the whole life.
#include <dawnforge/exporters/image.hpp>
#include <dawnforge/runtime/probe_math.hpp>
#include <dawnforge/runtime/scene_file.hpp>

#include <glm/glm.hpp>

#include <memory>
#include <string>
#include <vector>

namespace dawnforge::runtime {

struct ViewCamera {
    glm::dvec3 position{0.0, 50.0, 100.0};
    glm::dvec3 forward{0.0, -0.4, -1.0};  // normalised by the renderer
    double fovYDegrees = 50.0;
};

struct FrameSettings {
    ViewCamera camera;
    glm::dvec3 cameraVelocity{0.0};  // m/s: a world prefetches where the camera will be in a second
    double time = 0.0;       // seconds since the scene started (destruction, waves)
    double timeOfDay = 15.0; // hours
    double adaptSeconds = 0.0;  // `view`: seconds since the last frame, how far auto exposure moves; 0: it converges on this frame
};

struct PassTime {
    std::string name;
    double gpuMs = 0.0;  // GL_TIME_ELAPSED
    double cpuMs = 0.0;  // wall time on the CPU around the pass (its real cost when passes are synchronised)
};

// The probes of one frame.
struct ProbeStats {
    int wanted = 0;    // probes the lighting area around the player wants
    int captured = 0;  // captured this frame
    int injected = 0;  // of the wanted, those held and captured: what surfaces read
    int held = 0;      // in the cache
    double captureMs = 0.0;  // wall time of the capture, finished (glFinish)
};

// A probe as captured, read back for tests and debug views.
struct CapturedProbe {
    glm::dvec3 position{0.0};  // render space: a world's runtime coordinates less the render origin (a city's: the same)
    ShRgb radiance;        // SH L2 of the radiance it saw
    bool indoors = false;  // its IN tag (a roof above it in the overlook depth)
};

// A world's streaming in one frame (--stats "streaming").
struct StreamingStats {
    bool on = false;        // the scene is a world
    int nodes = 0;          // in the tileset
    int wanted = 0;         // nodes the camera's selection wants
    int resident = 0;       // on the GPU
    int drawn = 0;          // drawn this frame
    int loading = 0;        // asked for, in a worker, or waiting to upload
    int loads = 0;          // finished reading this frame
    int evictions = 0;      // left the GPU this frame
    int failed = 0;         // could not be read this frame (each warned once)
    double residentMB = 0.0;
    std::size_t uploadBytes = 0;
    double uploadMs = 0.0;  // CPU time of this frame's uploads
    double waitMs = 0.0;    // time this frame waited for its selection (render only)
    bool waited = false;
    bool complete = true;   // everything the camera wants is drawn
};

struct FrameStats {
    std::vector<PassTime> passes;
    double frameMs = 0.0;  // CPU wall time of the whole frame, including the final glFinish
    std::size_t drawCalls = 0;
    std::size_t triangles = 0;
    std::size_t oceanVertices = 0;
    std::size_t lod0Buildings = 0, lod1Buildings = 0, culledBuildings = 0;
    double exposure = 0.0;        // the multiplier the frame was shown with
    double sceneLuminance = 0.0;  // the HDR frame's centre-weighted log-average luminance
    std::string probePreset = "off";
    ProbeStats probes;
    StreamingStats streaming;
};

// How a world streams (ARCHITECTURE.md 7, Streaming).
struct StreamingOptions {
    double maxScreenError = 16.0;        // pixels: a node refines when its error on screen is larger
    std::size_t residentBudgetMB = 1536; // GPU bytes held at most (new loads wait above it)
    double lowWater = 0.85;              // eviction stops at this share of the budget (hysteresis)
    std::uint64_t keepFrames = 30;       // a node used within these frames is never evicted
    std::size_t uploadBudgetMB = 24;     // uploaded per frame at most (`render`'s waiting frame: unlimited)
    int workers = 2;                     // threads that read and parse tiles
    bool wait = false;                   // wait until the selection is resident (`render`: deterministic pictures)
};

struct RendererOptions {
    glm::ivec2 size{1280, 720};
    double lodDistance = 90.0;  // buildings nearer than this draw LOD0 (interiors, reveals); farther: LOD1
    int shadowMapSize = 2048;
    int probeBudget = 0;  // probes captured per frame at most; 0: all the lighting area wants (one frame converges)
    StreamingOptions streaming;
};

class Renderer {
public:
    // Loads everything; throws InputError for bad scene content (a city.glb that is not a
    // city, a VAT that does not match its mesh, ...).
    Renderer(const SceneFile& scene, const RendererOptions& options);
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // A camera that frames the whole scene (used when the scene names none).
    ViewCamera overviewCamera() const;
    static ViewCamera cameraOf(const SceneCamera& camera);

    // Draws one frame into the offscreen target; resizes it first if `size` differs.
    FrameStats render(const FrameSettings& frame);
    // The last frame's pixels (row 0 at the top), timed as the "readback" pass in `stats`.
    exporters::Image readPixels(FrameStats* stats = nullptr);
    // The last frame's linear HDR colour before exposure (row 0 at the top), for tests.
    std::vector<glm::vec3> readHdrPixels();
    // Every probe the cache holds, as captured (empty with probes off).
    std::vector<CapturedProbe> capturedProbes() const;
    // Copies the last frame into the default framebuffer (window).
    void present(glm::ivec2 windowSize);
    void resize(glm::ivec2 size);
    // glFinish after every pass: slower, but each pass's cpu_ms is then its real cost on any
    // driver (GPU timer queries are exact on real GPUs; llvmpipe defers work to flushes).
    void setSynchronisedPasses(bool on);
    // Overlook depth, shadow map etc. loaded: seconds spent loading, for --stats.
    double loadSeconds() const;
    double overlookMs() const;

private:
    struct State;
    std::unique_ptr<State> s_;
};

// --stats JSON: {"size":[w,h],"renderer":"...","passes":[{"name":..,"gpu_ms":..,"cpu_ms":..}],...}
std::string frameStatsJson(const FrameStats& stats, glm::ivec2 size, const std::string& device, double loadSeconds,
                           double overlookMs);

}  // namespace dawnforge::runtime
