// Fixed-seed fuzzing of fracture on CSG-style solids, where exact geometry meets rounding:
// polycubes on uneven lattices (coplanar faces everywhere, slabs 1e-6 thin, near-coincident
// vertices), extruded letters with concave outlines, many-sided prisms, far from the origin.
// Every case must fracture (or be refused as bad input), and every piece must be clean as
// written: closed, manifold and consistent after welding by float position, no degenerate
// triangle, and the pieces' volumes must add up to the solid's, computed here from its own
// construction.
#include "test_support.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/seed.hpp>
#include <dawnforge/sim/fracture.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <string>

using namespace dawnforge;

namespace {

struct Solid {
    std::string name;
    Mesh mesh;
    double volume = 0.0;
    double area = 0.0;
    double floatSpacing = 0.0;  // of float coordinates at the solid's largest coordinate
};

// ---- polycubes: filled cells of an uneven lattice ----

struct Lattice {
    std::array<std::vector<double>, 3> lines;  // coordinates of the cell boundaries per axis
    glm::ivec3 n{0};
    std::vector<char> filled;
    bool at(glm::ivec3 c) const {
        return c.x >= 0 && c.y >= 0 && c.z >= 0 && c.x < n.x && c.y < n.y && c.z < n.z &&
               filled[std::size_t((c.z * n.y + c.y) * n.x + c.x)];
    }
    void set(glm::ivec3 c) { filled[std::size_t((c.z * n.y + c.y) * n.x + c.x)] = 1; }
};

// Fills cells until no edge or corner of the lattice is shared by cells that touch only
// there (which would make the surface non-manifold): around each lattice vertex, the filled
// cells and the empty cells must each be one face-connected group.
void makeManifold(Lattice& l) {
    for (bool changed = true; changed;) {
        changed = false;
        for (int z = 0; z <= l.n.z; ++z)
            for (int y = 0; y <= l.n.y; ++y)
                for (int x = 0; x <= l.n.x; ++x) {
                    std::array<glm::ivec3, 8> cells{};
                    std::array<bool, 8> full{};
                    for (int i = 0; i < 8; ++i) {
                        cells[std::size_t(i)] = {x - 1 + (i & 1), y - 1 + ((i >> 1) & 1), z - 1 + ((i >> 2) & 1)};
                        full[std::size_t(i)] = l.at(cells[std::size_t(i)]);
                    }
                    auto groups = [&](bool value) {
                        std::array<int, 8> label{};
                        label.fill(-1);
                        int count = 0;
                        for (int s = 0; s < 8; ++s) {
                            if (full[std::size_t(s)] != value || label[std::size_t(s)] >= 0) continue;
                            std::vector<int> stack{s};
                            label[std::size_t(s)] = count;
                            while (!stack.empty()) {
                                const int c = stack.back();
                                stack.pop_back();
                                for (int bit : {1, 2, 4}) {
                                    const int d = c ^ bit;
                                    if (full[std::size_t(d)] == value && label[std::size_t(d)] < 0) {
                                        label[std::size_t(d)] = count;
                                        stack.push_back(d);
                                    }
                                }
                            }
                            ++count;
                        }
                        return count;
                    };
                    if (groups(true) <= 1 && groups(false) <= 1) continue;
                    for (const glm::ivec3& c : cells)
                        if (c.x >= 0 && c.y >= 0 && c.z >= 0 && c.x < l.n.x && c.y < l.n.y && c.z < l.n.z && !l.at(c)) {
                            l.set(c);
                            changed = true;
                        }
                }
    }
}

Solid polycube(Rng& rng, int index) {
    Lattice l;
    for (int axis = 0; axis < 3; ++axis) {
        l.n[axis] = rng.range(2, 5);
        double x = rng.uniform(-3.0, 3.0);
        l.lines[std::size_t(axis)].push_back(x);
        for (int i = 0; i < l.n[axis]; ++i) {
            static const double kSpacings[] = {1.0, 0.5, 2.0, 1e-3, 1e-6, 0.3333333};
            x += kSpacings[rng.below(6)];
            l.lines[std::size_t(axis)].push_back(x);
        }
    }
    l.filled.assign(std::size_t(l.n.x * l.n.y * l.n.z), 0);
    for (char& f : l.filled) f = rng.uniform() < 0.55;
    l.set({0, 0, 0});
    makeManifold(l);

    Solid s;
    s.name = "polycube " + std::to_string(index);
    std::map<std::array<int, 3>, std::uint32_t> vertexOf;
    auto vertex = [&](int x, int y, int z) {
        const auto [it, inserted] = vertexOf.try_emplace({x, y, z}, std::uint32_t(s.mesh.positions.size()));
        if (inserted)
            s.mesh.positions.emplace_back(float(l.lines[0][std::size_t(x)]), float(l.lines[1][std::size_t(y)]),
                                          float(l.lines[2][std::size_t(z)]));
        return it->second;
    };
    for (int z = 0; z < l.n.z; ++z)
        for (int y = 0; y < l.n.y; ++y)
            for (int x = 0; x < l.n.x; ++x) {
                if (!l.at({x, y, z})) continue;
                s.volume += (l.lines[0][std::size_t(x + 1)] - l.lines[0][std::size_t(x)]) *
                            (l.lines[1][std::size_t(y + 1)] - l.lines[1][std::size_t(y)]) *
                            (l.lines[2][std::size_t(z + 1)] - l.lines[2][std::size_t(z)]);
                for (int axis = 0; axis < 3; ++axis)
                    for (int side : {0, 1}) {
                        glm::ivec3 d(0);
                        d[axis] = side ? 1 : -1;
                        if (l.at(glm::ivec3(x, y, z) + d)) continue;
                        // The face's four corners, counter-clockwise seen from outside.
                        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
                        std::array<std::uint32_t, 4> q{};
                        const int corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
                        for (int k = 0; k < 4; ++k) {
                            glm::ivec3 c(x, y, z);
                            c[axis] += side;
                            c[u] += corner[side ? k : 3 - k][0];
                            c[v] += corner[side ? k : 3 - k][1];
                            q[std::size_t(k)] = vertex(c.x, c.y, c.z);
                        }
                        s.mesh.indices.insert(s.mesh.indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
                    }
            }
    return s;
}

// ---- prisms: an outline (counter-clockwise in x, z seen from +y) extruded along y ----

// Ear clipping of a simple polygon (counter-clockwise).
std::vector<std::array<std::size_t, 3>> earClip(const std::vector<glm::dvec2>& p) {
    std::vector<std::size_t> left(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) left[i] = i;
    auto cross = [](glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; };
    std::vector<std::array<std::size_t, 3>> tris;
    while (left.size() > 3) {
        bool clipped = false;
        for (std::size_t i = 0; i < left.size() && !clipped; ++i) {
            const std::size_t a = left[(i + left.size() - 1) % left.size()], b = left[i], c = left[(i + 1) % left.size()];
            if (cross(p[b] - p[a], p[c] - p[b]) <= 0.0) continue;  // reflex or flat
            bool empty = true;
            for (std::size_t j : left) {
                if (j == a || j == b || j == c) continue;
                if (cross(p[b] - p[a], p[j] - p[a]) >= 0 && cross(p[c] - p[b], p[j] - p[b]) >= 0 &&
                    cross(p[a] - p[c], p[j] - p[c]) >= 0)
                    empty = false;
            }
            if (!empty) continue;
            tris.push_back({a, b, c});
            left.erase(left.begin() + std::ptrdiff_t(i));
            clipped = true;
        }
        if (!clipped) break;
    }
    if (left.size() == 3) tris.push_back({left[0], left[1], left[2]});
    return tris;
}

Solid prism(const std::string& name, const std::vector<glm::dvec2>& outline, double height, glm::dvec3 offset) {
    Solid s;
    s.name = name;
    const std::size_t n = outline.size();
    double area = 0.0;
    for (std::size_t i = 0; i < n; ++i)
        area += 0.5 * (outline[i].x * outline[(i + 1) % n].y - outline[(i + 1) % n].x * outline[i].y);
    s.volume = area * height;
    for (double y : {0.0, height})
        for (const glm::dvec2& q : outline) s.mesh.positions.push_back(glm::vec3(offset + glm::dvec3(q.x, y, -q.y)));
    // (x, -y) in the plan keeps counter-clockwise outlines counter-clockwise seen from +y.
    for (const auto& t : earClip(outline)) {
        s.mesh.indices.insert(s.mesh.indices.end(), {std::uint32_t(n + t[0]), std::uint32_t(n + t[1]), std::uint32_t(n + t[2])});
        s.mesh.indices.insert(s.mesh.indices.end(), {std::uint32_t(t[0]), std::uint32_t(t[2]), std::uint32_t(t[1])});
    }
    for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint32_t j = (i + 1) % std::uint32_t(n);
        s.mesh.indices.insert(s.mesh.indices.end(), {i, j, std::uint32_t(n) + j, i, std::uint32_t(n) + j, std::uint32_t(n) + i});
    }
    return s;
}

std::vector<glm::dvec2> letter(int which, double w, double t) {
    switch (which % 4) {
        case 0: return {{0, 0}, {w, 0}, {w, t}, {t, t}, {t, w}, {0, w}};                                         // L
        case 1: return {{0, 0}, {w, 0}, {w, w}, {w - t, w}, {w - t, t}, {t, t}, {t, w}, {0, w}};               // U
        case 2: return {{0, w - t}, {0.5 * (w - t), w - t}, {0.5 * (w - t), 0}, {0.5 * (w + t), 0},
                        {0.5 * (w + t), w - t}, {w, w - t}, {w, w}, {0, w}};                                    // T
        default: return {{0, 0}, {w, 0}, {w, t}, {t, t}, {t, 0.5 * (w - t)}, {0.8 * w, 0.5 * (w - t)},
                         {0.8 * w, 0.5 * (w + t)}, {t, 0.5 * (w + t)}, {t, w - t}, {w, w - t}, {w, w}, {0, w}};  // E
    }
}

std::vector<Solid> solids() {
    Rng rng(20261123);
    std::vector<Solid> out;
    for (int i = 0; i < 16; ++i) out.push_back(polycube(rng, i));
    for (int i = 0; i < 8; ++i) {
        const double w = rng.uniform(1.0, 8.0), t = w * (i % 2 ? 1e-3 : rng.uniform(0.1, 0.4));
        const glm::dvec3 far = i >= 6 ? glm::dvec3(1e4, -250.0, 3e3) : glm::dvec3(0.0);
        out.push_back(prism("letter " + std::to_string(i), letter(i, w, t), rng.uniform(0.01, 5.0), far));
    }
    for (int sides : {3, 7, 64}) {
        std::vector<glm::dvec2> ngon;
        for (int k = 0; k < sides; ++k) {
            const double a = 2.0 * 3.141592653589793 * k / sides;
            ngon.push_back({std::cos(a), std::sin(a)});
        }
        out.push_back(prism("prism " + std::to_string(sides), ngon, sides == 64 ? 1e-3 : 2.0, glm::dvec3(0.5, 0.25, 0.125)));
    }
    // The solid is what its float corners enclose (rounding moved the 1e-6 slabs and the far
    // letters): its volume comes from them, by the divergence theorem, here.
    for (Solid& s : out) {
        double v = 0.0;
        for (std::size_t t = 0; t + 2 < s.mesh.indices.size(); t += 3) {
            const glm::dvec3 a(s.mesh.positions[s.mesh.indices[t]]), b(s.mesh.positions[s.mesh.indices[t + 1]]),
                c(s.mesh.positions[s.mesh.indices[t + 2]]);
            v += glm::dot(a, glm::cross(b, c)) / 6.0;
            s.area += 0.5 * glm::length(glm::cross(b - a, c - a));
        }
        s.volume = v;
        float largest = 0.0f;
        for (const glm::vec3& p : s.mesh.positions) largest = std::max({largest, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
        s.floatSpacing = double(std::nextafter(largest, INFINITY) - largest);
    }
    return out;
}

// The checks on one piece as a file holds it: float positions relative to the pivot.
void expectClean(const sim::FracturePiece& piece, const std::string& where) {
    std::map<std::array<float, 3>, std::uint32_t> weld;
    std::vector<std::uint32_t> id;
    for (const glm::vec3& p : piece.mesh.positions) id.push_back(weld.try_emplace({p.x, p.y, p.z}, std::uint32_t(weld.size())).first->second);
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    std::size_t degenerate = 0;
    for (std::size_t t = 0; t < piece.mesh.indices.size(); t += 3) {
        const std::uint32_t a = id[piece.mesh.indices[t]], b = id[piece.mesh.indices[t + 1]], c = id[piece.mesh.indices[t + 2]];
        const glm::dvec3 pa(piece.mesh.positions[piece.mesh.indices[t]]), pb(piece.mesh.positions[piece.mesh.indices[t + 1]]),
            pc(piece.mesh.positions[piece.mesh.indices[t + 2]]);
        if (a == b || b == c || a == c || glm::cross(pb - pa, pc - pa) == glm::dvec3(0.0)) ++degenerate;
        ++directed[{a, b}];
        ++directed[{b, c}];
        ++directed[{c, a}];
    }
    std::size_t bad = 0;
    for (const auto& [e, n] : directed) {
        const auto back = directed.find({e.second, e.first});
        if (n != 1 || back == directed.end() || back->second != 1) ++bad;
    }
    EXPECT_EQ(degenerate, 0u) << where;
    EXPECT_EQ(bad, 0u) << where << ": edges not used once each way";
}

}  // namespace

TEST(FractureFuzz, CsgStyleSolidsGiveCleanPiecesThatAddUp) {
    std::size_t fractured = 0;
    int k = 0;
    for (const Solid& solid : solids()) {
        sim::FractureSettings s;
        s.pieces = 6 + (k * 7) % 25;
        s.seed = std::uint64_t(++k);
        sim::FractureResult r;
        try {
            r = sim::fractureMesh(solid.mesh, s);
        } catch (const InputError& e) {
            ADD_FAILURE() << solid.name << " was refused: " << e.what();
            continue;
        }
        ++fractured;
        double total = 0.0;
        for (const sim::FracturePiece& p : r.pieces) {
            total += p.mass.volume;
            expectClean(p, solid.name + ", " + p.name);
        }
        // 1e-6 of the volume; but no float positions can hold a slab 1e-3 thin, or a letter
        // at 10 km, closer than the float spacing there: the surface may move by that much.
        EXPECT_NEAR(total, solid.volume, std::max(1e-6 * solid.volume, solid.area * solid.floatSpacing)) << solid.name;
    }
    EXPECT_EQ(fractured, 27u);
}
