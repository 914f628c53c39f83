#include "test_support.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/core/scene.hpp>
#include <dawnforge/core/seed.hpp>
#include <dawnforge/core/validate.hpp>
#include <dawnforge/exporters/gltf.hpp>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
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

// Debian's assimp-testmodels: real files from other tools, and deliberately broken ones.
const std::filesystem::path kModels = "/usr/share/assimp/models";

#define SKIP_WITHOUT_TEST_MODELS()                                                                \
    if (!std::filesystem::exists(kModels))                                                        \
    GTEST_SKIP() << kModels.string() << " is missing (Debian package assimp-testmodels; ./run installs it)"

void expectBounds(const Mesh& m, glm::dvec3 min, glm::dvec3 max, double tolerance) {
    const Bounds b = computeBounds(m.positions);
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(b.min[k], min[k], tolerance) << "min, axis " << k;
        EXPECT_NEAR(b.max[k], max[k], tolerance) << "max, axis " << k;
    }
}

double surfaceArea(const Mesh& m) {
    double area = 0.0;
    for (std::size_t t = 0; t < m.triangleCount(); ++t) {
        const glm::dvec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
                         c = m.positions[m.indices[3 * t + 2]];
        area += 0.5 * glm::length(glm::cross(b - a, c - a));
    }
    return area;
}

// Σ (b - a) × (c - a) / 2: the area-weighted normal, which the winding of every triangle
// decides (a flat mesh's area times its front normal).
glm::dvec3 vectorArea(const Mesh& m) {
    glm::dvec3 sum(0.0);
    for (std::size_t t = 0; t < m.triangleCount(); ++t) {
        const glm::dvec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
                         c = m.positions[m.indices[3 * t + 2]];
        sum += 0.5 * glm::cross(b - a, c - a);
    }
    return sum;
}

// A closed, outward, self-intersection-free solid of the given volume.
void expectSolid(const Mesh& m, double volume, double tolerance) {
    const MeshReport r = inspectMesh(m);
    EXPECT_TRUE(r.closed);
    EXPECT_TRUE(r.manifold);
    EXPECT_FALSE(r.selfIntersecting);
    EXPECT_TRUE(r.outwardOriented);
    ASSERT_TRUE(r.volume.has_value());
    EXPECT_NEAR(*r.volume, volume, tolerance);
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
    test::writeText(dir / "mesh.xyz", "solid x\n");
    expectInputError(dir / "mesh.xyz", "unknown mesh format");
}

