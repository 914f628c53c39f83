// HLOD meshes (hlod.hpp): a tile's far content with its bake folded into vertex attributes,
// and the merge-and-simplify step of every quadtree node. The simplifier is meshoptimizer's
// quadric edge collapse (Garland and Heckbert, "Surface simplification using quadric error
// metrics", SIGGRAPH 1997, as meshopt_simplify implements it in 0.18), and where that stops
// short of the target (from level 2 up), a vertex clustering of our own (the second pass).
//
// meshopt_simplify works on one vertex buffer but sees topology by position: vertices that
// share a position and differ in attributes are "wedges" of one point, and it collapses a
// seam's wedges together, each to a vertex of its own side. So the merged mesh is only welded
// where vertices are the same in every attribute that survives (position, normal, uv0,
// material): more wedges at a point than a seam has would lock it. The bake's values are
// left out of that key and averaged over each welded group, because neighbouring faces of
// one chart read the same texels up to rounding. No attribute is ever interpolated by either
// pass: every output vertex is an input vertex (the second pass moves it to another input
// vertex's position), so a triangle never mixes materials.
//
// Deterministic: one thread, sorts under a total order (ties broken by vertex index), sums in
// vertex or triangle order, and meshoptimizer's simplifier has no randomness.
#include "hlod.hpp"

#include <dawnforge/bake/bake_folder.hpp>
#include <dawnforge/bake/lighting.hpp>
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/materials.hpp>
#include <dawnforge/core/read_file.hpp>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
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

// ---------------------------------------------------------------------------------------
// The second pass: error-bounded vertex clustering, where meshopt_simplify stops short.
//
// Why: LOD1 shells and the ground are flat-shaded, so most points carry several wedges, and
// meshopt_simplify locks them (complex vertices). A level-1 result is made of little else, so
// from level 2 or 3 up the first pass keeps most of its input (0.88 at a 4 km² world's root).
// Measured on that root: welding by position does not free meshopt_simplify (per material, 0.77
// with open borders free, 0.88 locked); meshopt_simplifySloppy per material reaches 0.21, but
// clusters each material on a grid of its own, so a roof and its walls snap to different points
// and part (815 km of open edges, from the input's 232 km; 119 km with one clustering for every
// material, which snaps both sides of a shared edge to one point).
//
// The clustering: an octree of cubic cells over the points (vertices welded by position); a
// cell's point is its input point of least quadric error against the planes of the triangles
// around it (Garland and Heckbert's quadrics, area-weighted, as meshopt's sloppy simplifier
// picks them: roofs' and walls' corners stay), and its error the farthest any of those planes,
// or any point of the cell on an open edge, is from that point. A point joins its cell at the
// coarsest level whose error is within a limit, bisected for the largest triangle count at or
// under the target: flat ground takes big cells, detail small ones. A triangle with corners in
// three clusters joins their points (between the same three, once: the largest input triangle,
// its material and orientation); each corner is an input vertex of the triangle's material in
// its cluster (the one whose normal faces the new triangle most), moved to the cluster's point.
// Open borders are not locked: the error includes how far an open point moves, so it bounds the
// crack with a neighbouring node.

// Above this many times the target's triangle count after meshopt_simplify, the second pass
// runs. It removes a small excess at little cost (on the 4 km² world's level-2 nodes, 1.08 to
// 1.11 times the target: 5 mm more error), so the threshold is low.
constexpr double kSecondPassAbove = 1.05;

// A triangle's plane (unit normal, offset) and area; area 0 for a degenerate one.
struct Plane {
    glm::dvec3 normal{0.0};
    double offset = 0.0, area = 0.0;
    double distance(const glm::dvec3& p) const { return std::abs(glm::dot(normal, p) + offset); }
};

// The first pass's triangles by position: the first vertex at each used position (`points`,
// in order of first use), each index's point, each point's place from the least corner of
// their box, whether it is on an open edge (of one triangle, any material), triangles' planes.
struct PointMesh {
    std::vector<std::uint32_t> points, corners;
    std::vector<glm::dvec3> at;
    std::vector<bool> open;
    std::vector<Plane> planes;
};

