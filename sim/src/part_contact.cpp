#include "part_contact.hpp"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>

namespace dawnforge::sim::detail {

namespace {

struct Triangle {
    std::uint32_t part = 0;
    std::array<glm::dvec3, 3> p;
    glm::dvec3 normal{0.0};  // unit
    glm::dvec3 lo{0.0}, hi{0.0};
};

using Polygon = std::vector<glm::dvec2>;

double cross2(glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; }

double area2(const Polygon& p) {
    double s = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) s += cross2(p[i], p[(i + 1) % p.size()]);
    return 0.5 * s;
}

// The part of convex `subject` inside convex, counter-clockwise `clip` (Sutherland–Hodgman).
Polygon clipConvex(Polygon subject, const Polygon& clip) {
    for (std::size_t e = 0; e < clip.size() && !subject.empty(); ++e) {
        const glm::dvec2 a = clip[e], b = clip[(e + 1) % clip.size()];
        Polygon out;
        for (std::size_t i = 0; i < subject.size(); ++i) {
            const glm::dvec2 s = subject[i], t = subject[(i + 1) % subject.size()];
            const double ds = cross2(b - a, s - a), dt = cross2(b - a, t - a);
            if (ds >= 0.0) out.push_back(s);
            if ((ds >= 0.0) != (dt >= 0.0)) out.push_back(s + (t - s) * (ds / (ds - dt)));
        }
        subject = std::move(out);
    }
    return subject;
}

// Whether u lies on t's plane facing it and overlaps it by more than minArea.
bool touching(const Triangle& t, const Triangle& u, double distance, double minArea) {
    if (glm::dot(t.normal, u.normal) > -0.999) return false;
    for (const glm::dvec3& q : u.p)
        if (std::abs(glm::dot(q - t.p[0], t.normal)) > distance) return false;
    for (const glm::dvec3& q : t.p)
        if (std::abs(glm::dot(q - u.p[0], u.normal)) > distance) return false;
    const glm::dvec3 axis = std::abs(t.normal.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 e1 = glm::normalize(glm::cross(axis, t.normal)), e2 = glm::cross(t.normal, e1);
    auto flat = [&](const Triangle& x) {
        Polygon poly;
        for (const glm::dvec3& q : x.p) poly.push_back({glm::dot(q, e1), glm::dot(q, e2)});
        if (area2(poly) < 0.0) std::swap(poly[1], poly[2]);
        return poly;
    };
    const Polygon shared = clipConvex(flat(u), flat(t));
    return shared.size() >= 3 && area2(shared) > minArea;
}

}  // namespace

PartContacts partContacts(std::span<const Mesh* const> parts, double distance, double minArea) {
    std::vector<Triangle> tris;
    std::vector<std::size_t> first(parts.size() + 1, 0);
    glm::dvec3 lo(INFINITY), hi(-INFINITY);
    for (std::size_t i = 0; i < parts.size(); ++i) {
        const Mesh& m = *parts[i];
        first[i] = tris.size();
        for (std::size_t t = 0; t < m.triangleCount(); ++t) {
            Triangle tri;
            tri.part = std::uint32_t(i);
            for (std::size_t k = 0; k < 3; ++k) tri.p[k] = glm::dvec3(m.positions[m.indices[3 * t + k]]);
            const glm::dvec3 n = glm::cross(tri.p[1] - tri.p[0], tri.p[2] - tri.p[0]);
            tri.normal = glm::length(n) > 0.0 ? n / glm::length(n) : glm::dvec3(0.0);
            tri.lo = glm::min(tri.p[0], glm::min(tri.p[1], tri.p[2])) - distance;
            tri.hi = glm::max(tri.p[0], glm::max(tri.p[1], tri.p[2])) + distance;
            lo = glm::min(lo, tri.lo);
            hi = glm::max(hi, tri.hi);
            tris.push_back(tri);
        }
    }
    first[parts.size()] = tris.size();
    PartContacts out;
    out.planes.resize(parts.size());
    for (std::size_t i = 0; i < parts.size(); ++i) out.planes[i].assign(parts[i]->triangleCount(), kSurface);
    if (tris.empty()) return out;

    // Candidates through a uniform grid of about 1 m cells over the bounds.
    const glm::dvec3 extent = glm::max(hi - lo, glm::dvec3(1e-9));
    const glm::ivec3 n = glm::clamp(glm::ivec3(glm::ceil(extent / 1.0)), glm::ivec3(1), glm::ivec3(256));
    const glm::dvec3 cell = extent / glm::dvec3(n);
    auto cellOf = [&](const glm::dvec3& p) { return glm::clamp(glm::ivec3((p - lo) / cell), glm::ivec3(0), n - 1); };
    std::map<std::int64_t, std::vector<std::uint32_t>> buckets;
    auto key = [&](int x, int y, int z) { return (std::int64_t(z) * n.y + y) * n.x + x; };
    for (std::uint32_t k = 0; k < tris.size(); ++k) {
        const glm::ivec3 a = cellOf(tris[k].lo), b = cellOf(tris[k].hi);
        for (int z = a.z; z <= b.z; ++z)
            for (int y = a.y; y <= b.y; ++y)
                for (int x = a.x; x <= b.x; ++x) buckets[key(x, y, z)].push_back(k);
    }

    // Groups: union-find over touching triangles, the smallest index the representative.
    std::vector<std::uint32_t> parent(tris.size());
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    std::vector<char> touches(tris.size(), 0);
    std::vector<std::uint32_t> seen(tris.size(), UINT32_MAX);
    for (std::uint32_t k = 0; k < tris.size(); ++k) {
        const Triangle& t = tris[k];
        if (t.normal == glm::dvec3(0.0)) continue;
        const glm::ivec3 a = cellOf(t.lo), b = cellOf(t.hi);
        for (int z = a.z; z <= b.z; ++z)
            for (int y = a.y; y <= b.y; ++y)
                for (int x = a.x; x <= b.x; ++x) {
                    const auto it = buckets.find(key(x, y, z));
                    if (it == buckets.end()) continue;
                    for (std::uint32_t m : it->second) {
                        const Triangle& u = tris[m];
                        if (u.part <= t.part || seen[m] == k || u.normal == glm::dvec3(0.0)) continue;
                        seen[m] = k;
                        if (glm::any(glm::lessThan(u.hi, t.lo)) || glm::any(glm::lessThan(t.hi, u.lo))) continue;
                        if (!touching(t, u, distance, minArea)) continue;
                        touches[k] = touches[m] = 1;
                        const std::uint32_t ra = find(k), rb = find(m);
                        if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
                    }
                }
    }
    for (std::size_t i = 0; i < parts.size(); ++i)
        for (std::size_t t = first[i]; t < first[i + 1]; ++t) {
            if (!touches[t]) continue;
            const std::uint32_t root = find(std::uint32_t(t));
            if (root == t) ++out.groups;
            out.planes[i][t - first[i]] = contactKey(std::int64_t(root));
        }
    return out;
}

}  // namespace dawnforge::sim::detail
