// The restricted Voronoi diagram (rvd.hpp): three passes, each parallel.
//  1. The surface: a triangle whose three corners have the same nearest seed lies in that
//     seed's cell and is kept whole; the others are clipped, cell by cell, by the bisectors
//     they cross, starting from their corners' cells and moving across the cut edges.
//  2. The cells: each Voronoi cell is the bounding box clipped by its neighbours' bisectors,
//     with symbolic corners. Each face it shares with a higher seed becomes that pair's cap:
//     the face's sides where they run inside the mesh (their crossings with the surface are
//     the keys the surface pass made), closed by the surface's cut edges, triangulated once
//     (CGAL's constrained Delaunay, exact predicates) and given to both cells.
//  3. The pieces: each cell's surface and caps, checked to close by keys.
#include "rvd.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>
#include <CGAL/Interval_nt.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <map>
#include <optional>
#include <stdexcept>

namespace dawnforge::sim::detail {

namespace {

using IA = CGAL::Interval_nt_advanced;  // only under a CGAL::Protect_FPU_rounding guard
using EX = CGAL::Exact_rational;

// A point as x/w, y/w, z/w, and a plane a·x + b·y + c·z + d·w = 0.
template <class NT> struct Hom { NT x, y, z, w; };
template <class NT> struct Lin { NT a, b, c, d; };

template <class NT> NT at(const Lin<NT>& l, const Hom<NT>& p) { return l.a * p.x + l.b * p.y + l.c * p.z + l.d * p.w; }

template <class NT> Hom<NT> hom(const glm::dvec3& p) { return {NT(p.x), NT(p.y), NT(p.z), NT(1)}; }

template <class NT> NT det3(const NT& a0, const NT& b0, const NT& c0, const NT& a1, const NT& b1, const NT& c1,
                            const NT& a2, const NT& b2, const NT& c2) {
    return a0 * (b1 * c2 - b2 * c1) - b0 * (a1 * c2 - a2 * c1) + c0 * (a1 * b2 - a2 * b1);
}

// The point where three planes meet (Cramer's rule).
template <class NT> Hom<NT> meet(const Lin<NT>& p, const Lin<NT>& q, const Lin<NT>& r) {
    return {det3<NT>(-p.d, p.b, p.c, -q.d, q.b, q.c, -r.d, r.b, r.c), det3<NT>(p.a, -p.d, p.c, q.a, -q.d, q.c, r.a, -r.d, r.c),
            det3<NT>(p.a, p.b, -p.d, q.a, q.b, -q.d, r.a, r.b, -r.d), det3<NT>(p.a, p.b, p.c, q.a, q.b, q.c, r.a, r.b, r.c)};
}

// A plane the diagram uses: the bisector of seeds a and b (negative nearer a), the b-th face of
// the box (negative inside), or input triangle a's plane (negative behind it).
struct PlaneRef {
    enum Kind : std::uint8_t { Bisector, Box, Triangle } kind;
    std::uint32_t a, b;
};

// A corner and its interval approximation (one per corner: the predicates only take a dot
// product with it).
struct Corner {
    RvdKey key;
    Hom<IA> approx;
    std::int64_t label;  // the edge to the next corner: see Polygon and Face
};

class Diagram {
public:
    Diagram(const RvdSurface& s, const RvdSeeds& seeds)
        : surface_(s), seeds_(seeds), n_(std::uint32_t(seeds.points.size())) {
        const glm::dvec3 extent = seeds.boxMax - seeds.boxMin;
        scale_ = std::max({extent.x, extent.y, extent.z, 1e-300});
    }

    std::uint32_t seedCount() const { return n_; }

    template <class NT> Lin<NT> plane(PlaneRef p) const {
        switch (p.kind) {
        case PlaneRef::Bisector: return bisector<NT>(p.a, p.b);
        case PlaneRef::Box: {
            const int axis = int(p.b / 2);
            const bool max = p.b % 2 == 0;
            Lin<NT> l{NT(0), NT(0), NT(0), NT(max ? -seeds_.boxMax[axis] : seeds_.boxMin[axis])};
            (axis == 0 ? l.a : axis == 1 ? l.b : l.c) = NT(max ? 1.0 : -1.0);
            return l;
        }
        case PlaneRef::Triangle: break;
        }
        const auto& t = surface_.triangles[p.a];
        const Hom<NT> a = hom<NT>(surface_.points[t[0]]), b = hom<NT>(surface_.points[t[1]]), c = hom<NT>(surface_.points[t[2]]);
        const NT ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z, vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z;
        Lin<NT> l{uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx, NT(0)};
        l.d = -(l.a * a.x + l.b * a.y + l.c * a.z);
        return l;
    }

