#include "scene_gpu.hpp"

#include "ocean_gpu.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/exporters/vat_read.hpp>
#include <dawnforge/runtime/atlas.hpp>
#include <dawnforge/runtime/interior.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <chrono>
#include <limits>
#include <map>

namespace dawnforge::runtime {

namespace {

constexpr int kMaterials = 16;
constexpr int kOverlookSize = 1024;
// A world's sun shadow covers this radius around the ground ahead of the camera at at most
// kWorldShadowSize² texels (0.23 m, as a 450 m district's 2048²); a city's covers the whole city.
constexpr double kWorldShadowRadius = 120.0;
constexpr int kWorldShadowSize = 1024;

// The earliest start time of a destruction replacing each building.
std::map<std::uint32_t, double> replacedUntil(const SceneFile& scene) {
    std::map<std::uint32_t, double> until;
    for (const DestructionInstance& d : scene.destruction)
        if (d.replaces) {
            const auto [it, added] = until.try_emplace(std::uint32_t(*d.replaces), d.startTime);
            it->second = std::min(it->second, d.startTime);
        }
    return until;
}

// Binds `fbo` as a size² depth target and clears it.
void clearDepthTarget(GLuint fbo, int size) {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, size, size);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    glDisable(GL_CULL_FACE);
}

}  // namespace

