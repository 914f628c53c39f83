// Irradiance probes on the GPU (probes.hpp).
#include "probes.hpp"

#include <dawnforge/bake/lighting.hpp>
#include <dawnforge/core/primitives.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <utility>
#include <cmath>

namespace dawnforge::runtime {

namespace {

constexpr int kTile = 5;             // texels per side of a probe's cache tile
constexpr double kLampReach = 30.0;  // lamps farther than this from every probe of a batch are left out (m)
constexpr double kReach = 80.0;      // boxes farther than this from a probe are not captured (m)
constexpr glm::dvec3 kLightingArea{7.5, 4.0, 7.5};  // half the seed's 15 × 15 × 8 m around the player
constexpr glm::dvec3 kCachingArea = 2.0 * kLightingArea;  // captured ahead of need when a frame has budget left

// The Probes block of probe_light.glsl (std140).
struct ProbesBlock {
    glm::vec4 origin{0.0f};
    glm::ivec4 dims{0};
    glm::vec4 cache{1.0f, 1.0f, 0.0f, 0.0f};
};

// probe_box.glsl's ProxyBox.
struct GpuBox {
    glm::vec4 centre, u, w, up;
    glm::vec4 colours[6];
};

// probe_box.glsl's faces: forward and up.
constexpr glm::dvec3 kForward[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
constexpr glm::dvec3 kUp[6] = {{0, 1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}, {0, 1, 0}, {0, 1, 0}};

std::vector<GpuBox> gpuBoxes(std::span<const ProbeBox> boxes) {
    std::vector<GpuBox> out;
    out.reserve(boxes.size());
    for (const ProbeBox& b : boxes) {
        GpuBox g{glm::vec4(glm::vec3(b.centre), 0.0f), glm::vec4(glm::vec3(b.u), float(b.halfSize.x)),
                 glm::vec4(glm::vec3(b.w), float(b.halfSize.z)), glm::vec4(glm::vec3(b.up), float(b.halfSize.y)), {}};
        for (int f = 0; f < 6; ++f) g.colours[f] = glm::vec4(b.colours[std::size_t(f)], 1.0f);
        out.push_back(g);
    }
    return out;
}

// The injected volume: cache slot + 1 per cell. An integer texture is complete only with
// NEAREST filters.
gl::Texture indexTexture(glm::ivec3 dims) {
    gl::Texture t = gl::makeTexture(GL_TEXTURE_3D);
    glTextureStorage3D(t.id(), 1, GL_R32I, dims.x, dims.y, dims.z);
    glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return t;
}

}  // namespace

struct ProbeGpu::State {
    std::optional<ProbePreset> preset;
    ProbeSettings settings;
    std::unique_ptr<ProbeField> field;
    std::unique_ptr<ProbeCache> cache;
    std::vector<glm::dvec3> slotPosition;  // per cache slot
    std::vector<char> slotCaptured;
    int staticBoxes = 0, movingBoxes = 0, boxCount = 0, boxCapacity = 0, tilesPerRow = 1;
    std::vector<ProbeBox> proxies;  // as loaded
    std::vector<StreetLamp> lamps;
    gl::Buffer lampBuffer;
    std::vector<int> gone;          // buildings whose proxies are hidden (sorted)
    gl::Program cull, capture, project;
    gl::Buffer boxes, visible, commands, batch, coefficients, ubo, solidAngles;
    gl::Program sphere;
    gl::Buffer sphereVertices, shown;
    int sphereVertexCount = 0, shownCount = 0;
    gl::Texture cacheTexture, moments, index, gAlbedo, gNormal, gDepth;
    gl::Framebuffer gBuffer;
    gl::VertexArray vao;
    glm::ivec3 indexDims{0};
    ProbesBlock block;

