#include "scene_gpu.hpp"

#include "ocean_gpu.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/read_file.hpp>
#include <dawnforge/core/seed.hpp>
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

// The default mapping of an instance: every material in its own block, brick and plaster
// in one of their four half-size variants chosen from the instance id.
glm::uvec4 instanceBlocks(std::uint32_t id) {
    const std::uint64_t h = deriveSeed(0x6174'6c61'7300ull, "atlas variant", id);
    glm::uvec4 blocks(0u);
    for (int m = 0; m < kMaterials; ++m) {
        const int variant = int((h >> (2 * m)) & 3u);
        blocks[m / 4] |= encodeBlock(materialBlock(m, variant)) << (8 * (m % 4));
    }
    return blocks;
}

// Culling: is the box outside one of the six planes of `viewProj`?
bool outsideFrustum(const glm::mat4& viewProj, glm::vec3 lo, glm::vec3 hi) {
    const glm::mat4 m = glm::transpose(viewProj);
    const glm::vec4 planes[6] = {m[3] + m[0], m[3] - m[0], m[3] + m[1], m[3] - m[1], m[3] + m[2], m[3] - m[2]};
    for (const glm::vec4& p : planes) {
        const glm::vec3 far(p.x > 0 ? hi.x : lo.x, p.y > 0 ? hi.y : lo.y, p.z > 0 ? hi.z : lo.z);
        if (glm::dot(glm::vec3(p), far) + p.w < 0.0f) return true;
    }
    return false;
}

}  // namespace

void vertexLayout(GLuint vao) {
    glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, offsetof(StaticVertex, position));
    glVertexArrayAttribFormat(vao, 1, 3, GL_FLOAT, GL_FALSE, offsetof(StaticVertex, normal));
    glVertexArrayAttribFormat(vao, 2, 2, GL_FLOAT, GL_FALSE, offsetof(StaticVertex, uv0));
    glVertexArrayAttribFormat(vao, 3, 2, GL_FLOAT, GL_FALSE, offsetof(StaticVertex, uv1));
    glVertexArrayAttribFormat(vao, 4, 2, GL_FLOAT, GL_FALSE, offsetof(StaticVertex, uv2));
    glVertexArrayAttribIFormat(vao, 5, 1, GL_UNSIGNED_BYTE, offsetof(StaticVertex, material));
    glVertexArrayAttribFormat(vao, 9, 3, GL_FLOAT, GL_FALSE, offsetof(StaticVertex, light));
    for (GLuint a : {0u, 1u, 2u, 3u, 4u, 5u, 9u}) {
        glEnableVertexArrayAttrib(vao, a);
        glVertexArrayAttribBinding(vao, a, 0);
    }
}

