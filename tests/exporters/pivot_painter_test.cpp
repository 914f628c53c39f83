// Pivot Painter 2: the written files decoded the way Unreal's material functions decode them
// (ms_PivotPainter2_UnpackIntegerAsFloat, DecodeAxisVector, Decode8BitAlphaAxisExtent,
// CalculateMeshElementIndex), written out here from the published sources, against a tree
// whose every pivot, axis and extent the test computes itself.
#include "read_exr.hpp"
#include "test_support.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/scene.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/exporters/image.hpp>
#include <dawnforge/exporters/pivot_painter.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <bit>
#include <cmath>
#include <cstring>

using namespace dawnforge;
using namespace dawnforge::exporters;

namespace {

// A bar along its node's +X from 0 to `length`, 10 cm thick.
Mesh bar(float length) {
    Mesh m;
    for (int i = 0; i < 8; ++i)
        m.positions.push_back({i & 1 ? length : 0.0f, i & 2 ? 0.05f : -0.05f, i & 4 ? 0.05f : -0.05f});
    m.indices = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
    return m;
}

struct Spec {
    const char* name;
    int parentNode;  // index into the scene's nodes, -1 for a root
    glm::vec3 translation;
    glm::quat rotation;
    float length;  // 0: a node without a mesh
};

// A trunk up the Y axis, two branches, a twig, a leaf under a node with no mesh, and a rock.
const std::vector<Spec>& tree() {
    static const std::vector<Spec> specs = {
        {"trunk", -1, {0.3f, 0.0f, -0.2f}, glm::angleAxis(glm::radians(90.0f), glm::vec3(0, 0, 1)), 1.0f},
        {"branch_a", 0, {0.8f, 0.0f, 0.0f}, glm::angleAxis(glm::radians(-45.0f), glm::vec3(0, 0, 1)), 0.5f},
        {"twig", 1, {0.5f, 0.0f, 0.0f}, glm::angleAxis(glm::radians(30.0f), glm::normalize(glm::vec3(1, 1, 0))), 0.1f},
        {"branch_b", 0, {0.6f, 0.0f, 0.0f}, glm::angleAxis(glm::radians(50.0f), glm::normalize(glm::vec3(0.3f, 1, 0.2f))), 0.4f},
        {"empty", 3, {0.2f, 0.0f, 0.0f}, glm::angleAxis(glm::radians(20.0f), glm::vec3(1, 0, 0)), 0.0f},
        {"leaf", 4, {0.05f, 0.01f, 0.0f}, glm::angleAxis(glm::radians(-70.0f), glm::vec3(0, 1, 0)), 0.15f},
        {"rock", -1, {-0.9f, 0.1f, 0.4f}, glm::angleAxis(glm::radians(10.0f), glm::vec3(0, 1, 0)), 0.3f},
    };
    return specs;
}

// The tree as a GLB: the scene's nodes in spec order, children listed under their parents.
std::filesystem::path writeTree(const std::filesystem::path& dir) {
    Scene scene;
    for (const Spec& s : tree()) {
        Node node;
        node.name = s.name;
        node.translation = s.translation;
        node.rotation = s.rotation;
        if (s.length > 0.0f) {
            node.mesh = std::int32_t(scene.meshes.size());
            scene.meshes.push_back(bar(s.length));
        }
        if (s.parentNode < 0) scene.roots.push_back(std::uint32_t(scene.nodes.size()));
        else scene.nodes[std::size_t(s.parentNode)].children.push_back(std::uint32_t(scene.nodes.size()));
        scene.nodes.push_back(node);
    }
    const std::filesystem::path file = dir / "tree.glb";
    writeGlb(scene, file);
    return file;
}

struct Expected {
    std::string name;
    int parent;  // element index; a root's own
    glm::dvec3 pivot, xAxis;
    double extent;
};

// The mesh nodes depth first, as the files must list them, with what each must hold.
std::vector<Expected> expectedElements() {
    const std::vector<Spec>& specs = tree();
    std::vector<glm::dmat4> world(specs.size());
    std::vector<int> element(specs.size(), -1);
    std::vector<Expected> out;
    // Depth-first order of this tree: trunk, branch_a, twig, branch_b, empty, leaf, rock.
    for (std::size_t i = 0; i < specs.size(); ++i) {
        const Spec& s = specs[i];
        const glm::dmat4 local = glm::translate(glm::dmat4(1.0), glm::dvec3(s.translation)) * glm::mat4_cast(glm::dquat(s.rotation));
        world[i] = s.parentNode < 0 ? local : world[std::size_t(s.parentNode)] * local;
        if (s.length == 0.0f) continue;
        int parent = -1;
        for (int p = s.parentNode; p >= 0 && parent < 0; p = specs[std::size_t(p)].parentNode) parent = element[std::size_t(p)];
        element[i] = int(out.size());
        out.push_back({s.name, parent < 0 ? element[i] : parent, glm::dvec3(world[i][3]),
                       glm::normalize(glm::dvec3(world[i][0])), double(s.length)});
    }
    return out;
}

// The type of an EXR file's alpha channel.
Imf::PixelType alphaType(const test::Exr& exr) {
    for (const auto& [name, type] : exr.channels)
        if (name == "A") return type;
    return Imf::NUM_PIXELTYPES;
}

// ms_PivotPainter2_UnpackIntegerAsFloat: the float's bits back to the half's, minus 1024.
int unpackIntegerAsFloat(float n) {
    const std::uint32_t u = std::bit_cast<std::uint32_t>(n);
    const std::uint32_t sign = (u >> 16) & 0x8000u;
    const std::uint32_t exponent = std::uint32_t(int((u >> 23) & 0xffu) - 127 + 15) << 10;
    const std::uint32_t mantissa = (u >> 13) & 0x3ffu;
    return int((sign | exponent | mantissa) - 1024u);
}

// Unreal (cm, Z up, (x, z, y)) back to ours.
glm::dvec3 fromUnreal(double x, double y, double z, double scale) { return glm::dvec3(x, z, y) / scale; }

class PivotPainterFiles : public ::testing::Test {
protected:
    test::TempDir dir_;
    std::filesystem::path write(PivotPreset preset) {
        const std::filesystem::path out = dir_.path() / std::string(pivotPresetName(preset));
        const std::vector<MeshNode> nodes = loadMeshNodes(writeTree(dir_.path()));
        writePivotPainter(buildPivotPainter(nodes, preset, "tree.glb"), out, "tree");
        return out;
    }
};

}  // namespace