    void allocate();
    void uploadMoving(std::span<const ProbeBox> moving);
    void inject(glm::ivec3 lo, glm::ivec3 hi);
    std::vector<PlacedProbe> toCapture(glm::dvec3 focus, int budget, const std::vector<PlacedProbe>& wanted);
    void captureBatch(std::span<const PlacedProbe> probes);
    void cullBatch(int n);
    void drawBatch(std::span<const PlacedProbe> probes);
    void projectBatch(std::span<const PlacedProbe> probes);
};

ProbeGpu::ProbeGpu() : s_(std::make_unique<State>()) {}
ProbeGpu::~ProbeGpu() = default;

bool ProbeGpu::enabled() const { return s_->preset.has_value(); }

void ProbeGpu::load(std::vector<ProbeBox> boxes, int movingBoxes, std::vector<StreetLamp> lamps, const ProbePreset* preset,
                    const ProbeSettings& settings) {
    State& s = *s_;
    s.settings = settings;
    if (preset) s.preset = *preset;
    s.ubo = gl::makeBuffer(nullptr, sizeof(ProbesBlock), GL_DYNAMIC_STORAGE_BIT);
    s.index = indexTexture({1, 1, 1});
    const GLint none = 0;
    glTextureSubImage3D(s.index.id(), 0, 0, 0, 0, 1, 1, 1, GL_RED_INTEGER, GL_INT, &none);
    if (!preset) {
        s.cacheTexture = gl::makeTexture2D(GL_RGBA16F, kTile, kTile, 1, GL_LINEAR, GL_LINEAR, GL_CLAMP_TO_EDGE);
        s.moments = gl::makeTexture2D(GL_RG32F, 6, 1, 1, GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE);
        glNamedBufferSubData(s.ubo.id(), 0, sizeof(ProbesBlock), &s.block);
        return;
    }
    s.movingBoxes = std::max(movingBoxes, 0);
    s.boxCapacity = int(boxes.size()) + s.movingBoxes;
    s.tilesPerRow = preset->cacheTexels / kTile;
    s.allocate();
    setScene(std::move(boxes), std::move(lamps));
}

void ProbeGpu::setScene(std::vector<ProbeBox> boxes, std::vector<StreetLamp> lamps) {
    State& s = *s_;
    if (!s.preset) return;
    s.staticBoxes = s.boxCount = int(boxes.size());
    if (s.staticBoxes + s.movingBoxes > s.boxCapacity || !s.boxes) {  // the box buffer and each face's list of them
        s.boxCapacity = std::max(s.boxCapacity, s.staticBoxes + s.movingBoxes);
        s.boxes = gl::makeBuffer(nullptr, std::size_t(std::max(s.boxCapacity, 1)) * sizeof(GpuBox), GL_DYNAMIC_STORAGE_BIT);
        s.visible = gl::makeBuffer(nullptr, std::size_t(kProbeBatch) * 6 * std::size_t(std::max(s.boxCapacity, 1)) * sizeof(std::uint32_t));
    }
    if (!boxes.empty())
        glNamedBufferSubData(s.boxes.id(), 0, GLsizeiptr(boxes.size() * sizeof(GpuBox)), gpuBoxes(boxes).data());
    s.proxies = boxes;
    s.lamps = std::move(lamps);
    s.lampBuffer = gl::makeBuffer(nullptr, std::max<std::size_t>(s.lamps.size(), 1) * 2 * sizeof(glm::vec4), GL_DYNAMIC_STORAGE_BIT);
    s.field = std::make_unique<ProbeField>(std::move(boxes));
    s.cache = std::make_unique<ProbeCache>(s.preset->cacheProbes());
    s.slotPosition.assign(std::size_t(s.preset->cacheProbes()), glm::dvec3(0.0));
    s.slotCaptured.assign(std::size_t(s.preset->cacheProbes()), 0);
    const float zero[4] = {0, 0, 0, 0};
    glClearTexImage(s.cacheTexture.id(), 0, GL_RGBA, GL_FLOAT, zero);
    glClearTexImage(s.moments.id(), 0, GL_RG, GL_FLOAT, zero);
    const std::vector<int> gone = std::exchange(s.gone, {});  // hidden again among the new boxes
    setGoneBuildings(gone);
}

void ProbeGpu::State::allocate() {
    const int texels = preset->cacheTexels, size = settings.faceSize;
    cacheTexture = gl::makeTexture2D(GL_RGBA16F, texels, texels, 1, GL_LINEAR, GL_LINEAR, GL_CLAMP_TO_EDGE);
    moments = gl::makeTexture2D(GL_RG32F, 6 * tilesPerRow, tilesPerRow, 1, GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE);  // cleared by setScene
    coefficients = gl::makeBuffer(nullptr, std::size_t(preset->cacheProbes()) * 9 * sizeof(glm::vec4));
    commands = gl::makeBuffer(nullptr, std::size_t(kProbeBatch) * 6 * 4 * sizeof(std::uint32_t), GL_DYNAMIC_STORAGE_BIT);
    batch = gl::makeBuffer(nullptr, std::size_t(kProbeBatch) * sizeof(glm::vec4), GL_DYNAMIC_STORAGE_BIT);
    gAlbedo = gl::makeTexture2D(GL_RGBA8, 6 * size, kProbeBatch * size, 1, GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE);
    gNormal = gl::makeTexture2D(GL_RGBA32F, 6 * size, kProbeBatch * size, 1, GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE);
    gDepth = gl::makeTexture2D(GL_DEPTH_COMPONENT32F, 6 * size, kProbeBatch * size, 1, GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE);
    gBuffer = gl::makeFramebuffer();
    glNamedFramebufferTexture(gBuffer.id(), GL_COLOR_ATTACHMENT0, gAlbedo.id(), 0);
    glNamedFramebufferTexture(gBuffer.id(), GL_COLOR_ATTACHMENT1, gNormal.id(), 0);
    glNamedFramebufferTexture(gBuffer.id(), GL_DEPTH_ATTACHMENT, gDepth.id(), 0);
    const GLenum buffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glNamedFramebufferDrawBuffers(gBuffer.id(), 2, buffers);
    if (glCheckNamedFramebufferStatus(gBuffer.id(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw std::runtime_error("the GL driver cannot render the probes' G-buffer (RGBA8 + RGBA32F)");
    std::vector<float> omega;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) omega.push_back(float(cubeTexelSolidAngle(x, y, size)));
    solidAngles = gl::makeBuffer(omega);
    if (settings.show) {
        const Mesh ball = makeIcosphere(1.0f, 2);
        std::vector<glm::vec4> corners;
        for (std::uint32_t i : ball.indices) corners.emplace_back(ball.positions[i], 0.0f);
        sphereVertices = gl::makeBuffer(corners);
        sphereVertexCount = int(corners.size());
        shown = gl::makeBuffer(nullptr, std::size_t(preset->cacheProbes()) * sizeof(glm::vec4), GL_DYNAMIC_STORAGE_BIT);
        sphere = gl::makeProgram("probe_sphere.vert", "probe_sphere.frag");
    }
    cull = gl::makeComputeProgram("probe_cull.comp");
    capture = gl::makeProgram("probe_capture.vert", "probe_capture.frag");
    project = gl::makeComputeProgram("probe_project.comp");
    vao = gl::makeVertexArray();
    block.cache = glm::vec4(float(tilesPerRow), 1.0f / float(texels), settings.antiLeak ? 1.0f : 0.0f, 0.0f);
    block.dims.w = preset->basis == ProbeBasis::Sh ? 2 : 1;
}

void ProbeGpu::bind() const {
    glBindBufferBase(GL_UNIFORM_BUFFER, 3, s_->ubo.id());
    glBindTextureUnit(11, s_->cacheTexture.id());
    glBindTextureUnit(15, s_->moments.id());
    glBindTextureUnit(12, s_->index.id());
}

ProbeStats ProbeGpu::update(glm::dvec3 focus, int budget, std::span<const ProbeBox> moving) {
    State& s = *s_;
    ProbeStats counts;
    if (!s.preset) return counts;
    const double spacing = s.preset->spacing;
    const std::vector<PlacedProbe> wanted = s.field->place(focus, kLightingArea, spacing);
    counts.wanted = int(wanted.size());
    const std::vector<PlacedProbe> admitted = s.toCapture(focus, budget, wanted);
    for (const PlacedProbe& p : admitted) s.slotCaptured[std::size_t(p.slot)] = 0;  // a reused slot shows nothing until captured
    const glm::ivec3 lo(glm::ceil((focus - kLightingArea) / spacing - 0.5)), hi(glm::floor((focus + kLightingArea) / spacing - 0.5));
    bind();
    if (!admitted.empty()) {
        s.uploadMoving(moving);
        s.inject(lo, hi);  // the probes captured before: the second bounce reads them
        for (std::size_t first = 0; first < admitted.size(); first += kProbeBatch)
            s.captureBatch(std::span(admitted).subspan(first, std::min<std::size_t>(kProbeBatch, admitted.size() - first)));
    }
    s.inject(lo, hi);
    counts.captured = int(admitted.size());
    std::vector<glm::vec4> shown;
    for (const PlacedProbe& p : wanted)
        if (const int slot = s.cache->slotOf(p.key); slot >= 0) shown.emplace_back(glm::vec3(p.position), float(slot));
    counts.injected = int(shown.size());
    if (s.settings.show && !shown.empty())
        glNamedBufferSubData(s.shown.id(), 0, GLsizeiptr(shown.size() * sizeof(glm::vec4)), shown.data());
    s.shownCount = int(shown.size());
    counts.held = int(s.cache->size());
    return counts;
}

// The moving boxes (destruction pieces) follow the proxies in the box buffer.
void ProbeGpu::State::uploadMoving(std::span<const ProbeBox> moving) {
    const std::size_t count = std::min<std::size_t>(moving.size(), std::size_t(boxCapacity - staticBoxes));
    if (count > 0)
        glNamedBufferSubData(boxes.id(), GLintptr(std::size_t(staticBoxes) * sizeof(GpuBox)), GLsizeiptr(count * sizeof(GpuBox)),
                             gpuBoxes(moving.first(count)).data());
    boxCount = staticBoxes + int(count);
}

// The lighting area's cells [lo, hi] → cache slot + 1 of the held, captured probe there (0: none).
void ProbeGpu::State::inject(glm::ivec3 lo, glm::ivec3 hi) {
    const glm::ivec3 dims = glm::max(hi - lo + 1, glm::ivec3(1));
    std::vector<GLint> cells(std::size_t(dims.x) * std::size_t(dims.y) * std::size_t(dims.z), 0);
    for (int k = 0; k < dims.z; ++k)
        for (int j = 0; j < dims.y; ++j)
            for (int i = 0; i < dims.x; ++i) {
                const int slot = cache->slotOf(probeKey(lo + glm::ivec3(i, j, k)));
                if (slot >= 0 && slotCaptured[std::size_t(slot)])
                    cells[(std::size_t(k) * std::size_t(dims.y) + std::size_t(j)) * std::size_t(dims.x) + std::size_t(i)] = slot + 1;
            }
    if (dims != indexDims) {
        index = indexTexture(dims);
        indexDims = dims;
    }
    glTextureSubImage3D(index.id(), 0, 0, 0, 0, dims.x, dims.y, dims.z, GL_RED_INTEGER, GL_INT, cells.data());
    block.origin = glm::vec4(glm::vec3(preset->spacing * (glm::dvec3(lo) + 0.5)), float(preset->spacing));
    block.dims = glm::ivec4(dims, block.dims.w);
    glNamedBufferSubData(ubo.id(), 0, sizeof(ProbesBlock), &block);
    glBindTextureUnit(12, index.id());
}

// The new probes to capture this frame: the lighting area's first; with budget left over once
// the area is all held (the player is idle), the caching area's around it, so that probes are
// ready before the player gets there. Budget 0: the whole lighting area, nothing more.
std::vector<PlacedProbe> ProbeGpu::State::toCapture(glm::dvec3 focus, int budget, const std::vector<PlacedProbe>& wanted) {
    std::vector<PlacedProbe> admitted = cache->admit(wanted, focus, budget > 0 ? budget : int(wanted.size()));
    const bool areaHeld = std::all_of(wanted.begin(), wanted.end(), [&](const PlacedProbe& p) { return cache->holds(p.key); });
    if (budget > int(admitted.size()) && areaHeld) {
        const std::vector<PlacedProbe> more = cache->admit(field->place(focus, kCachingArea, preset->spacing), focus, budget - int(admitted.size()));
        admitted.insert(admitted.end(), more.begin(), more.end());
    }
    return admitted;
}

void ProbeGpu::State::captureBatch(std::span<const PlacedProbe> probes) {
    const int n = int(probes.size());
    std::vector<glm::vec4> positions;
    for (const PlacedProbe& p : probes) positions.emplace_back(glm::vec3(p.position), float(p.slot));
    glNamedBufferSubData(batch.id(), 0, GLsizeiptr(positions.size() * sizeof(glm::vec4)), positions.data());
    cullBatch(n);
    drawBatch(probes);
    projectBatch(probes);
    for (const PlacedProbe& p : probes) {
        slotPosition[std::size_t(p.slot)] = p.position;
        slotCaptured[std::size_t(p.slot)] = 1;
    }
}

// Which boxes each face of the batch's n probes sees: probe_cull.comp fills the face lists and
// the instance counts of the indirect draws.
void ProbeGpu::State::cullBatch(int n) {
    std::vector<std::uint32_t> reset;
    for (int f = 0; f < n * 6; ++f) reset.insert(reset.end(), {36u, 0u, 0u, 0u});
    glNamedBufferSubData(commands.id(), 0, GLsizeiptr(reset.size() * sizeof(std::uint32_t)), reset.data());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, boxes.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, visible.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, commands.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, batch.id());
    glUseProgram(cull.id());
    glUniform1ui(0, GLuint(boxCount));
    glUniform1f(1, float(kReach));
    glUniform1ui(2, GLuint(boxCapacity));
    glDispatchCompute(GLuint((boxCount + 63) / 64), GLuint(n), 1);
    glMemoryBarrier(GL_COMMAND_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
}

// One instanced indirect draw per cube face into the G-buffer: probe b's face f at (f, b).
void ProbeGpu::State::drawBatch(std::span<const PlacedProbe> probes) {
    const int size = settings.faceSize;
    glBindFramebuffer(GL_FRAMEBUFFER, gBuffer.id());
    // Only the batch's rows: a short batch (a frame's few new probes) clears little.
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, 0, 6 * size, int(probes.size()) * size);
    const float clear[4] = {0, 0, 0, 0};
    glClearNamedFramebufferfv(gBuffer.id(), GL_COLOR, 0, clear);
    glClearNamedFramebufferfv(gBuffer.id(), GL_COLOR, 1, clear);
    glClearNamedFramebufferfi(gBuffer.id(), GL_DEPTH_STENCIL, 0, 1.0f, 0);
    glDisable(GL_SCISSOR_TEST);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glUseProgram(capture.id());
    glBindVertexArray(vao.id());
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, commands.id());
    const glm::dmat4 proj = glm::perspective(glm::radians(90.0), 1.0, 0.05, 2.0 * kReach);
    for (std::size_t b = 0; b < probes.size(); ++b) {
        const glm::dvec3 p = probes[b].position;
        glUniform3fv(2, 1, glm::value_ptr(glm::vec3(p)));
        for (int f = 0; f < 6; ++f) {
            const int face = int(b) * 6 + f;
            const glm::mat4 viewProj(proj * glm::lookAt(p, p + kForward[f], kUp[f]));
            glViewport(f * size, int(b) * size, size, size);
            glUniformMatrix4fv(0, 1, GL_FALSE, glm::value_ptr(viewProj));
            glUniform1ui(1, GLuint(face * boxCapacity));
            glDrawArraysIndirect(GL_TRIANGLES, reinterpret_cast<const void*>(std::uintptr_t(face) * 16u));
        }
    }
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
}

// probe_project.comp: lights the G-buffer and writes each probe's tile and coefficients.
void ProbeGpu::State::projectBatch(std::span<const PlacedProbe> probes) {
    const int n = int(probes.size());
    std::vector<glm::vec4> near;  // the street lamps that may light what the batch sees
    for (const StreetLamp& lamp : lamps)
        if (std::any_of(probes.begin(), probes.end(), [&](const PlacedProbe& p) { return glm::length(p.position - lamp.position) < kLampReach; }))
            near.insert(near.end(), {glm::vec4(glm::vec3(lamp.position), 1.0f), glm::vec4(glm::vec3(lamp.colour), 1.0f)});
    if (!near.empty()) glNamedBufferSubData(lampBuffer.id(), 0, GLsizeiptr(near.size() * sizeof(glm::vec4)), near.data());
    glUseProgram(project.id());
    glBindTextureUnit(13, gAlbedo.id());
    glBindTextureUnit(14, gNormal.id());
    glBindImageTexture(0, cacheTexture.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
    glBindImageTexture(1, moments.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RG32F);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, coefficients.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, solidAngles.id());
    glUniform1i(0, settings.faceSize);
    glUniform1i(1, settings.multiBounce ? 1 : 0);
    glUniform1f(2, float(2.0 * kReach));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, lampBuffer.id());
    glUniform1i(3, GLint(near.size() / 2));
    glUniform3f(4, float(bake::kLampIntensity * bake::kStreetLampIntensity), float(bake::kLampSoftening), float(bake::kLampRange));
    glDispatchCompute(GLuint(n), 1, 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

void ProbeGpu::setGoneBuildings(std::span<const int> gone) {
    State& s = *s_;
    std::vector<int> sorted(gone.begin(), gone.end());
    std::sort(sorted.begin(), sorted.end());
    if (!s.preset || sorted == s.gone) return;
    s.gone = std::move(sorted);
    // A hidden box keeps its place with no size: its triangles are degenerate.
    std::vector<ProbeBox> boxes = s.proxies;
    for (ProbeBox& b : boxes)
        if (b.building >= 0 && std::binary_search(s.gone.begin(), s.gone.end(), b.building)) b.halfSize = glm::dvec3(0.0);
    glNamedBufferSubData(s.boxes.id(), 0, GLsizeiptr(boxes.size() * sizeof(GpuBox)), gpuBoxes(boxes).data());
}

std::size_t ProbeGpu::drawSpheres() const {
    const State& s = *s_;
    if (!s.preset || !s.settings.show || s.shownCount == 0) return 0;
    glUseProgram(s.sphere.id());
    glUniform1f(0, float(0.12 * s.preset->spacing));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, s.sphereVertices.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, s.shown.id());
    glBindVertexArray(s.vao.id());
    glDrawArraysInstanced(GL_TRIANGLES, 0, s.sphereVertexCount, s.shownCount);
    return 1;
}

std::vector<CapturedProbe> ProbeGpu::captured() const {
    const State& s = *s_;
    std::vector<CapturedProbe> out;
    if (!s.preset) return out;
    std::vector<glm::vec4> c(s.slotCaptured.size() * 9);
    glGetNamedBufferSubData(s.coefficients.id(), 0, GLsizeiptr(c.size() * sizeof(glm::vec4)), c.data());
    for (std::size_t slot = 0; slot < s.slotCaptured.size(); ++slot) {
        if (!s.slotCaptured[slot]) continue;
        CapturedProbe p;
        p.position = s.slotPosition[slot];
        for (int i = 0; i < 9; ++i) p.radiance.c[std::size_t(i)] = glm::dvec3(glm::vec3(c[slot * 9 + std::size_t(i)]));
        p.indoors = c[slot * 9].w > 1.5f;
        out.push_back(p);
    }
    return out;
}

}  // namespace dawnforge::runtime
