// Lightmap charts and their packing (charts.hpp).
#include <dawnforge/bake/charts.hpp>
#include "plane_geometry.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/union_find.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <array>
#include <deque>
#include <map>
#include <numeric>
#include <tuple>

namespace dawnforge::bake {

namespace {

constexpr double kWeldGrid = 1e-4;        // metres: positions closer than this weld
constexpr double kCoplanarCos = 0.99985;  // about 1°
constexpr double kCoplanarOffset = 2e-3;  // metres
constexpr std::uint32_t kNoTriangle = 0xffffffffu;
constexpr double kMinChartFill = 0.6;     // a face unfolds onto a chart only if the chart's box stays this full

glm::dvec3 at(const ChartMesh& m, std::size_t t, int k) { return glm::dvec3(m.positions[m.indices[3 * t + std::size_t(k)]]); }

// Canonical vertex per position on the weld grid.
std::vector<std::uint32_t> weld(std::span<const glm::vec3> positions) {
    using Key = std::tuple<long long, long long, long long>;
    const auto key = [&](std::uint32_t i) {
        const glm::vec3 p = positions[i];
        return Key{std::llround(double(p.x) / kWeldGrid), std::llround(double(p.y) / kWeldGrid), std::llround(double(p.z) / kWeldGrid)};
    };
    std::vector<std::uint32_t> order(positions.size());
    std::iota(order.begin(), order.end(), 0u);
    std::vector<Key> keys(positions.size());
    for (std::uint32_t i = 0; i < positions.size(); ++i) keys[i] = key(i);
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return keys[a] != keys[b] ? keys[a] < keys[b] : a < b; });
    std::vector<std::uint32_t> canonical(positions.size());
    for (std::size_t i = 0; i < order.size(); ++i)
        canonical[order[i]] = (i > 0 && keys[order[i]] == keys[order[i - 1]]) ? canonical[order[i - 1]] : order[i];
    return canonical;
}

int roundUp(int v, int step) { return (v + step - 1) / step * step; }

// Texels of a chart's block along one axis for an extent of `texels`.
int blockExtent(double texels) { return roundUp(std::max(1, int(std::ceil(texels - 1e-9))) + 2 * kChartMargin, kChartAlign); }

// A planar group of patches with one texel size.
struct Face {
    std::vector<std::uint32_t> triangles;
    glm::dvec3 normal{0.0, 1.0, 0.0};
    double area = 0.0;
    double texel = 0.25;
};

// Two faces sharing a welded edge (canonical vertex indices a < b).
struct Adjacency {
    std::uint32_t face, other, a, b;
};

// Texel cells a chart's triangles cover (conservatively), with the face that covers each.
class Occupancy {
public:
    static constexpr double kReach = 1.25;  // half a texel diagonal plus the filter's reach
    // The cells of triangle abc (texel coordinates).
    template <typename F>
    static void cells(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, F&& f) {
        const glm::dvec2 lo = glm::min(a, glm::min(b, c)) - kReach, hi = glm::max(a, glm::max(b, c)) + kReach;
        for (long long y = std::llround(std::floor(lo.y)); y <= std::llround(std::floor(hi.y)); ++y)
            for (long long x = std::llround(std::floor(lo.x)); x <= std::llround(std::floor(hi.x)); ++x)
                if (distanceToTriangle(glm::dvec2(double(x) + 0.5, double(y) + 0.5), a, b, c) <= kReach) f(x, y);
    }
    static std::uint64_t key(long long x, long long y) { return (std::uint64_t(std::uint32_t(x)) << 32) | std::uint32_t(y); }
    static double distanceToTriangle(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b, glm::dvec2 c);
    std::map<std::uint64_t, std::uint32_t> owner;  // cell -> face
};

double segmentDistance(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
    const glm::dvec2 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * ab));
}

double Occupancy::distanceToTriangle(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
    const double d1 = cross2(b - a, p - a), d2 = cross2(c - b, p - b), d3 = cross2(a - c, p - c);
    const bool neg = d1 < 0 || d2 < 0 || d3 < 0, pos = d1 > 0 || d2 > 0 || d3 > 0;
    if (!(neg && pos)) return 0.0;
    return std::min({segmentDistance(p, a, b), segmentDistance(p, b, c), segmentDistance(p, c, a)});
}

// The face's own plane frame: u horizontal on walls (v down, as image rows), x and z on floors.
void planeAxes(glm::dvec3 normal, glm::dvec3& e1, glm::dvec3& e2) {
    if (std::abs(normal.y) > 0.999) {
        e1 = {1, 0, 0};
        e2 = {0, 0, 1};
    } else {
        e1 = glm::normalize(glm::cross(glm::dvec3(0, 1, 0), normal));
        e2 = -glm::cross(normal, e1);
    }
}

