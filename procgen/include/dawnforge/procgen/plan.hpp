#pragma once
// The city plan: streets, the coast, blocks (faces of the street graph, through CGAL's 2D
// arrangements) and lots (recursive splits of a block, each touching a street).
// Plan coordinates: geometry2d.hpp. The city covers [0, size.x] x [0, size.y].
#include <dawnforge/core/progress.hpp>
#include <dawnforge/procgen/geometry2d.hpp>
#include <dawnforge/procgen/recipe.hpp>

#include <cstdint>
#include <vector>

namespace dawnforge::procgen {

struct Street {
    int id = 0;
    bool major = false;
    double width = 0.0;                 // kerb to kerb
    std::vector<glm::dvec2> polyline;   // centre line, clipped to the land
};

struct Block {
    int id = 0;
    Polygon2 curb;     // the kerb line: the arrangement face inset by half of each bounding street's width
    Polygon2 inner;    // the curb inset by the sidewalk width: what the lots share
    std::vector<int> lots;
};

struct Lot {
    int id = 0;
    int block = 0;
    Polygon2 polygon;               // convex, inside its block's inner polygon
    std::vector<bool> streetEdge;   // per edge i (polygon[i] -> polygon[i+1]): lies on the block's inner boundary
    int frontEdge = 0;              // the longest street edge: where the entrance goes
};

struct CityPlan {
    glm::dvec2 size{0.0};
    std::vector<Street> streets;
    std::vector<Block> blocks;      // sorted by centroid (y, then x); id = index
    std::vector<Lot> lots;          // block by block; id = index
    std::vector<glm::dvec2> coastline;  // west to east, x ascending; empty when there is no sea
};

// The plan for a whole city of `size` metres. Deterministic in (recipe, seed, size); it does
// not depend on tiles (a tile takes its part of the whole plan).
CityPlan planCity(const CityRecipe& recipe, std::uint64_t seed, glm::dvec2 size,
                  const ProgressFn& progress = noProgress);

// The coast's y at x (linear between coastline points); -infinity without a sea.
double coastY(const CityPlan& plan, double x);

}  // namespace dawnforge::procgen