    template <class NT> Hom<NT> point(const RvdKey& k) const {
        const auto& x = k.x;
        switch (k.kind) {
        case 0: return hom<NT>(surface_.points[x[0]]);
        case 1: {  // (a·f(b) − b·f(a)) / (f(b) − f(a)) on the line through a and b
            const Lin<NT> f = bisector<NT>(x[2], x[3]);
            const Hom<NT> a = hom<NT>(surface_.points[x[0]]), b = hom<NT>(surface_.points[x[1]]);
            const NT fa = at(f, a), fb = at(f, b);
            return {a.x * fb - b.x * fa, a.y * fb - b.y * fa, a.z * fb - b.z * fa, fb - fa};
        }
        case 2:
            return meet(plane<NT>({PlaneRef::Triangle, x[0], 0}), bisector<NT>(x[1], x[2]), bisector<NT>(x[1], x[3]));
        default: {  // sites: the seeds first (sorted), then the box faces
            std::array<Lin<NT>, 3> planes;
            std::size_t count = 0;
            for (std::size_t l = 1; l < 4; ++l)
                planes[count++] = x[l] < n_ ? bisector<NT>(x[0], x[l]) : plane<NT>({PlaneRef::Box, 0, x[l] - n_});
            return meet(planes[0], planes[1], planes[2]);
        }
        }
    }

    Hom<IA> approx(const RvdKey& k) const {
        CGAL::Protect_FPU_rounding<true> guard;
        return point<IA>(k);
    }

    // The sign of plane p at corner c, exactly.
    int side(const Corner& c, PlaneRef p) const {
        {
            CGAL::Protect_FPU_rounding<true> guard;
            const IA v = at(plane<IA>(p), c.approx);
            const CGAL::Uncertain<CGAL::Sign> sv = CGAL::sign(v), sw = CGAL::sign(c.approx.w);
            if (CGAL::is_certain(sv) && CGAL::is_certain(sw)) return int(CGAL::get_certain(sv)) * int(CGAL::get_certain(sw));
        }
        const Hom<EX> e = point<EX>(c.key);
        return int(CGAL::sign(at(plane<EX>(p), e))) * int(CGAL::sign(e.w));
    }

    // Whether corner c is in cell i rather than cell j: nearer i, or as near and i < j.
    bool in(const Corner& c, std::uint32_t i, std::uint32_t j) const {
        const int s = side(c, {PlaneRef::Bisector, i, j});
        return s < 0 || (s == 0 && i < j);
    }

    // A key's position: the interval's midpoint when it is tight, else the exact value rounded.
    glm::dvec3 position(const RvdKey& k) const {
        if (k.kind == 0) return surface_.points[k.x[0]];
        if (const std::optional<std::array<double, 6>> b = tightBounds(k))
            return {0.5 * (*b)[0] + 0.5 * (*b)[3], 0.5 * (*b)[1] + 0.5 * (*b)[4], 0.5 * (*b)[2] + 0.5 * (*b)[5]};
        const Hom<EX> e = point<EX>(k);
        if (CGAL::sign(e.w) == CGAL::ZERO) return surface_.points.empty() ? glm::dvec3(0.0) : surface_.points[0];
        return {CGAL::to_double(e.x / e.w), CGAL::to_double(e.y / e.w), CGAL::to_double(e.z / e.w)};
    }

    Corner corner(const RvdKey& k, std::int64_t label) const { return {k, approx(k), label}; }

    // The bisector's normal, from seed i towards seed j (in double: for choosing a projection).
    glm::dvec3 bisectorNormal(std::uint32_t i, std::uint32_t j) const {
        return seeds_.metric.bisectorNormal(seeds_.points[j] - seeds_.points[i]);
    }

private:
    // The key's coordinates as intervals (low x, y, z, high x, y, z), when each is within 1e-11 of
    // the box's size: far below the cutting grid's step (2^-29 of it).
    std::optional<std::array<double, 6>> tightBounds(const RvdKey& k) const {
        CGAL::Protect_FPU_rounding<true> guard;
        const Hom<IA> h = point<IA>(k);
        const CGAL::Uncertain<CGAL::Sign> w = CGAL::sign(h.w);
        if (!CGAL::is_certain(w) || CGAL::get_certain(w) == CGAL::ZERO) return std::nullopt;
        const IA q[3] = {h.x / h.w, h.y / h.w, h.z / h.w};
        std::array<double, 6> b{};
        for (int a = 0; a < 3; ++a) {
            if (q[a].sup() - q[a].inf() > 1e-11 * scale_) return std::nullopt;
            b[std::size_t(a)] = q[a].inf(), b[std::size_t(a) + 3] = q[a].sup();
        }
        return b;
    }

