#include "city_gpu.hpp"

#include <dawnforge/core/read_file.hpp>
#include <dawnforge/core/material_paint.hpp>
#include <dawnforge/runtime/atlas.hpp>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cstring>

namespace dawnforge::runtime {

namespace {

constexpr int kMaterials = 16;

// The far land is a backdrop: the shadow map, the overlook and a world's areas fit the city, not it.
bool isFarLand(const std::string& name) { return name.starts_with("land_"); }

// The lightmaps' second level: each texel the rounded mean of the 2 × 2 below it (the charts'
// blocks are aligned so that it never mixes two charts), made on the loading thread so the
// frame's thread only copies it.
std::vector<std::uint8_t> halfLevel(const LightmapArray& l) {
    const std::size_t n = std::size_t(l.size), h = n / 2;
    std::vector<std::uint8_t> out(h * h * 4u * std::size_t(l.layers));
    for (std::size_t layer = 0; layer < std::size_t(l.layers); ++layer) {
        const std::uint8_t* src = l.rgba.data() + layer * n * n * 4u;
        std::uint8_t* dst = out.data() + layer * h * h * 4u;
        for (std::size_t y = 0; y < h; ++y)
            for (std::size_t x = 0; x < h; ++x)
                for (std::size_t c = 0; c < 4; ++c) {
                    const auto at = [&](std::size_t dx, std::size_t dy) { return unsigned(src[((2 * y + dy) * n + 2 * x + dx) * 4u + c]); };
                    dst[(y * h + x) * 4u + c] = std::uint8_t((at(0, 0) + at(1, 0) + at(0, 1) + at(1, 1) + 2u) / 4u);
                }
    }
    return out;
}

}  // namespace

glm::uvec4 instanceBlocks(std::uint32_t id) {
    glm::uvec4 blocks(0u);
    for (int m = 0; m < kMaterials; ++m) blocks[m / 4] |= encodeBlock(materialBlock(m, materialVariant(id, m))) << (8 * (m % 4));
    return blocks;
}

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

// ---------------------------------------------------------------------------------------
// The CPU half.

std::size_t CityCpu::bytes() const {
    std::size_t n = vertices.size() * sizeof(StaticVertex) + indices.size() * 4 + instances.size() * sizeof(InstanceData) +
                    trees.bytes();
    if (baked) n += baked->lightmaps.rgba.size() + lightmapMip1.size();
    return n;
}

namespace {

struct CityBuilder {
    CityCpu& out;
    bool vertexBaked;
    std::map<std::string, std::size_t> buildingIndex;

    DrawRange append(const MeshNode& node, glm::vec3& lo, glm::vec3& hi) {
        DrawRange r;
        r.firstIndex = std::uint32_t(out.indices.size());
        r.baseVertex = std::int32_t(out.vertices.size());
        r.count = std::uint32_t(node.mesh.indices.size());
        const glm::mat3 normalMatrix = glm::transpose(glm::inverse(glm::mat3(node.world)));
        const std::vector<glm::vec3>* light = nullptr;
        if (out.baked) {
            const auto it = out.baked->lightmaps.nodeUv.find(node.name);
            if (it != out.baked->lightmaps.nodeUv.end() && it->second.size() == node.mesh.positions.size()) light = &it->second;
        }
        for (std::size_t i = 0; i < node.mesh.positions.size(); ++i) {
            StaticVertex v = staticVertex(node.mesh, i, node.world, normalMatrix);
            if (light) v.light = (*light)[i];
            if (vertexBaked) v.light = glm::vec3(0.0f, 0.0f, -2.0f);
            lo = glm::min(lo, v.position);
            hi = glm::max(hi, v.position);
            out.vertices.push_back(v);
        }
        out.indices.insert(out.indices.end(), node.mesh.indices.begin(), node.mesh.indices.end());
        return r;
    }