TEST_F(PivotPainterFiles, UnrealDecodesEveryPivotParentAxisAndExtent) {
    const std::filesystem::path out = write(PivotPreset::Unreal);
    const std::vector<Expected> want = expectedElements();
    const test::Exr pivots = test::readExr(out / "tree_pivots.exr");
    const Image axes = readPng(out / "tree_axes.png");
    EXPECT_EQ(alphaType(pivots), Imf::HALF);
    ASSERT_EQ(pivots.width, 3);  // ceil(√6) × ceil(6 / 3)
    ASSERT_EQ(pivots.height, 2);
    ASSERT_EQ(axes.width, 3);
    for (std::size_t i = 0; i < want.size(); ++i) {
        const float* p = pivots.rgba.data() + 4 * i;
        const std::uint8_t* a = axes.rgba.data() + 4 * i;
        // Half floats: 1 mm steps up to 2 m (every pivot here is within 1.2 m).
        EXPECT_LT(glm::length(fromUnreal(p[0], p[1], p[2], 100.0) - want[i].pivot), 1e-3) << want[i].name;
        EXPECT_EQ(unpackIntegerAsFloat(p[3]), want[i].parent) << want[i].name;
        // DecodeAxisVector: (rgb − 0.5) · 2, normalised; 8 bits hold each component within 1/255
        // (and float rounding of the rotations, 1e-7).
        const glm::dvec3 x = fromUnreal((a[0] / 255.0 - 0.5) * 2.0, (a[1] / 255.0 - 0.5) * 2.0, (a[2] / 255.0 - 0.5) * 2.0, 1.0);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(x[k], want[i].xAxis[k], 1.0 / 255.0 + 1e-6) << want[i].name;
        EXPECT_GT(glm::dot(glm::normalize(x), want[i].xAxis), std::cos(glm::radians(0.5))) << want[i].name;
        // Decode8BitAlphaAxisExtent: max(8, a · 2048) cm, in steps of 2048 / 255.
        EXPECT_NEAR(std::max(8.0, a[3] / 255.0 * 2048.0), std::max(8.0, 100.0 * want[i].extent), 1024.0 / 255.0 + 1e-6)
            << want[i].name;
    }
    // Texels past the last element stay empty.
    for (std::size_t k = 4 * want.size(); k < pivots.rgba.size(); ++k) EXPECT_EQ(pivots.rgba[k], 0.0f);
}

