#include "test_support.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/material_paint.hpp>
#include <dawnforge/core/materials.hpp>
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/exporters/image.hpp>
#include <dawnforge/exporters/material_images.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>

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
    for (const char* a : {"POSITION", "NORMAL", "TEXCOORD_0", "TEXCOORD_1", "_MATERIAL_ID", "_PIECE_ID"})
        EXPECT_TRUE(attributes.contains(a)) << a;
    EXPECT_FALSE(attributes.contains("COLOR_0"));  // a reader would paint it as a colour
    const nlohmann::json& ids = j["accessors"][attributes["_MATERIAL_ID"].get<int>()];
    EXPECT_EQ(ids["componentType"], 5126);  // FLOAT, as glTF's custom attributes may be
    EXPECT_EQ(ids["type"], "SCALAR");
    const int bigIndices = j["meshes"][1]["primitives"][0]["indices"];
    EXPECT_EQ(j["accessors"][bigIndices]["componentType"], 5125);  // UNSIGNED_INT above 65,535 vertices
}

// Two triangles per material ID, the IDs in a shuffled order (as a building's parts mix them):
// the file has a primitive per ID, and our reader gives back the vertices and the triangles in
// the mesh's order (city.json's building parts are ranges of triangles).
TEST(Gltf, MaterialIdsAndTheTriangleOrderSurviveTheRoundTrip) {
    TempDir dir;
    Scene scene;
    Mesh m;
    for (int k = 0; k < 32; ++k) {
        const int id = (k * 7 + 3) % 16;
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        m.positions.insert(m.positions.end(), {{float(k), 0, 0}, {float(k) + 1, 0, 0}, {float(k), 1, 0}});
        m.materialIds.insert(m.materialIds.end(), 3, std::uint8_t(id));
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
    }
    scene.addMeshNode(m);
    writeGlb(scene, dir / "ids.glb");
    EXPECT_EQ(glbJson(encodeGlb(scene))["meshes"][0]["primitives"].size(), 16u);
    const Mesh back = loadMesh(dir / "ids.glb");
    EXPECT_EQ(back.materialIds, m.materialIds);
    EXPECT_EQ(back.positions, m.positions);
    EXPECT_EQ(back.indices, m.indices);
}

// What a reader that knows nothing of ours gets: for each material a mesh uses, a primitive
// with a glTF material named after it (brick and plaster: the building's colour variant, as the
// runtime picks it), metal-roughness, glass blended; plain mean colours without pictures.
TEST(Gltf, EachMaterialIsAPrimitiveWithAMaterialAReaderUnderstands) {
    Scene scene;
    Mesh m = makeBox({0, 0, 0}, {1, 1, 1});  // 6 faces of 2 triangles: 2 brick, 2 glass, 2 asphalt
    m.name = "building_00007_lod0";
    m.materialIds.assign(m.vertexCount(), 0);
    const std::uint8_t ids[3] = {kBrick, kGlass, kAsphalt};
    for (std::size_t t = 0; t < m.triangleCount(); ++t)
        for (int c = 0; c < 3; ++c) m.materialIds[m.indices[3 * t + std::size_t(c)]] = ids[t / 2 % 3];
    scene.addMeshNode(m);
    const nlohmann::json j = glbJson(encodeGlb(scene));
    const nlohmann::json& prims = j["meshes"][0]["primitives"];
    std::map<std::string, nlohmann::json> byName;
    for (const nlohmann::json& p : prims) byName[j["materials"][p["material"].get<int>()]["name"]] = j["materials"][p["material"].get<int>()];
    const std::string brick = "brick_" + std::to_string(materialVariant(7, kBrick));
    ASSERT_EQ(byName.size(), 3u);
    ASSERT_TRUE(byName.contains(brick) && byName.contains("glass") && byName.contains("asphalt"));
    EXPECT_EQ(byName["glass"]["alphaMode"], "BLEND");
    EXPECT_FALSE(byName["asphalt"].contains("alphaMode"));
    const nlohmann::json& pbr = byName["asphalt"]["pbrMetallicRoughness"];
    EXPECT_NEAR(pbr["baseColorFactor"][0].get<double>(), materialMeanColour(kAsphalt).r, 1e-4);
    EXPECT_FALSE(pbr.contains("baseColorTexture"));
    EXPECT_FALSE(j.contains("images"));
    // The VAT meshes' form: one primitive, one material.
    const nlohmann::json one = glbJson(encodeGlb(scene, {.primitivePerMaterial = false}));
    EXPECT_EQ(one["meshes"][0]["primitives"].size(), 1u);
    EXPECT_EQ(one["materials"].size(), 1u);
}