    void add(const MeshNode& node, const std::map<std::uint32_t, double>& until) {
        const std::string& name = node.name;
        const bool lod0 = name.ends_with("_lod0"), lod1 = name.ends_with("_lod1");
        glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
        if (lod0 || lod1) {
            const std::string key = name.substr(0, name.size() - 5);
            auto [it, added] = buildingIndex.try_emplace(key, out.buildings.size());
            if (added) {
                CityBuilding b;
                b.min = lo, b.max = hi;
                // building_NNNNN: the id the city gave it; anything else: its order.
                std::uint32_t id = std::uint32_t(out.buildings.size());
                if (key.starts_with("building_")) id = std::uint32_t(std::strtoul(key.c_str() + 9, nullptr, 10));
                b.instance = std::uint32_t(out.instances.size());
                b.id = id;
                if (const auto u = until.find(id); u != until.end()) b.until = u->second;
                out.instances.push_back({instanceBlocks(id), id});
                out.buildings.push_back(b);
            }
            CityBuilding& b = out.buildings[it->second];
            (lod0 ? b.lod0 : b.lod1) = append(node, lo, hi);
            b.min = glm::min(b.min, lo), b.max = glm::max(b.max, hi);
        } else {
            CityStatic s;
            s.instance = std::uint32_t(out.instances.size());
            out.instances.push_back({instanceBlocks(0xffffu), 0xffffu});
            s.range = append(node, lo, hi);
            s.min = lo, s.max = hi;
            out.statics.push_back(s);
        }
        if (node.mesh.positions.empty()) return;
        out.fullMin = glm::min(out.fullMin, glm::dvec3(lo));
        out.fullMax = glm::max(out.fullMax, glm::dvec3(hi));
        if (isFarLand(name)) return;
        out.boundsMin = glm::min(out.boundsMin, glm::dvec3(lo));
        out.boundsMax = glm::max(out.boundsMax, glm::dvec3(hi));
    }
};

}  // namespace

CityCpu buildCityCpu(std::vector<MeshNode> nodes, std::optional<BakedCity> baked, bool vertexBaked,
                     const std::map<std::uint32_t, double>& until) {
    CityCpu out;
    out.baked = std::move(baked);
    out.trees = prepareTrees(nodes, instanceBlocks(0xffffu), out.boundsMin, out.boundsMax);
    out.fullMin = out.boundsMin, out.fullMax = out.boundsMax;
    CityBuilder builder{out, vertexBaked, {}};
    for (const MeshNode& node : nodes) builder.add(node, until);
    // A building with only one LOD draws it at every distance.
    for (CityBuilding& b : out.buildings) {
        if (b.lod0.count == 0) b.lod0 = b.lod1;
        if (b.lod1.count == 0) b.lod1 = b.lod0;
    }
    if (out.baked && out.baked->lightmaps.layers == 0) out.baked->lightmaps = LightmapArray{};
    if (out.baked) out.lightmapMip1 = halfLevel(out.baked->lightmaps);
    return out;
}

CityCpu loadCityCpu(const std::filesystem::path& cityDir, const std::map<std::uint32_t, double>& until) {
    const std::filesystem::path file = cityDir / "city.glb";
    std::vector<MeshNode> nodes = loadMeshNodes(file, ReadIn::thisProcess);
    std::optional<BakedCity> baked = loadBakedCity(cityDir, readBinaryFile(file));
    return buildCityCpu(std::move(nodes), std::move(baked), false, until);
}

void CityPrograms::make() {
    surface = gl::makeProgram("building.vert", "surface.frag");
    depth = gl::makeProgram("building.vert", "depth.frag", {"DEPTH_PASS"});
    trees.make();
}

void IndirectDraws::draw(GLuint vao, const std::vector<Command>& commands) {
    if (commands.empty()) return;
    const std::size_t bytes = commands.size() * sizeof(Command);
    if (bytes > capacity_) {
        capacity_ = std::max<std::size_t>(bytes * 2, 4096);
        buffer_ = gl::makeBuffer(nullptr, capacity_, GL_DYNAMIC_STORAGE_BIT);
    }
    glNamedBufferSubData(buffer_.id(), 0, GLsizeiptr(bytes), commands.data());
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, buffer_.id());
    glBindVertexArray(vao);
    glMultiDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT, nullptr, GLsizei(commands.size()), 0);
}

// ---------------------------------------------------------------------------------------
// The GPU half.

