// glTF 2.0 writer on tinygltf. Spec: https://registry.khronos.org/glTF/specs/2.0/glTF-2.0.html
#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/material_paint.hpp>
#include <dawnforge/core/materials.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/exporters/material_images.hpp>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <sstream>

namespace dawnforge::exporters {

namespace {

tinygltf::Value toValue(const nlohmann::json& j) {
    switch (j.type()) {
        case nlohmann::json::value_t::object: {
            tinygltf::Value::Object o;
            for (const auto& [key, value] : j.items()) o.emplace(key, toValue(value));
            return tinygltf::Value(std::move(o));
        }
        case nlohmann::json::value_t::array: {
            tinygltf::Value::Array a;
            for (const auto& value : j) a.push_back(toValue(value));
            return tinygltf::Value(std::move(a));
        }
        case nlohmann::json::value_t::string: return tinygltf::Value(j.get<std::string>());
        case nlohmann::json::value_t::boolean: return tinygltf::Value(j.get<bool>());
        case nlohmann::json::value_t::number_integer:
        case nlohmann::json::value_t::number_unsigned: {
            // tinygltf's integers are int: larger ones travel as doubles rather than wrap.
            const double d = j.get<double>();
            if (d >= std::numeric_limits<int>::min() && d <= std::numeric_limits<int>::max())
                return tinygltf::Value(j.get<int>());
            return tinygltf::Value(d);
        }
        case nlohmann::json::value_t::number_float: return tinygltf::Value(j.get<double>());
        default: return {};
    }
}

tinygltf::Value extrasOf(const std::string& json) {
    if (json.empty()) return {};
    const nlohmann::json j = nlohmann::json::parse(json, nullptr, false);
    DAWNFORGE_ASSERT(j.is_object(), "extras must be a JSON object");
    return toValue(j);
}

// Lays out the single binary buffer: each add() reserves a 4-byte-aligned bufferView and
// records how to fill it; fill() then writes every view straight into the GLB's BIN chunk
// (no intermediate copy of the whole buffer: city scenes run to a gigabyte).
class BufferBuilder {
public:
    explicit BufferBuilder(tinygltf::Model& model) : model_(model) { model_.buffers.emplace_back(); }

    using Writer = std::function<void(unsigned char*)>;

    // A buffer view of `bytes` at a multiple of `align` (EXT_structural_metadata's are at 8);
    // returns its index.
    int addView(Writer writer, std::size_t bytes, int target = 0, std::size_t align = 4) {
        size_ = (size_ + align - 1) & ~(align - 1);
        tinygltf::BufferView view;
        view.buffer = 0;
        view.byteOffset = size_;
        view.byteLength = bytes;
        view.target = target;
        writers_.push_back({size_, bytes, std::move(writer)});
        size_ += bytes;
        model_.bufferViews.push_back(view);
        return static_cast<int>(model_.bufferViews.size() - 1);
    }

    int add(Writer writer, std::size_t bytes, std::size_t count, int componentType, int type, int target,
            bool normalized = false) {
        tinygltf::Accessor accessor;
        accessor.bufferView = addView(std::move(writer), bytes, target);
        accessor.byteOffset = 0;
        accessor.componentType = componentType;
        accessor.type = type;
        accessor.count = count;
        accessor.normalized = normalized;
        model_.accessors.push_back(accessor);
        return static_cast<int>(model_.accessors.size() - 1);
    }
    int add(const void* data, std::size_t bytes, std::size_t count, int componentType, int type, int target,
            bool normalized = false) {
        return add([data, bytes](unsigned char* out) { std::memcpy(out, data, bytes); }, bytes, count, componentType,
                   type, target, normalized);
    }

    template <typename Vec>
    int addFloats(const std::vector<Vec>& values, int type, bool withBounds = false) {
        const int index = add(values.data(), values.size() * sizeof(Vec), values.size(), TINYGLTF_COMPONENT_TYPE_FLOAT,
                              type, TINYGLTF_TARGET_ARRAY_BUFFER);
        if (withBounds) {  // POSITION must state min and max
            Vec lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());
            for (const Vec& v : values) {
                lo = glm::min(lo, v);
                hi = glm::max(hi, v);
            }
            tinygltf::Accessor& a = model_.accessors[std::size_t(index)];
            for (int c = 0; c < Vec::length(); ++c) {
                a.minValues.push_back(lo[c]);
                a.maxValues.push_back(hi[c]);
            }
        }
        return index;
    }

