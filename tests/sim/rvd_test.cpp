// The restricted Voronoi diagram (sim/src/rvd.hpp) on its own: corners shared by key with the
// same bits in every cell, caps given to both cells and cancelling exactly, the surface parts
// partitioning every input triangle, and a mesh vertex on a bisector staying one key. The
// inside test is the test support's winding number, which shares nothing with the diagram.
#include "rvd.hpp"
#include "test_support.hpp"

#include <dawnforge/core/primitives.hpp>
#include <dawnforge/core/seed.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <set>

using namespace dawnforge;
using namespace dawnforge::sim::detail;

namespace {

struct Welded {
    Mesh mesh;
    std::vector<glm::dvec3> points;
    std::vector<std::array<std::uint32_t, 3>> triangles;
};

Welded welded(Mesh mesh) {
    Welded w{std::move(mesh), {}, {}};
    std::map<std::array<float, 3>, std::uint32_t> id;
    std::vector<std::uint32_t> of;
    for (const glm::vec3& p : w.mesh.positions) {
        const auto [it, inserted] = id.try_emplace({p.x, p.y, p.z}, std::uint32_t(w.points.size()));
        if (inserted) w.points.push_back(glm::dvec3(p));
        of.push_back(it->second);
    }
    for (std::size_t t = 0; t < w.mesh.triangleCount(); ++t)
        w.triangles.push_back({of[w.mesh.indices[3 * t]], of[w.mesh.indices[3 * t + 1]], of[w.mesh.indices[3 * t + 2]]});
    return w;
}

struct Diagram {
    Welded surface;
    std::vector<glm::dvec3> seeds;
    std::vector<std::vector<std::uint32_t>> neighbours;
    std::vector<RvdCell> cells;
    RvdStats stats;
};

// Every other seed as a neighbour: a superset of the Delaunay neighbours, with no CGAL here.
Diagram diagram(Mesh mesh, std::vector<glm::dvec3> seeds) {
    Diagram d{welded(std::move(mesh)), std::move(seeds), {}, {}, {}};
    const std::size_t n = d.seeds.size();
    d.neighbours.resize(n);
    for (std::uint32_t i = 0; i < n; ++i)
        for (std::uint32_t j = 0; j < n; ++j)
            if (i != j) d.neighbours[i].push_back(j);
    RvdSeeds s{d.seeds, d.neighbours, glm::dvec3(-1.1), glm::dvec3(1.1)};
    const Mesh& m = d.surface.mesh;
    d.cells = restrictedVoronoi({d.surface.points, d.surface.triangles}, s,
                                [&m](const glm::dvec3& p) { return test::windingNumber(m, p) > 0.5; }, &d.stats);
    return d;
}

std::vector<glm::dvec3> seedsInSphere(int count, double radius, std::uint64_t seed) {
    Rng rng(seed);
    std::vector<glm::dvec3> seeds;
    while (int(seeds.size()) < count) {
        const glm::dvec3 p(rng.uniform(-radius, radius), rng.uniform(-radius, radius), rng.uniform(-radius, radius));
        if (glm::length(p) < radius) seeds.push_back(p);
    }
    return seeds;
}

double signedVolume(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) { return glm::dot(a, glm::cross(b, c)) / 6.0; }

double area(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) { return 0.5 * glm::length(glm::cross(b - a, c - a)); }

const Diagram& sphere() {
    static const Diagram d = diagram(makeIcosphere(1.0f, 3), seedsInSphere(24, 0.95, 7));
    return d;
}

}  // namespace

TEST(Rvd, EveryCellClosesByKeysAndSharesItsCutCornersBitForBit) {
    const Diagram& d = sphere();
    ASSERT_EQ(d.cells.size(), 24u);
    EXPECT_GT(d.stats.wholeTriangles, d.stats.clippedTriangles);  // most triangles are copied whole
    EXPECT_GT(d.stats.clippedTriangles, 0u);
    std::map<RvdKey, glm::dvec3> position;
    std::map<RvdKey, std::set<std::size_t>> cellsOf;
    for (std::size_t i = 0; i < d.cells.size(); ++i) {
        const RvdCell& c = d.cells[i];
        EXPECT_TRUE(c.closed) << "cell " << i;
        EXPECT_FALSE(c.triangles.empty()) << "cell " << i;
        for (std::size_t k = 0; k < c.keys.size(); ++k) {
            const auto [it, inserted] = position.try_emplace(c.keys[k], c.points[k]);
            EXPECT_EQ(std::memcmp(&it->second, &c.points[k], sizeof(glm::dvec3)), 0) << "a key rounded two ways";
            cellsOf[c.keys[k]].insert(i);
        }
    }
    std::size_t cut = 0;
    for (const auto& [key, cells] : cellsOf) {
        if (key.kind == 0) continue;
        ++cut;
        EXPECT_GE(cells.size(), key.kind == 1 ? 2u : 3u) << "a cut corner in too few cells, kind " << key.kind;
    }
    EXPECT_GT(cut, 100u);
}