UploadStep CityGpu::upload(std::size_t budget) {
    UploadStep step;
    if (done_) return step;
    // Allocating storage stalls a CPU driver about as a copy of its size does: it costs that
    // much of the budget.
    const auto room = [&] { return step.cost < budget; };
    const auto allocate = [&](gl::Buffer& buffer, std::size_t bytes) {
        buffer = gl::makeBuffer(nullptr, std::max<std::size_t>(bytes, 4), GL_DYNAMIC_STORAGE_BIT);
        step.cost += bytes;
    };
    if (!started_) {
        started_ = true;
        bytes_ = cpu_.bytes();
        instances_ = gl::makeBuffer(cpu_.instances);
        step.copied += cpu_.instances.size() * sizeof(InstanceData);
        step.cost += cpu_.instances.size() * sizeof(InstanceData);
        allocate(vertices_, cpu_.vertices.size() * sizeof(StaticVertex));
    }
    if (!indices_ && room()) allocate(indices_, cpu_.indices.size() * 4);
    const int layers = cpu_.baked ? cpu_.baked->lightmaps.layers : 0;
    if (layers > 0 && !lightmaps_ && room()) {
        const LightmapArray& l = cpu_.baked->lightmaps;
        lightmaps_ = gl::makeTexture(GL_TEXTURE_2D_ARRAY);
        glTextureStorage3D(lightmaps_.id(), 2, GL_RGBA8, l.size, l.size, l.layers);
        step.cost += l.rgba.size() + cpu_.lightmapMip1.size();
    }
    // The trees in one piece, then vertices, indices and the lightmap's rows, a budget's worth
    // at a time.
    if (!treesDone_ && room()) {
        trees_.upload(cpu_.trees);
        step.cost += cpu_.trees.bytes();
        step.copied += cpu_.trees.bytes();
        treesDone_ = true;
    }
    const auto copy = [&](const gl::Buffer& buffer, const void* data, std::size_t total, std::size_t& done) {
        if (!buffer || done >= total || !room()) return;
        const std::size_t n = std::min(total - done, budget - step.cost);
        glNamedBufferSubData(buffer.id(), GLintptr(done), GLsizeiptr(n), static_cast<const std::uint8_t*>(data) + done);
        done += n;
        step.cost += n;
        step.copied += n;
    };
    copy(vertices_, cpu_.vertices.data(), cpu_.vertices.size() * sizeof(StaticVertex), vertexBytesDone_);
    copy(indices_, cpu_.indices.data(), cpu_.indices.size() * 4, indexBytesDone_);
    // The lightmap array's rows, level 0 then level 1, layer by layer.
    while (lightmaps_ && levelsDone_ < 2 && room()) {
        const LightmapArray& l = cpu_.baked->lightmaps;
        const int size = l.size >> levelsDone_;
        const std::uint8_t* data = levelsDone_ == 0 ? l.rgba.data() : cpu_.lightmapMip1.data();
        const std::size_t rowBytes = std::size_t(size) * 4u;
        const int rows = int(std::clamp<std::size_t>((budget - step.cost) / rowBytes, 1, std::size_t(size - rowsDone_)));
        glTextureSubImage3D(lightmaps_.id(), levelsDone_, 0, rowsDone_, layersDone_, size, rows, 1, GL_RGBA, GL_UNSIGNED_BYTE,
                            data + rowBytes * (std::size_t(size) * std::size_t(layersDone_) + std::size_t(rowsDone_)));
        step.cost += rowBytes * std::size_t(rows);
        step.copied += rowBytes * std::size_t(rows);
        rowsDone_ += rows;
        if (rowsDone_ == size) rowsDone_ = 0, ++layersDone_;
        if (layersDone_ == layers) layersDone_ = 0, ++levelsDone_;
    }
    const bool buffersDone = indices_ && vertexBytesDone_ == cpu_.vertices.size() * sizeof(StaticVertex) &&
                             indexBytesDone_ == cpu_.indices.size() * 4;
    if (treesDone_ && buffersDone && (layers == 0 || levelsDone_ == 2)) finishUpload();
    return step;
}

