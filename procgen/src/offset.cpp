// Polygon inset through CGAL's straight-skeleton offset (the only CGAL offset code of
// procgen; roofs build their own skeleton in roof.cpp).
#include <dawnforge/procgen/geometry2d.hpp>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/create_offset_polygons_2.h>

#include <cmath>

namespace dawnforge::procgen {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalPolygon = CGAL::Polygon_2<Kernel>;
}  // namespace

Polygon2 insetPolygon(std::span<const glm::dvec2> polygon, double distance) {
    if (polygon.size() < 3 || !(distance > 0.0)) return Polygon2(polygon.begin(), polygon.end());
    // Work relative to the first vertex: offsets far from the origin lose digits otherwise.
    const glm::dvec2 origin = polygon[0];
    if (!isSimple(polygon) || signedArea(polygon) <= 0.0) return {};
    CgalPolygon input;
    for (glm::dvec2 p : polygon) input.push_back(Kernel::Point_2(p.x - origin.x, p.y - origin.y));
    const auto parts = CGAL::create_interior_skeleton_and_offset_polygons_2(distance, input);
    Polygon2 best;
    double bestArea = 0.0;
    for (const auto& part : parts) {
        if (part->orientation() != CGAL::COUNTERCLOCKWISE) continue;
        const double area = std::abs(CGAL::to_double(part->area()));
        if (area <= bestArea) continue;
        bestArea = area;
        best.clear();
        for (auto v = part->vertices_begin(); v != part->vertices_end(); ++v)
            best.push_back({CGAL::to_double(v->x()) + origin.x, CGAL::to_double(v->y()) + origin.y});
    }
    return simplifyPolygon(best, 1e-7);
}

}  // namespace dawnforge::procgen