void addPlanesAndOpenPoints(PointMesh& pm) {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
    for (std::size_t t = 0; t + 2 < pm.corners.size(); t += 3) {
        const glm::dvec3 &a = pm.at[pm.corners[t]], &b = pm.at[pm.corners[t + 1]], &c = pm.at[pm.corners[t + 2]];
        const glm::dvec3 n = glm::cross(b - a, c - a);
        const double twiceArea = glm::length(n);
        Plane& plane = pm.planes.emplace_back();
        if (twiceArea > 0.0) plane = {n / twiceArea, -glm::dot(n / twiceArea, a), 0.5 * twiceArea};
        for (std::size_t k = 0; k < 3; ++k)
            edges.push_back(std::minmax(pm.corners[t + k], pm.corners[t + (k + 1) % 3]));
    }
    std::sort(edges.begin(), edges.end());
    pm.open.assign(pm.at.size(), false);
    for (std::size_t k = 0, end = 0; k < edges.size(); k = end) {
        for (end = k + 1; end < edges.size() && edges[end] == edges[k];) ++end;
        if (end == k + 1) pm.open[edges[k].first] = pm.open[edges[k].second] = true;
    }
}

PointMesh pointMesh(const Mesh& m) {
    // The same id for the same position bytes (-0 is +0 already), numbered in vertex order.
    std::vector<std::uint32_t> id(m.vertexCount());
    const std::size_t ids = meshopt_generateVertexRemap(id.data(), nullptr, m.vertexCount(), &m.positions[0].x,
                                                        m.vertexCount(), sizeof(glm::vec3));
    std::vector<std::uint32_t> first(ids, ~0u), pointOfId(ids, ~0u);
    for (std::uint32_t v = 0; v < id.size(); ++v)
        if (first[id[v]] == ~0u) first[id[v]] = v;
    PointMesh pm;
    for (std::uint32_t i : m.indices) {
        std::uint32_t& p = pointOfId[id[i]];
        if (p == ~0u) p = std::uint32_t(pm.points.size()), pm.points.push_back(first[id[i]]);
        pm.corners.push_back(p);
    }
    glm::dvec3 lo(std::numeric_limits<double>::max());
    for (std::uint32_t v : pm.points) lo = glm::min(lo, glm::dvec3(m.positions[v]));
    for (std::uint32_t v : pm.points) pm.at.push_back(glm::dvec3(m.positions[v]) - lo);
    addPlanesAndOpenPoints(pm);
    return pm;
}

// Each point's cell for cubic cells of `size`, the cells numbered in the order of their keys
// (three 21-bit coordinates: a level's cells are at most 2^20 to the points' extent).
std::vector<std::uint32_t> cellsOf(const PointMesh& pm, double size, std::size_t& count) {
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(pm.at.size());
    for (std::size_t p = 0; p < pm.at.size(); ++p) {
        const glm::dvec3 q = glm::floor(pm.at[p] / size);
        keyed[p] = {(std::uint64_t(q.x) << 42) | (std::uint64_t(q.y) << 21) | std::uint64_t(q.z), std::uint32_t(p)};
    }
    std::sort(keyed.begin(), keyed.end());
    std::vector<std::uint32_t> cell(pm.at.size());
    std::uint32_t n = 0;
    for (std::size_t k = 0; k < keyed.size(); ++k) {
        if (k > 0 && keyed[k].first != keyed[k - 1].first) ++n;
        cell[keyed[k].second] = n;
    }
    count = keyed.empty() ? 0 : std::size_t(n) + 1;
    return cell;
}

// The area-weighted squared distance to planes (Garland and Heckbert): p·Ap + 2b·p + c.
struct Quadric {
    glm::dmat3 a{0.0};
    glm::dvec3 b{0.0};
    double c = 0.0;
};