// Charts grown from faces by unfolding (see charts.hpp).
class ChartGrower {
public:
    ChartGrower(const ChartMesh& m, const std::vector<Face>& faces, const std::vector<Adjacency>& adjacency,
                const std::vector<std::int32_t>& faceOf, const std::vector<std::uint32_t>& canonical)
        : m_(m), faces_(faces), adjacency_(adjacency), faceOf_(faceOf), canonical_(canonical), placed_(faces.size(), 0) {
        for (std::size_t i = 0; i < adjacency_.size(); ++i) {
            if (firstAdjacency_.size() <= adjacency_[i].face) firstAdjacency_.resize(adjacency_[i].face + 1, std::uint32_t(-1));
            if (firstAdjacency_[adjacency_[i].face] == std::uint32_t(-1)) firstAdjacency_[adjacency_[i].face] = std::uint32_t(i);
        }
        firstAdjacency_.resize(faces.size() + 1, std::uint32_t(-1));
    }

    bool placed(std::size_t face) const { return placed_[face] != 0; }

    // A chart from `seed` and whatever unfolds onto it; returns its triangles and their 2D corners
    // (texel units, before the final rotation).
    std::pair<std::vector<std::uint32_t>, std::vector<glm::dvec2>> grow(std::uint32_t seed) {
        Occupancy occupancy;
        std::map<std::uint32_t, std::vector<glm::dvec2>> corners;  // face -> 3 per triangle
        const Face& f0 = faces_[seed];
        glm::dvec3 e1, e2;
        planeAxes(f0.normal, e1, e2);
        const glm::dvec3 origin = at(m_, f0.triangles.front(), 0);
        std::vector<glm::dvec2>& c0 = corners[seed];
        for (std::uint32_t t : f0.triangles)
            for (int k = 0; k < 3; ++k) {
                const glm::dvec3 d = at(m_, t, k) - origin;
                c0.emplace_back(glm::dot(d, e1) / f0.texel, glm::dot(d, e2) / f0.texel);
            }
        lo_ = glm::dvec2(INFINITY), hi_ = glm::dvec2(-INFINITY);
        area_ = 0.0;
        claim(seed, c0, occupancy);
        placed_[seed] = 1;
        std::deque<std::uint32_t> queue{seed};
        while (!queue.empty()) {
            const std::uint32_t g = queue.front();
            queue.pop_front();
            for (std::uint32_t i = firstAdjacency_[g]; i < adjacency_.size() && adjacency_[i].face == g; ++i) {
                const Adjacency& adj = adjacency_[i];
                if (placed_[adj.other] || faces_[adj.other].texel != faces_[g].texel) continue;
                std::vector<glm::dvec2> unfolded;
                if (!unfold(adj, corners.at(g), unfolded) || !fits(adj, unfolded, occupancy, corners.at(g))) continue;
                claim(adj.other, unfolded, occupancy);
                corners.emplace(adj.other, std::move(unfolded));
                placed_[adj.other] = 1;
                queue.push_back(adj.other);
            }
        }
        // Triangles in increasing order with their corners.
        std::vector<std::pair<std::uint32_t, std::array<glm::dvec2, 3>>> tris;
        for (const auto& [face, cs] : corners)
            for (std::size_t k = 0; k < faces_[face].triangles.size(); ++k)
                tris.push_back({faces_[face].triangles[k], {cs[3 * k], cs[3 * k + 1], cs[3 * k + 2]}});
        std::sort(tris.begin(), tris.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
        std::pair<std::vector<std::uint32_t>, std::vector<glm::dvec2>> out;
        for (const auto& [t, cs] : tris) {
            out.first.push_back(t);
            out.second.insert(out.second.end(), cs.begin(), cs.end());
        }
        return out;
    }

private:
    // 2D position of vertex `v` of face `face` among its corners.
    bool cornerOf(std::uint32_t face, const std::vector<glm::dvec2>& cs, std::uint32_t canonicalVertex, glm::dvec2& out) const {
        const Face& f = faces_[face];
        for (std::size_t k = 0; k < f.triangles.size(); ++k)
            for (int j = 0; j < 3; ++j)
                if (canonical_[m_.indices[3 * std::size_t(f.triangles[k]) + std::size_t(j)]] == canonicalVertex) {
                    out = cs[3 * k + std::size_t(j)];
                    return true;
                }
        return false;
    }

    // Face adj.other turned about the shared edge into the chart's plane, on the far side of the
    // edge from adj.face.
    bool unfold(const Adjacency& adj, const std::vector<glm::dvec2>& gCorners, std::vector<glm::dvec2>& out) const {
        glm::dvec2 pa(0.0), pb(0.0);
        if (!cornerOf(adj.face, gCorners, adj.a, pa) || !cornerOf(adj.face, gCorners, adj.b, pb)) return false;
        const Face& g = faces_[adj.face];
        const Face& f = faces_[adj.other];
        const glm::dvec3 qa(m_.positions[adj.a]), qb(m_.positions[adj.b]);
        const double len3 = glm::length(qb - qa), len2 = glm::length(pb - pa);
        if (len3 <= 1e-9 || len2 <= 1e-9) return false;
        const glm::dvec3 e1 = (qb - qa) / len3;
        glm::dvec3 e2 = glm::cross(f.normal, e1);
        if (glm::length(e2) < 1e-9) return false;
        e2 = glm::normalize(e2);
        const glm::dvec2 d = (pb - pa) / len2, perp(-d.y, d.x);
        // Which side of the edge each face lies on, from G's triangle on that edge (G may lie on
        // both sides of the edge's line: a facade around a window).
        glm::dvec2 gCentre(0.0);
        bool found = false;
        for (std::size_t k = 0; k < g.triangles.size() && !found; ++k) {
            int shared = 0;
            for (int j = 0; j < 3; ++j) {
                const std::uint32_t v = canonical_[m_.indices[3 * std::size_t(g.triangles[k]) + std::size_t(j)]];
                shared += v == adj.a || v == adj.b;
            }
            if (shared == 2) {
                gCentre = (gCorners[3 * k] + gCorners[3 * k + 1] + gCorners[3 * k + 2]) / 3.0;
                found = true;
            }
        }
        if (!found) return false;
        const double sg = cross2(d, gCentre - pa);
        double bf = 0.0;
        for (std::uint32_t t : f.triangles)
            for (int k = 0; k < 3; ++k) bf += glm::dot(at(m_, t, k) - qa, e2);
        if (std::abs(sg) < 1e-9 || std::abs(bf) < 1e-9) return false;
        const double sigma = (sg > 0 ? -1.0 : 1.0) * (bf > 0 ? 1.0 : -1.0);
        out.clear();
        for (std::uint32_t t : f.triangles)
            for (int k = 0; k < 3; ++k) {
                const glm::dvec3 x = at(m_, t, k) - qa;
                out.push_back(pa + (glm::dot(x, e1) * d + sigma * glm::dot(x, e2) * perp) / f.texel);
            }
        return true;
    }

    // Whether the unfolded face lands on free cells (cells of the face it hangs from count as
    // free within a texel of the shared edge) and keeps the chart within kMaxChartTexels.
    bool fits(const Adjacency& adj, const std::vector<glm::dvec2>& cs, const Occupancy& occupancy,
              const std::vector<glm::dvec2>& gCorners) const {
        glm::dvec2 lo = lo_, hi = hi_;
        for (const glm::dvec2& c : cs) lo = glm::min(lo, c), hi = glm::max(hi, c);
        if (hi.x - lo.x > kMaxChartTexels || hi.y - lo.y > kMaxChartTexels) return false;
        // Keep charts compact: their block is a rectangle, and empty corners of it are waste.
        const double area = area_ + faces_[adj.other].area / (faces_[adj.other].texel * faces_[adj.other].texel);
        const double box = (hi.x - lo.x + 2.0) * (hi.y - lo.y + 2.0), oldBox = (hi_.x - lo_.x + 2.0) * (hi_.y - lo_.y + 2.0);
        if (box > oldBox + 1e-9 && area < kMinChartFill * box) return false;
        glm::dvec2 pa(0.0), pb(0.0);
        cornerOf(adj.face, gCorners, adj.a, pa);
        cornerOf(adj.face, gCorners, adj.b, pb);
        bool ok = true;
        for (std::size_t k = 0; ok && k < cs.size(); k += 3)
            Occupancy::cells(cs[k], cs[k + 1], cs[k + 2], [&](long long x, long long y) {
                if (!ok) return;
                const auto it = occupancy.owner.find(Occupancy::key(x, y));
                if (it == occupancy.owner.end()) return;
                const glm::dvec2 centre(double(x) + 0.5, double(y) + 0.5);
                if (it->second == adj.face && segmentDistance(centre, pa, pb) <= 2.0 * Occupancy::kReach) return;
                ok = false;
            });
        return ok;
    }

    void claim(std::uint32_t face, const std::vector<glm::dvec2>& cs, Occupancy& occupancy) {
        for (const glm::dvec2& c : cs) lo_ = glm::min(lo_, c), hi_ = glm::max(hi_, c);
        area_ += faces_[face].area / (faces_[face].texel * faces_[face].texel);
        for (std::size_t k = 0; k < cs.size(); k += 3)
            Occupancy::cells(cs[k], cs[k + 1], cs[k + 2], [&](long long x, long long y) { occupancy.owner.try_emplace(Occupancy::key(x, y), face); });
    }

    const ChartMesh& m_;
    const std::vector<Face>& faces_;
    const std::vector<Adjacency>& adjacency_;
    const std::vector<std::int32_t>& faceOf_;
    const std::vector<std::uint32_t>& canonical_;
    std::vector<std::uint8_t> placed_;
    std::vector<std::uint32_t> firstAdjacency_;
    glm::dvec2 lo_{0.0}, hi_{0.0};  // the chart's bounds so far
    double area_ = 0.0;             // its faces' area, texels
};

// Turns a chart's corners to their minimum-area rectangle and sizes its block; the corners end
// up relative to the block's origin, centred in it.
Chart finishChart(std::vector<std::uint32_t> tris, std::vector<glm::dvec2> corners, double texel) {
    const double angle = minAreaRectAngle(convexHull(corners));
    const double c = std::cos(angle), s = std::sin(angle);
    glm::dvec2 lo(INFINITY), hi(-INFINITY);
    for (glm::dvec2& p : corners) {
        p = glm::dvec2(c * p.x + s * p.y, -s * p.x + c * p.y);
        lo = glm::min(lo, p), hi = glm::max(hi, p);
    }
    Chart chart;
    chart.texelMetres = texel;
    const glm::dvec2 extent = hi - lo;
    chart.size = {blockExtent(extent.x), blockExtent(extent.y)};
    const glm::dvec2 offset = 0.5 * (glm::dvec2(chart.size) - extent) - lo;
    for (glm::dvec2& p : corners) p += offset;
    chart.triangles = std::move(tris);
    chart.corners = std::move(corners);
    return chart;
}


// Triangle normals (unit, CCW front) and areas.
struct TriangleFrames {
    std::vector<glm::dvec3> normal;
    std::vector<double> area;
};

TriangleFrames triangleFrames(const ChartMesh& m, std::size_t nt) {
    TriangleFrames f{std::vector<glm::dvec3>(nt), std::vector<double>(nt)};
    for (std::size_t t = 0; t < nt; ++t) {
        const glm::dvec3 c = glm::cross(at(m, t, 1) - at(m, t, 0), at(m, t, 2) - at(m, t, 0));
        f.area[t] = 0.5 * glm::length(c);
        f.normal[t] = f.area[t] > 1e-12 ? c / (2.0 * f.area[t]) : glm::dvec3(0.0);
    }
    return f;
}

// Patches: triangles sharing a vertex index (never split, so each vertex has one UV).
UnionFind patchesOf(const ChartMesh& m, std::size_t nt) {
    UnionFind patches(nt);
    std::vector<std::uint32_t> firstUse(m.positions.size(), kNoTriangle);
    for (std::size_t t = 0; t < nt; ++t) {
        if (m.texelMetres[t] <= 0.0f) continue;
        for (int k = 0; k < 3; ++k) {
            std::uint32_t& f = firstUse[m.indices[3 * t + std::size_t(k)]];
            if (f == kNoTriangle) f = std::uint32_t(t);
            else patches.unite(f, std::uint32_t(t));
        }
    }
    return patches;
}

struct Edge {
    std::uint32_t group, a, b, tri;
};
bool sameEdge(const Edge& x, const Edge& y) { return x.group == y.group && x.a == y.a && x.b == y.b; }

// The welded edges of the charted triangles, sorted so that the triangles of an edge are adjacent.
std::vector<Edge> sortedEdges(const ChartMesh& m, std::size_t nt, std::span<const std::uint32_t> canonical, const TriangleFrames& tf) {
    const auto groupOf = [&](std::size_t t) { return m.group.empty() ? 0u : std::uint32_t(m.group[t]); };
    std::vector<Edge> edges;
    edges.reserve(3 * nt);
    for (std::size_t t = 0; t < nt; ++t) {
        if (m.texelMetres[t] <= 0.0f || tf.area[t] <= 1e-12) continue;
        for (int k = 0; k < 3; ++k) {
            std::uint32_t a = canonical[m.indices[3 * t + std::size_t(k)]], b = canonical[m.indices[3 * t + std::size_t((k + 1) % 3)]];
            if (a == b) continue;
            if (a > b) std::swap(a, b);
            edges.push_back({groupOf(t), a, b, std::uint32_t(t)});
        }
    }
    std::sort(edges.begin(), edges.end(),
              [](const Edge& x, const Edge& y) { return std::tie(x.group, x.a, x.b, x.tri) < std::tie(y.group, y.a, y.b, y.tri); });
    return edges;
}

// Faces: coplanar patches across welded edges; faceOf[t] = its face.
std::vector<Face> planarFaces(const ChartMesh& m, std::size_t nt, const std::vector<Edge>& edges, const UnionFind& patches,
                              const TriangleFrames& tf, std::vector<std::int32_t>& faceOf) {
    UnionFind uf = patches;
    const auto coplanar = [&](std::uint32_t s, std::uint32_t t) {
        return m.texelMetres[s] == m.texelMetres[t] && glm::dot(tf.normal[s], tf.normal[t]) >= kCoplanarCos &&
               std::abs(glm::dot(tf.normal[s], at(m, t, 0) - at(m, s, 0))) <= kCoplanarOffset;
    };
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        while (j < edges.size() && sameEdge(edges[j], edges[i])) ++j;
        for (std::size_t p = i; p < j; ++p)
            for (std::size_t q = p + 1; q < j; ++q)
                if (coplanar(edges[p].tri, edges[q].tri)) uf.unite(edges[p].tri, edges[q].tri);
        i = j;
    }
    std::vector<Face> faces;
    std::vector<std::int32_t> faceOfRoot(nt, -1);
    faceOf.assign(nt, -1);
    for (std::size_t t = 0; t < nt; ++t) {
        if (m.texelMetres[t] <= 0.0f) continue;
        const std::uint32_t r = uf.find(std::uint32_t(t));
        if (faceOfRoot[r] < 0) {
            faceOfRoot[r] = std::int32_t(faces.size());
            faces.emplace_back();
            faces.back().texel = m.texelMetres[t];
        }
        Face& f = faces[std::size_t(faceOfRoot[r])];
        f.triangles.push_back(std::uint32_t(t));
        f.normal += tf.area[t] * tf.normal[t];
        f.area += tf.area[t];
        f.texel = std::min(f.texel, double(m.texelMetres[t]));
        faceOf[t] = faceOfRoot[r];
    }
    for (Face& f : faces) f.normal = glm::length(f.normal) > 1e-15 ? glm::normalize(f.normal) : glm::dvec3(0, 1, 0);
    return faces;
}

