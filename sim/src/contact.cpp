#include "contact.hpp"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

namespace dawnforge::sim::detail {

namespace {

using Polygon = std::vector<glm::dvec2>;

glm::dvec3 normalOf(const CutFace& f) { return glm::cross(f.b - f.a, f.c - f.a); }  // length: twice the area

double cross2(glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; }

double signedArea(const Polygon& p) {
    double s = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) s += cross2(p[i], p[(i + 1) % p.size()]);
    return 0.5 * s;
}

// The part of convex `subject` inside the convex, counter-clockwise `clip` (Sutherland–Hodgman).
Polygon clipConvex(Polygon subject, const Polygon& clip) {
    for (std::size_t e = 0; e < clip.size() && !subject.empty(); ++e) {
        const glm::dvec2 p = clip[e], q = clip[(e + 1) % clip.size()];
        auto side = [&](glm::dvec2 x) { return cross2(q - p, x - p); };
        Polygon out;
        for (std::size_t i = 0; i < subject.size(); ++i) {
            const glm::dvec2 s = subject[i], t = subject[(i + 1) % subject.size()];
            const double ds = side(s), dt = side(t);
            if (ds >= 0.0) out.push_back(s);
            if ((ds >= 0.0) != (dt >= 0.0)) out.push_back(s + (t - s) * (ds / (ds - dt)));
        }
        subject = std::move(out);
    }
    return subject;
}

// A plane's faces seen along the axis its normals point most along, counter-clockwise.
struct Projection {
    int drop = 0;
    double lift = 1.0;  // 3D area per projected area
    glm::dvec2 operator()(const glm::dvec3& p) const {
        return drop == 0 ? glm::dvec2(p.y, p.z) : drop == 1 ? glm::dvec2(p.z, p.x) : glm::dvec2(p.x, p.y);
    }
    Polygon triangle(const CutFace& f) const {
        Polygon t{(*this)(f.a), (*this)(f.b), (*this)(f.c)};
        if (signedArea(t) < 0.0) std::swap(t[1], t[2]);
        return t;
    }
};

Projection projectionOf(std::span<const CutFace> faces, const std::vector<std::uint32_t>& group) {
    const glm::dvec3 first = normalOf(faces[group.front()]);
    glm::dvec3 sum(0.0);
    for (std::uint32_t i : group) {
        const glm::dvec3 n = normalOf(faces[i]);
        sum += glm::dot(n, first) >= 0.0 ? n : -n;
    }
    const glm::dvec3 n = glm::length(sum) > 0.0 ? glm::normalize(sum) : glm::dvec3(0, 0, 1);
    Projection proj;
    const glm::dvec3 m = glm::abs(n);
    proj.drop = m.x >= m.y && m.x >= m.z ? 0 : (m.y >= m.z ? 1 : 2);
    proj.lift = 1.0 / m[proj.drop];
    return proj;
}

bool sameCorners(const CutFace& f, const CutFace& g) {
    const std::array<glm::dvec3, 3> x{f.a, f.b, f.c}, y{g.a, g.b, g.c};
    return std::all_of(x.begin(), x.end(), [&](const glm::dvec3& p) { return std::find(y.begin(), y.end(), p) != y.end(); });
}

struct Sum {
    double area = 0.0;
    glm::dvec3 weighted{0.0}, normal{0.0};
};

// Adds what face t (of the lower piece) shares with face u to the pair's sum.
void addOverlap(const CutFace& t, const CutFace& u, const Projection& proj, Sum& sum) {
    const glm::dvec3 n = normalOf(t);
    if (glm::dot(n, normalOf(u)) >= 0.0) return;  // not facing each other
    double area;
    glm::dvec3 centroid;
    if (sameCorners(t, u)) {
        area = 0.5 * glm::length(n);
        centroid = (t.a + t.b + t.c) / 3.0;
    } else {
        const Polygon shared = clipConvex(proj.triangle(t), proj.triangle(u));
        if (shared.size() < 3) return;
        const double a2 = signedArea(shared);
        if (!(a2 > 0.0)) return;
        area = a2 * proj.lift;
        // The centroid of t's own plane point over the shared polygon's centroid.
        glm::dvec2 c2(0.0);
        for (std::size_t i = 0; i < shared.size(); ++i) {
            const glm::dvec2 p = shared[i], q = shared[(i + 1) % shared.size()];
            c2 += (p + q) * cross2(p, q);
        }
        c2 /= 6.0 * a2;
        // Back to 3D on t's plane: solve for the dropped coordinate.
        const int d = proj.drop, u1 = (d + 1) % 3, u2 = (d + 2) % 3;
        centroid[u1] = c2.x;
        centroid[u2] = c2.y;
        centroid[d] = n[d] != 0.0 ? t.a[d] - (n[u1] * (c2.x - t.a[u1]) + n[u2] * (c2.y - t.a[u2])) / n[d] : t.a[d];
    }
    sum.area += area;
    sum.weighted += area * centroid;
    sum.normal += area * glm::normalize(n);
}

// Candidate pairs of one plane through a uniform grid over the projected bounding boxes.
void planeContacts(std::span<const CutFace> faces, const std::vector<std::uint32_t>& group,
                   std::map<std::pair<std::uint32_t, std::uint32_t>, Sum>& sums) {
    const Projection proj = projectionOf(faces, group);
    glm::dvec2 lo(INFINITY), hi(-INFINITY);
    std::vector<std::array<glm::dvec2, 2>> boxes;
    for (std::uint32_t i : group) {
        const Polygon t = proj.triangle(faces[i]);
        const glm::dvec2 l = glm::min(t[0], glm::min(t[1], t[2])), h = glm::max(t[0], glm::max(t[1], t[2]));
        boxes.push_back({l, h});
        lo = glm::min(lo, l);
        hi = glm::max(hi, h);
    }
    const int n = std::clamp(int(std::sqrt(double(group.size()))), 1, 256);
    const glm::dvec2 cell = glm::max((hi - lo) / double(n), glm::dvec2(1e-300));
    auto cellOf = [&](glm::dvec2 p) { return glm::clamp(glm::ivec2((p - lo) / cell), glm::ivec2(0), glm::ivec2(n - 1)); };
    std::vector<std::vector<std::uint32_t>> buckets(std::size_t(n * n));
    for (std::uint32_t k = 0; k < group.size(); ++k) {
        const glm::ivec2 a = cellOf(boxes[k][0]), b = cellOf(boxes[k][1]);
        for (int y = a.y; y <= b.y; ++y)
            for (int x = a.x; x <= b.x; ++x) buckets[std::size_t(y * n + x)].push_back(k);
    }
    std::vector<std::uint32_t> seen(group.size(), UINT32_MAX);
    for (std::uint32_t k = 0; k < group.size(); ++k) {
        const CutFace& t = faces[group[k]];
        const glm::ivec2 a = cellOf(boxes[k][0]), b = cellOf(boxes[k][1]);
        std::vector<std::uint32_t> candidates;
        for (int y = a.y; y <= b.y; ++y)
            for (int x = a.x; x <= b.x; ++x)
                for (std::uint32_t m : buckets[std::size_t(y * n + x)])
                    if (seen[m] != k && faces[group[m]].piece > t.piece) {
                        seen[m] = k;
                        candidates.push_back(m);
                    }
        std::sort(candidates.begin(), candidates.end());
        for (std::uint32_t m : candidates) {
            if (glm::any(glm::lessThan(boxes[m][1], boxes[k][0])) || glm::any(glm::lessThan(boxes[k][1], boxes[m][0])))
                continue;
            addOverlap(t, faces[group[m]], proj, sums[{t.piece, faces[group[m]].piece}]);
        }
    }
}

}  // namespace

std::vector<Contact> contacts(std::span<const CutFace> faces, double minArea) {
    std::map<std::pair<std::int64_t, std::int64_t>, std::vector<std::uint32_t>> planes;
    for (std::uint32_t i = 0; i < faces.size(); ++i) planes[faces[i].plane].push_back(i);
    std::map<std::pair<std::uint32_t, std::uint32_t>, Sum> sums;
    for (const auto& [plane, group] : planes) planeContacts(faces, group, sums);
    std::vector<Contact> out;
    for (const auto& [pair, sum] : sums) {
        if (!(sum.area > minArea)) continue;
        out.push_back({pair.first, pair.second, sum.area, sum.weighted / sum.area, glm::normalize(sum.normal)});
    }
    return out;
}

}  // namespace dawnforge::sim::detail