// Each cell's point: the one of least error against the quadric of the triangles with a corner
// in the cell (the first point on ties).
std::vector<std::uint32_t> cellPoints(const PointMesh& pm, const std::vector<std::uint32_t>& cell, std::size_t cells) {
    std::vector<Quadric> q(cells);
    for (std::size_t t = 0; t < pm.planes.size(); ++t) {
        const Plane& plane = pm.planes[t];
        for (std::size_t k = 0; k < 3; ++k) {
            Quadric& to = q[cell[pm.corners[3 * t + k]]];
            to.a += plane.area * glm::outerProduct(plane.normal, plane.normal);
            to.b += plane.area * plane.offset * plane.normal;
            to.c += plane.area * plane.offset * plane.offset;
        }
    }
    std::vector<std::uint32_t> best(cells, ~0u);
    std::vector<double> least(cells, std::numeric_limits<double>::infinity());
    for (std::uint32_t p = 0; p < pm.at.size(); ++p) {
        const Quadric& e = q[cell[p]];
        const glm::dvec3& x = pm.at[p];
        const double error = glm::dot(x, e.a * x) + 2.0 * glm::dot(e.b, x) + e.c;
        if (error < least[cell[p]]) least[cell[p]] = error, best[cell[p]] = p;
    }
    return best;
}

// Each cell's error, in metres: the farthest the plane of a triangle with a corner in the cell,
// or a point of the cell on an open edge, is from the cell's point.
std::vector<double> cellErrors(const PointMesh& pm, const std::vector<std::uint32_t>& cell,
                               const std::vector<std::uint32_t>& point) {
    std::vector<double> error(point.size(), 0.0);
    for (std::size_t t = 0; t < pm.planes.size(); ++t)
        for (std::size_t k = 0; k < 3; ++k) {
            const std::uint32_t c = cell[pm.corners[3 * t + k]];
            if (pm.planes[t].area > 0.0) error[c] = std::max(error[c], pm.planes[t].distance(pm.at[point[c]]));
        }
    for (std::uint32_t p = 0; p < pm.at.size(); ++p)
        if (pm.open[p]) error[cell[p]] = std::max(error[cell[p]], glm::distance(pm.at[p], pm.at[point[cell[p]]]));
    return error;
}

// The clustering octree, its levels' cells numbered one after the other: by level, each point's
// cell; by cell, its point and error. Level 0's cell is the points' extent; each level halves
// it, down to the first where every point is alone (at most 2^20 cells to the extent).
struct Octree {
    std::vector<std::vector<std::uint32_t>> cellOf;
    std::vector<std::uint32_t> point;
    std::vector<double> error;
    double extent = 0.0;
};

Octree octreeOf(const PointMesh& pm) {
    Octree o;
    for (const glm::dvec3& p : pm.at) o.extent = std::max({o.extent, p.x, p.y, p.z});
    std::size_t cells = 0;
    for (int level = 0; level <= 20 && cells < pm.at.size(); ++level) {
        std::vector<std::uint32_t> cell = cellsOf(pm, std::max(o.extent, 1e-3) * std::exp2(-level), cells);
        const std::vector<std::uint32_t> point = cellPoints(pm, cell, cells);
        const std::vector<double> error = cellErrors(pm, cell, point);
        const auto offset = std::uint32_t(o.point.size());
        for (std::uint32_t& c : cell) c += offset;
        for (std::uint32_t p : point) o.point.push_back(p);
        o.error.insert(o.error.end(), error.begin(), error.end());
        o.cellOf.push_back(std::move(cell));
    }
    return o;
}

// Each point's cluster for an error limit: its cell at the coarsest level whose error is within
// the limit, or at the finest. Cells nest (halved sizes from one corner), so points that share
// a cell share their cluster.
std::vector<std::uint32_t> clustersOf(const Octree& o, double limit) {
    std::vector<std::uint32_t> cluster(o.cellOf.front().size());
    for (std::size_t p = 0; p < cluster.size(); ++p) {
        std::size_t level = 0;
        while (level + 1 < o.cellOf.size() && o.error[o.cellOf[level][p]] > limit) ++level;
        cluster[p] = o.cellOf[level][p];
    }
    return cluster;
}