    // f(x) = |x − s_a|² − |x − s_b|² in the metric: 2·M(s_b − s_a)·x + q(s_a) − q(s_b).
    template <class NT> Lin<NT> bisector(std::uint32_t i, std::uint32_t j) const {
        const glm::dvec3 &si = seeds_.points[i], &sj = seeds_.points[j];
        NT dx = NT(sj.x) - NT(si.x), dy = NT(sj.y) - NT(si.y), dz = NT(sj.z) - NT(si.z);
        NT qi = NT(si.x) * NT(si.x) + NT(si.y) * NT(si.y) + NT(si.z) * NT(si.z);
        NT qj = NT(sj.x) * NT(sj.x) + NT(sj.y) * NT(sj.y) + NT(sj.z) * NT(sj.z);
        if (const double shrink = seeds_.metric.shrink(); shrink != 0.0) {
            const glm::dvec3& g = seeds_.metric.grain;
            const NT gx(g.x), gy(g.y), gz(g.z), c(shrink);
            const NT gd = c * (gx * dx + gy * dy + gz * dz);
            dx = dx + gd * gx, dy = dy + gd * gy, dz = dz + gd * gz;
            const NT gi = gx * NT(si.x) + gy * NT(si.y) + gz * NT(si.z), gj = gx * NT(sj.x) + gy * NT(sj.y) + gz * NT(sj.z);
            qi = qi + c * gi * gi;
            qj = qj + c * gj * gj;
        }
        return {NT(2) * dx, NT(2) * dy, NT(2) * dz, qi - qj};
    }

