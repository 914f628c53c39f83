#pragma once
// Fracture of an assembly of closed parts that touch, such as a generated building (walls,
// slabs, panes, doors, ...): each part is broken the way its material breaks, and pieces of
// different parts that touch are bonded like pieces of one part.
//
// - Voronoi (brick, concrete, plaster, ...): cells as fractureMesh makes them; the parts
//   share `pieces` cells by volume, weighted like the seeds near the impact; a thin part gets
//   at least one cell per (2s)² of one face (s the mean cell's size), so a long band is not one piece.
// - Shards (glass): many small cells, about `shardSize` across, so a pane shatters.
// - Splinters (wood): cells stretched along the part's grain (Voronoi under a metric that
//   shortens distances along it), about `splinterWidth` wide and `splinterLength` long.
//
// Where two parts touch (faces on one plane, facing each other), their surface faces get a
// plane key of their own and become cut faces for the bonds: the bond between pieces of two
// parts is the overlap of what they really share, as between two pieces of one part. All
// parts are cut on one grid, so shared faces stay on one plane.
#include <dawnforge/core/materials.hpp>
#include <dawnforge/core/mesh.hpp>
#include <dawnforge/core/progress.hpp>
#include <dawnforge/sim/fracture.hpp>

#include <array>
#include <cstdint>
#include <span>
#include <string>

namespace dawnforge::sim {

// How one material breaks.
struct MaterialBreak {
    BreakStyle style = BreakStyle::Voronoi;
    double density = 2400.0;   // kg/m^3
    double strength = 3e6;     // Pa: the glue of its bonds (a bond between two materials takes the weaker)
};

// Per core material (core/materials.hpp): glass shatters into shards, wood splinters, the
// rest breaks into Voronoi cells; densities of the real materials (brick 1900, concrete
// 2400, plaster 1200, glass 2500, wood 600, metal 1500 for railings that are mostly air, ...);
// glue strengths: concrete 3e6 Pa; brick, trim, roof tiles and plaster (the render of a
// masonry wall) 1.5e6; wood 9e5; interior walls 6e5; glass 1.5e5. A bond breaks on the stress
// above what it carries at rest (SimulationSettings::strength), and a building's walls carry up
// to about 1e6 Pa of their own weight: strengths of that order keep a hole from bringing the
// rest down, unless the hit is hard (a generic mesh, light and unloaded, takes the
// simulation's default, 1e6).
std::array<MaterialBreak, kMaterialCount> defaultMaterialBreaks();

struct FracturePart {
    std::string kind;                 // what it is ("wall", "window", ...), recorded per piece
    std::uint8_t material = kConcrete;  // what it is made of: how it breaks and how heavy it is
    Mesh mesh;                        // closed, manifold, outward, world space
    glm::dvec3 grain{0.0, 1.0, 0.0};  // splinters run along this
};

struct PartsFractureSettings {
    double shardSize = 0.5;           // glass: shards about this wide (m)
    double splinterWidth = 0.15;      // wood: splinters about this wide (m)...
    double splinterLength = 0.9;      // ...and this long along the grain (m)
    // The rest as for one mesh: pieces (the Voronoi cells shared by the Voronoi parts by
    // weighted volume, at least one each), seed, impact and its radius and density boost
    // (weighting both how many cells each Voronoi part gets and where they fall), levels and
    // level pieces, cut-face material and UV scale, minVolume (pieces merge within their part).
    // points, density, roughness, grain and stretch are not used.
    FractureSettings common;
    std::array<MaterialBreak, kMaterialCount> materials = defaultMaterialBreaks();
};

// Fractures every part (each closed, manifold, outward and free of self-intersections:
// an InputError names the part that is not) and bonds the pieces, within a part and across
// parts that touch; each bond's strength is the weaker of its two pieces' materials'. Pieces come part by part; FracturePiece::part says which, and
// FractureResult::parts holds what each part became. Deterministic whatever the number of
// threads.
FractureResult fractureParts(std::span<const FracturePart> parts, const PartsFractureSettings& settings,
                             const ProgressFn& progress = noProgress);

}  // namespace dawnforge::sim