// The triangles (numbers, in order) whose corners lie in three clusters: between the same three
// in the same orientation, the largest (the first on ties).
std::vector<std::uint32_t> survivors(const PointMesh& pm, const std::vector<std::uint32_t>& cluster) {
    std::vector<std::array<std::uint32_t, 5>> keys;  // clusters (least first, order kept), -area, triangle
    for (std::size_t t = 0; t < pm.planes.size(); ++t) {
        std::array<std::uint32_t, 3> c{};
        for (std::size_t k = 0; k < 3; ++k) c[k] = cluster[pm.corners[3 * t + k]];
        if (c[0] == c[1] || c[1] == c[2] || c[2] == c[0]) continue;
        std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
        const auto area = std::bit_cast<std::uint32_t>(float(pm.planes[t].area));  // >= 0: bits in order
        keys.push_back({c[0], c[1], c[2], ~area, std::uint32_t(t)});
    }
    std::sort(keys.begin(), keys.end());
    std::vector<std::uint32_t> kept;
    for (std::size_t k = 0; k < keys.size(); ++k)
        if (k == 0 || !std::equal(keys[k].begin(), keys[k].begin() + 3, keys[k - 1].begin()))
            kept.push_back(keys[k][4]);
    std::sort(kept.begin(), kept.end());
    return kept;
}

// The error limit, bisected in log2 over 32 octaves below twice the extent (where every point
// is in one of level 0's eight cells), of the largest count at or under `target` triangles
// (the count falls, not always strictly, as the limit grows).
double clusterLimit(const PointMesh& pm, const Octree& o, std::size_t target) {
    double lo = -31.0, up = 1.0;  // log2 of the limit over the extent
    for (int step = 0; step < 20; ++step) {
        const double mid = 0.5 * (lo + up);
        (survivors(pm, clustersOf(o, o.extent * std::exp2(mid))).size() <= target ? up : lo) = mid;
    }
    return o.extent * std::exp2(up);
}

// Every used vertex as (cluster, material, vertex), sorted: a cluster's wedges of one material.
std::vector<std::array<std::uint32_t, 3>> wedgesByCluster(const Mesh& m, const PointMesh& pm,
                                                          const std::vector<std::uint32_t>& cluster) {
    std::vector<std::array<std::uint32_t, 3>> wedges(m.indices.size());
    for (std::size_t k = 0; k < m.indices.size(); ++k)
        wedges[k] = {cluster[pm.corners[k]], m.materialIds[m.indices[k]], m.indices[k]};
    std::sort(wedges.begin(), wedges.end());
    wedges.erase(std::unique(wedges.begin(), wedges.end()), wedges.end());
    return wedges;
}

// The wedge of `material` in `cluster` whose normal faces `normal` most (the least on ties).
std::uint32_t facingWedge(const Mesh& m, const std::vector<std::array<std::uint32_t, 3>>& wedges,
                          std::uint32_t cluster, std::uint32_t material, glm::vec3 normal) {
    auto it = std::lower_bound(wedges.begin(), wedges.end(), std::array<std::uint32_t, 3>{cluster, material, 0u});
    std::uint32_t best = (*it)[2];
    float most = -std::numeric_limits<float>::infinity();
    for (; it != wedges.end() && (*it)[0] == cluster && (*it)[1] == material; ++it)
        if (const float d = glm::dot(m.normals[(*it)[2]], normal); d > most) most = d, best = (*it)[2];
    return best;
}

struct Clustered {
    Mesh mesh;
    double error = 0.0;  // metres: the largest error of a cluster (cellErrors)
};

