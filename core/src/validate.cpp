// Mesh validation and repair. Topology (boundary, non-manifold edges and vertices,
// orientation, components) is counted directly on the position-welded triangles;
// the geometric questions go to CGAL Polygon Mesh Processing with exact predicates:
// self-intersections, volume, outward orientation, and the repair steps.
// This is the only translation unit of core that includes CGAL (it compiles slowly).
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/validate.hpp>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/stitch_borders.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <array>
#include <dawnforge/core/format.hpp>
#include <numeric>

namespace dawnforge {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using Polygon = std::vector<std::size_t>;

namespace {

struct UnionFind {
    std::vector<std::uint32_t> parent;
    explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
    std::uint32_t find(std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    }
    void unite(std::uint32_t a, std::uint32_t b) {
        a = find(a);
        b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
};

// Triangles over distinct welded vertices, as CGAL's polygon soups want them.
struct Soup {
    std::vector<Point> points;
    std::vector<Polygon> polygons;
};

Soup weldedSoup(const Mesh& mesh, std::size_t* repeatedCornerTriangles) {
    const std::vector<std::uint32_t> canonical = weldByPosition(mesh.positions);
    std::vector<std::size_t> compact(mesh.positions.size(), SIZE_MAX);
    Soup soup;
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        if (canonical[i] != i) continue;
        compact[i] = soup.points.size();
        const glm::vec3& p = mesh.positions[i];
        soup.points.emplace_back(p.x, p.y, p.z);
    }
    std::size_t repeated = 0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        Polygon tri(3);
        for (std::size_t k = 0; k < 3; ++k) tri[k] = compact[canonical[mesh.indices[3 * t + k]]];
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) {
            ++repeated;
            continue;
        }
        soup.polygons.push_back(std::move(tri));
    }
    if (repeatedCornerTriangles) *repeatedCornerTriangles = repeated;
    return soup;
}

Mesh toMesh(const SurfaceMesh& sm, const std::string& name) {
    Mesh out;
    out.name = name;
    std::vector<std::uint32_t> index(sm.number_of_vertices() + sm.number_of_removed_vertices());
    for (SurfaceMesh::Vertex_index v : sm.vertices()) {
        index[v] = static_cast<std::uint32_t>(out.positions.size());
        const Point& p = sm.point(v);
        out.positions.emplace_back(float(p.x()), float(p.y()), float(p.z()));
    }
    for (SurfaceMesh::Face_index f : sm.faces())
        for (SurfaceMesh::Vertex_index v : CGAL::vertices_around_face(sm.halfedge(f), sm))
            out.indices.push_back(index[v]);
    return out;
}

}  // namespace