void SceneGpu::load(const SceneFile& scene, int shadowMapSize, const StreamingOptions& streaming) {
    shadowSize_ = shadowMapSize;
    wind_ = scene.wind;
    programs_.make();
    vat_ = gl::makeProgram("vat.vert", "surface.frag");
    vatDepth_ = gl::makeProgram("vat.vert", "depth.frag", {"DEPTH_PASS"});
    dust_ = gl::makeProgram("dust.vert", "dust.frag");
    emptyVao_ = gl::makeVertexArray();

    // The atlas: 2048², mip levels 0..4 only, so no footprint leaves a block's padding.
    const AtlasImage atlas = generateAtlas();
    atlas_ = gl::makeTexture2D(GL_SRGB8_ALPHA8, atlas.size, atlas.size, kAtlasLevels, GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR,
                               GL_CLAMP_TO_EDGE);
    for (int l = 0; l < kAtlasLevels; ++l)
        glTextureSubImage2D(atlas_.id(), l, 0, 0, atlas.size >> l, atlas.size >> l, GL_RGBA, GL_UNSIGNED_BYTE,
                            atlas.rgba[std::size_t(l)].data());
    atlasMeans_ = gl::makeBuffer(atlas.blockMean.data(), sizeof(atlas.blockMean));

    const InteriorTextures interiors = generateInteriors(128, 8);  // 128² per room style: windows are small on screen
    roomStyles_ = interiors.styles;
    const int w = interiors.roomSize * interiors.styles, h = interiors.roomSize;
    for (auto [texture, pixels] : {std::pair{&rooms_, &interiors.rooms}, std::pair{&roomMiddle_, &interiors.middle}}) {
        *texture = gl::makeTexture2D(GL_SRGB8_ALPHA8, w, h, 1, GL_LINEAR, GL_LINEAR, GL_CLAMP_TO_EDGE);
        glTextureSubImage2D(texture->id(), 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, pixels->data());
    }
    std::vector<glm::vec4> tiles(kMaterials);
    for (int m = 0; m < kMaterials; ++m) tiles[std::size_t(m)] = glm::vec4(float(materialTileMetres(m)), 0, 0, 0);
    materialsUbo_ = gl::makeBuffer(tiles);

    boundsMin_ = glm::dvec3(std::numeric_limits<double>::max());
    boundsMax_ = glm::dvec3(-std::numeric_limits<double>::max());
    // Without a bake, one black layer: the shaders never read it (every vertex's layer is -1).
    noLightmaps_ = gl::makeTexture(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(noLightmaps_.id(), 1, GL_RGBA8, 1, 1, 1);
    const std::uint8_t black[4] = {0, 0, 0, 0};
    glTextureSubImage3D(noLightmaps_.id(), 0, 0, 0, 0, 1, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, black);
    if (scene.cityDir) loadCity(scene);
    if (scene.worldDir) {
        world_ = std::make_unique<TileStreamer>();
        world_->open(*scene.worldDir, streaming, replacedUntil(scene), scene.probes.preset != "off");
        boundsMin_ = world_->tiles().boundsMin, boundsMax_ = world_->tiles().boundsMax;
    }
    for (const DestructionInstance& d : scene.destruction) loadVat(d);
    checkReplaced(scene);
    if (boundsMin_.x > boundsMax_.x) boundsMin_ = glm::dvec3(-10.0), boundsMax_ = glm::dvec3(10.0);
    if (world_) shadowSize_ = std::min(shadowSize_, kWorldShadowSize);

    // The shadow map: depth with hardware comparison (sampler2DShadow).
    shadowMap_ = gl::makeTexture2D(GL_DEPTH_COMPONENT32F, shadowSize_, shadowSize_, 1, GL_LINEAR, GL_LINEAR, GL_CLAMP_TO_EDGE);
    glTextureParameteri(shadowMap_.id(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTextureParameteri(shadowMap_.id(), GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    shadowFbo_ = gl::makeFramebuffer();
    glNamedFramebufferTexture(shadowFbo_.id(), GL_DEPTH_ATTACHMENT, shadowMap_.id(), 0);
    glNamedFramebufferDrawBuffer(shadowFbo_.id(), GL_NONE);

    if (scene.ocean) loadOcean(*scene.ocean);
    // The ocean's shores and the probes' IN/OUT tags read it; a bake brings its own. A world
    // has none yet: its whole sea is open water (overlookArea() puts every point outside).
    if (world_) overlook_ = gl::makeTexture2D(GL_R32F, 1, 1, 1, GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE);
    else if (!bakedOverlook_ && (scene.ocean || scene.probes.preset != "off")) renderOverlook();
    gl::check("loading the scene");
}

void SceneGpu::loadCity(const SceneFile& scene) {
    city_.emplace(loadCityCpu(*scene.cityDir, replacedUntil(scene)));
    city_->upload(std::numeric_limits<std::size_t>::max());  // all of it at once
    if (!city_->empty()) boundsMin_ = city_->boundsMin(), boundsMax_ = city_->boundsMax();
    baked_ = city_->baked();
    if (city_->overlook()) loadOverlook(*city_->overlook());
}

// The bake's overlook depth (metres below `top`) in place of the one drawn at load.
void SceneGpu::loadOverlook(const OverlookDepth& o) {
    const auto t0 = std::chrono::steady_clock::now();
    overlook_ = gl::makeTexture2D(GL_R32F, o.width, o.height, 1, GL_LINEAR, GL_LINEAR, GL_CLAMP_TO_EDGE);
    glTextureSubImage2D(overlook_.id(), 0, 0, 0, o.width, o.height, GL_RED, GL_FLOAT, o.depth.data());
    overlookArea_ = glm::vec4(o.origin, glm::max(o.extent, glm::vec2(1e-3f)));
    overlookDepth_ = glm::vec4(o.top, 0.0f, 1.0f, 0.0f);
    overlookMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    bakedOverlook_ = true;
}

// A destruction may replace only a building the city has (a world: its plan.json's tiles own).
void SceneGpu::checkReplaced(const SceneFile& scene) const {
    const bool any = std::any_of(scene.destruction.begin(), scene.destruction.end(),
                                 [](const DestructionInstance& d) { return d.replaces.has_value(); });
    if (!any) return;
    const std::optional<std::set<std::uint32_t>> world = scene.worldDir ? worldBuildings(*scene.worldDir) : std::nullopt;
    for (const DestructionInstance& d : scene.destruction) {
        if (!d.replaces) continue;
        const auto id = std::uint32_t(*d.replaces);
        if (city_ && !city_->hasBuilding(id))
            throw InputError(format("destruction {}: \"replaces\": the city has no building {}", d.name, *d.replaces));
        if (world && !world->count(id))
            throw InputError(format("destruction {}: \"replaces\": the world has no building {}", d.name, *d.replaces));
    }
}

void SceneGpu::loadVat(const DestructionInstance& d) {
    const exporters::VatFile file = exporters::readVat(d.vatDir, d.name);
    if (file.preset != exporters::VatPreset::Native)
        throw InputError(format("{}: VAT {} uses the {} preset; the runtime plays native VATs", d.vatDir.string(), d.name,
                                exporters::vatPresetName(file.preset)));
    Vat v;
    v.name = d.name;
    v.layout = glm::vec4(float(file.layout.width), float(file.layout.rowsPerFrame), float(file.layout.height),
                         float(file.layout.frames));
    v.fps = file.fps;
    v.startTime = d.startTime;
    v.place = d.position;
    v.yawDegrees = d.yawDegrees;
    v.model = glm::translate(glm::mat4(1.0f), glm::vec3(d.position)) *
              glm::rotate(glm::mat4(1.0f), float(glm::radians(d.yawDegrees)), glm::vec3(0, 1, 0));
    // A building's destruction wears the building's own atlas blocks (its brick, its plaster).
    v.replacing = d.replaces.has_value();
    v.building = d.replaces ? std::uint32_t(*d.replaces) : 0xfffeu;
    v.blocks = instanceBlocks(v.building);
    for (auto [texture, data] : {std::pair{&v.position, &file.position}, std::pair{&v.rotation, &file.rotation}}) {
        *texture = gl::makeTexture2D(GL_RGBA32F, file.layout.width, file.layout.height, 1, GL_NEAREST, GL_NEAREST,
                                     GL_CLAMP_TO_EDGE);
        glTextureSubImage2D(texture->id(), 0, 0, 0, file.layout.width, file.layout.height, GL_RGBA, GL_FLOAT, data->data());
    }
    if (file.dustPuffs > 0) {
        const exporters::VatLayout& d = file.dustLayout;
        v.dust = gl::makeTexture2D(GL_RGBA32F, d.width, d.height, 1, GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE);
        glTextureSubImage2D(v.dust.id(), 0, 0, 0, d.width, d.height, GL_RGBA, GL_FLOAT, file.dust.data());
        v.dustLayout = glm::vec4(float(d.width), float(d.rowsPerFrame), float(d.frames), float(file.dustPuffs));
    }
    // Vertex data: the static layout, with uv1 = lookup, uv2 = (px, 0) and a ninth
    // attribute (py, pz) from TEXCOORD_3.
    const Mesh& m = file.mesh;
    struct VatVertex {
        StaticVertex base;
        glm::vec2 pivotYZ;
    };
    std::vector<VatVertex> vertices(m.positions.size());
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        vertices[i].base = staticVertex(m, i, glm::mat4(1.0f), glm::mat3(1.0f));
        vertices[i].pivotYZ = m.uv3.empty() ? glm::vec2(0) : m.uv3[i];
    }
    v.vertices = gl::makeBuffer(vertices);
    v.indices = gl::makeBuffer(m.indices);
    v.indexCount = std::uint32_t(m.indices.size());
    v.vao = gl::makeVertexArray();
    const GLuint vao = v.vao.id();
    vertexLayout(vao);
    glVertexArrayAttribFormat(vao, 8, 2, GL_FLOAT, GL_FALSE, offsetof(VatVertex, pivotYZ));
    glEnableVertexArrayAttrib(vao, 8);
    glVertexArrayAttribBinding(vao, 8, 0);
    glVertexArrayVertexBuffer(vao, 0, v.vertices.id(), 0, sizeof(VatVertex));
    glVertexArrayElementBuffer(vao, v.indices.id());
    v.boxes = VatPieceBoxes(file, v.model, v.startTime);
    // Bounds over the whole animation, placed.
    growPlacedBox(file.boundsMin, file.boundsMax, v.model, boundsMin_, boundsMax_);
    vats_.push_back(std::move(v));
}

std::vector<ProbeBox> SceneGpu::pieceBoxes(double time) const {
    std::vector<ProbeBox> out;
    for (const Vat& v : vats_)
        if (!v.replacing || time >= v.startTime) v.boxes.append(time, out);  // as drawVats draws them
    for (ProbeBox& b : out) b.centre -= origin_;
    return out;
}

std::optional<std::vector<ProbeBox>> SceneGpu::worldProbeBoxes() {
    if (!world_) return std::nullopt;
    std::vector<int> nodes;
    for (const TileStreamer::Drawn& d : drawn_)
        if (!d.hlod) nodes.push_back(d.node);
    std::sort(nodes.begin(), nodes.end());
    if (nodes == probeNodes_ && origin_ == probeOrigin_) return std::nullopt;
    probeNodes_ = std::move(nodes);
    probeOrigin_ = origin_;
    std::vector<ProbeBox> boxes;
    for (const TileStreamer::Drawn& d : drawn_)
        if (!d.hlod && d.proxies)
            for (ProbeBox b : *d.proxies) {
                b.centre += d.offset - origin_;
                boxes.push_back(std::move(b));
            }
    return boxes;
}

std::vector<int> SceneGpu::goneBuildings(double time) const {
    std::vector<int> gone;
    for (const Vat& v : vats_)
        if (v.replacing && time >= v.startTime) gone.push_back(int(v.building));
    return gone;
}

std::size_t SceneGpu::pieceCount() const {
    std::size_t n = 0;
    for (const Vat& v : vats_) n += v.boxes.pieces();
    return n;
}

void SceneGpu::loadOcean(const OceanSettings& settings) {
    hasOcean_ = true;
    oceanSettings_ = settings;
    waves_ = defaultWaves();
    ocean_ = gl::makeProgram("ocean.vert", "ocean.frag");
    const int cols = settings.columns, rows = settings.rows;
    std::vector<glm::vec2> grid;
    grid.reserve(std::size_t(cols) * std::size_t(rows));
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c) grid.emplace_back(float(c) / float(cols - 1), float(r));
    const std::vector<std::uint32_t> indices = oceanGridIndices(cols, rows);
    oceanIndexCount_ = std::uint32_t(indices.size());
    oceanVertices_ = gl::makeBuffer(grid);
    oceanIndices_ = gl::makeBuffer(indices);
    oceanRows_ = gl::makeBuffer(nullptr, sizeof(float) * std::size_t(rows), GL_DYNAMIC_STORAGE_BIT);
    oceanVao_ = gl::makeVertexArray();
    glVertexArrayAttribFormat(oceanVao_.id(), 0, 2, GL_FLOAT, GL_FALSE, 0);
    glEnableVertexArrayAttrib(oceanVao_.id(), 0);
    glVertexArrayAttribBinding(oceanVao_.id(), 0, 0);
    glVertexArrayVertexBuffer(oceanVao_.id(), 0, oceanVertices_.id(), 0, sizeof(glm::vec2));
    glVertexArrayElementBuffer(oceanVao_.id(), oceanIndices_.id());

    const WaveNoise noise = makeWaveNoise();
    waveNoise_ = uploadWaveNoise(noise);

    const OceanUniforms u = oceanUniforms(waves_, settings.level, settings.shoreDepth, settings.columns);
    oceanUbo_ = gl::makeBuffer(&u, sizeof(u));
}

// The overlook depth: an orthographic camera above the scene looking straight down, drawn
// once at load (terrain and buildings, LOD1); the ocean's vertex shader reads it to calm
// the waves near shores.
void SceneGpu::renderOverlook() {
    const auto t0 = std::chrono::steady_clock::now();
    overlook_ = gl::makeTexture2D(GL_DEPTH_COMPONENT32F, kOverlookSize, kOverlookSize, 1, GL_LINEAR, GL_LINEAR, GL_CLAMP_TO_EDGE);
    overlookFbo_ = gl::makeFramebuffer();
    glNamedFramebufferTexture(overlookFbo_.id(), GL_DEPTH_ATTACHMENT, overlook_.id(), 0);
    glNamedFramebufferDrawBuffer(overlookFbo_.id(), GL_NONE);

    const glm::vec3 lo(boundsMin_), hi(boundsMax_);
    const float top = hi.y + 10.0f, nearPlane = 1.0f, farPlane = top - (lo.y - 10.0f);
    // Looking down −Y with +Z towards the bottom of the image: texture u follows x, v follows z.
    const glm::mat4 view = glm::lookAt(glm::vec3(0, top, 0), glm::vec3(0, top - 1.0f, 0), glm::vec3(0, 0, -1));
    const glm::mat4 proj = glm::ortho(lo.x, hi.x, -hi.z, -lo.z, nearPlane, farPlane);
    // With up = −z, view x = world x and view y = −world z: v = 0 at z = hi.z... flip so
    // texture v grows with z.
    const glm::mat4 flip = glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, -1.0f, 1.0f));
    const glm::mat4 viewProj = flip * proj * view;
    overlookArea_ = glm::vec4(lo.x, lo.z, std::max(hi.x - lo.x, 1e-3f), std::max(hi.z - lo.z, 1e-3f));
    overlookDepth_ = glm::vec4(top, nearPlane, farPlane - nearPlane, 0.0f);

    clearDepthTarget(overlookFbo_.id(), kOverlookSize);
    if (city_) city_->drawDepth(programs_, indirect_, viewProj, glm::vec3(0.0f), -std::numeric_limits<double>::infinity(), nullptr);
    glFinish();
    overlookMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void SceneGpu::setCamera(glm::dvec3 position, glm::dvec3 forward, double fovY, double aspect, double nearPlane,
                         double farPlane) {
    camera_.position = position;
    camera_.forward = forward;
    camera_.fovYRadians = fovY;
    camera_.aspect = aspect;
    camera_.nearPlane = nearPlane;
    camera_.farPlane = farPlane;
}

glm::dvec3 SceneGpu::beginFrame(glm::dvec3 camera, const SelectionCamera& selection, const SelectionCamera* prefetch,
                                StreamingStats& stats) {
    if (!world_) return origin_ = glm::dvec3(0.0);
    origin_ = glm::round(camera / kOriginStep) * kOriginStep;
    origin_.y = 0.0;
    world_->update(selection, prefetch, stats);
    drawn_ = world_->drawn();
    return origin_;
}

double SceneGpu::shadowRadius() const {
    return world_ ? kWorldShadowRadius : std::max(0.5 * glm::length(boundsMax_ - boundsMin_), 1.0);
}

glm::vec4 SceneGpu::overlookArea() const {
    if (world_) return glm::vec4(1e30f, 1e30f, 1.0f, 1.0f);  // every point outside: open water
    return overlookArea_;
}

// The sun's orthographic camera, fitted around the scene's bounding sphere (a city) or the
// sphere of kWorldShadowRadius around the ground ahead of the camera (a world), in render space.
glm::mat4 SceneGpu::lightViewProj(glm::dvec3 sunDirection) {
    glm::vec3 centre(0.5 * (boundsMin_ + boundsMax_) - origin_);
    if (world_) {  // camera_ is in render space
        const glm::dvec3 level(camera_.forward.x, 0.0, camera_.forward.z);
        const double length = glm::length(level);
        const glm::dvec3 ahead = camera_.position + (length > 1e-6 ? 0.6 * kWorldShadowRadius / length : 0.0) * level;
        centre = glm::vec3(ahead.x, std::max(camera_.position.y - 40.0, 0.0), ahead.z);
    }
    const float radius = float(shadowRadius());
    const glm::vec3 dir = glm::normalize(glm::vec3(sunDirection));
    const glm::vec3 up = std::abs(dir.y) > 0.99f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
    const glm::mat4 view = glm::lookAt(centre + dir * 2.0f * radius, centre, up);
    const glm::mat4 proj = glm::ortho(-radius, radius, -radius, radius, 0.5f * radius, 3.5f * radius);
    lightViewProj_ = proj * view;
    return lightViewProj_;
}

void SceneGpu::bindShared() {
    glBindBufferBase(GL_UNIFORM_BUFFER, 1, materialsUbo_.id());
    glBindBufferBase(GL_UNIFORM_BUFFER, 4, atlasMeans_.id());
    glBindTextureUnit(0, atlas_.id());
    glBindTextureUnit(1, rooms_.id());
    glBindTextureUnit(2, roomMiddle_.id());
    glBindTextureUnit(8, noLightmaps_.id());
    glBindTextureUnit(6, overlook_.id());
    glBindTextureUnit(7, shadowMap_.id());
}

std::vector<StreetLamp> SceneGpu::lamps(const std::vector<StreetLamp>& cityLamps) {
    std::vector<StreetLamp> out = cityLamps;
    for (const TileStreamer::Drawn& d : drawn_)
        if (d.lamps)
            for (StreetLamp lamp : *d.lamps) {
                lamp.position += d.offset;
                out.push_back(lamp);
            }
    for (StreetLamp& lamp : out) lamp.position -= origin_;
    return out;
}

std::size_t SceneGpu::drawShadow(double time) {
    // The trees and the falling pieces cast shadows too.
    clearDepthTarget(shadowFbo_.id(), shadowSize_);
    std::size_t draws = 0;
    if (city_) draws += city_->drawDepth(programs_, indirect_, lightViewProj_, glm::vec3(0.0f), time, &wind_);
    for (const TileStreamer::Drawn& d : drawn_) {
        if (d.hlod) continue;  // far away, its light baked: it casts no sun shadow
        const glm::dvec3 lo = d.city->fullMin() + d.offset, hi = d.city->fullMax() + d.offset;
        if (outsideFrustum(lightViewProj_, glm::vec3(lo - origin_), glm::vec3(hi - origin_))) continue;
        draws += d.city->drawDepth(programs_, indirect_, lightViewProj_, offsetOf(d.offset), time, &wind_);
    }
    return draws + drawVats(time, true, nullptr);
}

// Depth first, then colour where the depth is the nearest: llvmpipe shades each pixel once
// instead of once per surface over it (the HLOD meshes are one draw each, in no order).
std::size_t SceneGpu::drawOpaque(glm::dvec3 camera, const glm::mat4& viewProj, double lodDistance, double time,
                                 FrameStats& stats) {
    std::size_t draws = 0;
    const auto drawAll = [&](FrameStats* st) {
        if (city_)
            draws += city_->drawOpaque(programs_, indirect_, {glm::vec3(0.0f), camera, viewProj, lodDistance, time}, wind_,
                                       roomStyles_, st);
        for (const TileStreamer::Drawn& d : drawn_)
            draws += d.city->drawOpaque(programs_, indirect_, {offsetOf(d.offset), camera - d.offset, viewProj, lodDistance, time},
                                        wind_, roomStyles_, st);
    };
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    drawAll(nullptr);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthFunc(GL_LEQUAL);
    glDepthMask(GL_FALSE);
    drawAll(&stats);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    glBindTextureUnit(8, noLightmaps_.id());
    return draws;
}

// Uniforms 2 and 3 of vat.vert and dust.vert: the frame at scene time `time` ((time − start) ×
// fps, clamped to the first and last frames) and the placement in render space (the
// translation less the origin, in double).
void SceneGpu::setPlayback(const Vat& v, double time) const {
    glUniform1f(2, float(std::clamp((time - v.startTime) * v.fps, 0.0, double(v.layout.w) - 1.0)));
    const glm::mat4 model = glm::translate(glm::mat4(1.0f), glm::vec3(v.place - origin_)) *
                            glm::rotate(glm::mat4(1.0f), float(glm::radians(v.yawDegrees)), glm::vec3(0, 1, 0));
    glUniformMatrix4fv(3, 1, GL_FALSE, glm::value_ptr(model));
}

std::size_t SceneGpu::drawVats(double time, bool depth, FrameStats* stats) {
    std::size_t draws = 0;
    glUseProgram(depth ? vatDepth_.id() : vat_.id());
    if (depth) glUniformMatrix4fv(0, 1, GL_FALSE, glm::value_ptr(lightViewProj_));
    else glUniform1i(4, roomStyles_);
    for (const Vat& v : vats_) {
        if (v.replacing && time < v.startTime) continue;  // the building stands until then
        glBindVertexArray(v.vao.id());
        glVertexAttribI4ui(6, v.blocks.x, v.blocks.y, v.blocks.z, v.blocks.w);
        glVertexAttribI1ui(7, v.building);
        glBindTextureUnit(3, v.position.id());
        glBindTextureUnit(4, v.rotation.id());
        glUniform4fv(1, 1, glm::value_ptr(v.layout));
        setPlayback(v, time);
        glDrawElements(GL_TRIANGLES, GLsizei(v.indexCount), GL_UNSIGNED_INT, nullptr);
        if (stats) stats->triangles += v.indexCount / 3;
        ++draws;
    }
    return draws;
}

std::size_t SceneGpu::drawDestruction(double time, FrameStats& stats) {
    return drawVats(time, false, &stats);  // into the HDR target the opaque pass bound
}

std::size_t SceneGpu::drawOcean(FrameStats& stats) {
    if (!hasOcean_) return 0;
    const OceanGrid grid = projectOceanGrid(camera_, oceanSettings_.level, oceanSettings_.columns, oceanSettings_.rows);
    if (!grid.visible) return 0;
    std::vector<float> rows(grid.rowNdcY.begin(), grid.rowNdcY.end());
    glNamedBufferSubData(oceanRows_.id(), 0, GLsizeiptr(rows.size() * sizeof(float)), rows.data());
    glUseProgram(ocean_.id());
    glUniform1f(0, oceanSettings_.ripples ? 1.0f : 0.0f);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, oceanRows_.id());
    glBindBufferBase(GL_UNIFORM_BUFFER, 2, oceanUbo_.id());
    glBindTextureUnit(5, waveNoise_.id());
    glBindVertexArray(oceanVao_.id());
    glDrawElements(GL_TRIANGLES, GLsizei(oceanIndexCount_), GL_UNSIGNED_INT, nullptr);
    stats.oceanVertices = std::size_t(grid.columns) * std::size_t(grid.rows);
    stats.triangles += oceanIndexCount_ / 3;
    return 1;
}

}  // namespace dawnforge::runtime