    const RvdSurface& surface_;
    const RvdSeeds& seeds_;
    std::uint32_t n_;
    double scale_ = 1.0;
};

RvdKey sortedKey(std::uint32_t kind, std::array<std::uint32_t, 4> x, std::size_t from) {
    std::sort(x.begin() + std::ptrdiff_t(from), x.end());
    return {kind, x};
}

// ---------------------------------------------------------------- the surface

// A convex polygon on input triangle t inside one cell. A corner's label names the edge to the
// next corner: >= 0, the bisector with that seed; < 0, the input edge from triangle corner
// -1 - label to the next.
struct Polygon {
    std::uint32_t cell = 0;
    std::vector<Corner> corners;
};

// Sutherland-Hodgman: the convex polygon `poly` clipped to cell i's side of seed j. Where an
// edge crosses the bisector, the crossing is the edge's corner that lies exactly on it, if one
// does (so that a mesh vertex on a bisector stays one key), or crossing(p, next) otherwise. The
// edges the cut makes are labelled j; a key repeated next to itself (a zero-length edge) merges.
template <class Crossing>
std::vector<Corner> clipPolygon(const Diagram& d, const std::vector<Corner>& poly, std::uint32_t i, std::uint32_t j,
                                Crossing&& crossing) {
    const std::size_t n = poly.size();
    std::vector<int> sign(n);
    std::vector<char> in(n);
    std::size_t count = 0;
    for (std::size_t k = 0; k < n; ++k) {
        sign[k] = d.side(poly[k], {PlaneRef::Bisector, i, j});
        count += std::size_t(in[k] = sign[k] < 0 || (sign[k] == 0 && i < j));
    }
    if (count == n) return poly;
    std::vector<Corner> out;
    if (count == 0) return out;
    auto push = [&out](const Corner& c) {
        if (!out.empty() && out.back().key == c.key) out.back().label = c.label;
        else out.push_back(c);
    };
    for (std::size_t k = 0; k < n; ++k) {
        const Corner& p = poly[k];
        const std::size_t next = (k + 1) % n;
        if (in[k]) push(p);
        if (in[k] == in[next]) continue;
        Corner c = sign[k] == 0 ? p : sign[next] == 0 ? poly[next] : crossing(p, poly[next]);
        c.label = in[k] ? std::int64_t(j) : p.label;
        push(c);
    }
    while (out.size() > 1 && out.back().key == out.front().key) out.pop_back();
    return out;
}

// Clips `poly` (in cell i, on triangle t) to the side of cell i against seed j. A crossing on
// an input edge is that edge cut by the bisector; one on a cut edge (the bisector with seed k),
// the triangle met by the Voronoi edge of i, j and k.
std::vector<Corner> clip(const Diagram& d, const std::vector<Corner>& poly, std::uint32_t i, std::uint32_t j,
                         std::uint32_t t, const std::array<std::uint32_t, 3>& tri) {
    return clipPolygon(d, poly, i, j, [&](const Corner& p, const Corner&) {
        if (p.label < 0) {
            const std::uint32_t a = tri[std::size_t(-1 - p.label)], b = tri[std::size_t(-p.label) % 3];
            return d.corner({1, {std::min(a, b), std::max(a, b), std::min(i, j), std::max(i, j)}}, 0);
        }
        return d.corner(sortedKey(2, {t, i, j, std::uint32_t(p.label)}, 1), 0);
    });
}

// The parts of mixed triangle t in every cell it meets, from its corners' cells outwards.
std::vector<Polygon> clipTriangle(const Diagram& d, const RvdSeeds& seeds, std::uint32_t t,
                                  const std::array<std::uint32_t, 3>& tri, const std::array<std::uint32_t, 3>& cornerCells) {
    std::vector<Polygon> out;
    std::vector<std::uint32_t> queue(cornerCells.begin(), cornerCells.end());
    std::sort(queue.begin(), queue.end());
    queue.erase(std::unique(queue.begin(), queue.end()), queue.end());
    std::array<Corner, 3> corners;
    for (std::size_t c = 0; c < 3; ++c) corners[c] = d.corner({0, {tri[c], 0, 0, 0}}, -1 - std::int64_t(c));
    for (std::size_t q = 0; q < queue.size(); ++q) {
        const std::uint32_t i = queue[q];
        std::vector<Corner> poly(corners.begin(), corners.end());
        for (std::uint32_t j : seeds.neighbours[i]) {
            if (d.in(corners[0], i, j) && d.in(corners[1], i, j) && d.in(corners[2], i, j)) continue;
            poly = clip(d, poly, i, j, t, tri);
            if (poly.empty()) break;
        }
        if (poly.size() < 3) continue;
        for (const Corner& c : poly)
            if (c.label >= 0 && std::find(queue.begin(), queue.end(), std::uint32_t(c.label)) == queue.end())
                queue.push_back(std::uint32_t(c.label));
        out.push_back({i, std::move(poly)});
    }
    return out;
}

// The nearest seed to point v (ties to the smaller index), walking the neighbour graph from `from`.
std::uint32_t nearestSeed(const Diagram& d, const RvdSeeds& seeds, const Corner& v, std::uint32_t from) {
    std::uint32_t at = from;
    for (bool moved = true; moved;) {
        moved = false;
        for (std::uint32_t j : seeds.neighbours[at])
            if (!d.in(v, at, j)) {
                at = j;
                moved = true;
                break;
            }
    }
    return at;
}

// ---------------------------------------------------------------- the cells

// A face of a Voronoi cell: the site it lies on (a seed, or seeds + box face) and its corners,
// counter-clockwise seen from outside the cell; a corner's label is the site of the face across
// the edge to the next corner.
struct Face {
    std::uint32_t site;
    std::vector<Corner> corners;
};

using Cell = std::vector<Face>;

Cell boxCell(const Diagram& d, std::uint32_t i) {
    const std::uint32_t n = d.seedCount();
    auto site = [n](int axis, int high) { return n + std::uint32_t(2 * axis + (high ? 0 : 1)); };
    Cell cell;
    for (int axis = 0; axis < 3; ++axis)
        for (int high = 0; high < 2; ++high) {
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            std::array<std::array<int, 2>, 4> uv{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
            if (!high) std::reverse(uv.begin(), uv.end());
            Face f{site(axis, high), {}};
            for (std::size_t k = 0; k < 4; ++k) {
                std::array<int, 3> c{};
                c[std::size_t(axis)] = high, c[std::size_t(u)] = uv[k][0], c[std::size_t(v)] = uv[k][1];
                const auto& next = uv[(k + 1) % 4];
                const int same = next[0] == uv[k][0] ? u : v;  // the axis that stays along the edge
                const RvdKey key = sortedKey(3, {i, site(0, c[0]), site(1, c[1]), site(2, c[2])}, 0);
                f.corners.push_back(d.corner(key, site(same, c[std::size_t(same)])));
            }
            cell.push_back(std::move(f));
        }
    return cell;
}

// The new face of a cell clipped by a bisector: each cut face gives the edge from where its
// corners come back inside (entry) to where they leave (exit), seen from the other side.
struct NewFace {
    struct Edge {
        Corner entry;
        RvdKey exit;
        std::uint32_t site;  // the cut face's
    };
    std::map<RvdKey, Edge> from;  // by entry key

    // The face's corners, or nullopt when the edges do not close into one loop.
    std::optional<std::vector<Corner>> loop() const {
        std::vector<Corner> corners;
        auto at = from.begin();
        for (std::size_t k = 0; k < from.size(); ++k) {
            if (at == from.end()) return std::nullopt;
            corners.push_back(at->second.entry);
            corners.back().label = at->second.site;
            at = from.find(at->second.exit);
        }
        if (at != from.begin()) return std::nullopt;
        return corners;
    }
};

// Clips cell i by the bisector with seed j. False when the new face does not close.
bool clipCell(const Diagram& d, Cell& cell, std::uint32_t i, std::uint32_t j) {
    NewFace made;
    Cell out;
    for (Face& f : cell) {
        Face g{f.site, clipPolygon(d, f.corners, i, j, [&](const Corner& p, const Corner&) {
                   return d.corner(sortedKey(3, {i, f.site, std::uint32_t(p.label), j}, 0), 0);
               })};
        if (g.corners.size() < 3) continue;  // outside, or touching the bisector along an edge at most
        for (std::size_t k = 0; k < g.corners.size(); ++k)
            if (g.corners[k].label == std::int64_t(j)) {
                const Corner& entry = g.corners[(k + 1) % g.corners.size()];
                if (!made.from.emplace(entry.key, NewFace::Edge{entry, g.corners[k].key, f.site}).second) return false;
            }
        out.push_back(std::move(g));
    }
    const std::optional<std::vector<Corner>> loop = made.loop();
    if (!loop) return false;
    if (loop->size() == 2) {  // the bisector only touches the cell along the edge of two faces: no face
        for (Face& f : out)
            for (Corner& c : f.corners)
                if (c.label == std::int64_t(j)) c.label = (*loop)[(*loop)[0].label == f.site ? 1 : 0].label;
    } else if (loop->size() >= 3) {
        out.push_back({j, *loop});
    }
    cell = std::move(out);
    return true;
}

std::optional<Cell> voronoiCell(const Diagram& d, const RvdSeeds& seeds, std::uint32_t i) {
    Cell cell = boxCell(d, i);
    std::vector<std::uint32_t> order = seeds.neighbours[i];  // nearest first: the cell shrinks soonest
    const glm::dvec3 s = seeds.points[i];
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        const double da = glm::length(seeds.points[a] - s), db = glm::length(seeds.points[b] - s);
        return da != db ? da < db : a < b;
    });
    for (std::uint32_t j : order)
        if (!clipCell(d, cell, i, j)) return std::nullopt;
    return cell;
}

// ---------------------------------------------------------------- caps

struct CapVertex {
    std::size_t index = 0;
    bool valid = false;
};
struct CapFace {
    int nesting = -1;
};
using CapK = CGAL::Exact_predicates_inexact_constructions_kernel;
using CapVb = CGAL::Triangulation_vertex_base_with_info_2<CapVertex, CapK>;
using CapFb = CGAL::Constrained_triangulation_face_base_2<CapK, CGAL::Triangulation_face_base_with_info_2<CapFace, CapK>>;
using CapCdt = CGAL::Constrained_Delaunay_triangulation_2<CapK, CGAL::Triangulation_data_structure_2<CapVb, CapFb>,
                                                          CGAL::Exact_predicates_tag>;

// Nesting levels from the outside: a face is inside the constraints' loops when odd.
void markNesting(CapCdt& cdt) {
    for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info().nesting = -1;
    std::vector<std::pair<CapCdt::Face_handle, int>> border{{cdt.infinite_face(), 0}};
    while (!border.empty()) {
        auto [start, level] = border.back();
        border.pop_back();
        if (start->info().nesting != -1) continue;
        std::vector<CapCdt::Face_handle> stack{start};
        start->info().nesting = level;
        while (!stack.empty()) {
            const CapCdt::Face_handle f = stack.back();
            stack.pop_back();
            for (int e = 0; e < 3; ++e) {
                const CapCdt::Face_handle g = f->neighbor(e);
                if (g->info().nesting != -1) continue;
                if (cdt.is_constrained({f, e})) {
                    border.emplace_back(g, level + 1);
                } else {
                    g->info().nesting = level;
                    stack.push_back(g);
                }
            }
        }
    }
}

using KeyTriangle = std::array<RvdKey, 3>;

// What one cell's surface says about its caps.
struct CellSurface {
    std::map<std::uint32_t, std::vector<std::pair<RvdKey, RvdKey>>> cuts;  // seed j -> edges on the bisector
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<RvdKey>> crossings;  // Voronoi edge (j, k) -> keys
};

class CapBuilder {
public:
    CapBuilder(const Diagram& d, const RvdSeeds& seeds, const std::function<bool(const glm::dvec3&)>& inside)
        : d_(d), seeds_(seeds), inside_(inside) {}

