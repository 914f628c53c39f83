// The street graph's faces through CGAL's 2D arrangements (exact predicates and
// constructions). All CGAL includes of the plan live here; plan.cpp sees plain data only
// (arrangement.hpp).
#include "arrangement.hpp"

#include <CGAL/Arr_consolidated_curve_data_traits_2.h>
#include <CGAL/Arr_segment_traits_2.h>
#include <CGAL/Arrangement_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include <algorithm>

namespace dawnforge::procgen {

namespace {
using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using SegmentTraits = CGAL::Arr_segment_traits_2<Kernel>;
using Traits = CGAL::Arr_consolidated_curve_data_traits_2<SegmentTraits, double>;
using Arrangement = CGAL::Arrangement_2<Traits>;
using Point = Kernel::Point_2;

glm::dvec2 toPlan(const Point& p) { return {CGAL::to_double(p.x()), CGAL::to_double(p.y())}; }

// Removes edges that have the same face on both sides (antennas), repeatedly: removing one
// can leave its neighbour dangling.
void removeDanglingEdges(Arrangement& arr) {
    for (;;) {
        std::vector<Arrangement::Halfedge_handle> dangling;
        for (auto e = arr.edges_begin(); e != arr.edges_end(); ++e)
            if (e->face() == e->twin()->face()) dangling.push_back(e);
        if (dangling.empty()) return;
        for (auto e : dangling) arr.remove_edge(e);
    }
}
}  // namespace

std::vector<ArrangementFace> arrangementFaces(std::span<const ArrangementSegment> segments) {
    std::vector<Traits::Curve_2> curves;
    curves.reserve(segments.size());
    for (const ArrangementSegment& s : segments) {
        const Point a(s.a.x, s.a.y), b(s.b.x, s.b.y);
        if (a == b) continue;
        curves.emplace_back(SegmentTraits::Curve_2(a, b), s.weight);
    }
    Arrangement arr;
    CGAL::insert(arr, curves.begin(), curves.end());
    removeDanglingEdges(arr);

    std::vector<ArrangementFace> faces;
    for (auto f = arr.faces_begin(); f != arr.faces_end(); ++f) {
        if (f->is_unbounded()) continue;
        ArrangementFace face;
        face.hasHoles = f->number_of_holes() > 0 || f->number_of_isolated_vertices() > 0;
        auto he = f->outer_ccb();
        const auto first = he;
        do {
            face.polygon.push_back(toPlan(he->source()->point()));
            double weight = 0.0;
            for (double w : he->curve().data()) weight = std::max(weight, w);
            face.edgeWeight.push_back(weight);
        } while (++he != first);
        faces.push_back(std::move(face));
    }
    return faces;
}

}  // namespace dawnforge::procgen