// A face that fills little of its rectangle (a ring: a wall's cap around a footprint) goes back
// to its patches, which then unfold one by one onto their neighbours.
void splitSparseFaces(const ChartMesh& m, std::vector<Face>& faces, UnionFind& patches, const TriangleFrames& tf,
                      std::vector<std::int32_t>& faceOf) {
    std::vector<Face> kept;
    for (Face& f : faces) {
        glm::dvec3 e1, e2;
        planeAxes(f.normal, e1, e2);
        std::vector<glm::dvec2> pts;
        for (std::uint32_t t : f.triangles)
            for (int k = 0; k < 3; ++k) pts.emplace_back(glm::dot(at(m, t, k), e1), glm::dot(at(m, t, k), e2));
        const std::vector<glm::dvec2> hull = convexHull(pts);
        const double angle = minAreaRectAngle(hull);
        const double c = std::cos(angle), sn = std::sin(angle);
        glm::dvec2 lo(INFINITY), hi(-INFINITY);
        for (const glm::dvec2& p : hull) {
            const glm::dvec2 q(c * p.x + sn * p.y, -sn * p.x + c * p.y);
            lo = glm::min(lo, q), hi = glm::max(hi, q);
        }
        const double rect = (hi.x - lo.x + 2.0 * f.texel) * (hi.y - lo.y + 2.0 * f.texel);
        if (f.area >= kMinChartFill * rect) {
            kept.push_back(std::move(f));
            continue;
        }
        std::map<std::uint32_t, Face> parts;
        for (std::uint32_t t : f.triangles) {
            Face& p = parts[patches.find(t)];
            p.triangles.push_back(t);
            p.normal = f.normal;
            p.area += tf.area[t];
            p.texel = f.texel;
        }
        for (auto& [root, p] : parts) kept.push_back(std::move(p));
    }
    std::sort(kept.begin(), kept.end(), [](const Face& a, const Face& b) { return a.triangles.front() < b.triangles.front(); });
    faces = std::move(kept);
    for (std::size_t fi = 0; fi < faces.size(); ++fi)
        for (std::uint32_t t : faces[fi].triangles) faceOf[t] = std::int32_t(fi);
}