    // The cap of cell i's face f (on seed j > i), oriented outward of cell i; nullopt when its
    // boundary does not close. Its edges on the surface are the cut edges of both cells (the
    // same edges, but for a mesh edge lying on the bisector: the cut edge of one side only).
    std::optional<std::vector<KeyTriangle>> cap(std::uint32_t i, const Face& f, const CellSurface& si,
                                                const CellSurface& sj) {
        const std::uint32_t j = f.site;
        std::vector<std::pair<RvdKey, RvdKey>> edges;
        if (const auto it = si.cuts.find(j); it != si.cuts.end())
            for (const auto& [a, b] : it->second) edges.emplace_back(b, a);
        if (const auto it = sj.cuts.find(i); it != sj.cuts.end()) edges.insert(edges.end(), it->second.begin(), it->second.end());
        std::sort(edges.begin(), edges.end());
        edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
        const bool cut = !edges.empty();
        bool crossed = false;
        for (std::size_t k = 0; k < f.corners.size(); ++k) {
            const Corner& a = f.corners[k];
            std::vector<RvdKey> across;
            if (a.label < std::int64_t(d_.seedCount())) {
                const auto other = std::uint32_t(a.label);
                for (const auto& [s, x, y] : {std::tuple{&si, j, other}, std::tuple{&sj, i, other}})
                    if (const auto it = s->crossings.find({std::min(x, y), std::max(x, y)}); it != s->crossings.end())
                        across.insert(across.end(), it->second.begin(), it->second.end());
            }
            crossed = crossed || !across.empty();
            if (!sideOfFace(a.key, f.corners[(k + 1) % f.corners.size()].key, across, edges)) return std::nullopt;
        }
        if (edges.empty()) return std::vector<KeyTriangle>{};
        if (!crossed && !cut) {  // wholly inside: the face itself
            if (edges.size() != f.corners.size()) return std::nullopt;
            std::vector<KeyTriangle> fan;
            for (std::size_t k = 1; k + 1 < f.corners.size(); ++k)
                fan.push_back({f.corners[0].key, f.corners[k].key, f.corners[k + 1].key});
            return fan;
        }
        try {
            return triangulate(i, j, edges);
        } catch (const std::exception&) {  // CGAL gave up on this cap: the cell falls back
            return std::nullopt;
        }
    }

private:
    bool insideAt(const RvdKey& k) {
        const auto it = insideOf_.find(k);
        if (it != insideOf_.end()) return it->second;
        return insideOf_.emplace(k, inside_(position(k))).first->second;
    }

