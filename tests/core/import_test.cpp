#include "test_support.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/core/scene.hpp>
#include <dawnforge/core/seed.hpp>
#include <dawnforge/exporters/gltf.hpp>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace dawnforge;
using namespace dawnforge::exporters;
using dawnforge::test::TempDir;

namespace {

// Expects loadMesh(file) to fail with an InputError naming the file and saying `problem`.
void expectInputError(const std::filesystem::path& file, const std::string& problem) {
    try {
        loadMesh(file);
        ADD_FAILURE() << file << " was accepted; expected: " << problem;
    } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(file.string()), std::string::npos) << what;
        EXPECT_NE(what.find(problem), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << "one line: " << what;
    }
}

}  // namespace

TEST(ImportObj, QuadsWithNormalsAndUvs) {
    const Mesh m = loadMesh(test::dataFile("cube_quads.obj"));
    EXPECT_EQ(m.triangleCount(), 12u);
    EXPECT_EQ(m.vertexCount(), 24u);  // each corner once per face: normals differ
    ASSERT_EQ(m.normals.size(), 24u);
    ASSERT_EQ(m.uv0.size(), 24u);
    EXPECT_EQ(computeBounds(m.positions).max, glm::dvec3(1, 1, 1));
    for (const glm::vec3& n : m.normals) EXPECT_FLOAT_EQ(glm::length(n), 1.0f);
}

TEST(ImportObj, BadFilesAreInputErrors) {
    TempDir dir;
    expectInputError(dir / "missing.obj", "no such file");
    test::writeText(dir / "empty.obj", "");
    expectInputError(dir / "empty.obj", "empty");
    test::writeText(dir / "comments.obj", "# nothing but a comment\n");
    expectInputError(dir / "comments.obj", "no triangles");
    expectInputError(test::dataFile("nan.obj"), "non-finite");
    expectInputError(test::dataFile("infinite.obj"), "non-finite");
    expectInputError(test::dataFile("bad_index.obj"), "vertex 9");
    expectInputError(test::dataFile("bad_index_quad.obj"), "vertex 40");
    std::filesystem::create_directory(dir / "folder.obj");
    expectInputError(dir / "folder.obj", "folder");
    test::writeText(dir / "mesh.stl", "solid x\n");
    expectInputError(dir / "mesh.stl", "unknown mesh format");
}

TEST(ImportObj, RandomBytesNeverCrash) {
    TempDir dir;
    Rng rng(5);
    for (int round = 0; round < 20; ++round) {
        std::string bytes(1 + rng.below(4096), '\0');
        for (char& c : bytes) c = static_cast<char>(rng.below(256));
        test::writeText(dir / "random.obj", bytes);
        test::writeText(dir / "random.glb", bytes);
        test::writeText(dir / "random.gltf", bytes);
        for (const char* name : {"random.obj", "random.glb", "random.gltf"}) {
            try {
                const Mesh m = loadMesh(dir / name);  // the odd random file may parse: then it is valid
                EXPECT_NO_THROW(validateMeshData(m, name));
            } catch (const InputError&) {
            }
        }
    }
}

TEST(ImportGltf, RoundTripKeepsAttributesAndAppliesNodeTransforms) {
    TempDir dir;
    Scene scene;
    Mesh box = makeBox({0, 0, 0}, {1, 2, 3}, 9);
    box.uv1.assign(box.vertexCount(), glm::vec2(0.25f, 0.75f));
    box.pieceIds.assign(box.vertexCount(), 70000);
    const std::uint32_t node = scene.addMeshNode(box, {10, 0, 0});
    scene.nodes[node].rotation = glm::angleAxis(glm::radians(90.0f), glm::vec3(0, 1, 0));
    writeGlb(scene, dir / "box.glb");

    const Mesh m = loadMesh(dir / "box.glb");
    ASSERT_EQ(m.vertexCount(), box.vertexCount());
    ASSERT_EQ(m.triangleCount(), box.triangleCount());
    // +90° about Y maps (x, y, z) to (z, y, -x), then +10 in x.
    const Bounds b = computeBounds(m.positions);
    EXPECT_NEAR(b.min.x, 10.0, 1e-5);
    EXPECT_NEAR(b.max.x, 13.0, 1e-5);
    EXPECT_NEAR(b.min.z, -1.0, 1e-5);
    EXPECT_NEAR(b.max.y, 2.0, 1e-5);
    ASSERT_EQ(m.materialIds.size(), m.vertexCount());
    for (std::uint8_t id : m.materialIds) EXPECT_EQ(id, 9);
    ASSERT_EQ(m.uv0.size(), m.vertexCount());
    for (std::size_t i = 0; i < m.uv0.size(); ++i) EXPECT_EQ(m.uv0[i], box.uv0[i]);
    ASSERT_EQ(m.uv1.size(), m.vertexCount());
    EXPECT_EQ(m.uv1[5], glm::vec2(0.25f, 0.75f));
    ASSERT_EQ(m.pieceIds.size(), m.vertexCount());
    EXPECT_EQ(m.pieceIds[3], 70000u);
    for (std::size_t i = 0; i < m.normals.size(); ++i) {  // normals rotated with the node
        const glm::vec3 expected = scene.nodes[node].rotation * box.normals[i];
        EXPECT_NEAR(glm::distance(m.normals[i], expected), 0.0f, 1e-5f);
    }
}

TEST(ImportGltf, BadFilesAreInputErrors) {
    TempDir dir;
    Scene scene;
    Mesh tri;
    tri.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    tri.indices = {0, 1, 99};
    scene.addMeshNode(tri);
    writeGlb(scene, dir / "bad_index.glb");
    expectInputError(dir / "bad_index.glb", "out of range");

    scene.meshes[0].indices = {0, 1, 2};
    scene.meshes[0].positions[1].x = std::numeric_limits<float>::quiet_NaN();
    writeGlb(scene, dir / "nan.glb");
    expectInputError(dir / "nan.glb", "");

    scene.meshes[0].positions[1].x = 1.0f;
    writeGlb(scene, dir / "good.glb");
    EXPECT_NO_THROW(loadMesh(dir / "good.glb"));
    std::string bytes = test::readText(dir / "good.glb");
    test::writeText(dir / "truncated.glb", bytes.substr(0, bytes.size() / 2));
    expectInputError(dir / "truncated.glb", "not a readable glTF");
    test::writeText(dir / "text.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": [{}], \"nodes\": [{\"mesh\": 3}]}");
    expectInputError(dir / "text.gltf", "");
    // An accessor that claims far more elements than its buffer holds.
    test::writeText(dir / "huge.gltf",
                    R"({"asset": {"version": "2.0"},
                        "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
                        "bufferViews": [{"buffer": 0, "byteLength": 36}],
                        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4611686018427387904, "type": "VEC3"}],
                        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
                        "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}]})");
    expectInputError(dir / "huge.gltf", "");
}