MeshReport inspectMesh(const Mesh& mesh) {
    MeshReport r;
    r.triangles = mesh.triangleCount();
    r.attributeVertices = mesh.vertexCount();
    r.bounds = computeBounds(mesh.positions);

    std::size_t repeated = 0;
    Soup soup = weldedSoup(mesh, &repeated);
    r.vertices = soup.points.size();
    r.degenerateTriangles = repeated;
    for (const Polygon& t : soup.polygons) {
        const Point &a = soup.points[t[0]], &b = soup.points[t[1]], &c = soup.points[t[2]];
        if (CGAL::collinear(a, b, c)) ++r.degenerateTriangles;
        r.area += std::sqrt(CGAL::to_double(Kernel::Triangle_3(a, b, c).squared_area()));
    }

    // Every use of an undirected edge, sorted so that uses of one edge are adjacent.
    struct EdgeUse {
        std::size_t lo, hi;
        std::uint32_t face;
        bool forward;  // the triangle walks lo -> hi
        bool operator<(const EdgeUse& o) const { return std::tie(lo, hi, face) < std::tie(o.lo, o.hi, o.face); }
    };
    const std::size_t faces = soup.polygons.size();
    std::vector<EdgeUse> uses;
    uses.reserve(3 * faces);
    for (std::size_t f = 0; f < faces; ++f)
        for (std::size_t k = 0; k < 3; ++k) {
            const std::size_t a = soup.polygons[f][k], b = soup.polygons[f][(k + 1) % 3];
            uses.push_back({std::min(a, b), std::max(a, b), static_cast<std::uint32_t>(f), a < b});
        }
    std::sort(uses.begin(), uses.end());

    UnionFind componentOf(faces);
    UnionFind fanOf(3 * faces);  // corners (face, k), joined across manifold edges around each vertex
    auto corner = [&](std::uint32_t face, std::size_t vertex) {
        const Polygon& t = soup.polygons[face];
        return 3 * face + static_cast<std::uint32_t>(vertex == t[0] ? 0 : vertex == t[1] ? 1 : 2);
    };
    r.consistentlyOriented = true;
    for (std::size_t i = 0; i < uses.size();) {
        std::size_t j = i;
        while (j < uses.size() && uses[j].lo == uses[i].lo && uses[j].hi == uses[i].hi) ++j;
        const std::size_t count = j - i;
        for (std::size_t k = i + 1; k < j; ++k) componentOf.unite(uses[i].face, uses[k].face);
        if (count == 1 && ++r.boundaryEdges <= 3) {
            const Point &a = soup.points[uses[i].lo], &b = soup.points[uses[i].hi];
            r.openEdges.emplace_back(glm::dvec3(a.x(), a.y(), a.z()), glm::dvec3(b.x(), b.y(), b.z()));
        }
        if (count > 2) ++r.nonManifoldEdges;
        if (count == 2) {
            if (uses[i].forward == uses[i + 1].forward) r.consistentlyOriented = false;
            for (std::size_t v : {uses[i].lo, uses[i].hi})
                fanOf.unite(corner(uses[i].face, v), corner(uses[i + 1].face, v));
        }
        i = j;
    }
    std::vector<std::uint32_t> firstFan(soup.points.size(), UINT32_MAX);
    std::vector<bool> pinched(soup.points.size(), false);
    for (std::uint32_t f = 0; f < faces; ++f)
        for (std::size_t k = 0; k < 3; ++k) {
            const std::size_t v = soup.polygons[f][k];
            const std::uint32_t fan = fanOf.find(3 * f + static_cast<std::uint32_t>(k));
            if (firstFan[v] == UINT32_MAX)
                firstFan[v] = fan;
            else if (firstFan[v] != fan)
                pinched[v] = true;
        }
    r.nonManifoldVertices = static_cast<std::size_t>(std::count(pinched.begin(), pinched.end(), true));
    for (std::uint32_t f = 0; f < faces; ++f)
        if (componentOf.find(f) == f) ++r.components;

    r.closed = faces > 0 && r.boundaryEdges == 0 && r.nonManifoldEdges == 0;
    r.manifold = r.nonManifoldEdges == 0 && r.nonManifoldVertices == 0;
    if (!r.manifold) r.consistentlyOriented = false;

    try {
        if (r.manifold && r.consistentlyOriented) {
            SurfaceMesh sm;
            PMP::polygon_soup_to_polygon_mesh(soup.points, soup.polygons, sm);
            r.selfIntersecting = PMP::does_self_intersect(sm);
            if (r.closed) {
                r.volume = PMP::volume(sm);
                r.outwardOriented = PMP::is_outward_oriented(sm);
            }
        } else {
            // Split non-manifold vertices and fix orientation so that CGAL can build a
            // mesh; faces meeting only at a split vertex or edge then count as touching.
            PMP::orient_polygon_soup(soup.points, soup.polygons);
            SurfaceMesh sm;
            PMP::polygon_soup_to_polygon_mesh(soup.points, soup.polygons, sm);
            r.selfIntersecting = PMP::does_self_intersect(sm);
        }
    } catch (const std::exception& e) {
        throw InputError(format("the geometric checks failed on this mesh: {}", e.what()));
    }
    return r;
}

Mesh repairMesh(const Mesh& mesh, RepairReport* report) {
    RepairReport local;
    RepairReport& rep = report ? *report : local;
    Soup soup;
    for (const glm::vec3& p : mesh.positions) soup.points.emplace_back(p.x, p.y, p.z);
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t)
        soup.polygons.push_back({mesh.indices[3 * t], mesh.indices[3 * t + 1], mesh.indices[3 * t + 2]});

    SurfaceMesh sm;
    try {
        const std::size_t pointsBefore = soup.points.size(), polygonsBefore = soup.polygons.size();
        PMP::repair_polygon_soup(soup.points, soup.polygons);
        if (soup.points.size() != pointsBefore)
            rep.actions.push_back(format("merged or removed {} duplicate or unused points",
                                              pointsBefore - soup.points.size()));
        if (soup.polygons.size() != polygonsBefore)
            rep.actions.push_back(format("removed {} degenerate or duplicate triangles",
                                              polygonsBefore - soup.polygons.size()));
        if (soup.polygons.empty()) throw InputError("no triangles are left after removing degenerate ones");
        const std::size_t beforeOrient = soup.points.size();
        if (!PMP::orient_polygon_soup(soup.points, soup.polygons))
            rep.actions.push_back(format("made the orientation consistent, splitting {} non-manifold points",
                                              soup.points.size() - beforeOrient));
        PMP::polygon_soup_to_polygon_mesh(soup.points, soup.polygons, sm);
        const std::size_t stitched = PMP::stitch_borders(sm);
        if (stitched > 0) rep.actions.push_back(format("stitched {} pairs of border edges", stitched));

        std::vector<SurfaceMesh::Halfedge_index> holes;
        PMP::extract_boundary_cycles(sm, std::back_inserter(holes));
        for (SurfaceMesh::Halfedge_index h : holes) {
            std::vector<SurfaceMesh::Face_index> patch;
            PMP::triangulate_hole(sm, h, std::back_inserter(patch));
        }
        if (!holes.empty()) rep.actions.push_back(format("filled {} holes", holes.size()));
        rep.closed = CGAL::is_closed(sm);
        if (rep.closed) {
            const bool outward = PMP::is_outward_oriented(sm);
            PMP::orient_to_bound_a_volume(sm);
            if (!outward) rep.actions.push_back("turned the normals outward");
        }
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        throw InputError(format("repair failed: {}", e.what()));
    }
    sm.collect_garbage();
    return toMesh(sm, mesh.name);
}

}  // namespace dawnforge