// A tree's ground cards are its leaf cards (as the runtime draws them): material "leaves", the
// leaf picture once across the card (a clamped sampler), cut out at alpha 0.5, both sides seen.
TEST(Gltf, ATreesLeafCardsWearTheLeafPictureCutOut) {
    Scene scene;
    Mesh m = makeBox({0, 0, 0}, {1, 1, 1}, kWood);
    m.name = "tree_oak_twig_0";
    for (std::size_t v = 0; v < 8; ++v) m.materialIds[v] = kGround;  // two faces of leaves
    scene.addMeshNode(m);
    const nlohmann::json j = glbJson(encodeGlb(scene, {.images = MaterialImages::kEmbedded}));
    ASSERT_EQ(j["materials"].size(), 2u);
    const nlohmann::json& leaves = j["materials"][0]["name"] == "leaves" ? j["materials"][0] : j["materials"][1];
    EXPECT_EQ(leaves["name"], "leaves");
    EXPECT_EQ(leaves["alphaMode"], "MASK");
    EXPECT_EQ(leaves["alphaCutoff"], 0.5);
    EXPECT_EQ(leaves["doubleSided"], true);
    const nlohmann::json& texture = leaves["pbrMetallicRoughness"]["baseColorTexture"];
    EXPECT_FALSE(texture.contains("extensions"));  // 0..1 across the card, not metres
    const nlohmann::json& sampler = j["samplers"][j["textures"][texture["index"].get<int>()]["sampler"].get<int>()];
    EXPECT_EQ(sampler["wrapS"], 33071);  // CLAMP_TO_EDGE
    // Elsewhere the same ground is ground.
    scene.meshes[0].name = "lot_7";
    const nlohmann::json ground = glbJson(encodeGlb(scene));
    EXPECT_TRUE(ground["materials"][0]["name"] == "ground" || ground["materials"][1]["name"] == "ground");
}

// With pictures: each material's base colour is its picture (a 256² PNG that decodes), repeated
// every materialTileMetres of TEXCOORD_0 (KHR_texture_transform), sampled with repeat wrapping
// and mipmaps; embedded once per material in the GLB, or linked to a shared folder.
TEST(Gltf, MaterialsWearTheirPicturesEmbeddedOrLinked) {
    TempDir dir;
    Scene scene;
    for (std::uint8_t id : {kRoofTiles, kGround}) {
        Mesh m = makeBox({0, 0, 0}, {1, 1, 1});
        m.materialIds.assign(m.vertexCount(), id);
        scene.addMeshNode(m);
    }
    scene.addMeshNode(scene.meshes[0]);  // roof tiles again: its picture is not embedded twice
    writeGlb(scene, dir / "embedded.glb", {.images = MaterialImages::kEmbedded});
    test::expectValidGltf(dir / "embedded.glb");
    const std::vector<unsigned char> bytes = test::readBytes(dir / "embedded.glb");
    const nlohmann::json j = glbJson(std::vector<std::byte>(reinterpret_cast<const std::byte*>(bytes.data()),
                                                            reinterpret_cast<const std::byte*>(bytes.data()) + bytes.size()));
    ASSERT_EQ(j["images"].size(), 2u);
    EXPECT_EQ(j["samplers"][0], nlohmann::json({{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 10497}, {"wrapT", 10497}}));
    EXPECT_NE(std::find(j["extensionsUsed"].begin(), j["extensionsUsed"].end(), "KHR_texture_transform"), j["extensionsUsed"].end());
    std::uint32_t jsonLength = 0;
    std::memcpy(&jsonLength, bytes.data() + 12, 4);
    const std::size_t bin = 20 + jsonLength + 8;
    for (const nlohmann::json& material : j["materials"]) {
        const nlohmann::json& texture = material["pbrMetallicRoughness"]["baseColorTexture"];
        const std::uint8_t id = material["name"] == "roof_tiles" ? kRoofTiles : kGround;
        const double scale = texture["extensions"]["KHR_texture_transform"]["scale"][0];
        EXPECT_DOUBLE_EQ(scale, 1.0 / materialTileMetres(id));
        const nlohmann::json& image = j["images"][j["textures"][texture["index"].get<int>()]["source"].get<int>()];
        EXPECT_EQ(image["mimeType"], "image/png");
        const nlohmann::json& view = j["bufferViews"][image["bufferView"].get<int>()];
        const std::size_t at = bin + view.value("byteOffset", std::size_t(0)), length = view["byteLength"];
        std::ofstream(dir / "picture.png", std::ios::binary).write(reinterpret_cast<const char*>(bytes.data() + at), std::streamsize(length));
        const Image picture = readPng(dir / "picture.png");
        EXPECT_EQ(picture.width, kMaterialImageSize);
        EXPECT_EQ(picture.height, kMaterialImageSize);
    }

    const nlohmann::json linked = glbJson(encodeGlb(scene, {.images = MaterialImages::kLinked, .imageFolder = "../../textures/"}));
    ASSERT_EQ(linked["images"].size(), 2u);
    EXPECT_EQ(linked["images"][0]["uri"], "../../textures/roof_tiles.png");
    EXPECT_EQ(linked["images"][1]["uri"], "../../textures/ground.png");
    EXPECT_EQ(writeMaterialImages(dir / "textures"), 23);  // 14 materials, brick and plaster four times, leaves
    EXPECT_EQ(writeMaterialImages(dir / "textures"), 0);   // the same bytes are not written again
    EXPECT_EQ(readPng(dir / "textures" / "brick_3.png").width, kMaterialImageSize);
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
