#include "test_support.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/exporters/gltf.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstring>

using namespace dawnforge;
using namespace dawnforge::exporters;
using dawnforge::test::TempDir;

namespace {

// A scene with every attribute, a hierarchy, extras, and one mesh too big for 16-bit indices.
Scene fullScene() {
    Scene scene;
    Mesh box = makeBox({0, 0, 0}, {1, 1, 1}, 13);
    box.uv1.assign(box.vertexCount(), glm::vec2(0.5f));
    box.pieceIds.assign(box.vertexCount(), 3);
    box.name = "box";
    const std::uint32_t parent = scene.addMeshNode(box, {1, 2, 3});
    scene.nodes[parent].extrasJson = R"({"piece": 3, "tags": ["a", "b"], "mass": 2.5})";
    Mesh big = makeIcosphere(2.0f, 7);  // 163,842 vertices
    big.name = "big";
    scene.meshes.push_back(std::move(big));
    Node child;
    child.name = "child";
    child.mesh = 1;
    child.scale = glm::vec3(0.5f);
    scene.nodes.push_back(child);
    scene.nodes[parent].children.push_back(1);
    scene.extrasJson = R"({"seed": 42})";
    return scene;
}

nlohmann::json glbJson(const std::vector<std::byte>& glb) {
    std::uint32_t length = 0;
    std::memcpy(&length, glb.data() + 12, 4);
    return nlohmann::json::parse(std::string(reinterpret_cast<const char*>(glb.data()) + 20, length));
}

}  // namespace

TEST(Gltf, SameSceneSameBytes) {
    EXPECT_EQ(encodeGlb(fullScene()), encodeGlb(fullScene()));
}

TEST(Gltf, StreamedFileIsTheEncodedBytes) {
    // writeGlb streams the binary chunk view by view; encodeGlb assembles it in memory.
    TempDir dir;
    writeGlb(fullScene(), dir / "full.glb");
    const std::vector<std::byte> encoded = encodeGlb(fullScene());
    const std::vector<unsigned char> written = test::readBytes(dir / "full.glb");
    ASSERT_EQ(written.size(), encoded.size());
    EXPECT_EQ(std::memcmp(written.data(), encoded.data(), written.size()), 0);
    std::uint32_t total = 0;
    std::memcpy(&total, encoded.data() + 8, 4);
    EXPECT_EQ(total, encoded.size());
    EXPECT_EQ(encoded.size() % 4, 0u);
}

TEST(Gltf, WrittenFilePassesTheKhronosValidator) {
    TempDir dir;
    writeGlb(fullScene(), dir / "full.glb");
    test::expectValidGltf(dir / "full.glb");
}

TEST(Gltf, LayoutFollowsTheConventions) {
    const nlohmann::json j = glbJson(encodeGlb(fullScene()));
    EXPECT_EQ(j["asset"]["version"], "2.0");
    EXPECT_EQ(j["scenes"][0]["extras"]["seed"], 42);
    EXPECT_EQ(j["scenes"][0]["nodes"].size(), 1u);  // the child is not a root
    const nlohmann::json& node = j["nodes"][0];
    EXPECT_EQ(node["name"], "box");
    EXPECT_EQ(node["translation"], nlohmann::json({1.0, 2.0, 3.0}));
    EXPECT_EQ(node["extras"]["tags"][1], "b");
    EXPECT_EQ(node["children"][0], 1);
    const nlohmann::json& attributes = j["meshes"][0]["primitives"][0]["attributes"];
    for (const char* a : {"POSITION", "NORMAL", "TEXCOORD_0", "TEXCOORD_1", "COLOR_0", "_PIECE_ID"})
        EXPECT_TRUE(attributes.contains(a)) << a;
    const nlohmann::json& color = j["accessors"][attributes["COLOR_0"].get<int>()];
    EXPECT_EQ(color["componentType"], 5121);  // UNSIGNED_BYTE
    EXPECT_EQ(color["normalized"], true);
    EXPECT_EQ(color["type"], "VEC4");
    const int bigIndices = j["meshes"][1]["primitives"][0]["indices"];
    EXPECT_EQ(j["accessors"][bigIndices]["componentType"], 5125);  // UNSIGNED_INT above 65,535 vertices
}

TEST(Gltf, MaterialIdsSurviveTheRoundTrip) {
    TempDir dir;
    Scene scene;
    Mesh m;
    for (int id = 0; id < 16; ++id) {  // one triangle per material ID
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        m.positions.insert(m.positions.end(), {{float(id), 0, 0}, {float(id) + 1, 0, 0}, {float(id), 1, 0}});
        m.materialIds.insert(m.materialIds.end(), 3, std::uint8_t(id));
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
    }
    scene.addMeshNode(m);
    writeGlb(scene, dir / "ids.glb");
    EXPECT_EQ(loadMesh(dir / "ids.glb").materialIds, m.materialIds);
}

TEST(Gltf, UnwritableOutputLeavesNothing) {
    TempDir dir;
    EXPECT_THROW(writeGlb(fullScene(), dir / "missing" / "x.glb"), InputError);
    EXPECT_TRUE(dir.entries().empty());
}

