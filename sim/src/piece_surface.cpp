#include "piece_surface.hpp"

#include <dawnforge/core/union_find.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <map>
#include <utility>

namespace dawnforge::sim::detail {

namespace {

using Edge = std::pair<std::uint32_t, std::uint32_t>;  // directed

// Grid coordinates are at most 2^25 apart, so these products (2^50) and sums are exact.
glm::i64vec3 cross(const glm::i64vec3& a, const glm::i64vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
std::int64_t dot(const glm::i64vec3& a, const glm::i64vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

bool flat(std::span<const glm::i64vec3> p, const GridTriangle& t) {
    return cross(p[t.v[1]] - p[t.v[0]], p[t.v[2]] - p[t.v[0]]) == glm::i64vec3(0);
}

// The triangle rotated so that its corner `first` comes first (the cyclic order is kept).
GridTriangle startingAt(GridTriangle t, int first) {
    std::rotate(t.v.begin(), t.v.begin() + first, t.v.end());
    std::rotate(t.attr.begin(), t.attr.begin() + first, t.attr.end());
    return t;
}

// Flips every zero-area triangle away into the neighbour across the edge that holds its
// middle corner. A flip can make a new flat triangle (when d is on the line too): the work
// list takes it again; a bound stops a cycle.
void flipFlatTriangles(std::span<const glm::i64vec3> p, std::vector<GridTriangle>& tris, CleanSurface& out) {
    std::vector<char> alive(tris.size(), 1);
    std::map<Edge, std::size_t> edgeOf;
    auto index = [&](std::size_t i) {
        for (int k = 0; k < 3; ++k) edgeOf[{tris[i].v[k], tris[i].v[(k + 1) % 3]}] = i;
    };
    auto unindex = [&](std::size_t i) {
        for (int k = 0; k < 3; ++k) {
            const auto it = edgeOf.find({tris[i].v[k], tris[i].v[(k + 1) % 3]});
            if (it != edgeOf.end() && it->second == i) edgeOf.erase(it);
        }
    };
    std::vector<std::size_t> work;
    for (std::size_t i = 0; i < tris.size(); ++i) {
        index(i);
        if (flat(p, tris[i])) work.push_back(i);
    }
    std::reverse(work.begin(), work.end());
    for (std::size_t steps = 0; !work.empty() && steps < 8 * tris.size() + 64; ++steps) {
        const std::size_t i = work.back();
        work.pop_back();
        if (!alive[i] || !flat(p, tris[i])) continue;
        // The corner strictly between the other two: t = (a, b, c) with c on ab.
        int middle = 0;
        for (int k = 0; k < 3; ++k) {
            const glm::i64vec3 c = p[tris[i].v[k]];
            if (dot(p[tris[i].v[(k + 1) % 3]] - c, p[tris[i].v[(k + 2) % 3]] - c) < 0) middle = k;
        }
        const GridTriangle t = startingAt(tris[i], (middle + 1) % 3);  // (a, b, c)
        const auto across = edgeOf.find({t.v[1], t.v[0]});
        if (across == edgeOf.end() || !alive[across->second]) continue;
        const std::size_t j = across->second;
        int at = 0;
        while (tris[j].v[at] != t.v[1]) ++at;
        const GridTriangle n = startingAt(tris[j], at);  // (b, a, d)
        unindex(i);
        unindex(j);
        alive[i] = 0;
        // c's attributes in the neighbour's face: along its edge from a to b.
        const glm::i64vec3 ab = p[t.v[1]] - p[t.v[0]], ac = p[t.v[2]] - p[t.v[0]];
        out.derived.push_back({n.attr[1], n.attr[0], double(dot(ac, ab)) / double(dot(ab, ab))});
        const std::uint32_t c = kDerived | std::uint32_t(out.derived.size() - 1);
        tris[j] = {{n.v[0], t.v[2], n.v[2]}, n.origin, {n.attr[0], c, n.attr[2]}};         // (b, c, d)
        tris.push_back({{t.v[2], n.v[1], n.v[2]}, n.origin, {c, n.attr[1], n.attr[2]}});  // (c, a, d)
        alive.push_back(1);
        index(j);
        index(tris.size() - 1);
        work.push_back(j);
        work.push_back(tris.size() - 1);
        ++out.flattened;
    }
    std::vector<GridTriangle> kept;
    for (std::size_t i = 0; i < tris.size(); ++i)
        if (alive[i]) {
            if (flat(p, tris[i])) ++out.unmended;
            kept.push_back(tris[i]);
        }
    tris = std::move(kept);
}

bool walks(const GridTriangle& t, std::uint32_t from, std::uint32_t to) {
    for (int k = 0; k < 3; ++k)
        if (t.v[k] == from && t.v[(k + 1) % 3] == to) return true;
    return false;
}

// Two triangles on the same three points, facing opposite ways, enclose nothing: a sliver
// that rounding flattened. Both go; every edge they used keeps one use in each direction.
void cancelOppositePairs(std::vector<GridTriangle>& tris, CleanSurface& out) {
    std::map<std::array<std::uint32_t, 3>, std::vector<std::size_t>> bySet;
    for (std::size_t i = 0; i < tris.size(); ++i) {
        std::array<std::uint32_t, 3> key = tris[i].v;
        std::sort(key.begin(), key.end());
        bySet[key].push_back(i);
    }
    std::vector<char> gone(tris.size(), 0);
    for (const auto& [key, list] : bySet)
        for (std::size_t a = 0; a < list.size(); ++a)
            for (std::size_t b = a + 1; b < list.size(); ++b) {
                const GridTriangle &s = tris[list[a]], &t = tris[list[b]];
                if (gone[list[a]] || gone[list[b]] || !walks(t, s.v[1], s.v[0])) continue;
                gone[list[a]] = gone[list[b]] = 1;
                out.cancelled += 2;
            }
    std::vector<GridTriangle> kept;
    for (std::size_t i = 0; i < tris.size(); ++i)
        if (!gone[i]) kept.push_back(tris[i]);
    tris = std::move(kept);
}

// Shells: triangles joined across edges used once in each direction and by nothing else.
std::vector<std::vector<std::uint32_t>> shells(const std::vector<GridTriangle>& tris) {
    std::map<Edge, std::vector<std::uint32_t>> users;  // undirected edge (low, high) -> triangles
    for (std::uint32_t i = 0; i < tris.size(); ++i)
        for (int k = 0; k < 3; ++k) users[std::minmax(tris[i].v[k], tris[i].v[(k + 1) % 3])].push_back(i);
    UnionFind sets(tris.size());
    for (const auto& [edge, list] : users) {
        if (list.size() != 2) continue;
        const GridTriangle &s = tris[list[0]], &t = tris[list[1]];
        const auto [a, b] = edge;  // s walks it one way, t the other
        if ((walks(s, a, b) && walks(t, b, a)) || (walks(s, b, a) && walks(t, a, b))) sets.unite(list[0], list[1]);
    }
    std::map<std::uint32_t, std::vector<std::uint32_t>> byRoot;
    for (std::uint32_t i = 0; i < tris.size(); ++i) byRoot[sets.find(i)].push_back(i);
    std::vector<std::vector<std::uint32_t>> out;
    for (auto& [root, list] : byRoot) out.push_back(std::move(list));
    return out;
}

// Six times the signed volume enclosed, about the shell's first corner (for precision); used
// for its sign and to compare shells, which real shells are far enough from zero to allow.
double volume6(std::span<const glm::i64vec3> p, const std::vector<GridTriangle>& tris,
               const std::vector<std::uint32_t>& shell) {
    const glm::i64vec3 o = p[tris[shell.front()].v[0]];
    double v = 0.0;
    for (std::uint32_t i : shell) {
        const glm::dvec3 a(p[tris[i].v[0]] - o), b(p[tris[i].v[1]] - o), c(p[tris[i].v[2]] - o);
        v += glm::dot(a, glm::cross(b, c));
    }
    return v;
}

// Whether `q` is inside the closed shell: crossings of a ray in an odd direction, so that it
// meets no edge or vertex of a grid-aligned surface by accident.
bool encloses(std::span<const glm::i64vec3> p, const std::vector<GridTriangle>& tris,
              const std::vector<std::uint32_t>& shell, const glm::dvec3& q) {
    const glm::dvec3 dir = glm::normalize(glm::dvec3(0.5773502691896257, 0.5773502691896258 + 1e-7, 0.5773502691896259 - 2e-7));
    int crossings = 0;
    for (std::uint32_t i : shell) {
        const glm::dvec3 a(p[tris[i].v[0]]), b(p[tris[i].v[1]]), c(p[tris[i].v[2]]);
        const glm::dvec3 e1 = b - a, e2 = c - a, h = glm::cross(dir, e2);
        const double det = glm::dot(e1, h);
        if (det == 0.0) continue;
        const glm::dvec3 s = q - a;
        const double u = glm::dot(s, h) / det;
        const glm::dvec3 qq = glm::cross(s, e1);
        const double v = glm::dot(dir, qq) / det;
        if (u < 0.0 || v < 0.0 || u + v > 1.0) continue;
        if (glm::dot(e2, qq) / det > 0.0) ++crossings;
    }
    return crossings % 2 == 1;
}

glm::i64vec3 smallestPoint(std::span<const glm::i64vec3> p, const std::vector<GridTriangle>& part) {
    glm::i64vec3 m = p[part.front().v[0]];
    auto less = [](const glm::i64vec3& a, const glm::i64vec3& b) {
        return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
    };
    for (const GridTriangle& t : part)
        for (std::uint32_t v : t.v) m = std::min(m, p[v], less);
    return m;
}

// Outward shells are parts; each inward shell joins the smallest outward shell that encloses it.
std::vector<std::vector<GridTriangle>> groupShells(std::span<const glm::i64vec3> p, const std::vector<GridTriangle>& tris) {
    const std::vector<std::vector<std::uint32_t>> all = shells(tris);
    std::vector<std::size_t> outward, inward;
    std::vector<double> volumes;
    for (std::size_t s = 0; s < all.size(); ++s) {
        volumes.push_back(volume6(p, tris, all[s]));
        (volumes.back() > 0.0 ? outward : inward).push_back(s);
    }
    std::vector<std::vector<std::uint32_t>> members(all.size());
    for (std::size_t s : outward) members[s] = all[s];
    for (std::size_t s : inward) {
        const glm::dvec3 q(p[tris[all[s].front()].v[0]]);
        std::size_t host = outward.empty() ? s : outward.front();
        double best = -1.0;
        for (std::size_t o : outward)
            if ((best < 0.0 || volumes[o] < best) && (outward.size() == 1 || encloses(p, tris, all[o], q))) {
                host = o;
                best = volumes[o];
            }
        members[host].insert(members[host].end(), all[s].begin(), all[s].end());
    }
    std::vector<std::vector<GridTriangle>> parts;
    for (std::vector<std::uint32_t>& m : members) {
        if (m.empty()) continue;
        std::sort(m.begin(), m.end());
        parts.emplace_back();
        for (std::uint32_t i : m) parts.back().push_back(tris[i]);
    }
    std::sort(parts.begin(), parts.end(), [&](const auto& a, const auto& b) {
        const glm::i64vec3 x = smallestPoint(p, a), y = smallestPoint(p, b);
        return std::tie(x.x, x.y, x.z) < std::tie(y.x, y.y, y.z);
    });
    return parts;
}

}  // namespace

CleanSurface cleanSurface(std::span<const glm::i64vec3> points, std::vector<GridTriangle> triangles) {
    CleanSurface out;
    std::erase_if(triangles, [&](const GridTriangle& t) {
        const bool collapsed = t.v[0] == t.v[1] || t.v[1] == t.v[2] || t.v[0] == t.v[2];
        out.collapsed += collapsed;
        return collapsed;
    });
    flipFlatTriangles(points, triangles, out);
    cancelOppositePairs(triangles, out);
    if (!triangles.empty()) out.parts = groupShells(points, triangles);
    return out;
}

}  // namespace dawnforge::sim::detail