    glm::dvec3 position(const RvdKey& k) {
        const auto it = positions_.find(k);
        if (it != positions_.end()) return it->second;
        return positions_.emplace(k, d_.position(k)).first->second;
    }

    // The parts of the face's side from a to b that run inside the mesh, split where the
    // surface crosses it; false when the crossings disagree with the ends.
    bool sideOfFace(const RvdKey& a, const RvdKey& b, std::vector<RvdKey>& across,
                    std::vector<std::pair<RvdKey, RvdKey>>& edges) {
        const glm::dvec3 pa = position(a), dir = position(b) - pa;
        std::sort(across.begin(), across.end());
        across.erase(std::unique(across.begin(), across.end()), across.end());
        std::vector<std::pair<double, RvdKey>> order;
        for (const RvdKey& k : across) order.emplace_back(glm::dot(position(k) - pa, dir), k);
        std::sort(order.begin(), order.end());
        bool in = insideAt(a);
        RvdKey from = a;
        for (const auto& [_, k] : order) {
            if (in) edges.emplace_back(from, k);
            in = !in;
            from = k;
        }
        if (in) edges.emplace_back(from, b);
        return in == insideAt(b);
    }

    std::optional<std::vector<KeyTriangle>> triangulate(std::uint32_t i, std::uint32_t j,
                                                        const std::vector<std::pair<RvdKey, RvdKey>>& edges) {
        std::map<RvdKey, int> degree;
        for (const auto& [a, b] : edges) {
            if (a == b) return std::nullopt;
            ++degree[a], --degree[b];
        }
        for (const auto& [_, deg] : degree)
            if (deg != 0) return std::nullopt;
        const glm::dvec3 normal = d_.bisectorNormal(i, j);
        const glm::dvec3 m = glm::abs(normal);
        const int axis = m.x >= m.y && m.x >= m.z ? 0 : m.y >= m.z ? 1 : 2;
        const bool flip = normal[axis] < 0;
        std::vector<RvdKey> keys;
        CapCdt cdt;
        std::map<RvdKey, CapCdt::Vertex_handle> handle;
        for (const auto& [k, _] : degree) {
            const glm::dvec3 p = position(k);
            const double u = p[(axis + 1) % 3], v = p[(axis + 2) % 3];
            const CapCdt::Vertex_handle h = cdt.insert(flip ? CapK::Point_2(v, u) : CapK::Point_2(u, v));
            if (h->info().valid) return std::nullopt;  // two keys at one point
            h->info() = {keys.size(), true};
            keys.push_back(k);
            handle[k] = h;
        }
        for (const auto& [a, b] : edges) cdt.insert_constraint(handle[a], handle[b]);
        if (cdt.number_of_vertices() != keys.size()) return std::nullopt;  // constraints crossed
        markNesting(cdt);
        std::vector<KeyTriangle> out;
        for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
            if (f->info().nesting % 2 == 1)
                out.push_back({keys[f->vertex(0)->info().index], keys[f->vertex(1)->info().index],
                               keys[f->vertex(2)->info().index]});
        std::sort(out.begin(), out.end());
        return out;
    }

