// How a building's parts share a fracture (fracture_parts.hpp): each part's cells, density, seed
// and grain, and the table of how each material breaks; fracture.cpp does the cutting.
#include "part_plan.hpp"

#include <dawnforge/core/seed.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace dawnforge::sim {

const char* breakStyleName(BreakStyle style) {
    switch (style) {
        case BreakStyle::Voronoi: return "voronoi";
        case BreakStyle::Shards: return "shards";
        case BreakStyle::Splinters: return "splinters";
    }
    return "voronoi";
}

std::array<MaterialBreak, kMaterialCount> defaultMaterialBreaks() {
    std::array<MaterialBreak, kMaterialCount> table;
    table.fill({BreakStyle::Voronoi, 2400.0, 3e6});
    table[kAsphalt].density = 2300.0;
    table[kPaving].density = 2300.0;
    table[kBrick] = {BreakStyle::Voronoi, 1900.0, 1.5e6};
    table[kPlaster] = {BreakStyle::Voronoi, 1200.0, 1.5e6};  // the render of a masonry wall: it breaks as the wall
    table[kGlass] = {BreakStyle::Shards, 2500.0, 1.5e5};
    table[kMetal].density = 1500.0;  // railings are bars and air, drawn as solid plates
    table[kTrim] = {BreakStyle::Voronoi, 2200.0, 1.5e6};
    table[kRoofTiles] = {BreakStyle::Voronoi, 1800.0, 1.5e6};
    table[kWood] = {BreakStyle::Splinters, 600.0, 9e5};
    table[kInteriorWall] = {BreakStyle::Voronoi, 1200.0, 6e5};
    table[kSand] = {BreakStyle::Voronoi, 1600.0, 3e5};
    table[kRubble] = {BreakStyle::Voronoi, 1900.0, 3e5};
    return table;
}

namespace {

// ∫ over the mesh of the impact weight 1 + boost·exp(−(d/r)²) (the density of seeds), by
// signed tetrahedra from the bounds' centre, each weighted at its centroid: exact for the
// plain volume, close enough to share cells out near the impact.
double weightedVolume(const Mesh& mesh, const FractureSettings& s) {
    const Bounds b = computeBounds(mesh.positions);
    const glm::dvec3 o = 0.5 * (b.min + b.max);
    double sum = 0.0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const glm::dvec3 a(mesh.positions[mesh.indices[3 * t]]), bb(mesh.positions[mesh.indices[3 * t + 1]]),
            c(mesh.positions[mesh.indices[3 * t + 2]]);
        const double volume = glm::dot(a - o, glm::cross(bb - o, c - o)) / 6.0;
        double weight = 1.0;
        if (s.impact) {
            const double d = glm::length(0.25 * (o + a + bb + c) - *s.impact) / s.impactRadius;
            weight += s.impactDensity * std::exp(-d * d);
        }
        sum += volume * weight;
    }
    return std::max(sum, 0.0);
}

// The length of a part as a bar whose section is h (the smallest extent of its bounds) by d: its
// surface's half is L·(h + d), its volume L·h·d. A band round a building is 46 m long; a wall,
// a slab or a block comes out no longer than about its perimeter's half.
double surfaceArea(const Mesh& mesh);
double barLength(const Mesh& mesh, double volume) {
    const Bounds b = computeBounds(mesh.positions);
    const glm::dvec3 e = b.max - b.min;
    const double h = std::max(std::min({e.x, e.y, e.z}), 1e-3);
    return std::max(0.0, (0.5 * surfaceArea(mesh) - volume / h) / h);
}

double surfaceArea(const Mesh& mesh) {
    double area = 0.0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const glm::dvec3 a(mesh.positions[mesh.indices[3 * t]]), b(mesh.positions[mesh.indices[3 * t + 1]]),
            c(mesh.positions[mesh.indices[3 * t + 2]]);
        area += 0.5 * glm::length(glm::cross(b - a, c - a));
    }
    return area;
}

}  // namespace

namespace detail {

std::vector<FractureSettings> planParts(std::span<const FracturePart> parts, const PartsFractureSettings& settings,
                                        FractureResult& result) {
    const std::size_t n = parts.size();
    std::vector<double> weights(n, 0.0);
    for (std::size_t i = 0; i < n; ++i)
        if (result.parts[i].style == BreakStyle::Voronoi) weights[i] = weightedVolume(parts[i].mesh, settings.common);
    const double totalWeight = std::accumulate(weights.begin(), weights.end(), 0.0);
    double voronoiVolume = 0.0;
    for (std::size_t i = 0; i < n; ++i)
        if (result.parts[i].style == BreakStyle::Voronoi) voronoiVolume += result.parts[i].volume;
    const double cellSize = std::cbrt(voronoiVolume / double(settings.common.pieces));
    std::vector<FractureSettings> partSettings(n, settings.common);
    for (std::size_t i = 0; i < n; ++i) {
        const FracturePart& part = parts[i];
        FractureSettings& ps = partSettings[i];
        const double area = 0.5 * surfaceArea(part.mesh);  // one face of a thin plate
        double cells = 1.0;
        switch (result.parts[i].style) {
            case BreakStyle::Voronoi:
                cells = totalWeight > 0.0 ? settings.common.pieces * weights[i] / totalWeight : 1.0;
                if (cellSize > 0.0)
                    cells = std::max({cells, area / (4.0 * cellSize * cellSize),
                                      barLength(part.mesh, result.parts[i].volume) / (2.0 * cellSize)});
                break;
            case BreakStyle::Shards: cells = area / (settings.shardSize * settings.shardSize); break;
            case BreakStyle::Splinters:
                cells = area / (settings.splinterWidth * settings.splinterLength);
                ps.grain = glm::normalize(part.grain);
                ps.stretch = settings.splinterLength / settings.splinterWidth;
                break;
        }
        ps.pieces = int(std::clamp(std::round(cells), 1.0, 100000.0));
        ps.density = settings.materials[part.material].density;
        ps.seed = deriveSeed(settings.common.seed, "fracture-part", i);
        ps.levels = 0;
        ps.points.clear();
        if (ps.pieces == 1) {  // the whole part is one piece: no seed to sample
            const Bounds b = computeBounds(part.mesh.positions);
            ps.points.push_back(0.5 * (b.min + b.max));
        }
        result.parts[i].cells = std::size_t(ps.pieces);
    }
    return partSettings;
}

}  // namespace detail

}  // namespace dawnforge::sim