// The second pass (see above) to `target` triangles.
Clustered clusterToTarget(const Mesh& m, std::size_t target) {
    const PointMesh pm = pointMesh(m);
    const Octree o = octreeOf(pm);
    const std::vector<std::uint32_t> cluster = clustersOf(o, clusterLimit(pm, o, target));
    const std::vector<std::array<std::uint32_t, 3>> wedges = wedgesByCluster(m, pm, cluster);
    Clustered out;
    out.mesh.name = m.name;
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> made;  // (cluster, wedge): output vertex
    for (std::uint32_t t : survivors(pm, cluster)) {
        std::array<std::uint32_t, 3> c{};
        for (std::size_t k = 0; k < 3; ++k) c[k] = cluster[pm.corners[3 * t + k]];
        auto at = [&](std::size_t k) { return m.positions[pm.points[o.point[c[k]]]]; };
        const glm::vec3 normal = glm::cross(at(1) - at(0), at(2) - at(0));
        for (std::size_t k = 0; k < 3; ++k) {
            const std::uint32_t w = facingWedge(m, wedges, c[k], m.materialIds[m.indices[3 * t]], normal);
            const auto [it, fresh] = made.try_emplace({c[k], w}, std::uint32_t(out.mesh.positions.size()));
            out.mesh.indices.push_back(it->second);
            if (!fresh) continue;
            out.mesh.positions.push_back(at(k));
            out.mesh.normals.push_back(m.normals[w]);
            out.mesh.uv0.push_back(m.uv0[w]);
            out.mesh.uv1.push_back(m.uv1[w]);
            out.mesh.uv2.push_back(m.uv2[w]);
            out.mesh.materialIds.push_back(m.materialIds[w]);
        }
    }
    for (std::uint32_t c : cluster) out.error = std::max(out.error, o.error[c]);
    return out;
}

// The first pass: meshopt_simplify to `target` triangles within `limit` (relative to the
// mesh's extent), open borders locked; its error in metres.
HlodMesh collapseEdges(const Mesh& welded, std::size_t target, double limit) {
    std::vector<std::uint32_t> indices(welded.indices.size());
    float relativeError = 0.0f;
    indices.resize(meshopt_simplify(indices.data(), welded.indices.data(), welded.indices.size(),
                                    &welded.positions[0].x, welded.vertexCount(), sizeof(glm::vec3), 3 * target,
                                    float(limit), meshopt_SimplifyLockBorder, &relativeError));
    const float scale = meshopt_simplifyScale(&welded.positions[0].x, welded.vertexCount(), sizeof(glm::vec3));
    return {compacted(welded, std::move(indices)), double(relativeError) * double(scale)};
}

// The first pass, and the second where the first stops short of the target (above); the errors
// add up, as a point of the second pass's input is up to the first's error away.
HlodMesh bothPasses(const Mesh& welded, std::size_t target, double limit) {
    HlodMesh first = collapseEdges(welded, target, limit);
    if (double(first.mesh.triangleCount()) <= kSecondPassAbove * double(target)) return first;
    Clustered second = clusterToTarget(first.mesh, target);
    return {std::move(second.mesh), first.error + second.error};
}

}  // namespace

Mesh tileHlodSource(const fs::path& tileDir) {
    const fs::path glb = tileDir / "city.glb";
    const std::vector<MeshNode> nodes = loadMeshNodes(glb, ReadIn::thisProcess);
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
    const std::size_t target = std::size_t(double(welded.triangleCount()) * settings.ratio);
    const HlodMesh simplified = bothPasses(welded, target, settings.maxError);
    std::vector<std::uint32_t> drawOrder(simplified.mesh.indices.size());  // the GPU's vertex cache: cheap to give
    meshopt_optimizeVertexCache(drawOrder.data(), simplified.mesh.indices.data(), simplified.mesh.indices.size(),
                                simplified.mesh.vertexCount());
    out.mesh = compacted(simplified.mesh, std::move(drawOrder));
    out.error = simplified.error;
    return out;
}

}  // namespace dawnforge::world
