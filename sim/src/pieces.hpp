#pragma once
// Fracture pieces between cutting and writing (plain data, no CGAL): the bonds from what
// pieces really share, and the merging of slivers into a neighbour.
#include <dawnforge/core/mesh.hpp>
#include <dawnforge/sim/fracture.hpp>
#include <dawnforge/sim/mass_properties.hpp>

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace dawnforge::sim::detail {

// The cut plane a triangle lies on: the two cells whose bisector it is (low, high); or none.
using PlaneKey = std::pair<std::int64_t, std::int64_t>;
inline constexpr PlaneKey kSurface{-1, -1};
inline PlaneKey planeKey(std::int64_t cell, std::int64_t neighbour) {
    return cell < neighbour ? PlaneKey{cell, neighbour} : PlaneKey{neighbour, cell};
}

// A piece as the cutting makes it: world space, corners on the fracture's fine grid. Once
// rounded for the files (roundForFiles), `mesh` holds float positions relative to `pivot`
// and the world positions are exactly pivot + those floats.
struct RawPiece {
    Mesh mesh;                                // world space; relative to the pivot once rounded
    std::vector<glm::dvec3> worldPositions;   // per mesh vertex
    std::vector<PlaneKey> planes;             // per triangle: its cut plane, or kSurface
    std::vector<glm::dvec3> points;           // the welded corners, for mass properties and merging
    std::vector<std::uint32_t> pointIndices;  // per triangle corner, into points
    std::int64_t cell = 0;                    // the cell that made it
    std::uint32_t level = 0;                  // 0, or the re-fracture level that made it
    std::int32_t part = -1;                   // fractureParts: the part it was cut from
    MassProperties mass;                      // once rounded: centerOfMass is the pivot
    glm::dvec3 pivot{0.0};                    // once rounded: a float point, the node translation
};

// The pieces as the files hold them. Each piece's pivot is its centre of mass rounded to
// float, and its corners are rounded, relative to the pivot, to a grid per axis on which
// every coordinate of the piece is an exact float (2^24 steps across its reach): the file holds
// exactly what is decided here, and the piece's own float precision (finer than the world's
// far from the origin) keeps its volume. The rounding can collapse an edge, flatten a triangle
// or make the piece touch itself: cleanSurface mends it, and a piece that splits is rounded
// again part by part.
std::vector<RawPiece> roundForFiles(std::vector<RawPiece> pieces, double density);

// A bond for every pair of pieces whose cut faces overlap by more than `minArea` (m^2).
std::vector<Bond> bondsBetween(std::span<const RawPiece> pieces, double minArea);

// Merges pieces below `minVolume` (m^3), smallest first, into the neighbour of the same part
// they share most area with: the faces between them go, which needs their shared triangles
// to coincide corner for corner; a sliver that shares its faces with nobody that way stays.
// Returns how many were merged.
std::size_t mergeSmallPieces(std::vector<RawPiece>& pieces, double minVolume, double density, double minArea);

}  // namespace dawnforge::sim::detail