TEST(ImportObj, RandomBytesNeverCrash) {
    TempDir dir;
    Rng rng(5);
    for (int round = 0; round < 20; ++round) {
        std::string bytes(1 + rng.below(4096), '\0');
        for (char& c : bytes) c = static_cast<char>(rng.below(256));
        const char* names[] = {"random.obj", "random.glb", "random.gltf", "random.fbx", "random.stl",
                               "random.ply", "random.off", "random.dae", "random.3ds"};
        for (const char* name : names) test::writeText(dir / name, bytes);
        for (const char* name : names) {
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

TEST(ImportObj, ConcaveFacesAreEarClipped) {
    // A fan from the first corner of the U-shaped caps overlaps itself across the notch;
    // Debian's tinyobjloader (2.0.0rc10) leaves holes in them (area 28.5, not closed).
    const Mesh m = loadMesh(test::dataFile("u_prism.obj"));
    EXPECT_EQ(m.triangleCount(), 2u * 6u + 8u * 2u);  // two 8-gons, eight quads
    expectSolid(m, 7.0, 1e-9);
    EXPECT_NEAR(surfaceArea(m), 30.0, 1e-9);  // overlapping cap triangles would add area
    for (std::size_t t = 0; t < m.triangleCount(); ++t) {
        const glm::dvec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
                         c = m.positions[m.indices[3 * t + 2]];
        if (a.z != b.z || b.z != c.z) continue;
        const double nz = glm::cross(b - a, c - a).z;  // every cap triangle faces out of its cap
        EXPECT_GT(a.z == 0.0 ? -nz : nz, 0.0) << "triangle " << t;
    }
}

TEST(ImportObj, ConcaveQuadsAreSplitThroughTheirReflexCorner) {
    // An arrowhead prism: caps (-1, 0), (0, 5), (1, 0), (0, 10), area 10 - 5 = 5. The shorter
    // diagonal (length 2, which tinyobjloader would take) runs outside the cap.
    TempDir dir;
    std::string obj;
    for (int z = 0; z < 2; ++z) obj += format("v -1 0 {}\nv 0 5 {}\nv 1 0 {}\nv 0 10 {}\n", z, z, z, z);
    obj += "f 4 3 2 1\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
    test::writeText(dir / "arrow.obj", obj);
    const Mesh m = loadMesh(dir / "arrow.obj");
    expectSolid(m, 5.0, 1e-9);
    EXPECT_NEAR(surfaceArea(m), 2 * 5.0 + 2 * std::sqrt(26.0) + 2 * std::sqrt(101.0), 1e-9);
}

TEST(ImportObj, DegeneratePolygonsStillGiveTheirTriangles) {
    TempDir dir;
    // Collinear corners, a bow tie, a repeated corner: n - 2 triangles each, no hang.
    test::writeText(dir / "odd.obj",
                    "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nv 3 1 0\nv 0 1 0\nv 3 0 1\n"
                    "f 1 2 3 4\n"
                    "f 1 4 6 5\n"
                    "f 1 2 2 4 5 6\n"
                    "f 1 2 3 4 5 6 7\n");
    EXPECT_EQ(loadMesh(dir / "odd.obj").triangleCount(), 2u + 2u + 4u + 5u);
}

TEST(ImportObj, LoadMeshNodesGivesTheFileAsOneNode) {
    const std::vector<MeshNode> nodes = loadMeshNodes(test::dataFile("cube_quads.obj"));
    ASSERT_EQ(nodes.size(), 1u);
    EXPECT_EQ(nodes[0].name, "cube_quads");
    EXPECT_EQ(nodes[0].mesh.triangleCount(), 12u);
}

// ---------------------------------------------------------------- Assimp formats

TEST(ImportFbx, ZUpCentimetresArriveInMetresYUp) {
    // tests/data/box_zup_cm.fbx: 3ds Max's axes (up +Z, front -Y), UnitScaleFactor 1 (cm),
    // a box x 0..200, y 0..100, z 0..50. In metres, +Y up: (x, y, z) -> (x, z, -y) / 100.
    const Mesh m = loadMesh(test::dataFile("box_zup_cm.fbx"));
    expectBounds(m, {0, 0, -1}, {2, 0.5, 0}, 1e-6);
    expectSolid(m, 1.0, 1e-6);  // a rotation: still outward
    EXPECT_TRUE(m.materialIds.empty()) << "other tools' files carry no dawnforge material IDs";

    // The same box in a left-handed file (right is -X): mirrored, and still outward.
    TempDir dir;
    std::string text = test::readText(test::dataFile("box_zup_cm.fbx"));
    const std::string sign = R"("CoordAxisSign", "int", "Integer", "",1)";
    ASSERT_NE(text.find(sign), std::string::npos);
    text.replace(text.find(sign), sign.size(), R"("CoordAxisSign", "int", "Integer", "",-1)");
    test::writeText(dir / "left_handed.fbx", text);
    const Mesh mirrored = loadMesh(dir / "left_handed.fbx");
    expectBounds(mirrored, {-2, 0, -1}, {0, 0.5, 0}, 1e-6);
    expectSolid(mirrored, 1.0, 1e-6);

    std::string metres = test::readText(test::dataFile("box_zup_cm.fbx"));
    const std::string unit = R"("UnitScaleFactor", "double", "Number", "",1)";
    metres.replace(metres.find(unit), unit.size(), R"("UnitScaleFactor", "double", "Number", "",100)");
    test::writeText(dir / "metres.fbx", metres);
    expectBounds(loadMesh(dir / "metres.fbx"), {0, 0, -100}, {200, 50, 0}, 1e-4);
}

TEST(ImportFbx, TestModelsInMetresYUp) {
    SKIP_WITHOUT_TEST_MODELS();
    // 3ds Max export, Z up, UnitScaleFactor 100 (metres): a 1.2 m cube standing on z = 0.
    const Mesh maxBox = loadMesh(kModels / "FBX/embedded_ascii/box.FBX");
    expectBounds(maxBox, {-0.6, 0, -0.6}, {0.6, 1.2, 0.6}, 1e-6);
    expectSolid(maxBox, 1.2 * 1.2 * 1.2, 1e-5);
    ASSERT_EQ(maxBox.normals.size(), maxBox.vertexCount());
    ASSERT_EQ(maxBox.uv0.size(), maxBox.vertexCount());

    // FBX SDK 2017 export, Y up, UnitScaleFactor 100: a rotated box about half a metre across.
    const Mesh box = loadMesh(kModels / "FBX/box.fbx");
    EXPECT_EQ(box.triangleCount(), 12u);
    expectBounds(box, {-0.2261, -0.1619, -0.0646}, {0.2845, 0.2443, 0.4647}, 1e-3);
    expectSolid(box, 0.0358, 1e-3);

    // spider.fbx is spider.obj written in centimetres (UnitScaleFactor 1, coordinates x100):
    // in metres the two agree, though different readers read them.
    const Mesh fbx = loadMesh(kModels / "FBX/spider.fbx");
    const Mesh obj = loadMesh(kModels / "OBJ/spider.obj");
    EXPECT_EQ(fbx.triangleCount(), obj.triangleCount());
    const Bounds b = computeBounds(obj.positions);
    expectBounds(fbx, b.min, b.max, 1e-3);
    EXPECT_NEAR(b.max.x - b.min.x, 150.6, 0.1);  // a 150 m spider, as spider.obj's numbers say

    const std::vector<MeshNode> nodes = loadMeshNodes(kModels / "FBX/cubes_with_names.fbx");
    ASSERT_FALSE(nodes.empty());
    for (const MeshNode& node : nodes) EXPECT_FALSE(node.name.empty());
}

TEST(ImportCollada, UnitAndUpAxisAreApplied) {
    SKIP_WITHOUT_TEST_MODELS();
    // <unit meter="0.0254"/> and Z_UP: a 2-inch cube standing on the ground.
    const Mesh m = loadMesh(kModels / "Collada/cube_with_2UVs.DAE");
    expectBounds(m, {-0.0254, 0, -0.0254}, {0.0254, 0.0508, 0.0254}, 1e-6);
    expectSolid(m, std::pow(0.0508, 3), 1e-8);
}

TEST(ImportStl, AsciiAndBinary) {
    TempDir dir;
    // A unit right tetrahedron, outward, in ASCII and in binary STL.
    const std::array<std::array<glm::vec3, 3>, 4> faces{{{{{0, 0, 0}, {0, 1, 0}, {1, 0, 0}}},
                                                         {{{0, 0, 0}, {1, 0, 0}, {0, 0, 1}}},
                                                         {{{0, 0, 0}, {0, 0, 1}, {0, 1, 0}}},
                                                         {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}}};
    std::string ascii = "solid tetra\n";
    std::string binary(80, ' ');
    auto put = [&](const void* p, std::size_t n) { binary.append(static_cast<const char*>(p), n); };
    const std::uint32_t count = faces.size();
    put(&count, 4);
    for (const auto& f : faces) {
        const glm::vec3 n = glm::normalize(glm::cross(f[1] - f[0], f[2] - f[0]));
        ascii += format("facet normal {} {} {}\nouter loop\n", n.x, n.y, n.z);
        put(&n, 12);
        for (const glm::vec3& v : f) {
            ascii += format("vertex {} {} {}\n", v.x, v.y, v.z);
            put(&v, 12);
        }
        ascii += "endloop\nendfacet\n";
        const std::uint16_t attributes = 0;
        put(&attributes, 2);
    }
    ascii += "endsolid tetra\n";
    test::writeText(dir / "ascii.stl", ascii);
    test::writeText(dir / "binary.stl", binary);
    for (const char* name : {"ascii.stl", "binary.stl"}) {
        SCOPED_TRACE(name);
        const Mesh m = loadMesh(dir / name);
        EXPECT_EQ(m.triangleCount(), 4u);
        expectBounds(m, {0, 0, 0}, {1, 1, 1}, 0.0);  // no unit in STL: metres as written
        expectSolid(m, 1.0 / 6.0, 1e-9);
        EXPECT_EQ(m.normals.size(), m.vertexCount());  // the facet normals
        EXPECT_TRUE(m.materialIds.empty());
    }
}

TEST(ImportStl, TestModelsAsciiAndBinaryAgree) {
    SKIP_WITHOUT_TEST_MODELS();
    const Mesh ascii = loadMesh(kModels / "STL/Spider_ascii.stl");
    const Mesh binary = loadMesh(kModels / "STL/Spider_binary.stl");
    EXPECT_EQ(ascii.triangleCount(), 1368u);
    EXPECT_EQ(binary.triangleCount(), 1368u);
    const Bounds b = computeBounds(ascii.positions);
    expectBounds(binary, b.min, b.max, 1e-5);
}

TEST(ImportPly, PolygonsAreTriangulated) {
    TempDir dir;
    // A unit cube of six quads (outward), with per-vertex normals and UVs.
    std::string ply = "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
                      "property float nx\nproperty float ny\nproperty float nz\nproperty float s\nproperty float t\n"
                      "element face 6\nproperty list uchar int vertex_indices\nend_header\n";
    for (int i = 0; i < 8; ++i) {
        const glm::vec3 p(i & 1, (i >> 1) & 1, (i >> 2) & 1);
        const glm::vec3 n = glm::normalize(p - 0.5f);
        ply += format("{} {} {} {} {} {} {} {}\n", p.x, p.y, p.z, n.x, n.y, n.z, p.x, p.y);
    }
    ply += "4 0 2 3 1\n4 4 5 7 6\n4 0 1 5 4\n4 2 6 7 3\n4 0 4 6 2\n4 1 3 7 5\n";
    test::writeText(dir / "cube.ply", ply);
    const Mesh m = loadMesh(dir / "cube.ply");
    EXPECT_EQ(m.triangleCount(), 12u);
    expectSolid(m, 1.0, 1e-9);
    EXPECT_EQ(m.normals.size(), m.vertexCount());
    EXPECT_EQ(m.uv0.size(), m.vertexCount());
    EXPECT_EQ(m.vertexCount(), 8u);  // identical vertices joined
}

TEST(ImportOff, QuadCubeAndBadHeaders) {
    TempDir dir;
    test::writeText(dir / "cube.off",
                    "OFF\n# a unit cube of quads\n8 6 12\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n"
                    "4 0 2 3 1\n4 4 5 7 6\n4 0 1 5 4\n4 2 6 7 3\n4 0 4 6 2\n4 1 3 7 5\n");
    const Mesh m = loadMesh(dir / "cube.off");
    EXPECT_EQ(m.triangleCount(), 12u);
    expectSolid(m, 1.0, 1e-9);
    EXPECT_TRUE(m.normals.empty());

    // What CGAL's data has and Assimp 5.2 refused: comments after values, colours of three
    // components; and a concave face (an L of six corners) that a fan would fold over.
    test::writeText(dir / "coloured.off",
                    "COFF # an L prism\n12 8 0\n"
                    "0 0 0 0.9 0 0 #red\n2 0 0 0.9 0 0\n2 1 0 0 0 0.9#blue\n1 1 0 0 0 0.9\n1 2 0 0 0 0.9\n0 2 0 0 0 0.9\n\n"
                    "0 0 1 0.9 0 0\n2 0 1 0.9 0 0\n2 1 1 0 0 0.9\n1 1 1 0 0 0.9\n1 2 1 0 0 0.9\n0 2 1 0 0 0.9\n"
                    "6 0 5 4 3 2 1 0.9 0 0 # bottom\n6 6 7 8 9 10 11\n"
                    "4 0 1 7 6\n4 1 2 8 7\n4 2 3 9 8\n4 3 4 10 9\n4 4 5 11 10\n4 5 0 6 11\n");
    const Mesh l = loadMesh(dir / "coloured.off");
    EXPECT_EQ(l.triangleCount(), 2u * 4u + 6u * 2u);
    expectSolid(l, 3.0, 1e-9);

    // A reader would allocate (and zero) 2^32 - 1 vertices before reading a line.
    test::writeText(dir / "huge.off", "OFF\n4294967295 1 0\n0 0 0\n3 0 0 0\n");
    expectInputError(dir / "huge.off", "the OFF header claims 4294967295 vertices");
    test::writeText(dir / "wraps.off", "OFF\n353535235358 6 0\n0 0 0\n");
    expectInputError(dir / "wraps.off", "more than the file's");
    test::writeText(dir / "text.off", "OFF\nthree vertices\n");
    expectInputError(dir / "text.off", "not a readable OFF file");
    test::writeText(dir / "index.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
    expectInputError(dir / "index.off", "not a readable OFF file");
}

TEST(ImportAssimp, BadFilesAreOneLineInputErrors) {
    TempDir dir;
    test::writeText(dir / "garbage.fbx", "Kaydara FBX Binary  and then nothing useful");
    expectInputError(dir / "garbage.fbx", "not a readable mesh file");
    test::writeText(dir / "no_faces.stl", "solid empty\nendsolid empty\n");
    expectInputError(dir / "no_faces.stl", "not a readable mesh file");
    test::writeText(dir / "points.ply",
                    "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
                    "end_header\n0 0 0\n1 1 1\n");
    expectInputError(dir / "points.ply", "");
    // An FBX whose axis system is not a rotation or a mirror.
    std::string text = test::readText(test::dataFile("box_zup_cm.fbx"));
    const std::string front = R"("FrontAxis", "int", "Integer", "",1)";
    text.replace(text.find(front), front.size(), R"("FrontAxis", "int", "Integer", "",2)");
    test::writeText(dir / "axes.fbx", text);
    expectInputError(dir / "axes.fbx", "the FBX axis system is invalid");
}

// ---------------------------------------------------------------- glTF primitive modes

TEST(ImportGltf, StripsAndFansMatchTheirTriangles) {
    SKIP_WITHOUT_TEST_MODELS();
    // The glTF Asset Generator's square in every mode: 06 and 13 are TRIANGLES (without and
    // with indices), 04 and 11 TRIANGLE_STRIP, 05 and 12 TRIANGLE_FAN.
    const std::filesystem::path folder = kModels / "glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode";
    auto file = [&](int n) { return folder / format("Mesh_PrimitiveMode_{}{}.gltf", n < 10 ? "0" : "", n); };
    const Mesh triangles = loadMesh(file(6));
    const glm::dvec3 front = vectorArea(triangles);
    ASSERT_GT(glm::length(front), 0.0);
    for (int n : {4, 5, 11, 12, 13}) {
        SCOPED_TRACE(file(n).filename().string());
        const Mesh m = loadMesh(file(n));
        EXPECT_EQ(m.triangleCount(), 2u);
        const Bounds b = computeBounds(triangles.positions);
        expectBounds(m, b.min, b.max, 0.0);
        EXPECT_NEAR(surfaceArea(m), surfaceArea(triangles), 1e-9);  // no overlap, no gap
        EXPECT_NEAR(glm::distance(vectorArea(m), front), 0.0, 1e-9);  // the same side in front
    }
    for (int n : {0, 1, 2, 3, 7, 8, 9, 10}) expectInputError(file(n), "contains no triangles");  // points, lines
}

TEST(ImportGltf, StripWindingAlternates) {
    // Hand-checked against the spec: strip triangle i is (i, i+1, i+2) for even i and
    // (i, i+2, i+1) for odd i; fan triangle i is (i+1, i+2, 0). A zig-zag strip of
    // 5 vertices up +y and a fan around the origin: every triangle faces +z.
    TempDir dir;
    auto write = [&](const std::string& name, int mode, const std::vector<glm::vec3>& points) {
        std::string bytes(reinterpret_cast<const char*>(points.data()), points.size() * sizeof(glm::vec3));
        test::writeText(dir / (name + ".bin"), bytes);
        glm::vec3 lo(1e9f), hi(-1e9f);
        for (const glm::vec3& p : points) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        test::writeText(dir / (name + ".gltf"),
                        format(R"({{"asset": {{"version": "2.0"}}, "buffers": [{{"uri": "{}.bin", "byteLength": {}}}],
                                   "bufferViews": [{{"buffer": 0, "byteLength": {}}}],
                                   "accessors": [{{"bufferView": 0, "componentType": 5126, "count": {}, "type": "VEC3",
                                                  "min": [{}, {}, {}], "max": [{}, {}, {}]}}],
                                   "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "mode": {}}}]}}],
                                   "nodes": [{{"mesh": 0}}], "scenes": [{{"nodes": [0]}}]}})",
                               name, bytes.size(), bytes.size(), points.size(), lo.x, lo.y, lo.z, hi.x, hi.y, hi.z,
                               mode));
    };
    write("strip", 5, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 2, 0}});
    write("fan", 6, {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {-1, 1, 0}});
    for (const char* name : {"strip.gltf", "fan.gltf"}) {
        SCOPED_TRACE(name);
        const Mesh m = loadMesh(dir / name);
        EXPECT_EQ(m.triangleCount(), 3u);
        for (std::size_t t = 0; t < m.triangleCount(); ++t) {
            const glm::dvec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
                             c = m.positions[m.indices[3 * t + 2]];
            EXPECT_GT(glm::cross(b - a, c - a).z, 0.0) << "triangle " << t << " faces +z";
        }
    }
}

