// HLOD meshes (world/src/hlod.hpp): a tile's far content (LOD1 shells, ground, trunks and crown
// cards, no lamps) with its bake folded into TEXCOORD_1/2, and meshoptimizer's simplification
// of merged children: about the asked ratio, a small error in metres, materials never mixed,
// locked borders that still meet their neighbour's, the same bytes on every run; and the second
// pass of the higher levels: the ratio still met, open borders moved no farther than its error.
#include "hlod.hpp"
#include "test_support.hpp"

#include <dawnforge/bake/bake.hpp>
#include <dawnforge/bake/bake_folder.hpp>
#include <dawnforge/bake/lighting.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/materials.hpp>
#include <dawnforge/core/read_file.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/procgen/city.hpp>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

namespace dawnforge::world {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

// A city folder of one 100 m tile (its city.glb and city.json), as `dawnforge city` writes it.
void writeTile(const fs::path& dir) {
    procgen::CitySettings settings;
    settings.size = {200.0, 200.0};
    settings.tileSize = 100.0;
    settings.tile = glm::ivec2(0, 0);
    procgen::City city = procgen::generateCity(settings);
    const std::string report = procgen::cityReportJson(city);
    const Scene scene = procgen::takeCityScene(city);
    fs::create_directories(dir);
    exporters::writeGlb(scene, dir / "city.glb");
    test::writeText(dir / "city.json", report);
}

// One tile written twice, the second copy baked coarsely (about a second), made on first use
// and shared by the tests that read a tile; removed at exit.
struct TileFolders {
    TempDir dir;
    Mesh source;  // tileHlodSource of the unbaked copy
    fs::path plain() const { return dir.path() / "plain"; }
    fs::path baked() const { return dir.path() / "baked"; }
    TileFolders() {
        writeTile(plain());
        writeTile(baked());
        bake::BakeSettings coarse;
        coarse.texel = 1.0;
        coarse.interiorTexel = 2.0;
        coarse.samples = 4;
        coarse.bounces = 1;
        bake::bakeCity(baked(), coarse);
        source = tileHlodSource(plain());
    }
};
const TileFolders& tile() {
    static const TileFolders folders;
    return folders;
}
const Mesh& source() { return tile().source; }
fs::path plain() { return tile().plain(); }
fs::path baked() { return tile().baked(); }

bool isTreeRoot(const std::string& name) { return name.starts_with("tree_") && name.find('_', 5) == std::string::npos; }
bool isShellOrGround(const std::string& name) {
    return (name.starts_with("building_") && name.ends_with("_lod1")) || name.starts_with("ground_") || name.starts_with("land_");
}

std::uint8_t materialOfTriangle(const Mesh& m, std::size_t t, bool& mixed) {
    const std::uint32_t* i = &m.indices[3 * t];
    mixed = m.materialIds[i[0]] != m.materialIds[i[1]] || m.materialIds[i[0]] != m.materialIds[i[2]];
    return m.materialIds[i[0]];
}

TEST(Hlod, SourceHoldsShellsGroundTrunksAndTwoCardsATree) {
    std::size_t expected = 0, trees = 0, lampTriangles = 0;
    for (const MeshNode& n : loadMeshNodes(plain() / "city.glb")) {
        if (isShellOrGround(n.name)) expected += n.mesh.triangleCount();
        if (isTreeRoot(n.name)) expected += n.mesh.triangleCount() + 4, ++trees;  // trunk, two quads
        if (n.name.starts_with("lamp_")) lampTriangles += n.mesh.triangleCount();
    }
    ASSERT_GT(trees, 0u);
    ASSERT_GT(lampTriangles, 0u);
    EXPECT_EQ(source().triangleCount(), expected);
    const std::size_t n = source().vertexCount();
    ASSERT_EQ(source().normals.size(), n);
    ASSERT_EQ(source().uv0.size(), n);
    ASSERT_EQ(source().materialIds.size(), n);
    // Lamps are gone: their poles are the only metal of a city (LOD1 shells have no railings).
    EXPECT_EQ(std::count(source().materialIds.begin(), source().materialIds.end(), std::uint8_t{kMetal}), 0);
    std::size_t cardTriangles = 0;
    bool mixed = false;
    for (std::size_t t = 0; t < source().triangleCount(); ++t) {
        cardTriangles += materialOfTriangle(source(), t, mixed) == kGround;
        EXPECT_FALSE(mixed);
    }
    EXPECT_GE(cardTriangles, 4 * trees);
}

TEST(Hlod, SourceWithoutABakeIsLitByTheOpenSky) {
    const std::size_t n = source().vertexCount();
    ASSERT_EQ(source().uv1.size(), n);
    ASSERT_EQ(source().uv2.size(), n);
    for (std::size_t v = 0; v < n; ++v) {
        ASSERT_EQ(source().uv1[v], glm::vec2(1.0f, 1.0f)) << v;  // sky, sun bounce
        ASSERT_EQ(source().uv2[v], glm::vec2(1.0f, 0.0f)) << v;  // ao, lamps
    }
}

// The decoded channels of the four texels around uv (those a bilinear tap reads): a filtered
// value lies between their least and greatest.
std::pair<glm::vec4, glm::vec4> texelRange(const bake::BakedReceiver& r, glm::vec2 uv) {
    const int x0 = int(std::floor(uv.x * float(r.width) - 0.5f)), y0 = int(std::floor(uv.y * float(r.height) - 0.5f));
    glm::vec4 lo(1e9f), hi(-1e9f);
    for (int y : {y0, y0 + 1})
        for (int x : {x0, x0 + 1}) {
            const std::size_t k = 4 * (std::size_t(std::clamp(y, 0, r.height - 1)) * std::size_t(r.width) +
                                       std::size_t(std::clamp(x, 0, r.width - 1)));
            glm::vec4 v;
            for (int c = 0; c < 4; ++c) v[c] = bake::decodeChannel(r.rgba[k + std::size_t(c)], c);
            lo = glm::min(lo, v);
            hi = glm::max(hi, v);
        }
    return {lo, hi};
}

TEST(Hlod, SourceFoldsTheBakeAtEachVertexsLightmapUv) {
    const Mesh lit = tileHlodSource(baked());
    ASSERT_EQ(lit.positions, source().positions);  // the same content, other light
    const bake::BakeFolder folder = bake::readBake(baked(), readBinaryFile(baked() / "city.glb"));
    std::map<std::string, std::pair<const bake::BakedReceiver*, const bake::BakedMesh*>> byNode;
    for (const bake::BakedReceiver& r : folder.receivers)
        for (const bake::BakedMesh& m : r.meshes) byNode[m.node] = {&r, &m};
    // The source holds the nodes in file order: a shell's or ground's vertices, or a trunk's
    // and its cards' (8 vertices), which have no bake.
    std::size_t v = 0, checked = 0;
    for (const MeshNode& n : loadMeshNodes(baked() / "city.glb")) {
        const bool kept = isShellOrGround(n.name);
        if (isTreeRoot(n.name))
            for (std::size_t end = v + n.mesh.vertexCount() + 8; v < end; ++v) {
                ASSERT_EQ(lit.uv1[v], glm::vec2(1.0f, 1.0f));
                ASSERT_EQ(lit.uv2[v], glm::vec2(1.0f, 0.0f));
            }
        if (!kept) continue;
        if (n.name.starts_with("land_")) {  // the far land is not baked: open sky
            for (std::size_t end = v + n.mesh.vertexCount(); v < end; ++v) ASSERT_EQ(lit.uv1[v], glm::vec2(1.0f, 1.0f));
            continue;
        }
        ASSERT_TRUE(byNode.count(n.name)) << n.name;
        const auto [receiver, mesh] = byNode.at(n.name);
        for (std::size_t k = 0; k < n.mesh.vertexCount(); ++k, ++v, ++checked) {
            const auto [lo, hi] = texelRange(*receiver, mesh->uv[k]);
            const glm::vec4 folded(lit.uv1[v], lit.uv2[v]);
            for (int c = 0; c < 4; ++c) {
                ASSERT_GE(folded[c], lo[c] - 1e-5f) << n.name << " vertex " << k << " channel " << c;
                ASSERT_LE(folded[c], hi[c] + 1e-5f) << n.name << " vertex " << k << " channel " << c;
            }
        }
    }
    EXPECT_EQ(v, lit.vertexCount());
    EXPECT_GT(checked, lit.vertexCount() / 2);
    // In range (bake_folder.hpp: sky 2, sun bounce 2, AO 1, lamps 4), and the light varies.
    glm::vec4 lo(1e9f), hi(-1e9f);
    for (std::size_t k = 0; k < lit.vertexCount(); ++k) {
        lo = glm::min(lo, glm::vec4(lit.uv1[k], lit.uv2[k]));
        hi = glm::max(hi, glm::vec4(lit.uv1[k], lit.uv2[k]));
    }
    for (int c = 0; c < 4; ++c) {
        EXPECT_GE(lo[c], 0.0f) << c;
        EXPECT_LE(hi[c], bake::kChannelRange[std::size_t(c)]) << c;
    }
    EXPECT_LT(lo.x + 0.3f, hi.x);  // sky: from shaded corners to open ground
    EXPECT_LT(lo.z + 0.3f, hi.z);  // AO
    EXPECT_GT(hi.w, 0.1f);         // lamps light something: lit rooms' windows, the pavement
}

TEST(Hlod, MissingCityGlbIsAnInputError) {
    TempDir dir;
    EXPECT_TRUE(test::contains(test::inputErrorOf([&] { tileHlodSource(dir.path()); }), "city.glb"));
}

TEST(Hlod, SimplifiesATileByAboutTheRatio) {
    for (double ratio : {0.5, 0.25}) {
        HlodSettings settings;
        settings.ratio = ratio;
        const HlodMesh h = simplifyHlod({source()}, settings);
        const double kept = double(h.mesh.triangleCount()) / double(source().triangleCount());
        EXPECT_LE(kept, ratio + 0.01) << ratio;
        EXPECT_GE(kept, ratio - 0.05) << ratio;  // meshopt stops at the target, not far below
        validateMeshData(h.mesh, "hlod");
        for (std::size_t t = 0; t < h.mesh.triangleCount(); ++t) {  // no two corners at one point
            const std::uint32_t* i = &h.mesh.indices[3 * t];
            const glm::vec3 &a = h.mesh.positions[i[0]], &b = h.mesh.positions[i[1]], &c = h.mesh.positions[i[2]];
            ASSERT_TRUE(a != b && b != c && c != a) << t;
        }
    }
}

TEST(Hlod, ErrorIsInMetresFiniteAndSmallAgainstTheTile) {
    const HlodSettings settings;
    const HlodMesh h = simplifyHlod({source()}, settings);
    const Bounds b = computeBounds(source().positions);
    const double extent = std::max({b.max.x - b.min.x, b.max.y - b.min.y, b.max.z - b.min.z});
    EXPECT_TRUE(std::isfinite(h.error));
    EXPECT_GT(h.error, 0.0);
    EXPECT_LE(h.error, settings.maxError * extent);
    EXPECT_LT(h.error, 0.01 * extent);  // a quarter of the triangles costs under 1 % of a tile
}

TEST(Hlod, EveryVertexIsAnInputVertexAndNoTriangleMixesMaterials) {
    const HlodMesh h = simplifyHlod({source()});
    using Key = std::tuple<float, float, float, float, float, float, float, float, int>;
    auto key = [](const Mesh& m, std::size_t v) {
        const glm::vec3 &p = m.positions[v], &n = m.normals[v];
        return Key{p.x, p.y, p.z, n.x, n.y, n.z, m.uv0[v].x, m.uv0[v].y, m.materialIds[v]};
    };
    std::set<Key> input;
    for (std::size_t v = 0; v < source().vertexCount(); ++v) input.insert(key(source(), v));
    for (std::size_t v = 0; v < h.mesh.vertexCount(); ++v) ASSERT_TRUE(input.count(key(h.mesh, v))) << v;
    std::set<std::uint8_t> before, after;
    bool mixed = false;
    for (std::size_t t = 0; t < h.mesh.triangleCount(); ++t) {
        after.insert(materialOfTriangle(h.mesh, t, mixed));
        ASSERT_FALSE(mixed) << t;
    }
    for (std::size_t t = 0; t < source().triangleCount(); ++t) before.insert(materialOfTriangle(source(), t, mixed));
    EXPECT_TRUE(std::includes(before.begin(), before.end(), after.begin(), after.end()));
    // Compact: every vertex is used.
    std::vector<bool> used(h.mesh.vertexCount(), false);
    for (std::uint32_t i : h.mesh.indices) used[i] = true;
    EXPECT_EQ(std::count(used.begin(), used.end(), false), 0);
}

TEST(Hlod, SameInputGivesTheSameBytes) {
    const HlodMesh a = simplifyHlod({source()});
    const HlodMesh b = simplifyHlod({tileHlodSource(plain())});
    EXPECT_EQ(a.mesh.indices, b.mesh.indices);
    EXPECT_EQ(a.mesh.positions, b.mesh.positions);
    EXPECT_EQ(a.mesh.normals, b.mesh.normals);
    EXPECT_EQ(a.mesh.uv0, b.mesh.uv0);
    EXPECT_EQ(a.mesh.uv1, b.mesh.uv1);
    EXPECT_EQ(a.mesh.uv2, b.mesh.uv2);
    EXPECT_EQ(a.mesh.materialIds, b.mesh.materialIds);
    EXPECT_EQ(a.error, b.error);
}

// A rolling height field over [x0, x0 + 10] × [0, 10], 20 × 20 quads, its vertices computed
// from the same formula in both neighbours, so their shared edge is bit for bit the same.
float heightAt(float x, float z) { return 0.4f * std::sin(0.5f * x) * std::cos(0.4f * z); }

Mesh heightGrid(float x0) {
    constexpr int kCells = 20;
    Mesh m;
    for (int j = 0; j <= kCells; ++j)
        for (int i = 0; i <= kCells; ++i) {
            const float x = x0 + 0.5f * float(i), z = 0.5f * float(j);
            m.positions.emplace_back(x, heightAt(x, z), z);
            const float dx = 0.2f * std::cos(0.5f * x) * std::cos(0.4f * z);    // d height / dx
            const float dz = -0.16f * std::sin(0.5f * x) * std::sin(0.4f * z);  // d height / dz
            m.normals.push_back(glm::normalize(glm::vec3(-dx, 1.0f, -dz)));
            m.uv0.emplace_back(x, z);
            m.materialIds.push_back(kGround);
        }
    const auto row = std::uint32_t(kCells + 1);
    for (std::uint32_t j = 0; j < std::uint32_t(kCells); ++j)
        for (std::uint32_t i = 0; i < std::uint32_t(kCells); ++i) {
            const std::uint32_t a = j * row + i;
            m.indices.insert(m.indices.end(), {a, a + row, a + 1, a + 1, a + row, a + row + 1});
        }
    return m;
}

std::set<std::tuple<float, float, float>> pointsOnLine(const Mesh& m, float x) {
    std::set<std::tuple<float, float, float>> out;
    for (const glm::vec3& p : m.positions)
        if (p.x == x) out.insert({p.x, p.y, p.z});
    return out;
}

TEST(Hlod, NeighboursSimplifiedApartStillShareTheirBorder) {
    const Mesh west = heightGrid(0.0f), east = heightGrid(10.0f);
    HlodSettings settings;
    settings.ratio = 0.2;
    const HlodMesh w = simplifyHlod({west}, settings), e = simplifyHlod({east}, settings);
    EXPECT_LT(w.mesh.triangleCount(), west.triangleCount() / 2);
    EXPECT_LT(e.mesh.triangleCount(), east.triangleCount() / 2);
    EXPECT_GT(w.error, 0.0);
    // Locked open borders: every vertex of the shared edge is still there, on both sides, and
    // so is every vertex of the outer edges (west's x = 0 is straight and flat: slivers along
    // it must not take its vertices away).
    EXPECT_EQ(pointsOnLine(west, 10.0f).size(), 21u);
    EXPECT_EQ(pointsOnLine(w.mesh, 10.0f), pointsOnLine(west, 10.0f));
    EXPECT_EQ(pointsOnLine(e.mesh, 10.0f), pointsOnLine(east, 10.0f));
    EXPECT_EQ(pointsOnLine(w.mesh, 0.0f), pointsOnLine(west, 0.0f));
    EXPECT_EQ(pointsOnLine(e.mesh, 20.0f), pointsOnLine(east, 20.0f));
}

TEST(Hlod, MergedNeighboursWeldAndSimplifyAcrossTheirSharedEdge) {
    const Mesh west = heightGrid(0.0f), east = heightGrid(10.0f);
    HlodSettings settings;
    settings.ratio = 0.2;
    const HlodMesh both = simplifyHlod({west, east}, settings);
    EXPECT_LE(both.mesh.triangleCount(), (west.triangleCount() + east.triangleCount()) / 4);
    // The shared edge is inside the merged mesh now: collapses cross it. The outer edges stay.
    EXPECT_LT(pointsOnLine(both.mesh, 10.0f).size(), 21u);
    EXPECT_EQ(pointsOnLine(both.mesh, 0.0f), pointsOnLine(west, 0.0f));
    EXPECT_EQ(pointsOnLine(both.mesh, 20.0f), pointsOnLine(east, 20.0f));
}

// The mesh moved by `by`, as moveFrame moves a child into its parent's frame.
Mesh movedBy(Mesh m, glm::vec3 by) {
    for (glm::vec3& p : m.positions) p += by;
    return m;
}

// A node's four children: `child` and copies of it one `size` east, north and north-east
// (glTF z is minus plan north).
std::vector<Mesh> fourChildren(const Mesh& child, float size) {
    return {child, movedBy(child, {size, 0.0f, 0.0f}), movedBy(child, {0.0f, 0.0f, -size}),
            movedBy(child, {size, 0.0f, -size})};
}

// What a vertex carries besides its position (the bake aside: the fixture has none).
using Attributes = std::tuple<float, float, float, float, float, int>;
Attributes attributesOf(const Mesh& m, std::size_t v) {
    const glm::vec3& n = m.normals[v];
    return {n.x, n.y, n.z, m.uv0[v].x, m.uv0[v].y, m.materialIds[v]};
}

// Levels 2 and 3 as hlodJob builds them from copies of the tile: their children are simplified
// already, flat-shaded shells and ground that meshopt_simplify alone barely reduces (it keeps
// 0.46 and 0.95 of the triangles here); the second pass takes every level to the ratio.
TEST(Hlod, HigherLevelsReachTheRatioWithoutMixingMaterials) {
    const HlodSettings settings;
    HlodMesh node = simplifyHlod({source()}, settings);
    float size = 100.0f;  // the fixture's tile
    for (int level = 2; level <= 3; ++level, size *= 2.0f) {
        const std::vector<Mesh> children = fourChildren(node.mesh, size);
        node = simplifyHlod(children, settings);
        std::size_t in = 0;
        std::set<Attributes> attributes;
        std::set<std::tuple<float, float, float>> positions;
        Bounds box = computeBounds(children.front().positions);
        for (const Mesh& c : children) {
            in += c.triangleCount();
            for (std::size_t v = 0; v < c.vertexCount(); ++v) {
                attributes.insert(attributesOf(c, v));
                positions.insert({c.positions[v].x, c.positions[v].y, c.positions[v].z});
            }
            const Bounds b = computeBounds(c.positions);
            box = {glm::min(box.min, b.min), glm::max(box.max, b.max)};
        }
        const double kept = double(node.mesh.triangleCount()) / double(in);
        EXPECT_NEAR(kept, settings.ratio, 0.1 * settings.ratio) << level;
        validateMeshData(node.mesh, "hlod");
        // Every vertex is an input vertex moved to an input position; no triangle mixes materials.
        for (std::size_t v = 0; v < node.mesh.vertexCount(); ++v) {
            const glm::vec3& p = node.mesh.positions[v];
            ASSERT_TRUE(attributes.count(attributesOf(node.mesh, v))) << level << " vertex " << v;
            ASSERT_TRUE(positions.count({p.x, p.y, p.z})) << level << " vertex " << v;
        }
        bool mixed = false;
        for (std::size_t t = 0; t < node.mesh.triangleCount(); ++t) {
            materialOfTriangle(node.mesh, t, mixed);
            ASSERT_FALSE(mixed) << level << " triangle " << t;
        }
        const double extent = std::max({box.max.x - box.min.x, box.max.y - box.min.y, box.max.z - box.min.z});
        EXPECT_TRUE(std::isfinite(node.error)) << level;
        EXPECT_GT(node.error, 0.0) << level;
        EXPECT_LT(node.error, 0.02 * extent) << level;
        const HlodMesh again = simplifyHlod(children, settings);
        EXPECT_EQ(again.mesh.indices, node.mesh.indices) << level;
        EXPECT_EQ(again.mesh.positions, node.mesh.positions) << level;
        EXPECT_EQ(again.mesh.normals, node.mesh.normals) << level;
        EXPECT_EQ(again.mesh.uv0, node.mesh.uv0) << level;
        EXPECT_EQ(again.mesh.uv1, node.mesh.uv1) << level;
        EXPECT_EQ(again.mesh.uv2, node.mesh.uv2) << level;
        EXPECT_EQ(again.mesh.materialIds, node.mesh.materialIds) << level;
        EXPECT_EQ(again.error, node.error) << level;
    }
}

// heightGrid flat-shaded: every triangle with three vertices of its own, its face's normal.
// Each point has six wedges: meshopt_simplify locks them all.
Mesh flatShaded(const Mesh& smooth) {
    Mesh m;
    for (std::size_t t = 0; t < smooth.triangleCount(); ++t) {
        const std::uint32_t* i = &smooth.indices[3 * t];
        const glm::vec3 &a = smooth.positions[i[0]], &b = smooth.positions[i[1]], &c = smooth.positions[i[2]];
        for (int k = 0; k < 3; ++k) {
            m.indices.push_back(std::uint32_t(m.positions.size()));
            m.positions.push_back(smooth.positions[i[k]]);
            m.normals.push_back(glm::normalize(glm::cross(b - a, c - a)));
            m.uv0.push_back(smooth.uv0[i[k]]);
            m.materialIds.push_back(smooth.materialIds[i[k]]);
        }
    }
    return m;
}

// The distance from p to the nearest vertex of m.
float nearestVertex(const Mesh& m, glm::vec3 p) {
    float nearest = std::numeric_limits<float>::infinity();
    for (const glm::vec3& q : m.positions) nearest = std::min(nearest, glm::distance(p, q));
    return nearest;
}

// The second pass does not lock open borders, but moves none of their points farther than its
// error: neighbours simplified apart meet within the sum of their errors.
TEST(Hlod, SecondPassMovesOpenBordersByNoMoreThanItsError) {
    const Mesh west = flatShaded(heightGrid(0.0f)), east = flatShaded(heightGrid(10.0f));
    HlodSettings settings;
    settings.ratio = 0.2;
    const HlodMesh w = simplifyHlod({west}, settings), e = simplifyHlod({east}, settings);
    for (const HlodMesh* h : {&w, &e}) {
        const double kept = double(h->mesh.triangleCount()) / double(west.triangleCount());
        EXPECT_NEAR(kept, settings.ratio, 0.1 * settings.ratio);
        EXPECT_GT(h->error, 0.0);
        EXPECT_LT(h->error, 1.0);  // under a tenth of the grid's width: it rolls gently
    }
    for (const auto& [x, y, z] : pointsOnLine(west, 10.0f)) {
        EXPECT_LE(nearestVertex(w.mesh, {x, y, z}), w.error) << x << " " << y << " " << z;
        EXPECT_LE(nearestVertex(e.mesh, {x, y, z}), e.error) << x << " " << y << " " << z;
    }
}

TEST(Hlod, EmptyInputGivesAnEmptyMesh) {
    for (const std::vector<Mesh>& children : {std::vector<Mesh>{}, std::vector<Mesh>{Mesh{}, Mesh{}}}) {
        const HlodMesh h = simplifyHlod(children);
        EXPECT_EQ(h.mesh.triangleCount(), 0u);
        EXPECT_EQ(h.mesh.vertexCount(), 0u);
        EXPECT_EQ(h.error, 0.0);
    }
}

TEST(Hlod, TrianglesWithTwoCornersAtOnePointAreDroppedAndChildrenMerged) {
    Mesh quad;
    quad.positions = {{0, 0, 0}, {1, 0, 0}, {1, 0, -1}, {0, 0, -1}, {2, 0, 0}, {1, 0, 0}};
    // A quad; a sliver on a line (kept: it carries topology); a repeated corner; two vertices
    // at one point.
    quad.indices = {0, 1, 2, 0, 2, 3, 0, 1, 4, 2, 2, 3, 0, 1, 5};
    HlodSettings keepAll;
    keepAll.ratio = 1.0;
    const HlodMesh h = simplifyHlod({quad, quad}, keepAll);
    // The two copies weld into one set of five vertices (the sixth is unused); three triangles each.
    EXPECT_EQ(h.mesh.triangleCount(), 6u);
    EXPECT_EQ(h.mesh.vertexCount(), 5u);
    EXPECT_EQ(h.error, 0.0);
    // Missing attributes take their defaults: an up normal, no bake's open-sky light.
    ASSERT_EQ(h.mesh.normals.size(), 5u);
    EXPECT_EQ(h.mesh.normals[0], glm::vec3(0.0f, 1.0f, 0.0f));
    EXPECT_EQ(h.mesh.uv1[0], glm::vec2(1.0f, 1.0f));
    EXPECT_EQ(h.mesh.uv2[0], glm::vec2(1.0f, 0.0f));
}

}  // namespace
}  // namespace dawnforge::world
