// HLOD meshes (hlod.hpp): a tile's far content with its bake folded into vertex attributes,
// and the merge-and-simplify step of every quadtree node. The simplifier is meshoptimizer's
// quadric edge collapse (Garland and Heckbert, "Surface simplification using quadric error
// metrics", SIGGRAPH 1997, as meshopt_simplify implements it in 0.18).
//
// meshopt_simplify works on one vertex buffer but sees topology by position: vertices that
// share a position and differ in attributes are "wedges" of one point, and it collapses a
// seam's wedges together, each to a vertex of its own side. So the merged mesh is only welded
// where vertices are the same in every attribute that survives (position, normal, uv0,
// material): more wedges at a point than a seam has would lock it. The bake's values are
// left out of that key and averaged over each welded group, because neighbouring faces of
// one chart read the same texels up to rounding. No attribute is ever interpolated by the
// simplifier: every output vertex is an input vertex, so a triangle never mixes materials.
//
// Deterministic: one thread, sorts under a total order (ties broken by vertex index), sums in
// vertex order, and meshoptimizer's simplifier has no randomness.
#include "hlod.hpp"

#include <dawnforge/bake/bake_folder.hpp>
#include <dawnforge/bake/lighting.hpp>
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/materials.hpp>
#include <dawnforge/core/read_file.hpp>

#include <glm/geometric.hpp>
#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <optional>
#include <string>
#include <utility>

namespace dawnforge::world {

namespace {

namespace fs = std::filesystem;

// What a vertex without a bake gets: lit by the open sky, no lamp light.
constexpr glm::vec2 kNoBakeSkySun{1.0f, 1.0f};  // TEXCOORD_1: (sky, sun bounce)
constexpr glm::vec2 kNoBakeAoLamps{1.0f, 0.0f}; // TEXCOORD_2: (ao, lamps)

// ---------------------------------------------------------------------------------------
// The bake, folded into vertex attributes.

// The bake, and where each baked node's lightmap UVs are: (receiver, mesh) indices.
struct BakeIndex {
    bake::BakeFolder folder;
    std::map<std::string, std::pair<std::size_t, std::size_t>> nodes;
};

std::optional<BakeIndex> readBakeIndex(const fs::path& tileDir, const fs::path& glb) {
    if (!bake::hasBake(tileDir)) return std::nullopt;
    std::optional<BakeIndex> index(std::in_place);
    index->folder = bake::readBake(tileDir, readBinaryFile(glb));
    const std::vector<bake::BakedReceiver>& receivers = index->folder.receivers;
    for (std::size_t r = 0; r < receivers.size(); ++r)
        for (std::size_t m = 0; m < receivers[r].meshes.size(); ++m) index->nodes[receivers[r].meshes[m].node] = {r, m};
    return index;
}

// The four decoded channels at uv, filtered bilinearly (texel centres at (i + 0.5) / size,
// clamped at the edges) on the stored bytes and decoded after, as the runtime's GPU samples
// the RGBA8 lightmap and its shader decodes. Charts keep a margin, so the taps stay in one.
glm::vec4 sampleLightmap(const bake::BakedReceiver& r, glm::vec2 uv) {
    const float fx = uv.x * float(r.width) - 0.5f, fy = uv.y * float(r.height) - 0.5f;
    const float x0 = std::floor(fx), y0 = std::floor(fy);
    const float tx = fx - x0, ty = fy - y0;
    auto stored = [&](int x, int y) {
        x = std::clamp(x, 0, r.width - 1);
        y = std::clamp(y, 0, r.height - 1);
        const std::uint8_t* p = &r.rgba[4 * (std::size_t(y) * std::size_t(r.width) + std::size_t(x))];
        return glm::vec4(p[0], p[1], p[2], p[3]) / 255.0f;
    };
    const int ix = int(x0), iy = int(y0);
    const glm::vec4 top = glm::mix(stored(ix, iy), stored(ix + 1, iy), tx);
    const glm::vec4 bottom = glm::mix(stored(ix, iy + 1), stored(ix + 1, iy + 1), tx);
    const glm::vec4 s = glm::mix(top, bottom, ty);
    glm::vec4 value;
    for (int c = 0; c < 4; ++c) value[c] = bake::kChannelRange[std::size_t(c)] * s[c] * s[c];
    return value;
}

// Replaces the node's TEXCOORD_1/2 (room data on glass) with the bake's channels, or the
// no-bake defaults when the node has none; drops what an HLOD mesh does not carry.
void foldBake(Mesh& mesh, const std::string& node, const BakeIndex* bake) {
    const std::size_t n = mesh.vertexCount();
    mesh.uv1.assign(n, kNoBakeSkySun);
    mesh.uv2.assign(n, kNoBakeAoLamps);
    mesh.uv3.clear();
    mesh.pieceIds.clear();
    if (!bake) return;
    const auto found = bake->nodes.find(node);
    if (found == bake->nodes.end()) return;
    const bake::BakedReceiver& receiver = bake->folder.receivers[found->second.first];
    const std::vector<glm::vec2>& uv = receiver.meshes[found->second.second].uv;
    if (uv.size() != n)
        throw InputError(format("bake of '{}': its UVs hold {} vertices, city.glb's mesh {}; bake the city again",
                                node, uv.size(), n));
    if (receiver.width <= 0 || receiver.height <= 0) return;
    for (std::size_t v = 0; v < n; ++v) {
        const glm::vec4 light = sampleLightmap(receiver, uv[v]);
        mesh.uv1[v] = {light.r, light.g};
        mesh.uv2[v] = {light.b, light.a};
    }
}

// ---------------------------------------------------------------------------------------
// A tile's content.

enum class Role { Skip, Shell, Ground, Tree };

Role roleOf(const std::string& name, bool inTree) {
    if (inTree) return Role::Tree;
    if (name.starts_with("building_") && name.ends_with("_lod1")) return Role::Shell;
    if (name.starts_with("ground_") || name.starts_with("land_")) return Role::Ground;  // the far land is the horizon
    return Role::Skip;  // LOD0, lamps
}

// For each node, the index of the tree_NNNNN node it belongs to (its trunk), or -1.
std::vector<int> treeOfNodes(const std::vector<MeshNode>& nodes) {
    std::vector<int> tree(nodes.size(), -1);
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        if (!nodes[i].name.starts_with("tree_")) continue;
        const int parent = nodes[i].parent;  // parents come first: theirs is known
        tree[i] = parent >= 0 && tree[std::size_t(parent)] >= 0 ? tree[std::size_t(parent)] : int(i);
    }
    return tree;
}

// Each tree's crown: the world box of its leaf cards (material `ground`), by trunk node.
std::map<int, Bounds> crownsOf(const std::vector<MeshNode>& nodes, const std::vector<int>& tree) {
    std::map<int, Bounds> crowns;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        const Mesh& m = nodes[i].mesh;
        if (tree[i] < 0 || m.materialIds.size() != m.vertexCount()) continue;
        for (std::size_t v = 0; v < m.vertexCount(); ++v) {
            if (m.materialIds[v] != kGround) continue;
            const glm::dvec3 p(glm::vec3(nodes[i].world * glm::vec4(m.positions[v], 1.0f)));
            Bounds& box = crowns.try_emplace(tree[i], Bounds{p, p}).first->second;
            box.min = glm::min(box.min, p);
            box.max = glm::max(box.max, p);
        }
    }
    return crowns;
}