// Faces meeting along a manifold edge, both ways, sorted, one entry per pair.
std::vector<Adjacency> faceAdjacency(const std::vector<Edge>& edges, const std::vector<std::int32_t>& faceOf) {
    std::vector<Adjacency> adjacency;
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        while (j < edges.size() && sameEdge(edges[j], edges[i])) ++j;
        if (j - i == 2) {
            const std::uint32_t f = std::uint32_t(faceOf[edges[i].tri]), g = std::uint32_t(faceOf[edges[i + 1].tri]);
            if (f != g) {
                adjacency.push_back({f, g, edges[i].a, edges[i].b});
                adjacency.push_back({g, f, edges[i].a, edges[i].b});
            }
        }
        i = j;
    }
    std::sort(adjacency.begin(), adjacency.end(), [](const Adjacency& x, const Adjacency& y) {
        return std::tie(x.face, x.other, x.a, x.b) < std::tie(y.face, y.other, y.a, y.b);
    });
    adjacency.erase(std::unique(adjacency.begin(), adjacency.end(),
                                [](const Adjacency& x, const Adjacency& y) { return x.face == y.face && x.other == y.other; }),
                    adjacency.end());
    return adjacency;
}

// Faces larger than a chart: cut into cells of patches, each its own chart (appended to
// `charts`); returns which faces were cut. Throws InputError for one polygon larger than a chart.
std::vector<std::uint8_t> cutOversizeFaces(const ChartMesh& m, const std::vector<Face>& faces, UnionFind& patches,
                                           std::vector<Chart>& charts) {
    std::vector<std::uint8_t> oversize(faces.size(), 0);
    for (std::size_t fi = 0; fi < faces.size(); ++fi) {
        const Face& f = faces[fi];
        glm::dvec3 e1, e2;
        planeAxes(f.normal, e1, e2);
        const glm::dvec3 o = at(m, f.triangles.front(), 0);
        glm::dvec2 lo(INFINITY), hi(-INFINITY);
        for (std::uint32_t t : f.triangles)
            for (int k = 0; k < 3; ++k) {
                const glm::dvec3 d = at(m, t, k) - o;
                const glm::dvec2 q(glm::dot(d, e1), glm::dot(d, e2));
                lo = glm::min(lo, q), hi = glm::max(hi, q);
            }
        if ((hi.x - lo.x) / f.texel <= kMaxChartTexels && (hi.y - lo.y) / f.texel <= kMaxChartTexels) continue;
        oversize[fi] = 1;
        const double cell = 0.9 * kMaxChartTexels * f.texel;
        std::map<std::pair<long long, long long>, std::vector<std::uint32_t>> cells;
        for (std::uint32_t t : f.triangles) {
            const glm::dvec3 d = at(m, patches.find(t), 0) - o;  // a patch goes where its first corner is
            const glm::dvec2 q = (glm::dvec2(glm::dot(d, e1), glm::dot(d, e2)) - lo) / cell;
            cells[{std::llround(std::floor(q.y)), std::llround(std::floor(q.x))}].push_back(t);
        }
        for (auto& [key, part] : cells) {
            std::sort(part.begin(), part.end());
            std::vector<glm::dvec2> corners;
            for (std::uint32_t t : part)
                for (int k = 0; k < 3; ++k) {
                    const glm::dvec3 d = at(m, t, k) - o;
                    corners.emplace_back(glm::dot(d, e1) / f.texel, glm::dot(d, e2) / f.texel);
                }
            Chart c = finishChart(std::move(part), std::move(corners), f.texel);
            if (c.size.x > kMaxChartTexels + 4 * kChartAlign || c.size.y > kMaxChartTexels + 4 * kChartAlign)
                throw InputError(format("a polygon spans {} x {} texels of {} m, more than a lightmap chart can hold ({})",
                                        c.size.x, c.size.y, f.texel, kMaxChartTexels));
            charts.push_back(std::move(c));
        }
    }
    return oversize;
}

}  // namespace

