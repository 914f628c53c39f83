// glTF 2.0 writer on tinygltf. Spec: https://registry.khronos.org/glTF/specs/2.0/glTF-2.0.html
#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/error.hpp>
#include <dawnforge/exporters/gltf.hpp>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include <cstring>
#include <limits>
#include <sstream>

namespace dawnforge {

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

// Appends data to the single buffer as its own bufferView (4-byte aligned) and adds an accessor.
class BufferBuilder {
public:
    explicit BufferBuilder(tinygltf::Model& model) : model_(model) { model_.buffers.emplace_back(); }

    int add(const void* data, std::size_t bytes, std::size_t count, int componentType, int type, int target,
            bool normalized = false) {
        std::vector<unsigned char>& buffer = model_.buffers[0].data;
        while (buffer.size() % 4) buffer.push_back(0);
        tinygltf::BufferView view;
        view.buffer = 0;
        view.byteOffset = buffer.size();
        view.byteLength = bytes;
        view.target = target;
        const auto* p = static_cast<const unsigned char*>(data);
        buffer.insert(buffer.end(), p, p + bytes);
        model_.bufferViews.push_back(view);

        tinygltf::Accessor accessor;
        accessor.bufferView = static_cast<int>(model_.bufferViews.size() - 1);
        accessor.byteOffset = 0;
        accessor.componentType = componentType;
        accessor.type = type;
        accessor.count = count;
        accessor.normalized = normalized;
        model_.accessors.push_back(accessor);
        return static_cast<int>(model_.accessors.size() - 1);
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

private:
    tinygltf::Model& model_;
};

tinygltf::Mesh encodeMesh(const Mesh& mesh, BufferBuilder& buffers, int material) {
    DAWNFORGE_ASSERT(!mesh.positions.empty() && !mesh.indices.empty(), "glTF meshes cannot be empty");
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.material = material;
    prim.attributes["POSITION"] = buffers.addFloats(mesh.positions, TINYGLTF_TYPE_VEC3, true);
    if (!mesh.normals.empty()) {
        // glTF requires unit normals: normalise, and give degenerate ones a valid direction.
        std::vector<glm::vec3> normals(mesh.normals.size());
        for (std::size_t i = 0; i < normals.size(); ++i) {
            const float len = glm::length(mesh.normals[i]);
            normals[i] = len > 1e-12f ? mesh.normals[i] / len : glm::vec3(0, 1, 0);
        }
        prim.attributes["NORMAL"] = buffers.addFloats(normals, TINYGLTF_TYPE_VEC3);
    }
    if (!mesh.uv0.empty()) prim.attributes["TEXCOORD_0"] = buffers.addFloats(mesh.uv0, TINYGLTF_TYPE_VEC2);
    if (!mesh.uv1.empty()) prim.attributes["TEXCOORD_1"] = buffers.addFloats(mesh.uv1, TINYGLTF_TYPE_VEC2);
    if (!mesh.uv2.empty()) prim.attributes["TEXCOORD_2"] = buffers.addFloats(mesh.uv2, TINYGLTF_TYPE_VEC2);
    if (!mesh.uv3.empty()) prim.attributes["TEXCOORD_3"] = buffers.addFloats(mesh.uv3, TINYGLTF_TYPE_VEC2);
    if (!mesh.materialIds.empty()) {
        std::vector<glm::u8vec4> colors;
        colors.reserve(mesh.materialIds.size());
        for (std::uint8_t id : mesh.materialIds) colors.push_back(materialIdToColor(id));
        prim.attributes["COLOR_0"] = buffers.add(colors.data(), colors.size() * 4, colors.size(),
                                                 TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC4,
                                                 TINYGLTF_TARGET_ARRAY_BUFFER, true);
    }
    if (!mesh.pieceIds.empty()) {
        std::vector<float> ids(mesh.pieceIds.begin(), mesh.pieceIds.end());
        prim.attributes["_PIECE_ID"] = buffers.add(ids.data(), ids.size() * 4, ids.size(),
                                                   TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR,
                                                   TINYGLTF_TARGET_ARRAY_BUFFER);
    }
    // The smallest index type that holds every index.
    const bool small = mesh.positions.size() <= 65535;
    if (small) {
        std::vector<std::uint16_t> idx(mesh.indices.begin(), mesh.indices.end());
        prim.indices = buffers.add(idx.data(), idx.size() * 2, idx.size(), TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                   TINYGLTF_TYPE_SCALAR, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
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

}  // namespace

std::vector<std::byte> encodeGlb(const Scene& scene, const GltfSettings& settings) {
    tinygltf::Model model;
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

    BufferBuilder buffers(model);
    for (const Mesh& mesh : scene.meshes) model.meshes.push_back(encodeMesh(mesh, buffers, 0));
    model.buffers[0].data.resize((model.buffers[0].data.size() + 3) & ~std::size_t(3), 0);

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
    tinygltf::Scene s;
    s.name = "scene";
    for (std::uint32_t r : scene.roots) s.nodes.push_back(static_cast<int>(r));
    s.extras = extrasOf(scene.extrasJson);
    model.scenes.push_back(std::move(s));
    model.defaultScene = 0;

    std::ostringstream stream;
    tinygltf::TinyGLTF writer;
    DAWNFORGE_ASSERT(writer.WriteGltfSceneToStream(&model, stream, false, true), "tinygltf could not encode the scene");
    const std::string bytes = std::move(stream).str();
    std::vector<std::byte> out(bytes.size());
    std::memcpy(out.data(), bytes.data(), bytes.size());
    return out;
}

void writeGlb(const Scene& scene, const std::filesystem::path& file, const GltfSettings& settings) {
    writeFileAtomically(file, encodeGlb(scene, settings));
}

}  // namespace dawnforge