    tinygltf::Accessor& accessor(int index) { return model_.accessors[std::size_t(index)]; }

    std::size_t size() const { return (size_ + 3) & ~std::size_t(3); }
    // Hands the whole buffer to `sink(data, bytes)` view by view, with the zero padding
    // between views; one view at a time is held in memory.
    template <typename Sink>
    void emit(Sink&& sink) const {
        static const unsigned char kZeros[8] = {0, 0, 0, 0, 0, 0, 0, 0};
        std::vector<unsigned char> chunk;
        std::size_t at = 0;
        for (const View& view : writers_) {
            sink(kZeros, view.offset - at);
            chunk.resize(view.bytes);
            view.writer(chunk.data());
            sink(chunk.data(), view.bytes);
            at = view.offset + view.bytes;
        }
        sink(kZeros, size() - at);
    }

private:
    tinygltf::Model& model_;
    std::size_t size_ = 0;
    struct View {
        std::size_t offset, bytes;
        Writer writer;
    };
    std::vector<View> writers_;
};

// The glTF materials a scene uses, numbered in order of first use: (material ID, variant), or
// (-1, 0) for meshes without material IDs.
class MaterialTable {
public:
    int index(int material, int variant) {
        const auto [it, added] = index_.try_emplace({material, variant}, int(keys_.size()));
        if (added) keys_.push_back({material, variant});
        return it->second;
    }
    const std::vector<std::pair<int, int>>& keys() const { return keys_; }

private:
    std::map<std::pair<int, int>, int> index_;
    std::vector<std::pair<int, int>> keys_;
};

// A float scalar attribute holding f(i) for vertex i (custom attributes: _MATERIAL_ID, _PIECE_ID,
// _FEATURE_ID_0).
template <typename F>
int addScalars(BufferBuilder& buffers, std::size_t n, F f) {
    return buffers.add(
        [n, f](unsigned char* out) {
            for (std::size_t i = 0; i < n; ++i) {
                const float v = f(i);
                std::memcpy(out + 4 * i, &v, 4);
            }
        },
        n * 4, n, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR, TINYGLTF_TARGET_ARRAY_BUFFER);
}

std::map<std::string, int> encodeAttributes(const Mesh& mesh, BufferBuilder& buffers) {
    std::map<std::string, int> attributes;
    attributes["POSITION"] = buffers.addFloats(mesh.positions, TINYGLTF_TYPE_VEC3, true);
    if (!mesh.normals.empty()) {
        // glTF requires unit normals: normalise, and give degenerate ones a valid direction.
        const std::vector<glm::vec3>& normals = mesh.normals;
        attributes["NORMAL"] = buffers.add(
            [&normals](unsigned char* out) {
                for (std::size_t i = 0; i < normals.size(); ++i) {
                    const float len = glm::length(normals[i]);
                    const glm::vec3 n = len > 1e-12f ? normals[i] / len : glm::vec3(0, 1, 0);
                    std::memcpy(out + 12 * i, &n, 12);
                }
            },
            normals.size() * 12, normals.size(), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3,
            TINYGLTF_TARGET_ARRAY_BUFFER);
    }
    if (!mesh.uv0.empty()) attributes["TEXCOORD_0"] = buffers.addFloats(mesh.uv0, TINYGLTF_TYPE_VEC2);
    if (!mesh.uv1.empty()) attributes["TEXCOORD_1"] = buffers.addFloats(mesh.uv1, TINYGLTF_TYPE_VEC2);
    if (!mesh.uv2.empty()) attributes["TEXCOORD_2"] = buffers.addFloats(mesh.uv2, TINYGLTF_TYPE_VEC2);
    if (!mesh.uv3.empty()) attributes["TEXCOORD_3"] = buffers.addFloats(mesh.uv3, TINYGLTF_TYPE_VEC2);
    if (const std::vector<std::uint8_t>& ids = mesh.materialIds; !ids.empty())
        attributes["_MATERIAL_ID"] = addScalars(buffers, ids.size(), [&ids](std::size_t i) { return float(ids[i]); });
    if (const std::vector<std::uint32_t>& ids = mesh.pieceIds; !ids.empty())
        attributes["_PIECE_ID"] = addScalars(buffers, ids.size(), [&ids](std::size_t i) { return float(ids[i]); });
    if (mesh.featureId >= 0) {  // EXT_mesh_features: one feature for the whole mesh
        DAWNFORGE_ASSERT(mesh.featureId < (1 << 24), "a feature id beyond float's integers");
        const auto id = static_cast<float>(mesh.featureId);
        attributes["_FEATURE_ID_0"] = addScalars(buffers, mesh.positions.size(), [id](std::size_t) { return id; });
    }
    return attributes;
}

// `indices` as an accessor of the smallest index type that holds `vertices` indices.
int addIndices(BufferBuilder& buffers, std::shared_ptr<const std::vector<std::uint32_t>> idx, std::size_t vertices) {
    if (vertices <= 65535)
        return buffers.add(
            [idx](unsigned char* out) {
                for (std::size_t i = 0; i < idx->size(); ++i) {
                    const auto v = static_cast<std::uint16_t>((*idx)[i]);
                    std::memcpy(out + 2 * i, &v, 2);
                }
            },
            idx->size() * 2, idx->size(), TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR,
            TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    return buffers.add([idx](unsigned char* out) { std::memcpy(out, idx->data(), idx->size() * 4); }, idx->size() * 4,
                       idx->size(), TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                       TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
}

// The mesh's triangles grouped by material ID (a triangle's first vertex's), in ID order, each
// group in the mesh's order; one group of every triangle (key -1) when there are no IDs or
// `perMaterial` is off.
std::vector<std::pair<int, std::shared_ptr<const std::vector<std::uint32_t>>>> trianglesByMaterial(const Mesh& mesh,
                                                                                                 bool perMaterial) {
    if (mesh.materialIds.empty() || !perMaterial)
        return {{-1, std::shared_ptr<const std::vector<std::uint32_t>>(&mesh.indices, [](const auto*) {})}};
    std::array<std::shared_ptr<std::vector<std::uint32_t>>, kMaterialIdCount> groups;
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        auto& group = groups[mesh.materialIds[mesh.indices[t]] & 15u];
        if (!group) group = std::make_shared<std::vector<std::uint32_t>>();
        group->insert(group->end(), mesh.indices.begin() + std::ptrdiff_t(t), mesh.indices.begin() + std::ptrdiff_t(t) + 3);
    }
    std::vector<std::pair<int, std::shared_ptr<const std::vector<std::uint32_t>>>> out;
    for (int m = 0; m < kMaterialIdCount; ++m)
        if (groups[std::size_t(m)]) out.emplace_back(m, groups[std::size_t(m)]);
    return out;
}

// The mesh's triangle order, which grouping by material loses and our own reader puts back
// (building parts are ranges of triangles, city.json): extras.triangle_primitive, an accessor of
// one unsigned byte per triangle in the mesh's order, the index of the primitive that holds it.
tinygltf::Value trianglePrimitives(const Mesh& mesh, const std::vector<std::pair<int, std::shared_ptr<const std::vector<std::uint32_t>>>>& groups,
                                   BufferBuilder& buffers) {
    std::array<std::uint8_t, kMaterialIdCount> primitive{};
    for (std::size_t k = 0; k < groups.size(); ++k) primitive[std::size_t(groups[k].first)] = std::uint8_t(k);
    const std::size_t triangles = mesh.triangleCount();
    const int accessor = buffers.add(
        [&mesh, primitive, triangles](unsigned char* out) {
            for (std::size_t t = 0; t < triangles; ++t) out[t] = primitive[mesh.materialIds[mesh.indices[3 * t]] & 15u];
        },
        triangles, triangles, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_SCALAR, 0);
    tinygltf::Value::Object extras;
    extras.emplace("triangle_primitive", tinygltf::Value(accessor));
    return tinygltf::Value(std::move(extras));
}

tinygltf::Mesh encodeMesh(const Mesh& mesh, BufferBuilder& buffers, MaterialTable& materials, bool perMaterial) {
    DAWNFORGE_ASSERT(!mesh.positions.empty() && !mesh.indices.empty(), "glTF meshes cannot be empty");
    const std::map<std::string, int> attributes = encodeAttributes(mesh, buffers);
    const std::uint32_t building = variantBuilding(mesh.name);
    const bool leafCards = mesh.name.starts_with("tree_");  // a tree's ground cards are its leaves (procgen's dressing)
    tinygltf::Mesh out;
    out.name = mesh.name;
    const auto groups = trianglesByMaterial(mesh, perMaterial);
    if (groups.size() > 1) out.extras = trianglePrimitives(mesh, groups, buffers);
    for (const auto& [material, indices] : groups) {
        tinygltf::Primitive prim;
        prim.mode = TINYGLTF_MODE_TRIANGLES;
        prim.attributes = attributes;
        if (material < 0) prim.material = materials.index(-1, 0);
        else if (material == kGround && leafCards) prim.material = materials.index(kLeafCards, 0);
        else prim.material = materials.index(material, materialVariant(building, material));
        prim.indices = addIndices(buffers, indices, mesh.positions.size());
        out.primitives.push_back(std::move(prim));
    }
    return out;
}

// A sampler's keys: times (SCALAR, with the min and max glTF requires of an input) and
// values (VEC3, or VEC4 quaternions x, y, z, w); not vertex data, so no buffer target.
int addSampler(tinygltf::Animation& out, BufferBuilder& buffers, const std::vector<float>& times,
               BufferBuilder::Writer values, int type) {
    tinygltf::AnimationSampler sampler;
    sampler.interpolation = "LINEAR";
    sampler.input = buffers.add(times.data(), times.size() * 4, times.size(), TINYGLTF_COMPONENT_TYPE_FLOAT,
                                TINYGLTF_TYPE_SCALAR, 0);
    buffers.accessor(sampler.input).minValues = {times.front()};
    buffers.accessor(sampler.input).maxValues = {times.back()};
    const std::size_t width = type == TINYGLTF_TYPE_VEC4 ? 16 : 12;
    sampler.output = buffers.add(std::move(values), times.size() * width, times.size(), TINYGLTF_COMPONENT_TYPE_FLOAT,
                                 type, 0);
    out.samplers.push_back(std::move(sampler));
    return static_cast<int>(out.samplers.size() - 1);
}

tinygltf::Animation encodeAnimation(const Animation& animation, BufferBuilder& buffers, std::size_t nodes) {
    tinygltf::Animation out;
    out.name = animation.name;
    auto channel = [&out](int sampler, std::uint32_t node, const char* path) {
        tinygltf::AnimationChannel c;
        c.sampler = sampler;
        c.target_node = static_cast<int>(node);
        c.target_path = path;
        out.channels.push_back(std::move(c));
    };
    for (const NodeTrack& track : animation.tracks) {
        DAWNFORGE_ASSERT(track.node < nodes, "an animation track refers to a missing node");
        DAWNFORGE_ASSERT(track.translationTimes.size() == track.translations.size() &&
                             track.rotationTimes.size() == track.rotations.size(),
                         "an animation track has as many keys as times");
        if (!track.translations.empty()) {
            const std::vector<glm::vec3>& t = track.translations;
            channel(addSampler(out, buffers, track.translationTimes,
                               [&t](unsigned char* o) { std::memcpy(o, t.data(), t.size() * 12); }, TINYGLTF_TYPE_VEC3),
                    track.node, "translation");
        }
        if (!track.rotations.empty()) {
            const std::vector<glm::quat>& r = track.rotations;
            auto xyzw = [&r](unsigned char* o) {  // glm's (w, x, y, z) is not its storage order everywhere
                for (std::size_t i = 0; i < r.size(); ++i) {
                    const float q[4] = {r[i].x, r[i].y, r[i].z, r[i].w};
                    std::memcpy(o + 16 * i, q, 16);
                }
            };
            channel(addSampler(out, buffers, track.rotationTimes, xyzw, TINYGLTF_TYPE_VEC4), track.node, "rotation");
        }
    }
    return out;
}

}  // namespace

namespace {

// A scene laid out as GLB: the JSON chunk in memory, the binary chunk produced view by view
// from the scene's meshes when written (the scene must outlive it).
class GlbLayout {
public:
    GlbLayout(const Scene& scene, const GltfSettings& settings);
    std::size_t size() const { return 12 + 8 + json_.size() + (buffers_.size() > 0 ? 8 + buffers_.size() : 0); }
    template <typename Sink>
    void emit(Sink&& sink) const;

private:
    tinygltf::Model model_;
    BufferBuilder buffers_{model_};
    std::string json_;
};

// EXT_structural_metadata for `table`: its schema (one class) and property table, each column
// in a buffer view at a multiple of 8 bytes (strings: the UTF-8 bytes and UINT32 offsets).
// Null when the table is empty.
nlohmann::ordered_json encodeFeatureTable(const FeatureTable& table, BufferBuilder& buffers) {
    if (table.className.empty()) return nullptr;
    nlohmann::ordered_json classProperties = nlohmann::ordered_json::object(), columns = nlohmann::ordered_json::object();
    const auto view = [&](const void* data, std::size_t bytes) {
        return buffers.addView([data, bytes](unsigned char* out) { std::memcpy(out, data, bytes); }, bytes, 0, 8);
    };
    for (const FeatureProperty& p : table.properties) {
        if (!p.uints.empty()) {
            DAWNFORGE_ASSERT(p.uints.size() == table.count, "a feature column of the wrong length");
            classProperties[p.name] = {{"type", "SCALAR"}, {"componentType", "UINT32"}};
            columns[p.name] = {{"values", view(p.uints.data(), p.uints.size() * 4)}};
        } else if (!p.floats.empty()) {
            DAWNFORGE_ASSERT(p.floats.size() == table.count, "a feature column of the wrong length");
            classProperties[p.name] = {{"type", "SCALAR"}, {"componentType", "FLOAT32"}};
            columns[p.name] = {{"values", view(p.floats.data(), p.floats.size() * 4)}};
        } else {
            DAWNFORGE_ASSERT(p.strings.size() == table.count, "a feature column of the wrong length");
            auto bytes = std::make_shared<std::string>();
            auto offsets = std::make_shared<std::vector<std::uint32_t>>(1, 0u);
            for (const std::string& text : p.strings) {
                *bytes += text;
                offsets->push_back(static_cast<std::uint32_t>(bytes->size()));
            }
            const int values = buffers.addView([bytes](unsigned char* out) { std::memcpy(out, bytes->data(), bytes->size()); },
                                               bytes->size(), 0, 8);
            const int at = buffers.addView(
                [offsets](unsigned char* out) { std::memcpy(out, offsets->data(), offsets->size() * 4); },
                offsets->size() * 4, 0, 8);
            classProperties[p.name] = {{"type", "STRING"}};
            columns[p.name] = {{"values", values}, {"stringOffsets", at}};
        }
    }
    return {{"schema", {{"id", "dawnforge"}, {"classes", {{table.className, {{"properties", classProperties}}}}}}},
            {"propertyTables", nlohmann::ordered_json::array(
                                   {{{"class", table.className}, {"count", table.count}, {"properties", columns}}})}};
}

// The root's EXT_structural_metadata and each featured mesh's EXT_mesh_features (on each of its
// primitives: every vertex the mesh's row), and both in extensionsUsed.
void addFeatureExtensions(nlohmann::ordered_json& json, const Scene& scene, const nlohmann::ordered_json& metadata) {
    json["extensions"]["EXT_structural_metadata"] = metadata;
    for (std::size_t m = 0; m < scene.meshes.size(); ++m)
        if (scene.meshes[m].featureId >= 0)
            for (nlohmann::ordered_json& prim : json["meshes"][m]["primitives"])
                prim["extensions"]["EXT_mesh_features"] = {
                    {"featureIds", {{{"featureCount", 1}, {"attribute", 0}, {"propertyTable", 0}}}}};
    nlohmann::ordered_json& used = json["extensionsUsed"];
    for (const char* name : {"EXT_mesh_features", "EXT_structural_metadata"}) used.push_back(name);
}

// A material's factors: the plain "default" (key -1), the leaf cards (kLeafCards: cut out where
// their picture's alpha is below 0.5, seen from both sides), or a material ID's surface; the base
// colour white under a picture, else the material's mean colour.
nlohmann::ordered_json materialFactors(int id, bool textured) {
    const auto tidy = [](float x) { return std::round(double(x) * 1e4) / 1e4; };  // the tables' digits, not float's
    const auto pbr = [&](glm::vec3 c, float opacity, float metallic, float roughness) {
        return nlohmann::ordered_json{{"baseColorFactor", {tidy(c.r), tidy(c.g), tidy(c.b), tidy(opacity)}},
                                      {"metallicFactor", tidy(metallic)},
                                      {"roughnessFactor", tidy(roughness)}};
    };
    if (id < 0) return {{"name", "default"}, {"pbrMetallicRoughness", pbr(glm::vec3(0.8f), 1.0f, 0.0f, 0.9f)}};
    if (id == kLeafCards) {
        nlohmann::ordered_json m{{"name", "leaves"},
                                 {"pbrMetallicRoughness", pbr(textured ? glm::vec3(1.0f) : leafMeanColour(), 1.0f, 0.0f, 0.8f)}};
        if (textured) m.update({{"alphaMode", "MASK"}, {"alphaCutoff", 0.5}, {"doubleSided", true}});
        return m;
    }
    const MaterialSurface surface = materialSurface(std::uint8_t(id));
    nlohmann::ordered_json m{{"name", ""},
                             {"pbrMetallicRoughness", pbr(textured ? glm::vec3(1.0f) : materialMeanColour(std::uint8_t(id)),
                                                          surface.opacity, surface.metallic, surface.roughness)}};
    if (surface.opacity < 1.0f) m["alphaMode"] = "BLEND";
    return m;
}

// One glTF material per key of `table` (gltf.hpp says what each gets), with the samplers,
// textures and images of their pictures: the top-level arrays to put in the glTF's JSON.
// Embedded pictures get their buffer views here, so call it before the model is written.
nlohmann::ordered_json encodeMaterials(const MaterialTable& table, const GltfSettings& settings, BufferBuilder& buffers) {
    nlohmann::ordered_json json = nlohmann::ordered_json::object();
    nlohmann::ordered_json materials = nlohmann::ordered_json::array(), images = nlohmann::ordered_json::array(),
                           textures = nlohmann::ordered_json::array();
    const bool textured = settings.images != MaterialImages::kNone;
    for (const auto& [id, variant] : table.keys()) {
        nlohmann::ordered_json m = materialFactors(id, textured);
        if (id < 0) {
            materials.push_back(std::move(m));
            continue;
        }
        const std::string file = materialImageName(id, variant);
        m["name"] = file.substr(0, file.size() - 4);
        if (textured) {
            // Material tiles repeat every materialTileMetres of TEXCOORD_0 (sampler 0); the leaf
            // picture spans its card once (sampler 1, clamped).
            nlohmann::ordered_json texture = {{"index", textures.size()}};
            if (id != kLeafCards) {
                const double repeat = 1.0 / materialTileMetres(id);
                texture["extensions"] = {{"KHR_texture_transform", {{"scale", {repeat, repeat}}}}};
            }
            m["pbrMetallicRoughness"]["baseColorTexture"] = std::move(texture);
            textures.push_back({{"sampler", id == kLeafCards ? 1 : 0}, {"source", images.size()}});
            if (settings.images == MaterialImages::kLinked) {
                images.push_back({{"uri", settings.imageFolder + file}});
            } else {
                const std::vector<std::byte>& png = materialImagePng(id, variant);
                const int view = buffers.addView([&png](unsigned char* out) { std::memcpy(out, png.data(), png.size()); },
                                                 png.size());
                images.push_back({{"bufferView", view}, {"mimeType", "image/png"}});
            }
        }
        materials.push_back(std::move(m));
    }
    if (!materials.empty()) json["materials"] = std::move(materials);
    if (images.empty()) return json;
    json["samplers"] = nlohmann::ordered_json::array(  // LINEAR, LINEAR_MIPMAP_LINEAR; REPEAT, then CLAMP_TO_EDGE
        {{{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 10497}, {"wrapT", 10497}},
         {{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 33071}, {"wrapT", 33071}}});
    json["textures"] = std::move(textures);
    json["images"] = std::move(images);
    return json;
}

GlbLayout::GlbLayout(const Scene& scene, const GltfSettings& settings) {
    tinygltf::Model& model = model_;
    BufferBuilder& buffers = buffers_;
    model.asset.version = "2.0";
    model.asset.generator = settings.generator;

    MaterialTable materials;
    for (const Mesh& mesh : scene.meshes) model.meshes.push_back(encodeMesh(mesh, buffers, materials, settings.primitivePerMaterial));
    const nlohmann::ordered_json metadata = encodeFeatureTable(scene.features, buffers);
    const nlohmann::ordered_json materialArrays = encodeMaterials(materials, settings, buffers);

    for (const Node& node : scene.nodes) {
        tinygltf::Node n;
        n.name = node.name;
        n.mesh = node.mesh;
        DAWNFORGE_ASSERT(node.mesh < static_cast<std::int32_t>(scene.meshes.size()), "node refers to a missing mesh");
        if (node.translation != glm::vec3(0.0f))
            n.translation = {node.translation.x, node.translation.y, node.translation.z};
        if (node.rotation != glm::quat(1.0f, 0.0f, 0.0f, 0.0f)) {
            const glm::quat q = glm::normalize(node.rotation);
            n.rotation = {q.x, q.y, q.z, q.w};
        }
        if (node.scale != glm::vec3(1.0f)) n.scale = {node.scale.x, node.scale.y, node.scale.z};
        for (std::uint32_t c : node.children) n.children.push_back(static_cast<int>(c));
        n.extras = extrasOf(node.extrasJson);
        model.nodes.push_back(std::move(n));
    }
    for (const Animation& animation : scene.animations)
        model.animations.push_back(encodeAnimation(animation, buffers, scene.nodes.size()));
    tinygltf::Scene s;
    s.name = "scene";
    for (std::uint32_t r : scene.roots) s.nodes.push_back(static_cast<int>(r));
    s.extras = extrasOf(scene.extrasJson);
    model.scenes.push_back(std::move(s));
    model.defaultScene = 0;

    // tinygltf writes the JSON (with an empty buffer); the GLB container is assembled here so
    // that the binary chunk is written once, in place (glTF 2.0 spec, "GLB File Format").
    std::ostringstream stream;
    tinygltf::TinyGLTF writer;
    DAWNFORGE_ASSERT(writer.WriteGltfSceneToStream(&model, stream, false, false), "tinygltf could not encode the scene");
    nlohmann::ordered_json json = nlohmann::ordered_json::parse(stream.str());
    if (!metadata.is_null()) addFeatureExtensions(json, scene, metadata);
    for (const auto& [key, value] : materialArrays.items()) json[key] = value;
    if (materialArrays.contains("textures")) json["extensionsUsed"].push_back("KHR_texture_transform");
    if (buffers.size() > 0)
        json["buffers"] = nlohmann::ordered_json::array({{{"byteLength", buffers.size()}}});
    else
        json.erase("buffers");
    json_ = json.dump();
    while (json_.size() % 4) json_.push_back(' ');
    DAWNFORGE_ASSERT(size() <= 0xffffffffu, "the scene is larger than a GLB can hold (4 GiB)");
}

template <typename Sink>
void GlbLayout::emit(Sink&& sink) const {
    unsigned char word[4];
    auto put32 = [&](std::uint32_t v) {
        for (int i = 0; i < 4; ++i) word[i] = static_cast<unsigned char>(v >> (8 * i));
        sink(word, 4);
    };
    put32(0x46546C67u);  // "glTF"
    put32(2);
    put32(static_cast<std::uint32_t>(size()));
    put32(static_cast<std::uint32_t>(json_.size()));
    put32(0x4E4F534Au);  // "JSON"
    sink(reinterpret_cast<const unsigned char*>(json_.data()), json_.size());
    if (buffers_.size() == 0) return;
    put32(static_cast<std::uint32_t>(buffers_.size()));
    put32(0x004E4942u);  // "BIN\0"
    buffers_.emit(sink);
}

}  // namespace

std::vector<std::byte> encodeGlb(const Scene& scene, const GltfSettings& settings) {
    const GlbLayout glb(scene, settings);
    std::vector<std::byte> out;
    out.reserve(glb.size());
    glb.emit([&](const unsigned char* data, std::size_t n) {
        const auto* b = reinterpret_cast<const std::byte*>(data);
        out.insert(out.end(), b, b + n);
    });
    return out;
}

void writeGlb(const Scene& scene, const std::filesystem::path& file, const GltfSettings& settings) {
    // Streamed to the file: a city's GLB is never held in memory whole.
    const GlbLayout glb(scene, settings);
    AtomicFile out(file);
    glb.emit([&](const unsigned char* data, std::size_t n) {
        out.stream().write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(n));
    });
    out.commit();
}

}  // namespace dawnforge::exporters
