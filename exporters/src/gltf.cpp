// glTF 2.0 writer on tinygltf. Spec: https://registry.khronos.org/glTF/specs/2.0/glTF-2.0.html
#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/error.hpp>
#include <dawnforge/exporters/gltf.hpp>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include <cstring>
#include <functional>
#include <limits>
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

tinygltf::Mesh encodeMesh(const Mesh& mesh, BufferBuilder& buffers, int material) {
    DAWNFORGE_ASSERT(!mesh.positions.empty() && !mesh.indices.empty(), "glTF meshes cannot be empty");
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.material = material;
    prim.attributes["POSITION"] = buffers.addFloats(mesh.positions, TINYGLTF_TYPE_VEC3, true);
    if (!mesh.normals.empty()) {
        // glTF requires unit normals: normalise, and give degenerate ones a valid direction.
        const std::vector<glm::vec3>& normals = mesh.normals;
        prim.attributes["NORMAL"] = buffers.add(
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
    if (!mesh.uv0.empty()) prim.attributes["TEXCOORD_0"] = buffers.addFloats(mesh.uv0, TINYGLTF_TYPE_VEC2);
    if (!mesh.uv1.empty()) prim.attributes["TEXCOORD_1"] = buffers.addFloats(mesh.uv1, TINYGLTF_TYPE_VEC2);
    if (!mesh.uv2.empty()) prim.attributes["TEXCOORD_2"] = buffers.addFloats(mesh.uv2, TINYGLTF_TYPE_VEC2);
    if (!mesh.uv3.empty()) prim.attributes["TEXCOORD_3"] = buffers.addFloats(mesh.uv3, TINYGLTF_TYPE_VEC2);
    if (!mesh.materialIds.empty()) {
        const std::vector<std::uint8_t>& ids = mesh.materialIds;
        prim.attributes["COLOR_0"] = buffers.add(
            [&ids](unsigned char* out) {
                for (std::size_t i = 0; i < ids.size(); ++i) {
                    const glm::u8vec4 c = materialIdToColor(ids[i]);
                    std::memcpy(out + 4 * i, &c, 4);
                }
            },
            ids.size() * 4, ids.size(), TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC4,
            TINYGLTF_TARGET_ARRAY_BUFFER, true);
    }
    if (!mesh.pieceIds.empty()) {
        const std::vector<std::uint32_t>& ids = mesh.pieceIds;
        prim.attributes["_PIECE_ID"] = buffers.add(
            [&ids](unsigned char* out) {
                for (std::size_t i = 0; i < ids.size(); ++i) {
                    const float f = static_cast<float>(ids[i]);
                    std::memcpy(out + 4 * i, &f, 4);
                }
            },
            ids.size() * 4, ids.size(), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR, TINYGLTF_TARGET_ARRAY_BUFFER);
    }
    if (mesh.featureId >= 0) {  // EXT_mesh_features: one feature for the whole mesh, a float (4-byte aligned, exact to 2^24)
        DAWNFORGE_ASSERT(mesh.featureId < (1 << 24), "a feature id beyond float's integers");
        const std::size_t n = mesh.positions.size();
        const auto id = static_cast<float>(mesh.featureId);
        prim.attributes["_FEATURE_ID_0"] = buffers.add(
            [n, id](unsigned char* out) {
                for (std::size_t i = 0; i < n; ++i) std::memcpy(out + 4 * i, &id, 4);
            },
            n * 4, n, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR, TINYGLTF_TARGET_ARRAY_BUFFER);
    }
    // The smallest index type that holds every index.
    const bool small = mesh.positions.size() <= 65535;
    if (small) {
        const std::vector<std::uint32_t>& idx = mesh.indices;
        prim.indices = buffers.add(
            [&idx](unsigned char* out) {
                for (std::size_t i = 0; i < idx.size(); ++i) {
                    const auto v = static_cast<std::uint16_t>(idx[i]);
                    std::memcpy(out + 2 * i, &v, 2);
                }
            },
            idx.size() * 2, idx.size(), TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR,
            TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    } else {
        prim.indices = buffers.add(mesh.indices.data(), mesh.indices.size() * 4, mesh.indices.size(),
                                   TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                                   TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    }
    tinygltf::Mesh out;
    out.name = mesh.name;
    out.primitives.push_back(std::move(prim));
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

// The root's EXT_structural_metadata and each featured mesh's EXT_mesh_features (its one
// primitive: every vertex the mesh's row), and both in extensionsUsed.
void addFeatureExtensions(nlohmann::ordered_json& json, const Scene& scene, const nlohmann::ordered_json& metadata) {
    json["extensions"]["EXT_structural_metadata"] = metadata;
    for (std::size_t m = 0; m < scene.meshes.size(); ++m)
        if (scene.meshes[m].featureId >= 0)
            json["meshes"][m]["primitives"][0]["extensions"]["EXT_mesh_features"] = {
                {"featureIds", {{{"featureCount", 1}, {"attribute", 0}, {"propertyTable", 0}}}}};
    nlohmann::ordered_json& used = json["extensionsUsed"];
    for (const char* name : {"EXT_mesh_features", "EXT_structural_metadata"}) used.push_back(name);
}

GlbLayout::GlbLayout(const Scene& scene, const GltfSettings& settings) {
    tinygltf::Model& model = model_;
    BufferBuilder& buffers = buffers_;
    model.asset.version = "2.0";
    model.asset.generator = settings.generator;

    // One material: vertex colours carry the material ID, so the base colour stays white.
    tinygltf::Material material;
    material.name = "dawnforge_atlas";
    material.pbrMetallicRoughness.baseColorFactor = {1.0, 1.0, 1.0, 1.0};
    material.pbrMetallicRoughness.metallicFactor = 0.0;
    material.pbrMetallicRoughness.roughnessFactor = 1.0;
    material.doubleSided = false;
    model.materials.push_back(material);

    for (const Mesh& mesh : scene.meshes) model.meshes.push_back(encodeMesh(mesh, buffers, 0));
    const nlohmann::ordered_json metadata = encodeFeatureTable(scene.features, buffers);

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
