#pragma once
// Voronoi fracture of a closed mesh (CGAL inside; plain data outside).
//
// Seeds are sampled uniformly inside the volume (points drawn in the grid cells that lie
// inside the mesh or meet its surface, kept when CGAL's exact inside test says so),
// optionally denser around an impact point, or given by the caller.
// Each seed's Voronoi cell (bisector half-spaces of its Delaunay neighbours, clipped to
// the mesh's bounding box) is intersected with the mesh by CGAL corefinement with exact
// predicates. Cells are processed in a bounding-box hierarchy: each level intersects the
// mesh with a box around a group of cells, so a cell meets only the part of the mesh
// that can reach it. A cell that cuts the mesh into several parts gives several pieces.
// With roughness > 0, pieces are instead meshed from OpenVDB level sets with noisy cut
// surfaces (the exact path stays the default).
#include <dawnforge/core/materials.hpp>
#include <dawnforge/core/mesh.hpp>
#include <dawnforge/core/progress.hpp>
#include <dawnforge/sim/mass_properties.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace dawnforge::sim {

// The largest input fracture takes: it needs about 5 KB of memory per input triangle
// (measured: 350 MB for 75,000 triangles into 50 pieces), so 2 million fit in 10 GB.
inline constexpr std::size_t kMaxFractureTriangles = 2'000'000;

// How the cells cut the mesh: the restricted Voronoi diagram in one pass over the mesh (cells
// it cannot close by its symbolic corners fall back to corefinement), or one CGAL
// corefinement per cell (the older path, kept for comparison).
enum class FractureMethod : std::uint8_t { Rvd, Corefine };
const char* fractureMethodName(FractureMethod method);  // "rvd", "corefine"

struct FractureSettings {
    int pieces = 50;                            // seeds (Voronoi cells) for uniform sampling
    std::uint64_t seed = 1;
    std::optional<glm::dvec3> impact;           // cluster seeds around this point...
    double impactRadius = 1.0;                  // ...within about this radius (m)
    double impactDensity = 20.0;                // seeds near the impact are up to 1 + this many times denser
    std::vector<glm::dvec3> points;             // caller's seeds: used instead of sampling when not empty
    double density = 2400.0;                    // kg/m^3 (concrete)
    std::uint8_t interiorMaterial = kRubble;    // material ID of cut faces
    double interiorUvScale = 1.0;               // metres per UV unit on cut faces
    double minVolume = 0.0;                     // pieces smaller than this merge into their largest neighbour
    int levels = 0;                             // fracture pieces near the impact again, this many times
    int levelPieces = 8;                        // pieces per re-fractured piece
    double roughness = 0.0;                     // > 0: noisy cut surfaces of this amplitude (m), via OpenVDB level sets
    double roughScale = 0.0;                    // noise wavelength (m); 0: four times the roughness
    double voxelSize = 0.0;                     // level-set voxel (m); 0: half the roughness, within diag/400..diag/50
    glm::dvec3 grain{0.0, 1.0, 0.0};            // cells are stretched along this direction...
    double stretch = 1.0;                       // ...this many times (splinters of wood); 1: round cells
    FractureMethod method = FractureMethod::Rvd;
};

struct FracturePiece {
    std::string name;                           // piece_0000, piece_0001, ...
    Mesh mesh;                                  // relative to the centre of mass (the pivot)
    MassProperties mass;                        // centre of mass in world space
    std::uint32_t cell = 0;                     // the seed (Voronoi cell) it came from
    std::uint32_t level = 0;                    // 0, or the re-fracture level that made it
    std::int32_t part = -1;                     // fractureParts: the part it came from; -1 otherwise
    std::uint8_t material = 0;                  // fractureParts: what its part is made of
    bool closed = false;
};

struct Bond {
    std::uint32_t a = 0, b = 0;                 // piece indices, a < b
    double area = 0.0;                          // shared cut-face area (m^2)
    glm::dvec3 centroid{0.0};                   // of the shared face
    glm::dvec3 normal{0.0};                     // unit, pointing from a to b
    double strength = 0.0;                      // Pa; 0: SimulationSettings::strength decides
};

// One part of an assembly as fractureParts broke it.
enum class BreakStyle : std::uint8_t { Voronoi, Shards, Splinters };
const char* breakStyleName(BreakStyle style);  // "voronoi", "shards", "splinters"

struct PartResult {
    std::string kind;                           // as given ("wall", "window", ...)
    std::uint8_t material = 0;                  // as given
    BreakStyle style = BreakStyle::Voronoi;
    double volume = 0.0;                        // m^3, of the part's mesh
    std::size_t triangles = 0;                  // of the part's mesh
    std::size_t pieces = 0;                     // it broke into
    std::size_t cells = 0;                      // Voronoi cells (seeds) it was given
};

struct FractureResult {
    std::vector<FracturePiece> pieces;
    std::vector<Bond> bonds;
    std::vector<PartResult> parts;              // fractureParts: per part, in order; empty otherwise
    std::vector<glm::dvec3> seeds;              // level 0 seeds
    double inputVolume = 0.0;
    std::size_t inputTriangles = 0;
    std::size_t merged = 0;                     // pieces merged away by minVolume
    std::size_t cells = 0;                      // Voronoi cells cut, all levels
    std::size_t fallbackCells = 0;              // of them, cut by corefinement where the Rvd method could not close them
    std::vector<std::string> notes;             // what was done to the input first (turned outward), one sentence each
};

// Fractures `mesh`, which must be closed, manifold and free of self-intersections (throws
// InputError saying what is wrong otherwise, or when a piece cannot be computed). A mesh
// inside out or inconsistently oriented is oriented first (orientMesh()), said in `notes`. Deterministic: the same mesh and settings give the same result
// whatever the number of threads.
FractureResult fractureMesh(const Mesh& mesh, const FractureSettings& settings, const ProgressFn& progress = noProgress);

// Seeds only (the first stage of fractureMesh), for tests and tools.
std::vector<glm::dvec3> sampleFractureSeeds(const Mesh& mesh, const FractureSettings& settings);

}  // namespace dawnforge::sim