// A vertical card from a to b (at the crown's foot) up to `top`, facing `normal`; uv0 in metres.
void addCard(Mesh& m, glm::vec3 a, glm::vec3 b, float top, glm::vec3 normal) {
    const auto base = std::uint32_t(m.positions.size());
    const float width = glm::distance(a, b), height = top - a.y;
    const glm::vec3 corners[4] = {a, b, {b.x, top, b.z}, {a.x, top, a.z}};
    const glm::vec2 uvs[4] = {{0.0f, 0.0f}, {width, 0.0f}, {width, height}, {0.0f, height}};
    for (int k = 0; k < 4; ++k) {
        m.positions.push_back(corners[k]);
        m.normals.push_back(normal);
        m.uv0.push_back(uvs[k]);
        m.materialIds.push_back(kGround);
    }
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

// Two crossed vertical cards, along x and along z through the crown's centre, as wide and as
// tall as its box: a tree seen from afar (its leaves' material, so the atlas's green).
Mesh crownCards(const Bounds& crown) {
    const glm::vec3 lo(crown.min), hi(crown.max), c = 0.5f * (lo + hi);
    Mesh m;
    addCard(m, {lo.x, lo.y, c.z}, {hi.x, lo.y, c.z}, hi.y, {0.0f, 0.0f, 1.0f});
    addCard(m, {c.x, lo.y, hi.z}, {c.x, lo.y, lo.z}, hi.y, {1.0f, 0.0f, 0.0f});
    foldBake(m, {}, nullptr);
    return m;
}

// ---------------------------------------------------------------------------------------
// Merging, welding, compaction.

// A child with every HLOD attribute, missing ones given their defaults (flat-shaded normals
// by area; material 0; the no-bake light), so that merging never fills light with zeros.
Mesh withHlodAttributes(const Mesh& child) {
    for (std::uint32_t i : child.indices) DAWNFORGE_ASSERT(i < child.vertexCount(), "a child's index is out of range");
    Mesh m;
    m.positions = child.positions;
    m.indices = child.indices;
    const std::size_t n = m.vertexCount();
    m.normals = child.normals.size() == n ? child.normals : std::vector<glm::vec3>(n, glm::vec3(0.0f));
    if (child.normals.size() != n) {
        for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
            const glm::vec3 &a = m.positions[m.indices[t]], &b = m.positions[m.indices[t + 1]],
                            &c = m.positions[m.indices[t + 2]];
            for (int k = 0; k < 3; ++k) m.normals[m.indices[t + std::size_t(k)]] += glm::cross(b - a, c - a);
        }
        for (glm::vec3& v : m.normals) v = glm::length(v) > 0.0f ? glm::normalize(v) : glm::vec3(0.0f, 1.0f, 0.0f);
    }
    m.uv0 = child.uv0.size() == n ? child.uv0 : std::vector<glm::vec2>(n, glm::vec2(0.0f));
    m.uv1 = child.uv1.size() == n ? child.uv1 : std::vector<glm::vec2>(n, kNoBakeSkySun);
    m.uv2 = child.uv2.size() == n ? child.uv2 : std::vector<glm::vec2>(n, kNoBakeAoLamps);
    m.materialIds = child.materialIds.size() == n ? child.materialIds : std::vector<std::uint8_t>(n, 0);
    return m;
}