    const Diagram& d_;
    const RvdSeeds& seeds_;
    const std::function<bool(const glm::dvec3&)>& inside_;
    std::map<RvdKey, bool> insideOf_;
    std::map<RvdKey, glm::dvec3> positions_;
};

// ---------------------------------------------------------------- assembly

struct Caps {
    std::vector<std::vector<KeyTriangle>> perNeighbour;  // parallel to the seed's neighbour list (higher seeds only)
    std::vector<char> failed;                            // per neighbour
};

// A corner between two cut edges (bisectors with seeds j and k) is where the Voronoi edge of
// the cell, j and k crosses the surface: usually an input triangle met by it, but also a mesh
// vertex or edge lying exactly on it.
CellSurface cellSurface(const std::vector<const Polygon*>& polygons) {
    CellSurface s;
    for (const Polygon* p : polygons) {
        const std::vector<Corner>& c = p->corners;
        for (std::size_t k = 0; k < c.size(); ++k) {
            const std::int64_t before = c[(k + c.size() - 1) % c.size()].label, after = c[k].label;
            if (after >= 0) s.cuts[std::uint32_t(after)].emplace_back(c[k].key, c[(k + 1) % c.size()].key);
            if (before >= 0 && after >= 0 && before != after)
                s.crossings[std::minmax(std::uint32_t(before), std::uint32_t(after))].push_back(c[k].key);
        }
    }
    return s;
}

// True when every directed edge has its opposite as often as itself.
bool closesByKeys(const RvdCell& cell) {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
    for (const RvdCell::Triangle& t : cell.triangles)
        for (std::size_t k = 0; k < 3; ++k) edges.emplace_back(t.v[k], t.v[(k + 1) % 3]);
    std::sort(edges.begin(), edges.end());
    for (std::size_t k = 0; k < edges.size();) {
        std::size_t end = k;
        while (end < edges.size() && edges[end] == edges[k]) ++end;
        const auto [lo, hi] = std::equal_range(edges.begin(), edges.end(), std::pair{edges[k].second, edges[k].first});
        if (hi - lo != std::ptrdiff_t(end - k)) return false;
        k = end;
    }
    return true;
}

class Assembler {
public:
    Assembler(const Diagram& d, RvdCell& out) : d_(d), out_(out) {}
    std::uint32_t index(const RvdKey& k) {
        const auto [it, inserted] = local_.try_emplace(k, std::uint32_t(out_.keys.size()));
        if (inserted) {
            out_.keys.push_back(k);
            out_.points.push_back(d_.position(k));
        }
        return it->second;
    }
    void add(const RvdKey& a, const RvdKey& b, const RvdKey& c, std::int64_t origin) {
        out_.triangles.push_back({{index(a), index(b), index(c)}, origin});
    }

private:
    const Diagram& d_;
    RvdCell& out_;
    std::map<RvdKey, std::uint32_t> local_;
};

// Pass 1: every vertex's cell, then the mixed triangles' parts, gathered per cell in triangle order.
struct SurfacePass {
    std::vector<std::vector<Polygon>> parts;                                     // per mixed triangle
    std::vector<std::vector<std::pair<std::uint32_t, const Polygon*>>> perCell;  // (triangle, its part; none: whole)
    std::size_t mixed = 0;
};

SurfacePass cutSurface(const Diagram& d, const RvdSurface& surface, const RvdSeeds& seeds) {
    std::vector<std::uint32_t> vertexCell(surface.points.size(), 0);
    std::uint32_t hint = 0;
    for (std::size_t v = 0; v < surface.points.size(); ++v)
        hint = vertexCell[v] = nearestSeed(d, seeds, d.corner({0, {std::uint32_t(v), 0, 0, 0}}, 0), hint);
    std::vector<std::uint32_t> mixed;
    for (std::uint32_t t = 0; t < surface.triangles.size(); ++t) {
        const auto& tri = surface.triangles[t];
        if (vertexCell[tri[0]] != vertexCell[tri[1]] || vertexCell[tri[0]] != vertexCell[tri[2]]) mixed.push_back(t);
    }
    SurfacePass pass{std::vector<std::vector<Polygon>>(mixed.size()), {}, mixed.size()};
    tbb::parallel_for(std::size_t(0), mixed.size(), [&](std::size_t m) {
        const auto& tri = surface.triangles[mixed[m]];
        pass.parts[m] = clipTriangle(d, seeds, mixed[m], tri, {vertexCell[tri[0]], vertexCell[tri[1]], vertexCell[tri[2]]});
    });
    pass.perCell.resize(d.seedCount());
    for (std::uint32_t t = 0, m = 0; t < surface.triangles.size(); ++t) {
        if (m < mixed.size() && mixed[m] == t) {
            for (const Polygon& p : pass.parts[m]) pass.perCell[p.cell].emplace_back(t, &p);
            ++m;
        } else {
            pass.perCell[vertexCell[surface.triangles[t][0]]].emplace_back(t, nullptr);
        }
    }
    return pass;
}

// Pass 2: each Voronoi cell, and its caps with higher seeds.
struct CapPass {
    std::vector<Caps> caps;
    std::vector<char> cellFailed;
};

CapPass cutCaps(const Diagram& d, const RvdSeeds& seeds, const SurfacePass& surface,
                const std::function<bool(const glm::dvec3&)>& inside) {
    const std::uint32_t n = d.seedCount();
    std::vector<CellSurface> surfaces(n);
    tbb::parallel_for(std::uint32_t(0), n, [&](std::uint32_t i) {
        std::vector<const Polygon*> polygons;
        for (const auto& [_, p] : surface.perCell[i])
            if (p) polygons.push_back(p);
        surfaces[i] = cellSurface(polygons);
    });
    CapPass pass{std::vector<Caps>(n), std::vector<char>(n, 0)};
    tbb::parallel_for(std::uint32_t(0), n, [&](std::uint32_t i) {
        const std::vector<std::uint32_t>& nb = seeds.neighbours[i];
        Caps& caps = pass.caps[i];
        caps.perNeighbour.resize(nb.size());
        caps.failed.assign(nb.size(), 0);
        const std::optional<Cell> cell = voronoiCell(d, seeds, i);
        if (!cell) {
            pass.cellFailed[i] = 1;
            return;
        }
        CapBuilder builder(d, seeds, inside);
        for (const Face& f : *cell) {
            if (f.site >= n || f.site < i) continue;
            const std::size_t k = std::size_t(std::lower_bound(nb.begin(), nb.end(), f.site) - nb.begin());
            std::optional<std::vector<KeyTriangle>> c = builder.cap(i, f, surfaces[i], surfaces[f.site]);
            if (c) caps.perNeighbour[k] = std::move(*c);
            else caps.failed[k] = 1;
        }
    });
    return pass;
}

// Pass 3: cell i's surface and caps (its own with higher seeds; the lower seeds', reversed),
// closed by keys or reported.
RvdCell assembleCell(const Diagram& d, const RvdSurface& surface, const RvdSeeds& seeds, const SurfacePass& parts,
                     const CapPass& caps, std::uint32_t i) {
    RvdCell out;
    Assembler a(d, out);
    for (const auto& [t, p] : parts.perCell[i]) {
        if (!p) {
            const auto& tri = surface.triangles[t];
            a.add({0, {tri[0], 0, 0, 0}}, {0, {tri[1], 0, 0, 0}}, {0, {tri[2], 0, 0, 0}}, std::int64_t(t));
            continue;
        }
        for (std::size_t k = 1; k + 1 < p->corners.size(); ++k)
            a.add(p->corners[0].key, p->corners[k].key, p->corners[k + 1].key, std::int64_t(t));
    }
    bool failed = caps.cellFailed[i];
    const std::vector<std::uint32_t>& nb = seeds.neighbours[i];
    for (std::size_t k = 0; k < nb.size(); ++k) {
        const std::uint32_t j = nb[k], lo = std::min(i, j);
        const std::vector<std::uint32_t>& lowNb = seeds.neighbours[lo];
        const std::size_t at = i < j ? k : std::size_t(std::lower_bound(lowNb.begin(), lowNb.end(), i) - lowNb.begin());
        if (at >= lowNb.size() || lowNb[at] != std::max(i, j) || caps.cellFailed[lo] || caps.caps[lo].failed[at]) {
            failed = true;
            continue;
        }
        for (const KeyTriangle& t : caps.caps[lo].perNeighbour[at]) {
            if (i < j) a.add(t[0], t[1], t[2], -1 - std::int64_t(j));
            else a.add(t[0], t[2], t[1], -1 - std::int64_t(j));
        }
    }
    out.closed = !failed && closesByKeys(out);
    return out;
}

}  // namespace

std::vector<RvdCell> restrictedVoronoi(const RvdSurface& surface, const RvdSeeds& seeds,
                                       const std::function<bool(const glm::dvec3&)>& inside, RvdStats* stats) {
    const Diagram d(surface, seeds);
    std::vector<RvdCell> cells(d.seedCount());
    if (cells.empty()) return cells;
    const SurfacePass parts = cutSurface(d, surface, seeds);
    const CapPass caps = cutCaps(d, seeds, parts, inside);
    tbb::parallel_for(std::uint32_t(0), d.seedCount(),
                      [&](std::uint32_t i) { cells[i] = assembleCell(d, surface, seeds, parts, caps, i); });
    if (stats) {
        stats->clippedTriangles = parts.mixed;
        stats->wholeTriangles = surface.triangles.size() - parts.mixed;
    }
    return cells;
}

}  // namespace dawnforge::sim::detail