ChartSet makeCharts(const ChartMesh& m) {
    DAWNFORGE_ASSERT(m.indices.size() % 3 == 0, "makeCharts(): three indices per triangle");
    const std::size_t nt = m.indices.size() / 3;
    DAWNFORGE_ASSERT(m.texelMetres.size() == nt, "makeCharts(): one texel size per triangle");
    const TriangleFrames tf = triangleFrames(m, nt);
    UnionFind patches = patchesOf(m, nt);
    const std::vector<std::uint32_t> canonical = weld(m.positions);
    const std::vector<Edge> edges = sortedEdges(m, nt, canonical, tf);
    std::vector<std::int32_t> faceOf;
    std::vector<Face> faces = planarFaces(m, nt, edges, patches, tf, faceOf);
    splitSparseFaces(m, faces, patches, tf, faceOf);
    const std::vector<Adjacency> adjacency = faceAdjacency(edges, faceOf);

    ChartSet set;
    set.chartOf.assign(nt, -1);
    const std::vector<std::uint8_t> oversize = cutOversizeFaces(m, faces, patches, set.charts);
    // Everything else grows by unfolding, largest faces first; oversized faces never join a chart.
    std::vector<std::uint32_t> order;
    for (std::uint32_t fi = 0; fi < faces.size(); ++fi)
        if (!oversize[fi]) order.push_back(fi);
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        return faces[a].area != faces[b].area ? faces[a].area > faces[b].area : a < b;
    });
    std::vector<Adjacency> growable;
    for (const Adjacency& a : adjacency)
        if (!oversize[a.face] && !oversize[a.other]) growable.push_back(a);
    ChartGrower grower(m, faces, growable, faceOf, canonical);
    for (std::uint32_t fi : order) {
        if (grower.placed(fi)) continue;
        auto [tris, corners] = grower.grow(fi);
        set.charts.push_back(finishChart(std::move(tris), std::move(corners), faces[fi].texel));
    }
    std::sort(set.charts.begin(), set.charts.end(), [](const Chart& a, const Chart& b) { return a.triangles.front() < b.triangles.front(); });
    for (std::size_t c = 0; c < set.charts.size(); ++c) {
        for (std::uint32_t t : set.charts[c].triangles) set.chartOf[t] = std::int32_t(c);
        set.blockTexels += std::size_t(set.charts[c].size.x) * std::size_t(set.charts[c].size.y);
        set.largestBlock = glm::max(set.largestBlock, set.charts[c].size);
    }
    return set;
}