// The children one after the other. Not appendMesh: it renormalises normals, and a vertex
// should come out of every level of the quadtree with the bytes it went in with.
Mesh mergeChildren(const std::vector<Mesh>& children) {
    Mesh merged;
    merged.name = "hlod";
    for (const Mesh& child : children) {
        if (child.indices.empty()) continue;
        const Mesh m = withHlodAttributes(child);
        const auto base = std::uint32_t(merged.vertexCount());
        for (std::uint32_t i : m.indices) merged.indices.push_back(base + i);
        auto append = [](auto& to, const auto& from) { to.insert(to.end(), from.begin(), from.end()); };
        append(merged.positions, m.positions);
        append(merged.normals, m.normals);
        append(merged.uv0, m.uv0);
        append(merged.uv1, m.uv1);
        append(merged.uv2, m.uv2);
        append(merged.materialIds, m.materialIds);
    }
    // meshopt finds a point's wedges by the bytes of its position: -0 and +0 must agree.
    for (glm::vec3& p : merged.positions) p += glm::vec3(0.0f);
    return merged;
}

// Whether vertices a and b agree in every attribute the weld keeps (all but the bake).
bool sameSurfacePoint(const Mesh& m, std::uint32_t a, std::uint32_t b) {
    return m.positions[a] == m.positions[b] && m.normals[a] == m.normals[b] && m.uv0[a] == m.uv0[b] &&
           m.materialIds[a] == m.materialIds[b];
}

// A strict weak order of those attributes, vertex index last, so that sorting is total.
bool surfacePointBefore(const Mesh& m, std::uint32_t a, std::uint32_t b) {
    auto key = [&](std::uint32_t v) {
        const glm::vec3 &p = m.positions[v], &n = m.normals[v];
        const glm::vec2& t = m.uv0[v];
        return std::make_tuple(p.x, p.y, p.z, n.x, n.y, n.z, t.x, t.y, m.materialIds[v], v);
    };
    return key(a) < key(b);
}

// Points every index at the first vertex of its group of equal surface points, and gives that
// vertex the group's mean bake (summed in vertex order, so the bytes never depend on the sort).
void weldSurfacePoints(Mesh& m) {
    const std::size_t n = m.vertexCount();
    std::vector<std::uint32_t> order(n), first(n);
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(),
              [&](std::uint32_t a, std::uint32_t b) { return surfacePointBefore(m, a, b); });
    for (std::size_t k = 0; k < n; ++k)
        first[order[k]] = k > 0 && sameSurfacePoint(m, order[k - 1], order[k]) ? first[order[k - 1]] : order[k];
    std::vector<glm::vec2> skySun(n, glm::vec2(0.0f)), aoLamps(n, glm::vec2(0.0f));
    std::vector<std::uint32_t> count(n, 0);
    for (std::size_t v = 0; v < n; ++v) {
        skySun[first[v]] += m.uv1[v];
        aoLamps[first[v]] += m.uv2[v];
        ++count[first[v]];
    }
    for (std::size_t v = 0; v < n; ++v)
        if (count[v] > 0) {
            m.uv1[v] = skySun[v] / float(count[v]);
            m.uv2[v] = aoLamps[v] / float(count[v]);
        }
    for (std::uint32_t& i : m.indices) i = first[i];
}

