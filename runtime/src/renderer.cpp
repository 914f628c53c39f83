// The renderer: GPU resources for a scene and the frame graph that draws it.
#include <dawnforge/runtime/renderer.hpp>

#include "flares.hpp"
#include "gl.hpp"
#include "probes.hpp"
#include "scene_gpu.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/read_file.hpp>
#include <dawnforge/runtime/sky.hpp>

#include <nlohmann/json.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <optional>

namespace dawnforge::runtime {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

constexpr double kNear = 0.5, kFar = 4000.0;

// The Frame uniform block of common.glsl (std140: mat4 and vec4 only).
struct FrameBlock {
    glm::mat4 viewProj, invViewProj, lightViewProj;
    glm::vec4 cameraPos, sunDir, sunColor, skyZenith, skyHorizon, groundColor, viewport, overlook, overlookDepth, origin;
};

// The render origin's x and z modulo this (Frame.origin): phases of the waves, continuous as
// the origin moves except where it wraps.
constexpr double kPhaseWrap = 8192.0;

// A minimal frame graph: passes in a fixed order, each bracketed by a GL_TIME_ELAPSED
// query and a CPU clock. The timings are collected after the frame's glFinish.
class FrameGraph {
public:
    void add(std::string name, std::function<void()> run) {
        GLuint q = 0;
        glCreateQueries(GL_TIME_ELAPSED, 1, &q);
        passes_.push_back({std::move(name), std::move(run), gl::Query(q), 0.0});
    }
    // synchronise: glFinish after each pass, so its CPU time is what it cost even on a
    // driver that defers the work to a later flush (llvmpipe rasterises at flush time).
    void execute(bool synchronise) {
        for (Pass& p : passes_) {
            const auto t0 = Clock::now();
            glBeginQuery(GL_TIME_ELAPSED, p.query.id());
            p.run();
            glEndQuery(GL_TIME_ELAPSED);
            if (synchronise) glFinish();
            p.cpuMs = msSince(t0);
        }
    }
    void collect(std::vector<PassTime>& out) const {
        for (const Pass& p : passes_) {
            GLuint64 ns = 0;
            glGetQueryObjectui64v(p.query.id(), GL_QUERY_RESULT, &ns);
            out.push_back({p.name, double(ns) * 1e-6, p.cpuMs});
        }
    }

private:
    struct Pass {
        std::string name;
        std::function<void()> run;
        gl::Query query;
        double cpuMs;
    };
    std::vector<Pass> passes_;
};

struct Target {
    glm::ivec2 size{0};
    gl::Texture hdr, depth, ldr;
    gl::Framebuffer hdrFbo, ldrFbo;
    gl::Framebuffer flareFbo;  // the HDR colour alone: the flare pass reads the depth texture
};

Target makeTarget(glm::ivec2 size) {
    Target t;
    t.size = size;
    t.hdr = gl::makeTexture(GL_TEXTURE_2D);
    glTextureStorage2D(t.hdr.id(), 1, GL_RGBA16F, size.x, size.y);
    t.depth = gl::makeTexture(GL_TEXTURE_2D);
    glTextureStorage2D(t.depth.id(), 1, GL_DEPTH_COMPONENT32F, size.x, size.y);
    t.ldr = gl::makeTexture(GL_TEXTURE_2D);
    glTextureStorage2D(t.ldr.id(), 1, GL_RGBA8, size.x, size.y);
    t.hdrFbo = gl::makeFramebuffer();
    glNamedFramebufferTexture(t.hdrFbo.id(), GL_COLOR_ATTACHMENT0, t.hdr.id(), 0);
    glNamedFramebufferTexture(t.hdrFbo.id(), GL_DEPTH_ATTACHMENT, t.depth.id(), 0);
    t.ldrFbo = gl::makeFramebuffer();
    glNamedFramebufferTexture(t.ldrFbo.id(), GL_COLOR_ATTACHMENT0, t.ldr.id(), 0);
    t.flareFbo = gl::makeFramebuffer();
    glNamedFramebufferTexture(t.flareFbo.id(), GL_COLOR_ATTACHMENT0, t.hdr.id(), 0);
    for (GLuint fbo : {t.hdrFbo.id(), t.ldrFbo.id(), t.flareFbo.id()})
        if (glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw std::runtime_error("the GL driver cannot render to an RGBA16F/RGBA8 framebuffer");
    return t;
}

// GL's row 0 is the bottom; images start at the top. `row` is in elements.
template <class T>
void flipRows(std::vector<T>& pixels, std::size_t row, int rows) {
    for (int y = 0; y < rows / 2; ++y)
        std::swap_ranges(pixels.begin() + std::ptrdiff_t(row * std::size_t(y)), pixels.begin() + std::ptrdiff_t(row * std::size_t(y + 1)),
                         pixels.begin() + std::ptrdiff_t(row * std::size_t(rows - 1 - y)));
}

}  // namespace

struct Renderer::State {
    RendererOptions options;
    SceneGpu scene;
    Target target;
    gl::Program sky, tonemap, exposure;
    gl::Buffer exposureState;  // exposure.comp's: the exposure, the scene's luminance, the target
    gl::Buffer frameUbo;
    gl::VertexArray emptyVao;
    FrameGraph graph;
    FlarePass flares;
    ProbeGpu probes;
    glm::dvec3 cameraForward{0.0, 0.0, -1.0};
    std::vector<StreetLamp> lamps;       // the city's (runtime coordinates)
    std::vector<StreetLamp> frameLamps;  // this frame's, in render space (a world's drawn tiles')
    bool lensFlares = true;
    Lighting lighting;
    glm::vec4 lens{0.0f};  // flare.vert's near, far, projection[1][1]
    FrameSettings frame;
    FrameStats stats;
    glm::mat4 viewProj{1.0f};
    glm::dvec3 cameraPos{0.0};
    ExposureSettings exposureSettings;
    double loadSeconds = 0.0;
    bool synchronise = false;
    std::string probesOn = "off";  // the preset drawn