// Two mip levels of the lightmaps (bake/charts.hpp: kLightmapLevels), both uploaded.
void CityGpu::finishUpload() {
    vao_ = gl::makeVertexArray();
    instancedLayout(vao_.id(), vertices_.id(), indices_.id(), instances_.id(), sizeof(InstanceData),
                    offsetof(InstanceData, blocks), offsetof(InstanceData, building));
    if (lightmaps_) {
        const GLuint id = lightmaps_.id();
        glTextureParameteri(id, GL_TEXTURE_MAX_LEVEL, 1);
        glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
        glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(id, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureParameteri(id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        baked_ = true;
    }
    buildings_ = std::move(cpu_.buildings);
    statics_ = std::move(cpu_.statics);
    if (cpu_.baked) overlook_ = std::move(cpu_.baked->overlook);
    boundsMin_ = cpu_.boundsMin, boundsMax_ = cpu_.boundsMax;
    fullMin_ = cpu_.fullMin, fullMax_ = cpu_.fullMax;
    cpu_ = CityCpu{};
    done_ = true;
}

bool CityGpu::hasBuilding(std::uint32_t id) const {
    return std::any_of(buildings_.begin(), buildings_.end(), [id](const CityBuilding& b) { return b.id == id; });
}

std::size_t CityGpu::drawDepth(const CityPrograms& p, IndirectDraws& indirect, const glm::mat4& viewProj, glm::vec3 offset,
                               double time, const WindSettings* wind) {
    if (!done_) return 0;
    std::size_t draws = 0;
    if (!statics_.empty() || !buildings_.empty()) {
        glUseProgram(p.depth.id());
        glUniformMatrix4fv(0, 1, GL_FALSE, glm::value_ptr(viewProj));
        glUniform3f(8, offset.x, offset.y, offset.z);
        std::vector<IndirectDraws::Command> commands;
        for (const CityStatic& s : statics_)
            if (!outsideFrustum(viewProj, s.min + offset, s.max + offset))
                commands.push_back({s.range.count, 1, s.range.firstIndex, s.range.baseVertex, s.instance});
        for (const CityBuilding& b : buildings_)
            if (time < b.until && !outsideFrustum(viewProj, b.min + offset, b.max + offset))
                commands.push_back({b.lod1.count, 1, b.lod1.firstIndex, b.lod1.baseVertex, b.instance});
        indirect.draw(vao_.id(), commands);
        draws = commands.empty() ? 0 : 1;
    }
    if (wind) draws += trees_.draw(p.trees, *wind, time, viewProj, true, offset, nullptr);
    return draws;
}

std::size_t CityGpu::drawOpaque(const CityPrograms& p, IndirectDraws& indirect, const CityDraw& d, const WindSettings& wind,
                                int roomStyles, FrameStats* stats) {
    if (!done_) return 0;
    const bool depthOnly = stats == nullptr;
    FrameStats scratch;  // the depth pre-pass counts nothing
    FrameStats& st = stats ? *stats : scratch;
    std::size_t draws = 0;
    if (!statics_.empty() || !buildings_.empty()) {
        glUseProgram(depthOnly ? p.depth.id() : p.surface.id());
        if (depthOnly) glUniformMatrix4fv(0, 1, GL_FALSE, glm::value_ptr(d.viewProj));
        else glUniform1i(4, roomStyles);
        glUniform3f(8, d.offset.x, d.offset.y, d.offset.z);
        if (lightmaps_ && !depthOnly) glBindTextureUnit(8, lightmaps_.id());
        std::vector<IndirectDraws::Command> commands;
        for (const CityStatic& s : statics_) {
            if (outsideFrustum(d.viewProj, s.min + d.offset, s.max + d.offset)) continue;
            commands.push_back({s.range.count, 1, s.range.firstIndex, s.range.baseVertex, s.instance});
            st.triangles += s.range.count / 3;
        }
        // Buildings nearest first: what they hide fails the depth test before it is shaded.
        std::vector<std::pair<double, std::size_t>> order;
        for (std::size_t k = 0; k < buildings_.size(); ++k) {
            const CityBuilding& b = buildings_[k];
            if (d.time >= b.until) continue;  // its destruction has taken its place
            if (outsideFrustum(d.viewProj, b.min + d.offset, b.max + d.offset)) {
                ++st.culledBuildings;
                continue;
            }
            order.emplace_back(glm::length(glm::clamp(d.camera, glm::dvec3(b.min), glm::dvec3(b.max)) - d.camera), k);
        }
        std::sort(order.begin(), order.end());
        for (const auto& [distance, k] : order) {
            const CityBuilding& b = buildings_[k];
            // A building that a destruction replaces draws LOD0 at any distance, as its pieces do.
            const bool near = distance < d.lodDistance || b.until < std::numeric_limits<double>::infinity();
            const DrawRange& r = near ? b.lod0 : b.lod1;
            ++(near ? st.lod0Buildings : st.lod1Buildings);
            commands.push_back({r.count, 1, r.firstIndex, r.baseVertex, b.instance});
            st.triangles += r.count / 3;
        }
        indirect.draw(vao_.id(), commands);
        draws = commands.empty() ? 0 : 1;
    }
    return draws + trees_.draw(p.trees, wind, d.time, d.viewProj, depthOnly, d.offset, stats);
}

}  // namespace dawnforge::runtime