TEST(ImportGltf, Gltf1AndDracoAreRefusedByName) {
    TempDir dir;
    const std::string v1 = "glTF 1.0 is not supported (re-export as glTF 2.0)";
    const std::string draco = "Draco-compressed meshes are not supported (export without Draco compression)";
    test::writeText(dir / "v1.gltf", R"({"asset": {"version": "1.0"}, "meshes": {"box": {"primitives": []}}})");
    expectInputError(dir / "v1.gltf", v1);
    test::writeText(dir / "v1_unversioned.gltf", R"({"accessors": {"a": {}}, "meshes": {}})");
    expectInputError(dir / "v1_unversioned.gltf", v1);
    std::string glb = "glTF";
    const std::uint32_t header[2] = {1, 20};  // KHR_binary_glTF: version 1
    glb.append(reinterpret_cast<const char*>(header), 8);
    glb.append(8, '\0');
    test::writeText(dir / "v1.glb", glb);
    expectInputError(dir / "v1.glb", v1);

    const std::string required = R"({"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_draco_mesh_compression"],
        "extensionsRequired": ["KHR_draco_mesh_compression"], "meshes": [], "nodes": []})";
    test::writeText(dir / "draco.gltf", required);
    expectInputError(dir / "draco.gltf", draco);
    // Used, not required, but the accessors hold no uncompressed fallback.
    test::writeText(dir / "draco_used.gltf", R"({"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_draco_mesh_compression"],
        "accessors": [{"componentType": 5126, "count": 3, "type": "VEC3"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0},
                   "extensions": {"KHR_draco_mesh_compression": {"bufferView": 0, "attributes": {"POSITION": 0}}}}]}],
        "nodes": [{"mesh": 0}]})");
    expectInputError(dir / "draco_used.gltf", draco);
    // Used, not required, with an uncompressed fallback (the spec's rule): read as glTF.
    test::writeText(dir / "draco_fallback.gltf", R"({"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_draco_mesh_compression"],
        "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0},
                   "extensions": {"KHR_draco_mesh_compression": {"bufferView": 0, "attributes": {"POSITION": 0}}}}]}],
        "nodes": [{"mesh": 0}]})");
    EXPECT_EQ(loadMesh(dir / "draco_fallback.gltf").triangleCount(), 1u);
}

TEST(ImportGltf, TestModelsGltf1AndDracoAreRefusedByName) {
    SKIP_WITHOUT_TEST_MODELS();
    for (const char* name : {"glTF/TwoBoxes/TwoBoxes.gltf", "glTF/CesiumMilkTruck/CesiumMilkTruck.gltf",
                             "glTF/BoxTextured-glTF-Binary/BoxTextured.glb"})
        expectInputError(kModels / name, "glTF 1.0 is not supported (re-export as glTF 2.0)");
    expectInputError(kModels / "glTF2/draco/2CylinderEngine.gltf",
                     "Draco-compressed meshes are not supported (export without Draco compression)");
    EXPECT_EQ(loadMesh(kModels / "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb").triangleCount(), 121496u);
}