    void addPasses();
    void loadProbes(const SceneFile& scene);
};

// The frame graph. Each pass binds what it draws into.
void Renderer::State::addPasses() {
    State& s = *this;
    s.graph.add("shadow", [&s] {
        s.stats.drawCalls += s.scene.drawShadow(s.frame.time);
    });
    s.graph.add("probes", [&s] {
        if (!s.probes.enabled()) return;
        // The lighting area sits ahead of the player, where what they see is.
        const auto t0 = Clock::now();
        if (std::optional<std::vector<ProbeBox>> boxes = s.scene.worldProbeBoxes()) s.probes.setScene(std::move(*boxes), s.frameLamps);
        s.probes.setGoneBuildings(s.scene.goneBuildings(s.frame.time));
        const std::vector<ProbeBox> pieces = s.scene.pieceBoxes(s.frame.time);
        const glm::dvec3 focus = s.cameraPos - s.scene.renderOrigin() + 7.5 * s.cameraForward;  // in render space
        s.stats.probes = s.probes.update(focus, s.options.probeBudget, pieces);
        if (s.stats.probes.captured > 0) {
            glFinish();
            s.stats.probes.captureMs = msSince(t0);
        }
    });
    s.graph.add("opaque", [&s] {
        glBindFramebuffer(GL_FRAMEBUFFER, s.target.hdrFbo.id());
        glViewport(0, 0, s.target.size.x, s.target.size.y);
        glDepthMask(GL_TRUE);
        glClearDepth(1.0);
        const float black[4] = {0, 0, 0, 1};
        glClearNamedFramebufferfv(s.target.hdrFbo.id(), GL_COLOR, 0, black);
        glClear(GL_DEPTH_BUFFER_BIT);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDisable(GL_CULL_FACE);  // city meshes are closed but their winding is not relied on
        s.stats.drawCalls += s.scene.drawOpaque(s.cameraPos, s.viewProj, s.options.lodDistance, s.frame.time, s.stats);
        s.stats.drawCalls += s.probes.drawSpheres();
    });
    s.graph.add("destruction", [&s] { s.stats.drawCalls += s.scene.drawDestruction(s.frame.time, s.stats); });
    s.graph.add("sky", [&s] {
        glDepthFunc(GL_LEQUAL);
        glDepthMask(GL_FALSE);
        glUseProgram(s.sky.id());
        glBindVertexArray(s.emptyVao.id());
        glDrawArrays(GL_TRIANGLES, 0, 3);
        glDepthMask(GL_TRUE);
        glDepthFunc(GL_LESS);
        s.stats.drawCalls += 1;
    });
    s.graph.add("ocean", [&s] {
        glEnable(GL_BLEND);
        glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        s.stats.drawCalls += s.scene.drawOcean(s.stats);
        glDisable(GL_BLEND);
    });
    // The destructions' dust over everything drawn: the HDR colour alone is bound, as the puffs
    // read the depth for their soft edges.
    s.graph.add("dust", [&s] {
        glBindFramebuffer(GL_FRAMEBUFFER, s.target.flareFbo.id());
        s.stats.drawCalls += s.scene.drawDust(s.frame.time, s.target.depth.id(), s.lens, s.stats);
    });
    // Measured before the flares: a lens's ghosts do not close the eye.
    s.graph.add("exposure", [&s] {
        const ExposureSettings& e = s.exposureSettings;
        glUseProgram(s.exposure.id());
        glBindTextureUnit(0, s.target.hdr.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 9, s.exposureState.id());
        const double night = s.lighting.night;
        const double key = e.key * std::exp2(e.nightStops * night);
        const double max = std::exp2(glm::mix(std::log2(e.max), std::log2(e.nightMax), night));
        glUniform4f(0, float(key), float(e.min), float(max), e.fixed ? float(*e.fixed) : 0.0f);
        const double dt = s.frame.adaptSeconds;
        glUniform1f(1, dt > 0.0 ? float(1.0 - std::exp(-e.speed * dt)) : 1.0f);
        glDispatchCompute(1, 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    });
    s.graph.add("flares", [&s] {
        if (!s.lensFlares) return;
        glBindFramebuffer(GL_FRAMEBUFFER, s.target.flareFbo.id());
        s.stats.drawCalls += s.flares.draw(flareLights(s.lighting, s.frameLamps), s.target.depth.id(), s.lens);
    });
    s.graph.add("tonemap", [&s] {
        glBindFramebuffer(GL_FRAMEBUFFER, s.target.ldrFbo.id());
        glViewport(0, 0, s.target.size.x, s.target.size.y);
        glDisable(GL_DEPTH_TEST);
        glUseProgram(s.tonemap.id());
        glBindTextureUnit(0, s.target.hdr.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 9, s.exposureState.id());
        glBindVertexArray(s.emptyVao.id());
        glDrawArrays(GL_TRIANGLES, 0, 3);
        s.stats.drawCalls += 1;
    });
}

// The probes read the bake's proxy boxes: a preset other than "off" needs them.
void Renderer::State::loadProbes(const SceneFile& scene) {
    State& s = *this;
    const ProbeSettings& settings = scene.probes;
    const std::optional<ProbePreset> preset = probePreset(settings.preset);
    if (!preset) {
        if (settings.preset != "off") throw InputError(format("unknown probe preset \"{}\" (off, low, mid or high)", settings.preset));
        s.probes.load({}, 0, {}, nullptr, settings);
        return;
    }
    // A world's proxies come with its tiles (SceneGpu::worldProbeBoxes); a city's are its bake's.
    std::vector<ProbeBox> boxes;
    if (!scene.worldDir) {
        const std::filesystem::path proxies = scene.cityDir ? *scene.cityDir / "bake" / "proxies.json" : std::filesystem::path();
        std::error_code ec;
        if (!scene.cityDir || !std::filesystem::is_regular_file(proxies, ec))
            throw InputError(format("probes \"{}\" need the city's bake ({}): run `dawnforge bake` on the city, or use probes \"off\"",
                                    settings.preset, scene.cityDir ? proxies.string() : std::string("the scene has no city")));
        boxes = parseProbeBoxes(readTextFile(proxies), proxies.string());
    }
    s.probes.load(std::move(boxes), int(s.scene.pieceCount()), s.lamps, &*preset, settings);
    s.probesOn = settings.preset;
}

Renderer::Renderer(const SceneFile& sceneFile, const RendererOptions& options) : s_(std::make_unique<State>()) {
    const auto t0 = Clock::now();
    State& s = *s_;
    s.options = options;
    if (options.size.x < 1 || options.size.y < 1 || options.size.x > 16384 || options.size.y > 16384)
        throw InputError(format("image size {}x{} is out of range (1 to 16384)", options.size.x, options.size.y));
    s.scene.load(sceneFile, options.shadowMapSize, options.streaming);
    s.lensFlares = sceneFile.lensFlares;
    if (s.lensFlares) s.flares.load();
    // city.json's street lamps: the flares show them, the probes' capture is lit by them.
    if (sceneFile.cityDir && (s.lensFlares || sceneFile.probes.preset != "off")) s.lamps = readStreetLamps(*sceneFile.cityDir);
    s.loadProbes(sceneFile);
    s.target = makeTarget(options.size);
    s.sky = gl::makeProgram("fullscreen.vert", "sky.frag");
    s.tonemap = gl::makeProgram("fullscreen.vert", "tonemap.frag");
    s.exposure = gl::makeComputeProgram("exposure.comp");
    s.exposureSettings = sceneFile.exposure;
    const float noExposureYet[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    s.exposureState = gl::makeBuffer(noExposureYet, sizeof(noExposureYet), GL_DYNAMIC_STORAGE_BIT);
    s.frameUbo = gl::makeBuffer(nullptr, sizeof(FrameBlock), GL_DYNAMIC_STORAGE_BIT);
    s.emptyVao = gl::makeVertexArray();

    s.addPasses();
    glFinish();
    gl::check("loading the scene");
    s.loadSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
}

Renderer::~Renderer() = default;

double Renderer::loadSeconds() const { return s_->loadSeconds; }
double Renderer::overlookMs() const { return s_->scene.overlookMs(); }

ViewCamera Renderer::cameraOf(const SceneCamera& camera) {
    ViewCamera v;
    v.position = camera.position;
    v.forward = glm::normalize(camera.target - camera.position);
    v.fovYDegrees = camera.fovDegrees;
    return v;
}

ViewCamera Renderer::overviewCamera() const {
    const glm::dvec3 lo = s_->scene.boundsMin(), hi = s_->scene.boundsMax();
    const glm::dvec3 centre = 0.5 * (lo + hi), size = hi - lo;
    const double extent = std::max({size.x, size.z, 1.0});
    ViewCamera v;
    v.position = centre + glm::dvec3(0.45 * extent, 0.55 * extent, 0.75 * extent);
    v.forward = glm::normalize(glm::dvec3(centre.x, lo.y, centre.z) - v.position);
    return v;
}

std::vector<CapturedProbe> Renderer::capturedProbes() const { return s_->probes.captured(); }

void Renderer::setSynchronisedPasses(bool on) { s_->synchronise = on; }

void Renderer::resize(glm::ivec2 size) {
    if (size != s_->target.size && size.x > 0 && size.y > 0) s_->target = makeTarget(size);
}

namespace {

// What a world's selection sees: the camera in runtime coordinates.
SelectionCamera selectionCamera(const ViewCamera& cam, const glm::dmat4& proj, int height) {
    SelectionCamera c;
    c.position = cam.position;
    c.viewProj = proj * glm::lookAt(cam.position, cam.position + cam.forward, glm::dvec3(0, 1, 0));
    c.screenHeight = double(height);
    c.fovYRadians = glm::radians(cam.fovYDegrees);
    return c;
}

// Where a moving camera will be in a second: the streaming asks for that view's tiles too.
std::optional<SelectionCamera> prefetchCamera(const ViewCamera& cam, glm::dvec3 velocity, const glm::dmat4& proj, int height) {
    if (glm::length(velocity) < 0.1) return std::nullopt;
    ViewCamera ahead = cam;
    ahead.position += velocity;
    return selectionCamera(ahead, proj, height);
}

}  // namespace

FrameStats Renderer::render(const FrameSettings& frame) {
    State& s = *s_;
    const auto t0 = Clock::now();
    s.frame = frame;
    s.stats = FrameStats{};
    const glm::ivec2 size = s.target.size;
    ViewCamera cam = frame.camera;
    cam.forward = glm::normalize(cam.forward);
    if (std::abs(cam.forward.y) > 0.9999) cam.forward = glm::normalize(cam.forward + glm::dvec3(0, 0, -1e-3));
    s.cameraPos = cam.position;
    s.cameraForward = cam.forward;
    s.stats.probePreset = s.probesOn;
    const double aspect = double(size.x) / double(size.y);
    const glm::dmat4 proj = glm::perspective(glm::radians(cam.fovYDegrees), aspect, kNear, kFar);
    const std::optional<SelectionCamera> ahead = prefetchCamera(cam, frame.cameraVelocity, proj, size.y);
    const glm::dvec3 origin = s.scene.beginFrame(cam.position, selectionCamera(cam, proj, size.y), ahead ? &*ahead : nullptr,
                                                 s.stats.streaming);
    // Camera-relative: the view and everything the GPU sees are in render space (less `origin`).
    const glm::dvec3 eye = cam.position - origin;
    const glm::dmat4 view = glm::lookAt(eye, eye + cam.forward, glm::dvec3(0, 1, 0));
    const glm::dmat4 viewProj = proj * view;
    s.viewProj = glm::mat4(viewProj);
    s.scene.setCamera(eye, cam.forward, glm::radians(cam.fovYDegrees), aspect, kNear, kFar);
    s.frameLamps = s.scene.lamps(s.lamps);

    const Lighting light = lightingAt(frame.timeOfDay);
    s.lighting = light;
    s.lens = glm::vec4(float(kNear), float(kFar), float(proj[1][1]), 0.0f);
    FrameBlock block;
    block.viewProj = glm::mat4(viewProj);
    block.invViewProj = glm::mat4(glm::inverse(viewProj));
    block.lightViewProj = s.scene.lightViewProj(light.sunDirection);
    block.cameraPos = glm::vec4(glm::vec3(eye), float(frame.time));
    block.sunDir = glm::vec4(glm::vec3(light.sunDirection), float(light.night));
    block.sunColor = glm::vec4(glm::vec3(light.sunColor), float(s.scene.shadowDepthPerMetre() * 0.2));
    block.skyZenith = glm::vec4(glm::vec3(light.zenith), 0.0f);
    block.skyHorizon = glm::vec4(glm::vec3(light.horizon), 0.0f);
    block.groundColor = glm::vec4(glm::vec3(light.ground), 0.0f);
    block.viewport = glm::vec4(float(size.x), float(size.y), 1.0f / float(size.x), 1.0f / float(size.y));
    block.overlook = s.scene.overlookArea();
    block.overlookDepth = s.scene.overlookDepthRange();
    block.origin = glm::vec4(float(std::fmod(origin.x, kPhaseWrap)), float(origin.y), float(std::fmod(origin.z, kPhaseWrap)), 0.0f);
    glNamedBufferSubData(s.frameUbo.id(), 0, sizeof(block), &block);
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, s.frameUbo.id());
    s.scene.bindShared();
    s.probes.bind();

    s.graph.execute(s.synchronise);
    glFinish();
    s.graph.collect(s.stats.passes);
    float exposure[2] = {0.0f, 0.0f};
    glGetNamedBufferSubData(s.exposureState.id(), 0, sizeof(exposure), exposure);
    s.stats.exposure = exposure[0];
    s.stats.sceneLuminance = exposure[1];
    s.stats.frameMs = msSince(t0) - s.stats.streaming.waitMs;  // the frame's cost, not its wait for tiles
    gl::check("rendering a frame");
    return s.stats;
}

exporters::Image Renderer::readPixels(FrameStats* stats) {
    const auto t0 = Clock::now();
    const glm::ivec2 size = s_->target.size;
    exporters::Image image{size.x, size.y, std::vector<std::uint8_t>(std::size_t(size.x) * std::size_t(size.y) * 4)};
    glBindFramebuffer(GL_READ_FRAMEBUFFER, s_->target.ldrFbo.id());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, size.x, size.y, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
    flipRows(image.rgba, std::size_t(size.x) * 4, size.y);
    gl::check("reading pixels back");
    if (stats) {
        const double ms = msSince(t0);
        stats->passes.push_back({"readback", 0.0, ms});  // a CPU copy: no GPU query
        stats->frameMs += ms;
    }
    return image;
}

std::vector<glm::vec3> Renderer::readHdrPixels() {
    const glm::ivec2 size = s_->target.size;
    std::vector<glm::vec3> pixels(std::size_t(size.x) * std::size_t(size.y));
    glGetTextureImage(s_->target.hdr.id(), 0, GL_RGB, GL_FLOAT, GLsizei(pixels.size() * sizeof(glm::vec3)), pixels.data());
    flipRows(pixels, std::size_t(size.x), size.y);
    gl::check("reading HDR pixels back");
    return pixels;
}

void Renderer::present(glm::ivec2 windowSize) {
    glBlitNamedFramebuffer(s_->target.ldrFbo.id(), 0, 0, 0, s_->target.size.x, s_->target.size.y, 0, 0, windowSize.x,
                           windowSize.y, GL_COLOR_BUFFER_BIT, GL_LINEAR);
}

std::string frameStatsJson(const FrameStats& stats, glm::ivec2 size, const std::string& device, double loadSeconds,
                           double overlookMs) {
    const auto ms = [](double v) { return std::round(v * 1000.0) / 1000.0; };
    nlohmann::ordered_json j;
    j["size"] = {size.x, size.y};
    j["device"] = device;
    j["load_s"] = ms(loadSeconds);
    j["overlook_ms"] = ms(overlookMs);
    j["frame_ms"] = ms(stats.frameMs);
    double gpu = 0.0;
    nlohmann::ordered_json passes = nlohmann::ordered_json::array();
    for (const PassTime& p : stats.passes) {
        passes.push_back({{"name", p.name}, {"gpu_ms", ms(p.gpuMs)}, {"cpu_ms", ms(p.cpuMs)}});
        gpu += p.gpuMs;
    }
    j["gpu_ms"] = ms(gpu);
    j["exposure"] = {{"value", std::round(stats.exposure * 1e4) / 1e4}, {"scene_luminance", std::round(stats.sceneLuminance * 1e5) / 1e5}};
    j["draw_calls"] = stats.drawCalls;
    j["triangles"] = stats.triangles;
    j["ocean_vertices"] = stats.oceanVertices;
    j["buildings"] = {{"lod0", stats.lod0Buildings}, {"lod1", stats.lod1Buildings}, {"culled", stats.culledBuildings}};
    if (stats.probePreset != "off") {
        const double probeMs = stats.probes.captureMs;
        j["probes"] = {{"preset", stats.probePreset},
                       {"wanted", stats.probes.wanted},
                       {"captured", stats.probes.captured},
                       {"injected", stats.probes.injected},
                       {"held", stats.probes.held},
                       {"capture_ms", ms(probeMs)},
                       {"per_second", probeMs > 0.0 ? ms(1000.0 * stats.probes.captured / probeMs) : 0.0}};
    }
    if (stats.streaming.on) {
        const StreamingStats& st = stats.streaming;
        j["streaming"] = {{"nodes", st.nodes},         {"wanted", st.wanted},   {"resident", st.resident},
                          {"drawn", st.drawn},         {"loading", st.loading}, {"loads", st.loads},
                          {"evictions", st.evictions}, {"failed", st.failed},   {"resident_mb", ms(st.residentMB)},
                          {"upload_mb", ms(double(st.uploadBytes) / (1024.0 * 1024.0))},
                          {"upload_ms", ms(st.uploadMs)}, {"wait_ms", ms(st.waitMs)}, {"complete", st.complete}};
    }
    j["passes"] = std::move(passes);
    return j.dump(2) + "\n";
}

}  // namespace dawnforge::runtime
