#include "tetrahedralize.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>

#include <tetgen.h>

namespace dawnforge::sim::detail {

Tetrahedra tetrahedralize(std::span<const glm::dvec3> points, std::span<const std::array<std::uint32_t, 3>> triangles) {
    tetgenio in, out;  // tetgenio frees its arrays with delete[] in its destructor
    in.firstnumber = 0;
    in.numberofpoints = static_cast<int>(points.size());
    in.pointlist = new REAL[points.size() * 3];
    for (std::size_t i = 0; i < points.size(); ++i) {
        in.pointlist[3 * i] = points[i].x;
        in.pointlist[3 * i + 1] = points[i].y;
        in.pointlist[3 * i + 2] = points[i].z;
    }
    in.numberoffacets = static_cast<int>(triangles.size());
    in.facetlist = new tetgenio::facet[triangles.size()];
    for (std::size_t f = 0; f < triangles.size(); ++f) {
        tetgenio::facet& facet = in.facetlist[f];
        tetgenio::init(&facet);
        facet.numberofpolygons = 1;
        facet.polygonlist = new tetgenio::polygon[1];
        tetgenio::init(&facet.polygonlist[0]);
        facet.polygonlist[0].numberofvertices = 3;
        facet.polygonlist[0].vertexlist = new int[3];
        for (int k = 0; k < 3; ++k) facet.polygonlist[0].vertexlist[k] = static_cast<int>(triangles[f][std::size_t(k)]);
    }
    // p: tetrahedralise the piecewise linear complex; Y: keep the surface triangles as
    // they are (no Steiner points on the boundary); Q: quiet.
    char switches[] = "pYQ";
    try {
        ::tetrahedralize(switches, &in, &out);
    } catch (int code) {
        throw InputError(format("TetGen could not tetrahedralise the mesh (error {}): is it closed and free of "
                                "self-intersections?", code));
    }
    Tetrahedra result;
    result.points.reserve(std::size_t(out.numberofpoints));
    for (int i = 0; i < out.numberofpoints; ++i)
        result.points.emplace_back(out.pointlist[3 * i], out.pointlist[3 * i + 1], out.pointlist[3 * i + 2]);
    const int corners = out.numberofcorners;
    result.tets.reserve(std::size_t(out.numberoftetrahedra));
    for (int t = 0; t < out.numberoftetrahedra; ++t) {
        const int* c = out.tetrahedronlist + std::size_t(t) * std::size_t(corners);
        result.tets.push_back({std::uint32_t(c[0]), std::uint32_t(c[1]), std::uint32_t(c[2]), std::uint32_t(c[3])});
    }
    return result;
}

}  // namespace dawnforge::sim::detail
