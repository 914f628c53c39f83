#pragma once
// The surface of a fracture piece once its corners are rounded to the grid the files can hold
// exactly: rounding can collapse an edge (two corners on one grid point), flatten a triangle
// (three corners on one line) or make a piece touch itself along an edge or at a corner.
// cleanSurface() mends all three on plain data, with exact integer arithmetic.
#include <glm/ext/vector_int3_sized.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace dawnforge::sim::detail {

// A corner's attributes (normal, UVs, material) are the caller's vertex `attr`; a corner that a
// flip made on a neighbour's edge has kDerived | i, the i-th entry of CleanSurface::derived.
inline constexpr std::uint32_t kDerived = 0x80000000u;

struct GridTriangle {
    std::array<std::uint32_t, 3> v;    // indices into the grid points, counter-clockwise seen from outside
    std::int64_t origin;               // what the triangle lies on (carried through, never read)
    std::array<std::uint32_t, 3> attr{};  // per corner, carried through (see kDerived)
};

// The attributes of a corner made on the edge from the corner with attributes `from` to the one
// with `to`, at `t` of the way: interpolate them.
struct DerivedCorner {
    std::uint32_t from = 0, to = 0;
    double t = 0.0;
};

struct CleanSurface {
    std::vector<std::vector<GridTriangle>> parts;  // closed parts, each with the cavities it encloses
    std::size_t collapsed = 0;                     // triangles dropped: two corners on one grid point
    std::size_t flattened = 0;                     // zero-area triangles flipped away into a neighbour
    std::size_t cancelled = 0;                     // triangles dropped in pairs: the same points, facing apart
    std::size_t unmended = 0;                      // zero-area triangles left (no neighbour to flip with)
    std::vector<DerivedCorner> derived;            // attributes of corners that flips made
};

// Drops collapsed triangles; replaces each zero-area triangle (a, b, c) with c on edge ab, and
// its neighbour (b, a, d), by (b, c, d) and (c, a, d), which carry the neighbour's origin;
// drops pairs of triangles on the same points facing opposite ways (a flattened sliver); then
// splits the surface where it touches itself: triangles are connected across edges used by
// exactly two triangles in opposite directions, and each connected shell is a part, except that
// an inward shell (a cavity: negative volume) joins the outward shell that encloses it.
// Parts come in the order of their smallest grid point; triangles keep their relative order.
CleanSurface cleanSurface(std::span<const glm::i64vec3> points, std::vector<GridTriangle> triangles);

}  // namespace dawnforge::sim::detail
