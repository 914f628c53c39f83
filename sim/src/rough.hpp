#pragma once
// Rough cut surfaces through OpenVDB level sets, kept to one translation unit.
//
// A piece is the zero level set of max(mesh SDF, max_k g_k), where g_k is the signed
// distance to cell plane k plus noise. The noise is antisymmetric across each bisector
// (cell i adds it, its neighbour subtracts it), so two neighbours share one noisy
// boundary; all pieces are meshed on one world-aligned voxel lattice.
#include <dawnforge/core/mesh.hpp>

#include <cstdint>
#include <vector>

namespace dawnforge::sim::detail {

struct RoughPlane {
    glm::dvec3 normal;        // unit; the cell is where dot(normal, p) + offset + noise < 0
    double offset;
    double noiseSign;         // +1 or -1 across a bisector (opposite for the neighbour), 0 on a bounding plane
    std::int64_t neighbour;   // global cell across it, or -1
};

struct RoughCell {
    std::vector<RoughPlane> planes;
    glm::dvec3 lo, hi;        // bounding box of the exact cell
};

struct RoughSettings {
    double amplitude = 0.05;  // noise amplitude (m)
    double featureSize = 0.2; // noise wavelength (m)
    double voxelSize = 0.02;  // lattice spacing (m)
    std::uint64_t seed = 1;
    std::uint8_t interiorMaterial = 15;
    double uvScale = 1.0;     // metres per UV unit
};

struct RoughPiece {
    Mesh mesh;                              // world space, with normals, uv0, material IDs
    std::vector<std::int64_t> triangleKeys; // neighbour cell across each triangle, or -1
};

// Pieces of each cell (several when a cell cuts the mesh into islands), in a fixed order.
std::vector<std::vector<RoughPiece>> roughPieces(const Mesh& input, const std::vector<RoughCell>& cells,
                                                 const RoughSettings& settings);

}  // namespace dawnforge::sim::detail