void growPlacedBox(glm::dvec3 boxMin, glm::dvec3 boxMax, const glm::mat4& model, glm::dvec3& lo, glm::dvec3& hi) {
    for (int c = 0; c < 8; ++c) {
        const glm::dvec3 corner((c & 1) ? boxMax.x : boxMin.x, (c & 2) ? boxMax.y : boxMin.y, (c & 4) ? boxMax.z : boxMin.z);
        const glm::dvec3 p = glm::dvec3(model * glm::vec4(glm::vec3(corner), 1.0f));
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
}

void instancedLayout(GLuint vao, GLuint vertices, GLuint indices, GLuint instances, GLsizei instanceStride,
                     GLuint blocksOffset, GLuint buildingOffset) {
    vertexLayout(vao);
    glVertexArrayVertexBuffer(vao, 0, vertices, 0, sizeof(StaticVertex));
    glVertexArrayElementBuffer(vao, indices);
    glVertexArrayAttribIFormat(vao, 6, 4, GL_UNSIGNED_INT, blocksOffset);
    glVertexArrayAttribIFormat(vao, 7, 1, GL_UNSIGNED_INT, buildingOffset);
    for (GLuint a : {6u, 7u}) {
        glEnableVertexArrayAttrib(vao, a);
        glVertexArrayAttribBinding(vao, a, 1);
    }
    glVertexArrayVertexBuffer(vao, 1, instances, 0, instanceStride);
    glVertexArrayBindingDivisor(vao, 1, 1);
}

StaticVertex staticVertex(const Mesh& m, std::size_t i, const glm::mat4& world, const glm::mat3& normalMatrix) {
    StaticVertex v{};
    v.position = glm::vec3(world * glm::vec4(m.positions[i], 1.0f));
    v.normal = m.normals.empty() ? glm::vec3(0, 1, 0) : glm::normalize(normalMatrix * m.normals[i]);
    v.uv0 = m.uv0.empty() ? glm::vec2(0) : m.uv0[i];
    v.uv1 = m.uv1.empty() ? glm::vec2(0) : m.uv1[i];
    v.uv2 = m.uv2.empty() ? glm::vec2(0) : m.uv2[i];
    v.material = m.materialIds.empty() ? 0 : std::uint8_t(m.materialIds[i] & 15u);
    v.light = glm::vec3(0.0f, 0.0f, -1.0f);
    return v;
}

void SceneGpu::load(const SceneFile& scene, int shadowMapSize) {
    shadowSize_ = shadowMapSize;
    wind_ = scene.wind;
    surface_ = gl::makeProgram("building.vert", "surface.frag");
    surfaceDepth_ = gl::makeProgram("building.vert", "depth.frag", {"DEPTH_PASS"});
    vat_ = gl::makeProgram("vat.vert", "surface.frag");
    vatDepth_ = gl::makeProgram("vat.vert", "depth.frag", {"DEPTH_PASS"});

    // The atlas: 2048², mip levels 0..4 only, so no footprint leaves a block's padding.
    const AtlasImage atlas = generateAtlas();
    atlas_ = gl::makeTexture2D(GL_SRGB8_ALPHA8, atlas.size, atlas.size, kAtlasLevels, GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR,
                               GL_CLAMP_TO_EDGE);
    for (int l = 0; l < kAtlasLevels; ++l)
        glTextureSubImage2D(atlas_.id(), l, 0, 0, atlas.size >> l, atlas.size >> l, GL_RGBA, GL_UNSIGNED_BYTE,
                            atlas.rgba[std::size_t(l)].data());

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
    vao_ = gl::makeVertexArray();
    // Without a bake, one black layer: the shaders never read it (every vertex's layer is -1).
    lightmaps_ = gl::makeTexture(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(lightmaps_.id(), 1, GL_RGBA8, 1, 1, 1);
    const std::uint8_t black[4] = {0, 0, 0, 0};
    glTextureSubImage3D(lightmaps_.id(), 0, 0, 0, 0, 1, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, black);
    if (scene.cityDir) loadCity(*scene.cityDir);
    for (const DestructionInstance& d : scene.destruction) loadVat(d);
    for (const DestructionInstance& d : scene.destruction)
        if (d.replaces) replaceBuilding(d);
    if (boundsMin_.x > boundsMax_.x) boundsMin_ = glm::dvec3(-10.0), boundsMax_ = glm::dvec3(10.0);

    // The shadow map: depth with hardware comparison (sampler2DShadow).
    shadowMap_ = gl::makeTexture2D(GL_DEPTH_COMPONENT32F, shadowSize_, shadowSize_, 1, GL_LINEAR, GL_LINEAR, GL_CLAMP_TO_EDGE);
    glTextureParameteri(shadowMap_.id(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTextureParameteri(shadowMap_.id(), GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    shadowFbo_ = gl::makeFramebuffer();
    glNamedFramebufferTexture(shadowFbo_.id(), GL_DEPTH_ATTACHMENT, shadowMap_.id(), 0);
    glNamedFramebufferDrawBuffer(shadowFbo_.id(), GL_NONE);

    if (scene.ocean) loadOcean(*scene.ocean);
    // The ocean's shores and the probes' IN/OUT tags read it; a bake brings its own.
    if (!bakedOverlook_ && (scene.ocean || scene.probes.preset != "off")) renderOverlook();
    gl::check("loading the scene");
}

void SceneGpu::loadCity(const std::filesystem::path& cityDir) {
    const std::filesystem::path file = cityDir / "city.glb";
    std::vector<MeshNode> nodes = loadMeshNodes(file);
    trees_.load(nodes, instanceBlocks(0xffffu), boundsMin_, boundsMax_);
    const std::optional<BakedCity> baked = loadBakedCity(cityDir, readBinaryFile(file));
    std::vector<StaticVertex> vertices;
    std::vector<std::uint32_t> indices;
    std::vector<InstanceData> instances;
    std::map<std::string, std::size_t> buildingIndex;

    const auto append = [&](const MeshNode& node, glm::vec3& lo, glm::vec3& hi) {
        DrawRange r;
        r.firstIndex = std::uint32_t(indices.size());
        r.baseVertex = std::int32_t(vertices.size());
        r.count = std::uint32_t(node.mesh.indices.size());
        const glm::mat3 normalMatrix = glm::transpose(glm::inverse(glm::mat3(node.world)));
        const std::vector<glm::vec3>* light = nullptr;
        if (baked) {
            const auto it = baked->lightmaps.nodeUv.find(node.name);
            if (it != baked->lightmaps.nodeUv.end() && it->second.size() == node.mesh.positions.size()) light = &it->second;
        }
        for (std::size_t i = 0; i < node.mesh.positions.size(); ++i) {
            vertices.push_back(staticVertex(node.mesh, i, node.world, normalMatrix));
            if (light) vertices.back().light = (*light)[i];
            lo = glm::min(lo, vertices.back().position);
            hi = glm::max(hi, vertices.back().position);
        }
        indices.insert(indices.end(), node.mesh.indices.begin(), node.mesh.indices.end());
        return r;
    };
    for (const MeshNode& node : nodes) {
        const std::string& name = node.name;
        const bool lod0 = name.ends_with("_lod0"), lod1 = name.ends_with("_lod1");
        glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
        if (lod0 || lod1) {
            const std::string key = name.substr(0, name.size() - 5);
            auto [it, added] = buildingIndex.try_emplace(key, buildings_.size());
            if (added) {
                Building b;
                b.min = lo, b.max = hi;
                // building_NNNNN: the id the city gave it; anything else: its order.
                std::uint32_t id = std::uint32_t(buildings_.size());
                if (key.starts_with("building_")) id = std::uint32_t(std::strtoul(key.c_str() + 9, nullptr, 10));
                b.instance = std::uint32_t(instances.size());
                b.id = id;
                instances.push_back({instanceBlocks(id), id});
                buildings_.push_back(b);
            }
            Building& b = buildings_[it->second];
            (lod0 ? b.lod0 : b.lod1) = append(node, lo, hi);
            b.min = glm::min(b.min, lo), b.max = glm::max(b.max, hi);
        } else {
            Static s;
            s.instance = std::uint32_t(instances.size());
            instances.push_back({instanceBlocks(0xffffu), 0xffffu});
            s.range = append(node, lo, hi);
            statics_.push_back(s);
        }
        // The far land is a backdrop: the shadow map and the overlook fit the city, not it.
        if (name.starts_with("land_")) continue;
        boundsMin_ = glm::min(boundsMin_, glm::dvec3(lo));
        boundsMax_ = glm::max(boundsMax_, glm::dvec3(hi));
    }
    // A building with only one LOD draws it at every distance.
    for (Building& b : buildings_) {
        if (b.lod0.count == 0) b.lod0 = b.lod1;
        if (b.lod1.count == 0) b.lod1 = b.lod0;
    }
    vertices_ = gl::makeBuffer(vertices);
    indices_ = gl::makeBuffer(indices);
    instances_ = gl::makeBuffer(instances);
    instancedLayout(vao_.id(), vertices_.id(), indices_.id(), instances_.id(), sizeof(InstanceData),
                    offsetof(InstanceData, blocks), offsetof(InstanceData, building));
    if (baked) {
        loadLightmaps(baked->lightmaps);
        if (baked->overlook) loadOverlook(*baked->overlook);
    }
}

// Two mip levels (bake/charts.hpp: kLightmapLevels), the second averaged by GL: the charts'
// blocks are aligned so that it never mixes two charts.
void SceneGpu::loadLightmaps(const LightmapArray& lightmaps) {
    if (lightmaps.layers == 0) return;
    lightmaps_ = gl::makeTexture(GL_TEXTURE_2D_ARRAY);
    const GLuint id = lightmaps_.id();
    glTextureStorage3D(id, 2, GL_RGBA8, lightmaps.size, lightmaps.size, lightmaps.layers);
    glTextureSubImage3D(id, 0, 0, 0, 0, lightmaps.size, lightmaps.size, lightmaps.layers, GL_RGBA, GL_UNSIGNED_BYTE,
                        lightmaps.rgba.data());
    glTextureParameteri(id, GL_TEXTURE_MAX_LEVEL, 1);
    glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(id, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glGenerateTextureMipmap(id);
    baked_ = true;
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

// The building a destruction replaces is hidden from its start time on.
void SceneGpu::replaceBuilding(const DestructionInstance& d) {
    for (Building& b : buildings_)
        if (b.id == std::uint32_t(*d.replaces)) {
            b.until = std::min(b.until, d.startTime);
            return;
        }
    throw InputError(format("destruction {}: \"replaces\": the city has no building {}", d.name, *d.replaces));
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
    return out;
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

    drawShells(overlookFbo_.id(), kOverlookSize, viewProj, -std::numeric_limits<double>::infinity());
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

// The sun's orthographic camera, fitted around the scene's bounding sphere.
glm::mat4 SceneGpu::lightViewProj(glm::dvec3 sunDirection) {
    const glm::vec3 centre(0.5 * (boundsMin_ + boundsMax_));
    const float radius = float(sceneRadius());
    const glm::vec3 dir = glm::normalize(glm::vec3(sunDirection));
    const glm::vec3 up = std::abs(dir.y) > 0.99f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
    const glm::mat4 view = glm::lookAt(centre + dir * 2.0f * radius, centre, up);
    const glm::mat4 proj = glm::ortho(-radius, radius, -radius, radius, 0.5f * radius, 3.5f * radius);
    lightViewProj_ = proj * view;
    return lightViewProj_;
}

void SceneGpu::bindShared() {
    glBindBufferBase(GL_UNIFORM_BUFFER, 1, materialsUbo_.id());
    glBindTextureUnit(0, atlas_.id());
    glBindTextureUnit(1, rooms_.id());
    glBindTextureUnit(2, roomMiddle_.id());
    glBindTextureUnit(8, lightmaps_.id());
    glBindTextureUnit(6, overlook_.id());
    glBindTextureUnit(7, shadowMap_.id());
}

std::size_t SceneGpu::drawStatic(const std::vector<Command>& commands) {
    if (commands.empty()) return 0;
    const std::size_t bytes = commands.size() * sizeof(Command);
    if (bytes > indirectCapacity_) {
        indirectCapacity_ = std::max<std::size_t>(bytes * 2, 4096);
        indirect_ = gl::makeBuffer(nullptr, indirectCapacity_, GL_DYNAMIC_STORAGE_BIT);
    }
    glNamedBufferSubData(indirect_.id(), 0, GLsizeiptr(bytes), commands.data());
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, indirect_.id());
    glBindVertexArray(vao_.id());
    glMultiDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT, nullptr, GLsizei(commands.size()), 0);
    return 1;
}

// Depth of the ground and every building's LOD1 shell into `fbo` (cleared first).
std::size_t SceneGpu::drawShells(GLuint fbo, int size, const glm::mat4& viewProj, double time) {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, size, size);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    glDisable(GL_CULL_FACE);
    if (statics_.empty() && buildings_.empty()) return 0;
    glUseProgram(surfaceDepth_.id());
    glUniformMatrix4fv(0, 1, GL_FALSE, glm::value_ptr(viewProj));
    std::vector<Command> commands;
    for (const Static& s : statics_) commands.push_back({s.range.count, 1, s.range.firstIndex, s.range.baseVertex, s.instance});
    for (const Building& b : buildings_)
        if (time < b.until) commands.push_back({b.lod1.count, 1, b.lod1.firstIndex, b.lod1.baseVertex, b.instance});
    return drawStatic(commands);
}

std::size_t SceneGpu::drawShadow(double time) {
    // The trees and the falling pieces cast shadows too. In sequence: drawShells binds and
    // clears the shadow map (the operands of + have no order).
    std::size_t draws = drawShells(shadowFbo_.id(), shadowSize_, lightViewProj_, time);
    draws += trees_.draw(wind_, time, &lightViewProj_, nullptr);
    return draws + drawVats(time, true, nullptr);
}

std::size_t SceneGpu::drawOpaque(glm::dvec3 camera, const glm::mat4& viewProj, double lodDistance, double time,
                                 FrameStats& stats) {
    // Trees after the city, or alone where a scene has nothing else.
    if (statics_.empty() && buildings_.empty()) return trees_.draw(wind_, time, nullptr, &stats);
    glUseProgram(surface_.id());
    glUniform1i(4, roomStyles_);
    std::vector<Command> commands;
    for (const Static& s : statics_) {
        commands.push_back({s.range.count, 1, s.range.firstIndex, s.range.baseVertex, s.instance});
        stats.triangles += s.range.count / 3;
    }
    for (const Building& b : buildings_) {
        if (time >= b.until) continue;  // its destruction has taken its place
        if (outsideFrustum(viewProj, b.min, b.max)) {
            ++stats.culledBuildings;
            continue;
        }
        const glm::dvec3 nearest = glm::clamp(camera, glm::dvec3(b.min), glm::dvec3(b.max));
        // A building that a destruction replaces draws LOD0 at any distance, as its pieces do.
        const bool near = glm::length(nearest - camera) < lodDistance || b.until < std::numeric_limits<double>::infinity();
        const DrawRange& r = near ? b.lod0 : b.lod1;
        ++(near ? stats.lod0Buildings : stats.lod1Buildings);
        commands.push_back({r.count, 1, r.firstIndex, r.baseVertex, b.instance});
        stats.triangles += r.count / 3;
    }
    const std::size_t city = drawStatic(commands);  // first: the operands of + have no order
    return city + trees_.draw(wind_, time, nullptr, &stats);
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
        const double frame = std::clamp((time - v.startTime) * v.fps, 0.0, double(v.layout.w) - 1.0);
        glUniform1f(2, float(frame));
        glUniformMatrix4fv(3, 1, GL_FALSE, glm::value_ptr(v.model));
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