namespace {

// Skyline bottom-left packing in units of kChartAlign texels. Returns the height used, or -1
// when a block is wider than the atlas.
int skylinePack(int width, std::span<const glm::ivec2> sizes, std::span<const std::size_t> order, std::vector<glm::ivec2>& origins) {
    const int wu = width / kChartAlign;
    std::vector<int> heights(std::size_t(wu), 0);
    int top = 0;
    origins.assign(sizes.size(), glm::ivec2(0));
    for (std::size_t idx : order) {
        const int bw = sizes[idx].x / kChartAlign, bh = sizes[idx].y / kChartAlign;
        if (bw > wu) return -1;
        // Sliding-window maximum of the skyline over bw columns: the lowest place, leftmost on ties.
        std::deque<int> window;
        int bestX = 0, bestY = INT32_MAX;
        for (int x = 0; x < wu; ++x) {
            while (!window.empty() && heights[std::size_t(window.back())] <= heights[std::size_t(x)]) window.pop_back();
            window.push_back(x);
            if (window.front() <= x - bw) window.pop_front();
            if (x >= bw - 1) {
                const int y = heights[std::size_t(window.front())];
                if (y < bestY) bestY = y, bestX = x - bw + 1;
            }
        }
        for (int x = bestX; x < bestX + bw; ++x) heights[std::size_t(x)] = bestY + bh;
        origins[idx] = glm::ivec2(bestX, bestY) * kChartAlign;
        top = std::max(top, (bestY + bh) * kChartAlign);
    }
    return top;
}

}  // namespace