TEST(Gltf, LargeIntegersInExtrasAreNotWrapped) {
    Scene scene;
    scene.addMeshNode(makeBox({0, 0, 0}, {1, 1, 1}));
    scene.extrasJson = R"({"seed": 12345678901, "small": -7})";
    const nlohmann::json j = glbJson(encodeGlb(scene));
    EXPECT_EQ(j["scenes"][0]["extras"]["seed"].get<double>(), 12345678901.0);
    EXPECT_EQ(j["scenes"][0]["extras"]["small"], -7);
}

// Features (EXT_mesh_features + EXT_structural_metadata), read back from the bytes as a reader
// would: each featured mesh's vertices carry its row, and the property table's columns (a
// UINT32, a FLOAT32 and a STRING one, each at a multiple of 8 bytes) hold the values in order.
TEST(Gltf, FeaturesAreRowsOfTheSchemasPropertyTable) {
    Scene scene;
    scene.features.className = "thing";
    scene.features.count = 3;
    scene.features.properties = {{"id", {7, 8, 9}, {}, {}}, {"height", {}, {1.5f, 2.5f, 3.5f}, {}},
                                 {"roof", {}, {}, {"flat", "", "gable"}}};
    for (int row : {2, 0}) {
        Mesh m = makeBox({0, 0, 0}, {1, 1, 1});
        m.featureId = row;
        scene.addMeshNode(m);
    }
    scene.addMeshNode(makeBox({0, 0, 0}, {1, 1, 1}));  // no feature
    const std::vector<std::byte> glb = encodeGlb(scene);
    const nlohmann::json j = glbJson(glb);
    std::uint32_t jsonLength = 0;
    std::memcpy(&jsonLength, glb.data() + 12, 4);
    const std::byte* bin = glb.data() + 20 + jsonLength + 8;
    const auto view = [&](int index, int align = 8) {
        const nlohmann::json& v = j["bufferViews"][std::size_t(index)];
        EXPECT_EQ(v.value("byteOffset", 0) % align, 0) << "view " << index;
        return std::pair{bin + v.value("byteOffset", 0), v["byteLength"].get<std::size_t>()};
    };
    EXPECT_EQ(j["extensionsUsed"], nlohmann::json({"EXT_mesh_features", "EXT_structural_metadata"}));
    const nlohmann::json& meta = j["extensions"]["EXT_structural_metadata"];
    EXPECT_EQ(meta["schema"]["classes"]["thing"]["properties"]["roof"]["type"], "STRING");
    const nlohmann::json& table = meta["propertyTables"][0];
    EXPECT_EQ(table["class"], "thing");
    EXPECT_EQ(table["count"], 3);
    const auto [ids, idBytes] = view(table["properties"]["id"]["values"].get<int>());
    ASSERT_EQ(idBytes, 12u);
    std::uint32_t id[3];
    std::memcpy(id, ids, 12);
    EXPECT_EQ(std::vector<std::uint32_t>(id, id + 3), (std::vector<std::uint32_t>{7, 8, 9}));
    const auto [heights, heightBytes] = view(table["properties"]["height"]["values"].get<int>());
    float h[3];
    ASSERT_EQ(heightBytes, 12u);
    std::memcpy(h, heights, 12);
    EXPECT_EQ(h[2], 3.5f);
    const auto [text, textBytes] = view(table["properties"]["roof"]["values"].get<int>());
    const auto [offsets, offsetBytes] = view(table["properties"]["roof"]["stringOffsets"].get<int>());
    ASSERT_EQ(offsetBytes, 16u);
    std::uint32_t at[4];
    std::memcpy(at, offsets, 16);
    const std::string all(reinterpret_cast<const char*>(text), textBytes);
    EXPECT_EQ(all.substr(at[0], at[1] - at[0]), "flat");
    EXPECT_EQ(all.substr(at[1], at[2] - at[1]), "");
    EXPECT_EQ(all.substr(at[2], at[3] - at[2]), "gable");
    // The meshes: rows 2 and 0 in every vertex; the third has no feature.
    for (const auto& [mesh, row] : {std::pair{0, 2.0f}, std::pair{1, 0.0f}}) {
        const nlohmann::json& prim = j["meshes"][std::size_t(mesh)]["primitives"][0];
        EXPECT_EQ(prim["extensions"]["EXT_mesh_features"]["featureIds"][0]["propertyTable"], 0);
        const nlohmann::json& accessor = j["accessors"][prim["attributes"]["_FEATURE_ID_0"].get<std::size_t>()];
        const auto [values, bytes] = view(accessor["bufferView"].get<int>(), 4);
        for (std::size_t i = 0; i < accessor["count"].get<std::size_t>(); ++i) {
            float f = 0.0f;
            std::memcpy(&f, values + 4 * i, 4);
            ASSERT_EQ(f, row) << "mesh " << mesh << " vertex " << i;
        }
    }
    EXPECT_FALSE(j["meshes"][2]["primitives"][0].contains("extensions"));
    TempDir dir;
    writeGlb(scene, dir / "features.glb");
    test::expectValidGltf(dir / "features.glb");
    EXPECT_EQ(loadMeshNodes(dir / "features.glb").size(), 3u) << "our own reader ignores the extensions";
}