TEST_F(PivotPainterFiles, NativeHoldsThemInMetresAndFloats) {
    const std::filesystem::path out = write(PivotPreset::Native);
    const std::vector<Expected> want = expectedElements();
    const test::Exr pivots = test::readExr(out / "tree_pivots.exr"), axes = test::readExr(out / "tree_axes.exr");
    EXPECT_EQ(alphaType(pivots), Imf::FLOAT);
    for (std::size_t i = 0; i < want.size(); ++i) {
        const float* p = pivots.rgba.data() + 4 * i;
        const float* a = axes.rgba.data() + 4 * i;
        EXPECT_LT(glm::length(glm::dvec3(p[0], p[1], p[2]) - want[i].pivot), 1e-6) << want[i].name;
        EXPECT_EQ(p[3], float(want[i].parent)) << want[i].name;
        EXPECT_LT(glm::length(glm::dvec3(a[0], a[1], a[2]) - want[i].xAxis), 1e-6) << want[i].name;
        EXPECT_NEAR(a[3], want[i].extent, 1e-5) << want[i].name;
    }
}

// CalculateMeshElementIndex: floor(uv · size) gives each vertex its element's texel, and the
// mesh is the tree's, element by element.
TEST_F(PivotPainterFiles, EveryVertexAddressesItsElementsTexel) {
    const std::filesystem::path out = write(PivotPreset::Unreal);
    const std::vector<Expected> want = expectedElements();
    const std::vector<MeshNode> written = loadMeshNodes(out / "tree.glb");
    ASSERT_EQ(written.size(), 1u);
    const Mesh& m = written[0].mesh;
    ASSERT_EQ(m.positions.size(), 8 * want.size());
    ASSERT_EQ(m.uv1.size(), m.positions.size());
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
        const int index = int(std::floor(m.uv1[v].x * 3.0f)) + 3 * int(std::floor(m.uv1[v].y * 2.0f));
        EXPECT_EQ(index, int(v / 8)) << "vertex " << v;
        // The bar's base corners sit 5 cm about the element's pivot.
        if (v % 2 == 0) {
            EXPECT_NEAR(glm::length(glm::dvec3(m.positions[v]) - want[v / 8].pivot), std::sqrt(0.005), 1e-5);
        }
    }
    const auto json = nlohmann::json::parse(test::readText(out / "tree_pivots.json"));
    EXPECT_EQ(json["levels"].get<int>(), 3);  // trunk, branch, twig (the empty node is no level)
    EXPECT_EQ(json["elements"][5]["name"], "rock");
}

TEST_F(PivotPainterFiles, SameInputSameBytes) {
    const std::filesystem::path a = write(PivotPreset::Unreal);
    const auto first = test::readBytes(a / "tree_pivots.exr");
    const auto axes = test::readBytes(a / "tree_axes.png");
    const std::filesystem::path b = write(PivotPreset::Unreal);
    EXPECT_EQ(test::readBytes(b / "tree_pivots.exr"), first);
    EXPECT_EQ(test::readBytes(b / "tree_axes.png"), axes);
}

TEST(PivotPainter, NoHierarchyOrTooManyElementsAreInputErrors) {
    std::vector<MeshNode> nodes(2);
    for (MeshNode& n : nodes) n.mesh = bar(1.0f);
    EXPECT_TRUE(test::contains(test::inputErrorOf([&] { buildPivotPainter(nodes, PivotPreset::Unreal, "f.glb"); }),
                               "f.glb: no node hierarchy"));
    std::vector<MeshNode> many(kPivotUnrealMaxElements + 1);
    for (std::size_t i = 0; i < many.size(); ++i) many[i].parent = i == 0 ? -1 : 0, many[i].mesh = bar(0.1f);
    EXPECT_TRUE(test::contains(test::inputErrorOf([&] { buildPivotPainter(many, PivotPreset::Unreal, "big.glb"); }),
                               "at most 30720"));
    EXPECT_NO_THROW(buildPivotPainter(many, PivotPreset::Native, "big.glb"));
    nodes[1].parent = 0;
    nodes[1].world = glm::translate(glm::mat4(1.0f), glm::vec3(700.0f, 0.0f, 0.0f));
    EXPECT_TRUE(test::contains(test::inputErrorOf([&] { buildPivotPainter(nodes, PivotPreset::Unreal, "f.glb"); }),
                               "a half float holds 655 m"));
    EXPECT_NO_THROW(buildPivotPainter(nodes, PivotPreset::Native, "f.glb"));
    nodes[1].world = glm::scale(glm::mat4(1.0f), glm::vec3(0.0f, 1.0f, 1.0f));
    EXPECT_TRUE(test::contains(test::inputErrorOf([&] { buildPivotPainter(nodes, PivotPreset::Unreal, "f.glb"); }),
                               "scaled to nothing along its X axis"));
}