TEST(Rvd, CapsAreGivenToBothCellsAndCancelExactlyInTheVolumeSum) {
    const Diagram& d = sphere();
    std::set<std::pair<std::size_t, std::size_t>> pairs;
    double volume = 0.0, capVolume = 0.0;
    std::size_t capTriangles = 0;
    for (std::size_t i = 0; i < d.cells.size(); ++i) {
        const RvdCell& c = d.cells[i];
        for (const RvdCell::Triangle& t : c.triangles) {
            const double v = signedVolume(c.points[t.v[0]], c.points[t.v[1]], c.points[t.v[2]]);
            volume += v;
            if (t.origin >= 0) continue;
            capVolume += v;
            ++capTriangles;
            pairs.insert(std::minmax(i, std::size_t(-1 - t.origin)));
        }
    }
    EXPECT_GT(capTriangles, 50u);
    for (const auto& [a, b] : pairs) {
        std::multiset<std::array<RvdKey, 3>> fromA, fromB;
        double volumeA = 0.0, volumeB = 0.0;  // in the order each cell holds them
        for (const std::size_t side : {a, b}) {
            const RvdCell& c = d.cells[side];
            const auto other = std::int64_t(side == a ? b : a);
            for (const RvdCell::Triangle& t : c.triangles) {
                if (t.origin != -1 - other) continue;
                (side == a ? volumeA : volumeB) += signedVolume(c.points[t.v[0]], c.points[t.v[1]], c.points[t.v[2]]);
                std::array<RvdKey, 3> k{c.keys[t.v[0]], c.keys[t.v[1]], c.keys[t.v[2]]};
                if (side == b) std::swap(k[1], k[2]);
                std::rotate(k.begin(), std::min_element(k.begin(), k.end()), k.end());
                (side == a ? fromA : fromB).insert(k);
            }
        }
        EXPECT_EQ(fromA, fromB) << "cells " << a << " and " << b << " disagree on their cap";
        EXPECT_EQ(volumeA, -volumeB) << "cells " << a << " and " << b;  // exact negatives, not nearly
    }
    EXPECT_NEAR(capVolume, 0.0, 1e-14);  // summed across pairs, only the sum's own rounding is left
    double input = 0.0;
    for (const auto& t : d.surface.triangles)
        input += signedVolume(d.surface.points[t[0]], d.surface.points[t[1]], d.surface.points[t[2]]);
    EXPECT_NEAR(volume / input, 1.0, 1e-12);
}

TEST(Rvd, TheSurfacePartsPartitionEveryInputTriangle) {
    const Diagram& d = sphere();
    std::vector<double> covered(d.surface.triangles.size(), 0.0);
    std::vector<std::size_t> parts(d.surface.triangles.size(), 0);
    for (const RvdCell& c : d.cells)
        for (const RvdCell::Triangle& t : c.triangles)
            if (t.origin >= 0) {
                covered[std::size_t(t.origin)] += area(c.points[t.v[0]], c.points[t.v[1]], c.points[t.v[2]]);
                ++parts[std::size_t(t.origin)];
            }
    std::size_t split = 0;
    for (std::size_t t = 0; t < covered.size(); ++t) {
        const auto& tri = d.surface.triangles[t];
        const double whole = area(d.surface.points[tri[0]], d.surface.points[tri[1]], d.surface.points[tri[2]]);
        EXPECT_NEAR(covered[t] / whole, 1.0, 1e-12) << "triangle " << t;
        split += parts[t] > 1;
    }
    EXPECT_GT(split, 50u);
}

TEST(Rvd, AMeshVertexOnABisectorStaysOneKey) {
    // The bisector x = 0 of these two seeds runs along mesh edges and through mesh vertices.
    const Diagram d = diagram(test::gridBox(4), {{-0.5, 0.1, 0.2}, {0.5, 0.1, 0.2}});
    std::set<std::array<double, 3>> vertices;
    for (const glm::dvec3& p : d.surface.points) vertices.insert({p.x, p.y, p.z});
    double volume = 0.0;
    for (const RvdCell& c : d.cells) {
        EXPECT_TRUE(c.closed);
        for (std::size_t k = 0; k < c.keys.size(); ++k) {
            if (c.keys[k].kind == 0) continue;
            EXPECT_FALSE(vertices.count({c.points[k].x, c.points[k].y, c.points[k].z})) << "a cut corner on a vertex";
        }
        for (const RvdCell::Triangle& t : c.triangles) volume += signedVolume(c.points[t.v[0]], c.points[t.v[1]], c.points[t.v[2]]);
    }
    EXPECT_NEAR(volume, 8.0, 1e-12);
}