LightmapLayout packLightmap(const ChartMesh& m, ChartSet set, std::span<const glm::ivec2> extraBlocks, const std::string& name) {
    LightmapLayout layout;
    layout.chartOf = std::move(set.chartOf);
    layout.charts = std::move(set.charts);
    std::vector<glm::ivec2> sizes;
    for (const Chart& c : layout.charts) sizes.push_back(c.size);
    for (glm::ivec2 e : extraBlocks) {
        DAWNFORGE_ASSERT(e.x % kChartAlign == 0 && e.y % kChartAlign == 0 && e.x > 0 && e.y > 0, "extra blocks are multiples of kChartAlign");
        sizes.push_back(e);
    }
    std::vector<std::size_t> order(sizes.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return std::tie(sizes[b].y, sizes[b].x, a) < std::tie(sizes[a].y, sizes[a].x, b);
    });
    double area = 0.0;
    int widest = kChartAlign;
    for (glm::ivec2 s : sizes) area += double(s.x) * double(s.y), widest = std::max(widest, s.x);
    int width = std::max(widest, roundUp(int(std::ceil(std::sqrt(area * 1.1))), 16));
    std::vector<glm::ivec2> origins;
    int height = sizes.empty() ? kChartAlign : 0;
    for (int attempt = 0; !sizes.empty(); ++attempt) {
        height = skylinePack(width, sizes, order, origins);
        // Keep atlases roughly square: widen and pack again when much taller than wide.
        if (height <= width + width / 2 || attempt == 4 || width >= kMaxLightmapSize) break;
        width = std::min(kMaxLightmapSize, roundUp(int(width * 1.25), 16));
    }
    if (width > kMaxLightmapSize || height > kMaxLightmapSize)
        throw InputError(format("{}: its lightmap would be {} x {} texels, more than {} on a side", name, width, height,
                                kMaxLightmapSize));
    layout.size = {width, std::max(height, kChartAlign)};
    for (std::size_t c = 0; c < layout.charts.size(); ++c) {
        layout.charts[c].origin = origins[c];
        for (glm::dvec2& p : layout.charts[c].corners) p += glm::dvec2(origins[c]);
    }
    for (std::size_t e = 0; e < extraBlocks.size(); ++e) {
        layout.extraOrigins.push_back(origins[layout.charts.size() + e]);
        layout.extraSizes.push_back(extraBlocks[e]);
    }
    // Vertex UVs from their triangles' charts; vertices of no chart stay at (0, 0).
    layout.uv.assign(m.positions.size(), glm::vec2(0.0f));
    std::vector<std::int32_t> vertexChart(m.positions.size(), -1);
    for (std::size_t c = 0; c < layout.charts.size(); ++c) {
        const Chart& chart = layout.charts[c];
        for (std::size_t i = 0; i < chart.triangles.size(); ++i)
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t v = m.indices[3 * std::size_t(chart.triangles[i]) + std::size_t(k)];
                if (vertexChart[v] == -1) {
                    vertexChart[v] = std::int32_t(c);
                    layout.uv[v] = glm::vec2(chart.corners[3 * i + std::size_t(k)]);
                } else if (vertexChart[v] != std::int32_t(c)) {
                    ++layout.conflictingVertices;
                }
            }
    }
    return layout;
}