// Drops triangles with two corners at one point. A sliver with three distinct corners on a
// line stays: it carries topology (on a straight locked border, dropping one would orphan
// the middle vertex that the neighbour's mesh still uses) and covers no pixel.
void dropDegenerateTriangles(const std::vector<glm::vec3>& positions, std::vector<std::uint32_t>& indices) {
    std::size_t kept = 0;
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
        const glm::vec3 &a = positions[indices[t]], &b = positions[indices[t + 1]], &c = positions[indices[t + 2]];
        if (a == b || b == c || c == a) continue;
        std::copy_n(&indices[t], 3, &indices[kept]);
        kept += 3;
    }
    indices.resize(kept);
}

template <typename T>
std::vector<T> remapped(const std::vector<T>& values, const std::vector<std::uint32_t>& remap, std::size_t count) {
    std::vector<T> out(count);
    for (std::size_t v = 0; v < values.size(); ++v)
        if (remap[v] != ~0u) out[remap[v]] = values[v];
    return out;
}

// The mesh of `indices` alone: unused vertices removed, the rest in order of first use.
Mesh compacted(const Mesh& m, std::vector<std::uint32_t> indices) {
    std::vector<std::uint32_t> remap(m.vertexCount());
    const std::size_t count = meshopt_optimizeVertexFetchRemap(remap.data(), indices.data(), indices.size(),
                                                               m.vertexCount());
    Mesh out;
    out.name = m.name;
    for (std::uint32_t& i : indices) i = remap[i];
    out.indices = std::move(indices);
    out.positions = remapped(m.positions, remap, count);
    out.normals = remapped(m.normals, remap, count);
    out.uv0 = remapped(m.uv0, remap, count);
    out.uv1 = remapped(m.uv1, remap, count);
    out.uv2 = remapped(m.uv2, remap, count);
    out.materialIds = remapped(m.materialIds, remap, count);
    return out;
}

}  // namespace

Mesh tileHlodSource(const fs::path& tileDir) {
    const fs::path glb = tileDir / "city.glb";
    const std::vector<MeshNode> nodes = loadMeshNodes(glb);
    const std::optional<BakeIndex> bake = readBakeIndex(tileDir, glb);
    const std::vector<int> tree = treeOfNodes(nodes);
    const std::map<int, Bounds> crowns = crownsOf(nodes, tree);
    Mesh out;
    out.name = tileDir.filename().string();
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        const MeshNode& node = nodes[i];
        const Role role = roleOf(node.name, tree[i] >= 0);
        // Of a tree only its trunk (the tree_NNNNN node) stays; its crown becomes two cards.
        if (role == Role::Skip || (role == Role::Tree && tree[i] != int(i))) continue;
        Mesh mesh = node.mesh;
        foldBake(mesh, node.name, bake ? &*bake : nullptr);
        appendMesh(out, mesh, node.world);
        if (role != Role::Tree) continue;
        if (const auto crown = crowns.find(int(i)); crown != crowns.end()) appendMesh(out, crownCards(crown->second));
    }
    return out;
}

HlodMesh simplifyHlod(const std::vector<Mesh>& children, const HlodSettings& settings) {
    DAWNFORGE_ASSERT(settings.ratio >= 0.0 && settings.ratio <= 1.0, "ratio must be in [0, 1]");
    DAWNFORGE_ASSERT(settings.maxError >= 0.0 && std::isfinite(settings.maxError), "maxError must be finite, >= 0");
    Mesh merged = mergeChildren(children);
    weldSurfacePoints(merged);
    dropDegenerateTriangles(merged.positions, merged.indices);
    const Mesh welded = compacted(merged, std::move(merged.indices));
    HlodMesh out;
    if (welded.indices.empty()) {
        out.mesh.name = welded.name;
        return out;
    }
    const std::size_t triangles = welded.triangleCount();
    const auto target = std::size_t(double(triangles) * settings.ratio) * 3;
    std::vector<std::uint32_t> indices(welded.indices.size());
    float relativeError = 0.0f;
    indices.resize(meshopt_simplify(indices.data(), welded.indices.data(), welded.indices.size(),
                                    &welded.positions[0].x, welded.vertexCount(), sizeof(glm::vec3), target,
                                    float(settings.maxError), meshopt_SimplifyLockBorder, &relativeError));
    const float scale = meshopt_simplifyScale(&welded.positions[0].x, welded.vertexCount(), sizeof(glm::vec3));
    std::vector<std::uint32_t> drawOrder(indices.size());  // the GPU's vertex cache: cheap to give
    meshopt_optimizeVertexCache(drawOrder.data(), indices.data(), indices.size(), welded.vertexCount());
    out.mesh = compacted(welded, std::move(drawOrder));
    out.error = double(relativeError) * double(scale);
    return out;
}

}  // namespace dawnforge::world
