#pragma once
// The restricted Voronoi diagram of a closed surface: the pieces of a Voronoi fracture in one
// pass over the mesh, instead of one mesh boolean per cell (Yan, Lévy et al., SGP 2009; the
// clipped form of Yan, Wang, Lévy, Liu, CAD 2013).
//
// Every corner is symbolic: a key naming what made it (an input vertex; an input edge cut by
// a bisector; an input triangle met by a Voronoi edge; a corner of a Voronoi cell), so that
// neighbouring pieces share corners by identity. Sides are decided exactly (an interval filter,
// then rational arithmetic), ties going to the seed with the smaller index; each key's
// position is a function of the key alone, so every piece that has it rounds it the same way.
//
// A cell whose surface does not close by keys (degenerate seeds or meshes) is reported, not
// guessed at: the caller cuts that one another way. Plain data here; CGAL stays inside rvd.cpp.
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace dawnforge::sim::detail {

// What made a corner. kind: 0 input vertex (x[0]); 1 input edge (x[0] < x[1]) cut by the
// bisector of seeds x[2] < x[3]; 2 input triangle x[0] met by the Voronoi edge of seeds
// x[1] < x[2] < x[3]; 3 a Voronoi cell corner, sites x[0] < ... < x[3] (a site is a seed, or
// seeds + b for the b-th face of the bounding box).
struct RvdKey {
    std::uint32_t kind = 0;
    std::array<std::uint32_t, 4> x{};
    auto operator<=>(const RvdKey&) const = default;
};

struct RvdSurface {
    std::span<const glm::dvec3> points;
    std::span<const std::array<std::uint32_t, 3>> triangles;  // counter-clockwise from outside
};

// The metric of stretched cells: distances along the unit grain shrink by `stretch`, so cells come
// out `stretch` times longer along it (splinters). Its bisectors are still planes: through the
// midpoint of two seeds, normal to M·(b − a) with M = I + shrink()·g·gᵀ; its Delaunay neighbours
// are those of the seeds squeezed along the grain.
struct Metric {
    glm::dvec3 grain{0.0, 1.0, 0.0};  // unit
    double stretch = 1.0;
    double shrink() const { return 1.0 / (stretch * stretch) - 1.0; }
    glm::dvec3 squeeze(const glm::dvec3& p) const { return p + (1.0 / stretch - 1.0) * glm::dot(p, grain) * grain; }
    glm::dvec3 bisectorNormal(const glm::dvec3& d) const { return d + shrink() * glm::dot(d, grain) * grain; }
};

struct RvdSeeds {
    std::span<const glm::dvec3> points;
    std::span<const std::vector<std::uint32_t>> neighbours;  // per seed, sorted: at least its Delaunay neighbours
    glm::dvec3 boxMin{0.0}, boxMax{0.0};                       // strictly around the surface
    Metric metric{};
};

// One cell's pieces before rounding: closed by keys when `closed`.
struct RvdCell {
    struct Triangle {
        std::array<std::uint32_t, 3> v;  // into points/keys
        std::int64_t origin;             // >= 0: the input triangle; < 0: the cap with seed -1 - origin
    };
    std::vector<glm::dvec3> points;
    std::vector<RvdKey> keys;
    std::vector<Triangle> triangles;
    bool closed = true;  // false: the keys do not close (the caller must cut this cell another way)
};

struct RvdStats {
    std::size_t wholeTriangles = 0, clippedTriangles = 0;
};

// The cells of `seeds` restricted to the volume `surface` bounds. `inside` says whether a
// point lies inside the surface (called on corners of Voronoi cells only, from many threads).
std::vector<RvdCell> restrictedVoronoi(const RvdSurface& surface, const RvdSeeds& seeds,
                                       const std::function<bool(const glm::dvec3&)>& inside, RvdStats* stats = nullptr);

}  // namespace dawnforge::sim::detail