std::vector<std::int32_t> blockOwners(const LightmapLayout& layout) {
    std::vector<std::int32_t> owner(std::size_t(layout.size.x) * std::size_t(layout.size.y), kUnowned);
    const auto fill = [&](glm::ivec2 origin, glm::ivec2 size, std::int32_t id) {
        for (int y = origin.y; y < origin.y + size.y; ++y)
            for (int x = origin.x; x < origin.x + size.x; ++x) owner[std::size_t(y) * std::size_t(layout.size.x) + std::size_t(x)] = id;
    };
    for (std::size_t c = 0; c < layout.charts.size(); ++c) fill(layout.charts[c].origin, layout.charts[c].size, std::int32_t(c));
    for (std::size_t e = 0; e < layout.extraOrigins.size(); ++e) fill(layout.extraOrigins[e], layout.extraSizes[e], kExtraBlock + std::int32_t(e));
    return owner;
}

namespace {

// The point of triangle abc nearest to p (2D), as barycentrics (wa, wb, wc). Ericson,
// Real-Time Collision Detection, 5.1.5.
glm::dvec3 closestBarycentric(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
    const glm::dvec2 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return {1, 0, 0};
    const glm::dvec2 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return {0, 1, 0};
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        const double v = d1 / (d1 - d3);
        return {1 - v, v, 0};
    }
    const glm::dvec2 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return {0, 0, 1};
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        const double w = d2 / (d2 - d6);
        return {1 - w, 0, w};
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return {0, 1 - w, w};
    }
    const double denom = 1.0 / (va + vb + vc);
    const double v = vb * denom, w = vc * denom;
    return {1 - v - w, v, w};
}

}  // namespace

std::vector<TexelSample> sampleTexels(const ChartMesh& m, const LightmapLayout& layout) {
    constexpr double kReach = 0.70711;  // half a texel's diagonal
    std::vector<TexelSample> out;
    struct Best {
        double distance = INFINITY;
        std::uint32_t triangle = 0;
        glm::dvec3 bary{0.0};
    };
    std::vector<Best> best;
    for (const Chart& chart : layout.charts) {
        best.assign(std::size_t(chart.size.x) * std::size_t(chart.size.y), Best{});
        for (std::size_t i = 0; i < chart.triangles.size(); ++i) {
            const std::uint32_t t = chart.triangles[i];
            const glm::dvec2 a = chart.corners[3 * i], b = chart.corners[3 * i + 1], c = chart.corners[3 * i + 2];
            if (std::abs(cross2(b - a, c - a)) < 1e-12) continue;  // no area
            const glm::dvec2 lo = glm::min(a, glm::min(b, c)) - kReach, hi = glm::max(a, glm::max(b, c)) + kReach;
            const int x0 = std::max(chart.origin.x, int(std::floor(lo.x))), x1 = std::min(chart.origin.x + chart.size.x - 1, int(std::floor(hi.x)));
            const int y0 = std::max(chart.origin.y, int(std::floor(lo.y))), y1 = std::min(chart.origin.y + chart.size.y - 1, int(std::floor(hi.y)));
            for (int y = y0; y <= y1; ++y)
                for (int x = x0; x <= x1; ++x) {
                    const glm::dvec2 centre(x + 0.5, y + 0.5);
                    const glm::dvec3 w = closestBarycentric(centre, a, b, c);
                    const double d = glm::length(w.x * a + w.y * b + w.z * c - centre);
                    if (d > kReach) continue;
                    Best& slot = best[std::size_t(y - chart.origin.y) * std::size_t(chart.size.x) + std::size_t(x - chart.origin.x)];
                    if (d < slot.distance) slot = {d, t, w};  // triangles come in increasing order: ties keep the first
                }
        }
        for (int y = 0; y < chart.size.y; ++y)
            for (int x = 0; x < chart.size.x; ++x) {
                const Best& b = best[std::size_t(y) * std::size_t(chart.size.x) + std::size_t(x)];
                if (!std::isfinite(b.distance)) continue;
                TexelSample s;
                s.texel = std::uint32_t(chart.origin.y + y) * std::uint32_t(layout.size.x) + std::uint32_t(chart.origin.x + x);
                s.triangle = b.triangle;
                s.position = glm::vec3(b.bary.x * at(m, b.triangle, 0) + b.bary.y * at(m, b.triangle, 1) + b.bary.z * at(m, b.triangle, 2));
                const glm::dvec3 n = glm::cross(at(m, b.triangle, 1) - at(m, b.triangle, 0), at(m, b.triangle, 2) - at(m, b.triangle, 0));
                s.normal = glm::vec3(glm::normalize(n));
                out.push_back(s);
            }
    }
    return out;
}

}  // namespace dawnforge::bake
