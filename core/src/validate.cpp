// Mesh validation, orientation and repair. Topology (boundary, non-manifold edges and
// vertices, orientation, components) is counted directly on the position-welded triangles;
// the geometric questions go to CGAL Polygon Mesh Processing with exact predicates:
// self-intersections, volume, the nesting of shells, and the repair steps. The repair
// resolves self-intersections as mesh arrangements do (Zhou, Grinspun, Zorin, Jacobson,
// "Mesh Arrangements for Solid Geometry", SIGGRAPH 2016): CGAL's autorefinement splits
// the triangles along their intersections, and the faces kept are those between a region
// of winding number 0 and one of winding number 1 (the union's boundary), the winding
// numbers counted by ray crossings with exact predicates.
// Besides import_off.cpp (CGAL's OFF reader), this is the only translation unit of core that
// includes CGAL (it compiles slowly).
//
// CGAL's assertions stay on here, Release or not: with NDEBUG they compile to nothing, and
// a precondition that bad input breaks (inside autorefinement, say) then ends in a
// segmentation fault instead of a CGAL::Failure_exception that repairMesh() turns into an
// InputError. The kernel below is a type of this file's own so that no CGAL template is
// instantiated both here and in sim's CGAL code, which is compiled without assertions.
#define CGAL_DEBUG 1

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/union_find.hpp>
#include <dawnforge/core/validate.hpp>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Filtered_kernel.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/manifoldness.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/shape_predicates.h>
#include <CGAL/Polygon_mesh_processing/stitch_borders.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>

namespace dawnforge {

namespace PMP = CGAL::Polygon_mesh_processing;
// Exact predicates, inexact constructions: the same as CGAL's Epick, as a distinct type.
using Kernel = CGAL::Filtered_kernel<CGAL::Simple_cartesian<double>>;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using Face = SurfaceMesh::Face_index;
using Halfedge = SurfaceMesh::Halfedge_index;
using Vertex = SurfaceMesh::Vertex_index;
using Edge = SurfaceMesh::Edge_index;
using AabbTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>>>;
using Polygon = std::vector<std::size_t>;

namespace {

constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

// A mesh thinner than this, relative to its bounding box diagonal, has no volume: float
// coordinates hold about 7 digits, so a flat sheet written as floats is this thick.
constexpr double kFlatThickness = 1e-6;

std::string thousands(std::size_t n) {
    const std::string digits = std::to_string(n);
    std::string out;
    for (std::size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
        out += digits[i];
    }
    return out;
}

// "1 hole", "5,120 holes"
std::string counted(std::size_t n, std::string_view one, std::string_view many) {
    return thousands(n) + ' ' + std::string(n == 1 ? one : many);
}

glm::dvec3 vec(const Point& p) { return {p.x(), p.y(), p.z()}; }

// Triangles over distinct welded vertices, as CGAL's polygon soups want them.
struct Soup {
    std::vector<Point> points;
    std::vector<Polygon> polygons;
};

// `source`, if given, receives for each polygon the index of the mesh triangle it came from.
Soup weldedSoup(const Mesh& mesh, std::size_t* repeatedCornerTriangles, std::vector<std::uint32_t>* source = nullptr) {
    const std::vector<std::uint32_t> canonical = weldByPosition(mesh.positions);
    std::vector<std::size_t> compact(mesh.positions.size(), kNone);
    Soup soup;
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        if (canonical[i] != i) continue;
        compact[i] = soup.points.size();
        const glm::vec3& p = mesh.positions[i];
        soup.points.emplace_back(p.x, p.y, p.z);
    }
    std::size_t repeated = 0;
    soup.polygons.reserve(mesh.triangleCount());
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        Polygon tri(3);
        for (std::size_t k = 0; k < 3; ++k) tri[k] = compact[canonical[mesh.indices[3 * t + k]]];
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) {
            ++repeated;
            continue;
        }
        soup.polygons.push_back(std::move(tri));
        if (source) source->push_back(static_cast<std::uint32_t>(t));
    }
    if (repeatedCornerTriangles) *repeatedCornerTriangles = repeated;
    return soup;
}

// How the triangles of a soup connect. Half-edge 3f+k runs from corner k of face f to
// corner k+1; a corner 3f+k is corner k of face f.
struct Topology {
    std::vector<std::int64_t> twin;         // per half-edge: its partner when two faces share the edge, else -1
    std::vector<std::uint32_t> component;  // per face: the first face of its component (joined by shared edges)
    std::vector<std::uint32_t> fan;        // per corner: the first corner of its fan (joined across twin edges)
    std::vector<bool> pinched;             // per point: its corners form several fans
    std::size_t components = 0, boundaryEdges = 0, nonManifoldEdges = 0, nonManifoldVertices = 0;
    bool consistentlyOriented = true;  // every edge used twice is walked once in each direction
    std::vector<std::pair<std::size_t, std::size_t>> openEdges;  // the first few boundary edges
    bool closed() const { return boundaryEdges == 0 && nonManifoldEdges == 0; }
    bool manifold() const { return nonManifoldEdges == 0 && nonManifoldVertices == 0; }
};

Topology analyse(const std::vector<Polygon>& faces, std::size_t pointCount) {
    Topology t;
    struct EdgeUse {
        std::size_t lo, hi;
        std::uint32_t halfedge;
        bool operator<(const EdgeUse& o) const { return std::tie(lo, hi, halfedge) < std::tie(o.lo, o.hi, o.halfedge); }
    };
    std::vector<EdgeUse> uses;
    uses.reserve(3 * faces.size());
    for (std::size_t f = 0; f < faces.size(); ++f)
        for (std::size_t k = 0; k < 3; ++k) {
            const std::size_t a = faces[f][k], b = faces[f][(k + 1) % 3];
            uses.push_back({std::min(a, b), std::max(a, b), static_cast<std::uint32_t>(3 * f + k)});
        }
    std::sort(uses.begin(), uses.end());
    auto forward = [&](std::uint32_t h) { return faces[h / 3][h % 3] < faces[h / 3][(h % 3 + 1) % 3]; };
    auto corner = [&](std::uint32_t face, std::size_t point) {
        const Polygon& p = faces[face];
        return 3 * face + static_cast<std::uint32_t>(point == p[0] ? 0 : point == p[1] ? 1 : 2);
    };

    t.twin.assign(3 * faces.size(), -1);
    UnionFind componentOf(faces.size());
    UnionFind fanOf(3 * faces.size());
    for (std::size_t i = 0; i < uses.size();) {
        std::size_t j = i;
        while (j < uses.size() && uses[j].lo == uses[i].lo && uses[j].hi == uses[i].hi) ++j;
        const std::size_t count = j - i;
        for (std::size_t k = i + 1; k < j; ++k) componentOf.unite(uses[i].halfedge / 3, uses[k].halfedge / 3);
        if (count == 1 && ++t.boundaryEdges <= 3) t.openEdges.emplace_back(uses[i].lo, uses[i].hi);
        if (count > 2) ++t.nonManifoldEdges;
        if (count == 2) {
            const std::uint32_t a = uses[i].halfedge, b = uses[i + 1].halfedge;
            t.twin[a] = b;
            t.twin[b] = a;
            if (forward(a) == forward(b)) t.consistentlyOriented = false;
            for (std::size_t v : {uses[i].lo, uses[i].hi}) fanOf.unite(corner(a / 3, v), corner(b / 3, v));
        }
        i = j;
    }
    t.fan.resize(3 * faces.size());
    for (std::uint32_t c = 0; c < t.fan.size(); ++c) t.fan[c] = fanOf.find(c);
    std::vector<std::uint32_t> firstFan(pointCount, UINT32_MAX);
    t.pinched.assign(pointCount, false);
    for (std::uint32_t c = 0; c < t.fan.size(); ++c) {
        const std::size_t v = faces[c / 3][c % 3];
        if (firstFan[v] == UINT32_MAX)
            firstFan[v] = t.fan[c];
        else if (firstFan[v] != t.fan[c])
            t.pinched[v] = true;
    }
    t.nonManifoldVertices = static_cast<std::size_t>(std::count(t.pinched.begin(), t.pinched.end(), true));
    t.component.resize(faces.size());
    for (std::uint32_t f = 0; f < faces.size(); ++f) {
        t.component[f] = componentOf.find(f);
        if (t.component[f] == f) ++t.components;
    }
    return t;
}

// A soup that is manifold and consistently oriented, as a Surface_mesh whose face i is
// polygon i; points that no polygon uses are left out (CGAL's algorithms expect none).
// Throws InputError(`failure`) when the soup is not such a soup (checked first: adding
// the faces of one that is not can crash Surface_mesh, as orient_polygon_soup() leaves
// some soups, e.g. fracture pieces that touch). Built face by face rather than with
// polygon_soup_to_polygon_mesh(), which would check the soup a second time.
// The soup as a CGAL mesh. `knownManifold`: analyse() found it manifold and consistently
// oriented, which is what CGAL's own check would find again, at a quarter of a fracture's time.
SurfaceMesh toSurfaceMesh(const Soup& soup, const char* failure = "the triangles do not form a manifold surface",
                          bool knownManifold = false) {
    if (!knownManifold && !PMP::is_polygon_soup_a_polygon_mesh(soup.polygons)) throw InputError(failure);
    SurfaceMesh sm;
    std::vector<Vertex> vertex(soup.points.size());
    sm.reserve(static_cast<SurfaceMesh::size_type>(soup.points.size()),
               static_cast<SurfaceMesh::size_type>(3 * soup.polygons.size() / 2 + 3),
               static_cast<SurfaceMesh::size_type>(soup.polygons.size()));
    std::vector<bool> used(soup.points.size(), false);
    for (const Polygon& p : soup.polygons)
        for (std::size_t v : p) used[v] = true;
    for (std::size_t i = 0; i < soup.points.size(); ++i)
        if (used[i]) vertex[i] = sm.add_vertex(soup.points[i]);
    for (const Polygon& p : soup.polygons)
        if (sm.add_face(vertex[p[0]], vertex[p[1]], vertex[p[2]]) == SurfaceMesh::null_face()) throw InputError(failure);
    return sm;
}

Soup toSoup(const SurfaceMesh& sm) {
    Soup soup;
    std::vector<std::size_t> index(sm.number_of_vertices() + sm.number_of_removed_vertices(), kNone);
    for (Vertex v : sm.vertices()) {
        index[v] = soup.points.size();
        soup.points.push_back(sm.point(v));
    }
    soup.polygons.reserve(sm.number_of_faces());
    for (Face f : sm.faces()) {
        Polygon p;
        for (Vertex v : CGAL::vertices_around_face(sm.halfedge(f), sm)) p.push_back(index[v]);
        soup.polygons.push_back(std::move(p));
    }
    return soup;
}

Mesh toMesh(const Soup& soup, const std::string& name) {
    Mesh out;
    out.name = name;
    out.positions.reserve(soup.points.size());
    for (const Point& p : soup.points) out.positions.emplace_back(float(p.x()), float(p.y()), float(p.z()));
    out.indices.reserve(3 * soup.polygons.size());
    for (const Polygon& p : soup.polygons)
        for (std::size_t v : p) out.indices.push_back(static_cast<std::uint32_t>(v));
    return out;
}

// Signed volume of the given faces, measured from `origin` (near the faces, for precision).
double signedVolume(const Soup& soup, const glm::dvec3& origin) {
    double six = 0.0;
    for (const Polygon& p : soup.polygons) {
        const glm::dvec3 a = vec(soup.points[p[0]]) - origin, b = vec(soup.points[p[1]]) - origin,
                         c = vec(soup.points[p[2]]) - origin;
        six += glm::dot(a, glm::cross(b, c));
    }
    return six / 6.0;
}

glm::dvec3 centre(const std::vector<Point>& points) {
    if (points.empty()) return glm::dvec3(0.0);
    glm::dvec3 lo = vec(points[0]), hi = lo;
    for (const Point& p : points) {
        lo = glm::min(lo, vec(p));
        hi = glm::max(hi, vec(p));
    }
    return 0.5 * (lo + hi);
}

// CGAL reports failed assertions and internal errors as CGAL::Failure_exception, whose text
// names CGAL's source lines, not the user's mesh: say what it means instead. Any other
// exception keeps its own text, on one line.
std::string inOurWords(const std::exception& e) {
    if (dynamic_cast<const CGAL::Failure_exception*>(&e))
        return "the surface there is too tangled, or too nearly flat, for the geometry to be computed; clean that part "
               "up in a modelling tool";
    return oneLine(e.what());
}

enum class Flatness { Solid, Plane, Line, Point };

// Whether the points span space: Plane when all lie in one plane (exactly, or within a
// millionth of their extent).
template <typename PointRange>
Flatness flatness(const PointRange& points) {
    auto it = std::begin(points);
    if (it == std::end(points)) return Flatness::Point;
    const Point p0 = *it;
    Point p1 = p0, p2 = p0;
    double far = 0.0;
    for (const Point& p : points)
        if (const double d = CGAL::squared_distance(p0, p); d > far) {
            far = d;
            p1 = p;
        }
    if (far == 0.0) return Flatness::Point;
    double wide = 0.0;
    const glm::dvec3 axis = vec(p1) - vec(p0);
    for (const Point& p : points)
        if (const double d = glm::length(glm::cross(axis, vec(p) - vec(p0))); d > wide && !CGAL::collinear(p0, p1, p)) {
            wide = d;
            p2 = p;
        }
    if (wide == 0.0) return Flatness::Line;
    // In the plane, or within a millionth of the mesh's size of it: a flat mesh that passed
    // through another tool's float formatting is still flat (CGAL's plane.off, jittered by
    // 1e-7, failed deep inside the self-intersection repair).
    const glm::dvec3 normal = glm::normalize(glm::cross(axis, vec(p2) - vec(p0)));
    const double tolerance = 1e-6 * std::sqrt(far);
    for (const Point& p : points)
        if (std::abs(glm::dot(normal, vec(p) - vec(p0))) > tolerance && !CGAL::coplanar(p0, p1, p2, p))
            return Flatness::Solid;
    return Flatness::Plane;
}

// The closed shells (connected components) of a closed triangle mesh and how they nest,
// from CGAL's volume_connected_components().
struct Shells {
    std::vector<std::size_t> ofFace;  // per face index: its shell
    std::vector<std::size_t> level;   // per shell: how many shells enclose it
    std::vector<std::size_t> parent;  // per shell: the shell directly around it, kNone at level 0 (or when unclear)
    std::vector<bool> outward;        // per shell: its normals point out of what it encloses
    std::vector<double> volume;       // per shell: signed volume
    std::vector<std::size_t> faces;   // per shell: number of faces
    std::size_t size() const { return level.size(); }
};

Shells findShells(SurfaceMesh& sm) {
    Shells s;
    auto shellOf = sm.add_property_map<Face, std::size_t>("f:dawnforge_shell", 0).first;
    std::vector<std::vector<std::size_t>> parents;
    CGAL::Constant_property_map<Face, std::size_t> unused(0);
    // CGAL's own orientation test per shell asserts on a flat top (several highest
    // vertices; CGAL 5.5 takes any of them as the extreme one): the sign of each shell's
    // volume says the same for a shell that does not intersect itself.
    PMP::volume_connected_components(sm, unused,
                                     CGAL::parameters::face_connected_component_map(shellOf)
                                         .nesting_levels(std::ref(s.level))
                                         .volume_inclusions(std::ref(parents))
                                         .do_orientation_tests(false));
    s.parent.assign(s.size(), kNone);
    for (std::size_t i = 0; i < s.size() && i < parents.size(); ++i)
        if (parents[i].size() == 1) s.parent[i] = parents[i][0];
    s.ofFace.resize(sm.number_of_faces() + sm.number_of_removed_faces());
    s.volume.assign(s.size(), 0.0);
    s.faces.assign(s.size(), 0);
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (Vertex v : sm.vertices()) {
        lo = glm::min(lo, vec(sm.point(v)));
        hi = glm::max(hi, vec(sm.point(v)));
    }
    const glm::dvec3 origin = 0.5 * (lo + hi);
    for (Face f : sm.faces()) {
        const std::size_t shell = shellOf[f];
        s.ofFace[f] = shell;
        ++s.faces[shell];
        const Halfedge h = sm.halfedge(f);
        const glm::dvec3 a = vec(sm.point(sm.source(h))) - origin, b = vec(sm.point(sm.target(h))) - origin,
                         c = vec(sm.point(sm.target(sm.next(h)))) - origin;
        s.volume[shell] += glm::dot(a, glm::cross(b, c)) / 6.0;
    }
    sm.remove_property_map(shellOf);
    s.outward.resize(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) s.outward[i] = s.volume[i] > 0.0;
    return s;
}

// Shells that orient_to_bound_a_volume() would reverse: an even nesting level must face
// out, an odd one (a cavity) in.
std::vector<bool> shellsToReverse(const Shells& s) {
    std::vector<bool> reverse(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) reverse[i] = (s.level[i] % 2 == 0) != s.outward[i];
    return reverse;
}

void reverseShells(SurfaceMesh& sm, const Shells& s, const std::vector<bool>& reverse) {
    std::vector<Face> faces;
    for (Face f : sm.faces())
        if (reverse[s.ofFace[f]]) faces.push_back(f);
    if (!faces.empty()) PMP::reverse_face_orientations(faces, sm);
}

// ---------------------------------------------------------------------------------------
// Orientation

// Flips `flip` so that every component of a closed, manifold soup is consistently
// oriented, keeping the winding of the larger area of each component.
void orientConsistently(const Soup& soup, const Topology& topo, std::vector<bool>& flip) {
    const std::size_t n = soup.polygons.size();
    flip.assign(n, false);
    std::vector<bool> seen(n, false);
    std::vector<std::uint32_t> stack, members;
    for (std::uint32_t seed = 0; seed < n; ++seed) {
        if (seen[seed]) continue;
        seen[seed] = true;
        stack.assign(1, seed);
        members.clear();
        while (!stack.empty()) {
            const std::uint32_t f = stack.back();
            stack.pop_back();
            members.push_back(f);
            for (std::uint32_t k = 0; k < 3; ++k) {
                const std::int64_t other = topo.twin[3 * f + k];
                if (other < 0) continue;
                const std::uint32_t g = static_cast<std::uint32_t>(other) / 3,
                                    m = static_cast<std::uint32_t>(other) % 3;
                // Two faces agree when they walk their shared edge in opposite directions.
                const bool sameDirection = soup.polygons[f][k] == soup.polygons[g][m];
                const bool flipG = flip[f] != sameDirection;
                if (!seen[g]) {
                    seen[g] = true;
                    flip[g] = flipG;
                    stack.push_back(g);
                } else if (flip[g] != flipG) {
                    throw RepairableMeshError(
                        "the mesh cannot be oriented: one of its shells is one-sided (like a Klein bottle), so it "
                        "intersects itself");
                }
            }
        }
        double kept = 0.0, flipped = 0.0;
        for (std::uint32_t f : members) {
            const Polygon& p = soup.polygons[f];
            const double area = std::sqrt(CGAL::squared_area(soup.points[p[0]], soup.points[p[1]], soup.points[p[2]]));
            (flip[f] ? flipped : kept) += area;
        }
        if (flipped > kept)
            for (std::uint32_t f : members) flip[f] = !flip[f];
    }
}

// ---------------------------------------------------------------------------------------
// Repair

// Records which polygons orient_polygon_soup() reversed.
struct ReversalRecorder : PMP::Default_orientation_visitor {
    std::vector<bool>* reversed;
    void polygon_orientation_reversed(std::size_t i) { (*reversed)[i] = !(*reversed)[i]; }
};

// Removes both triangles of each pair that covers the same three points in opposite
// directions: the wall between two solids that touch face to face, or a flat double
// sheet. Returns the number of pairs.
std::size_t removeOppositePairs(std::vector<Polygon>& polygons) {
    std::vector<std::pair<std::array<std::size_t, 3>, std::size_t>> keys;
    keys.reserve(polygons.size());
    for (std::size_t i = 0; i < polygons.size(); ++i) {
        if (polygons[i].size() != 3) continue;
        std::array<std::size_t, 3> k{polygons[i][0], polygons[i][1], polygons[i][2]};
        std::sort(k.begin(), k.end());
        keys.emplace_back(k, i);
    }
    std::sort(keys.begin(), keys.end());
    std::vector<bool> remove(polygons.size(), false);
    std::size_t pairs = 0;
    // Same-orientation duplicates are gone already (repair_polygon_soup), so two faces
    // over the same points are opposite.
    for (std::size_t i = 0; i + 1 < keys.size(); ++i)
        if (keys[i].first == keys[i + 1].first && !remove[keys[i].second]) {
            remove[keys[i].second] = remove[keys[i + 1].second] = true;
            ++pairs;
            ++i;
        }
    if (pairs == 0) return 0;
    // Not polygons[out++] = std::move(polygons[i]): before the first removed face out == i,
    // and a vector moved onto itself is left empty (libstdc++), which crashed analyse().
    std::erase_if(polygons, [&](const Polygon& p) { return remove[std::size_t(&p - polygons.data())]; });
    return pairs;
}

std::string flatMessage(Flatness f) {
    switch (f) {
        case Flatness::Point:
            return "the mesh has no volume: all its points coincide";
        case Flatness::Line:
            return "the mesh has no volume: all its points lie on one line";
        default:
            return "the mesh has no volume: it is flat (all its points lie in one plane)";
    }
}

std::size_t countDegenerateFaces(const SurfaceMesh& sm) {
    std::size_t n = 0;
    for (Face f : sm.faces())
        if (PMP::is_degenerate_triangle_face(f, sm)) ++n;
    return n;
}

// Removes the components whose points all lie in one plane (they enclose nothing).
std::size_t removeFlatComponents(SurfaceMesh& sm) {
    auto ccOf = sm.add_property_map<Face, std::size_t>("f:dawnforge_cc", 0).first;
    const std::size_t count = PMP::connected_components(sm, ccOf);
    std::vector<std::vector<Point>> points(count);
    for (Face f : sm.faces())
        for (Vertex v : CGAL::vertices_around_face(sm.halfedge(f), sm)) points[ccOf[f]].push_back(sm.point(v));
    std::vector<std::size_t> flat;
    for (std::size_t c = 0; c < count; ++c)
        if (flatness(points[c]) != Flatness::Solid) flat.push_back(c);
    if (!flat.empty()) {
        PMP::remove_connected_components(sm, flat, ccOf);
        sm.collect_garbage();
    }
    sm.remove_property_map(ccOf);
    return flat.size();
}

// Fills the hole at border half-edge `h` with a fan around its centroid: the fallback
// when CGAL's triangulate_hole() finds no triangulation.
void fillWithFan(SurfaceMesh& sm, Halfedge h) {
    std::vector<Halfedge> border;
    glm::dvec3 sum(0.0);
    for (Halfedge b : CGAL::halfedges_around_face(h, sm)) {
        border.push_back(b);
        sum += vec(sm.point(sm.source(b)));
    }
    sum /= double(border.size());
    const Vertex centre = sm.add_vertex(Point(sum.x, sum.y, sum.z));
    for (Halfedge b : border)
        if (sm.add_face(sm.source(b), sm.target(b), centre) == SurfaceMesh::null_face())
            throw InputError("the repair could not fill a hole of the mesh");
}

constexpr std::size_t kMaxCubicHoleEdges = 64;

// A crack left by a cut is a few edges long; a longer one means the cut went wrong.
constexpr std::size_t kMaxCrackEdges = 64;

// Fills every hole with at most `maxEdges` edges; returns the number filled.
std::size_t fillHoles(SurfaceMesh& sm, std::size_t maxEdges = kNone) {
    std::vector<Halfedge> holes;
    PMP::extract_boundary_cycles(sm, std::back_inserter(holes));
    std::size_t filled = 0;
    for (Halfedge h : holes) {
        const auto border = CGAL::halfedges_around_face(h, sm);
        const auto edges = static_cast<std::size_t>(std::distance(border.begin(), border.end()));
        if (edges > maxEdges) continue;
        std::vector<Face> patch;
        // Where the Delaunay-based search finds nothing, CGAL falls back to a search cubic
        // in the hole's length: seconds for a few hundred edges. Past 64, a fan does.
        PMP::triangulate_hole(sm, h, std::back_inserter(patch),
                              CGAL::parameters::do_not_use_cubic_algorithm(edges > kMaxCubicHoleEdges));
        if (patch.empty()) fillWithFan(sm, h);
        ++filled;
    }
    return filled;
}

// Turns each shell the way the input meant it: the winding that most of its area had in
// the input (the `intent` of a face is +1 where orient_polygon_soup() kept the input's
// winding, -1 where it reversed it, 0 for new faces). Then every outermost shell faces
// out; where one was inside out, its whole nest is turned with it.
void orientAsIntended(SurfaceMesh& sm, SurfaceMesh::Property_map<Face, std::int8_t> intent) {
    {
        Shells s = findShells(sm);
        std::vector<double> vote(s.size(), 0.0);
        for (Face f : sm.faces()) {
            const Halfedge h = sm.halfedge(f);
            const double area = std::sqrt(
                CGAL::squared_area(sm.point(sm.source(h)), sm.point(sm.target(h)), sm.point(sm.target(sm.next(h)))));
            vote[s.ofFace[f]] += intent[f] * area;
        }
        std::vector<bool> reverse(s.size());
        for (std::size_t i = 0; i < s.size(); ++i) reverse[i] = vote[i] < 0.0;
        reverseShells(sm, s, reverse);
    }
    Shells s = findShells(sm);
    std::vector<bool> reverse(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) {
        std::size_t root = i;
        while (s.parent[root] != kNone) root = s.parent[root];
        reverse[i] = s.volume[root] < 0.0;
    }
    reverseShells(sm, s, reverse);
}

// The winding number of the surface at `q`: the signed count of its crossings with the
// ray from q through `towards`, +1 where the ray leaves a triangle through its front (q is
// behind it), -1 where it enters. Nothing when the ray grazes an edge or a vertex, where
// it would count a crossing twice.
std::optional<int> windingAlong(const AabbTree& tree, const SurfaceMesh& sm, const Point& q, const Point& towards) {
    std::vector<Face> hits;
    tree.all_intersected_primitives(Kernel::Ray_3(q, towards), std::back_inserter(hits));
    int winding = 0;
    for (Face f : hits) {
        const Halfedge h = sm.halfedge(f);
        const Point &a = sm.point(sm.source(h)), &b = sm.point(sm.target(h)), &c = sm.point(sm.target(sm.next(h)));
        if (CGAL::orientation(q, towards, a, b) == CGAL::COPLANAR ||
            CGAL::orientation(q, towards, b, c) == CGAL::COPLANAR ||
            CGAL::orientation(q, towards, c, a) == CGAL::COPLANAR)
            return std::nullopt;
        switch (CGAL::orientation(a, b, c, q)) {
            case CGAL::NEGATIVE:
                ++winding;
                break;
            case CGAL::POSITIVE:
                --winding;
                break;
            default:
                return std::nullopt;
        }
    }
    return winding;
}

// The winding number just in front of face f (the majority of three rays), or nothing
// when no ray gives a clean count.
std::optional<int> windingInFront(const AabbTree& tree, const SurfaceMesh& sm, Face f) {
    const Halfedge h = sm.halfedge(f);
    const glm::dvec3 a = vec(sm.point(sm.source(h))), b = vec(sm.point(sm.target(h))),
                     c = vec(sm.point(sm.target(sm.next(h))));
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double twiceArea = glm::length(n);
    if (twiceArea == 0.0) return std::nullopt;
    // A step off the face that is small against the face, so that no other sheet lies between.
    const glm::dvec3 q = (a + b + c) / 3.0 + (1e-4 * std::sqrt(twiceArea) / twiceArea) * n;
    const Point from(q.x, q.y, q.z);
    static constexpr std::array<glm::dvec3, 3> kDirections{
        glm::dvec3(0.5377, 1.8339, -2.2588), glm::dvec3(0.8622, 0.3188, -1.3077), glm::dvec3(-0.4336, 0.3426, 3.5784)};
    std::vector<int> counts;
    for (const glm::dvec3& d : kDirections) {
        const glm::dvec3 t = q + d * (1.0 + glm::length(q));
        if (const std::optional<int> w = windingAlong(tree, sm, from, Point(t.x, t.y, t.z))) counts.push_back(*w);
    }
    if (counts.empty()) return std::nullopt;
    std::sort(counts.begin(), counts.end());
    return counts[counts.size() / 2];
}

// Keeps the faces that bound the solid, the region where the winding number is positive:
// those with nothing in front of them (winding 0; behind them it is then 1). The faces of
// a shell left inside another, or of the part of a sheet that runs inside the solid,
// go. Faces are judged by patches (connected across edges that are not `cut`): a few faces
// of each, and every face where those disagree. Returns the number of faces removed.
std::size_t removeEnclosedFaces(SurfaceMesh& sm, SurfaceMesh::Property_map<Edge, bool> cut) {
    auto patchOf = sm.add_property_map<Face, std::size_t>("f:dawnforge_patch", 0).first;
    const std::size_t patches = PMP::connected_components(sm, patchOf, CGAL::parameters::edge_is_constrained_map(cut));
    std::vector<std::vector<Face>> members(patches);
    for (Face f : sm.faces()) members[patchOf[f]].push_back(f);
    sm.remove_property_map(patchOf);

    AabbTree tree(sm.faces().begin(), sm.faces().end(), sm);
    auto keep = [&](Face f) {
        const std::optional<int> w = windingInFront(tree, sm, f);
        return !w || *w == 0;  // a face that cannot be judged stays
    };
    std::vector<Face> doomed;
    for (const std::vector<Face>& patch : members) {
        const std::array<std::size_t, 3> samples{0, patch.size() / 2, patch.size() - 1};
        const bool first = keep(patch[samples[0]]);
        bool agree = true;
        for (std::size_t i = 1; i < samples.size() && agree; ++i) agree = keep(patch[samples[i]]) == first;
        if (agree) {
            if (!first) doomed.insert(doomed.end(), patch.begin(), patch.end());
        } else {
            for (Face f : patch)
                if (!keep(f)) doomed.push_back(f);
        }
    }
    for (Face f : doomed) CGAL::Euler::remove_face(sm.halfedge(f), sm);
    if (!doomed.empty()) sm.collect_garbage();
    return doomed.size();
}

std::size_t countShells(SurfaceMesh& sm) {
    auto ccOf = sm.add_property_map<Face, std::size_t>("f:dawnforge_count", 0).first;
    const std::size_t n = PMP::connected_components(sm, ccOf);
    sm.remove_property_map(ccOf);
    return n;
}

// A step from `p` along `direction` (a unit vector or zero) of `length`, but at least 64
// float steps, rounded to float so that it survives being stored.
Point stepFrom(const glm::dvec3& p, const glm::dvec3& direction, double length) {
    const double ulp = std::ldexp(1.0, std::ilogb(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z), 1e-30})) - 23);
    const glm::vec3 moved(p + std::max(length, 64.0 * ulp) * direction);
    return Point(moved.x, moved.y, moved.z);
}

// Where a vertex of one fan of triangles goes to part from another fan at the same point:
// towards the middle of its fan's ring (into its own cone) and against the fan's normal
// (into its own solid). `ring` is the mean of the ring's points, `normal` the fan's
// area-weighted normal, `edge` its longest edge.
glm::dvec3 intoOwnFan(const glm::dvec3& p, const glm::dvec3& ring, const glm::dvec3& normal, double edge) {
    glm::dvec3 d = edge > 0.0 ? (ring - p) / edge : glm::dvec3(0.0);
    if (const double n = glm::length(normal); n > 0.0) d -= normal / n;
    const double length = glm::length(d);
    return length > 0.0 ? d / length : d;
}

// Distinct vertices at one position (left by splitting a non-manifold point, or where
// parts touch) are moved apart, each a thousandth of its longest edge into its own fan
// (intoOwnFan()): autorefinement needs distinct vertices at distinct positions. Returns
// the number of positions shared.
std::size_t separateCoincidentVertices(SurfaceMesh& sm) {
    std::vector<Vertex> order;
    for (Vertex v : sm.vertices())
        if (!sm.is_isolated(v)) order.push_back(v);
    std::sort(order.begin(), order.end(), [&](Vertex a, Vertex b) { return sm.point(a) < sm.point(b); });
    std::vector<std::pair<Vertex, Point>> moves;
    std::size_t shared = 0;
    for (std::size_t i = 0; i < order.size();) {
        std::size_t j = i + 1;
        while (j < order.size() && sm.point(order[j]) == sm.point(order[i])) ++j;
        if (j - i > 1) ++shared;
        for (std::size_t k = i; j - i > 1 && k < j; ++k) {
            const Vertex v = order[k];
            const glm::dvec3 p = vec(sm.point(v));
            glm::dvec3 normal(0.0), ring(0.0);
            double longest = 0.0, count = 0.0;
            for (Halfedge h : CGAL::halfedges_around_target(sm.halfedge(v), sm)) {
                const glm::dvec3 a = vec(sm.point(sm.source(h)));
                longest = std::max(longest, glm::length(a - p));
                ring += a;
                count += 1.0;
                if (sm.is_border(h)) continue;
                const glm::dvec3 c = vec(sm.point(sm.target(sm.next(h))));
                normal += glm::cross(p - a, c - p);
            }
            moves.emplace_back(v, stepFrom(p, intoOwnFan(p, ring / count, normal, longest), 1e-3 * longest));
        }
        i = j;
    }
    for (const auto& [v, p] : moves) sm.point(v) = p;
    return shared;
}

bool onFloatGrid(const Point& point) {
    const Point p = point;  // a copy: see roundToFloat()
    const glm::vec3 f(p.x(), p.y(), p.z());
    return double(f.x) == p.x() && double(f.y) == p.y() && double(f.z) == p.z();
}

// The mesh again from its faces, with coincident points merged (so the two sides of a
// cut are stitched), duplicate faces and coincident opposite pairs dropped, non-manifold
// points split and the copies moved apart.
void rebuild(SurfaceMesh& sm) {
    Soup soup = toSoup(sm);
    PMP::repair_polygon_soup(soup.points, soup.polygons, CGAL::parameters::require_same_orientation(true));
    removeOppositePairs(soup.polygons);
    if (soup.polygons.empty()) throw InputError(flatMessage(Flatness::Plane));
    if (const Topology topo = analyse(soup.polygons, soup.points.size());
        !topo.manifold() || !topo.consistentlyOriented)
        PMP::orient_polygon_soup(soup.points, soup.polygons);
    sm = toSurfaceMesh(soup,
                       "the repair failed: the surface left after resolving the self-intersections cannot be "
                       "oriented consistently");
    separateCoincidentVertices(sm);
    // Cutting along the intersections leaves slivers (a new vertex a hair from an old one,
    // a triangle a hair high) that rounding to float would fold over: collapse the edges
    // and flip the caps shorter than a hundred-thousandth of the mesh's size.
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (Vertex v : sm.vertices()) {
        lo = glm::min(lo, vec(sm.point(v)));
        hi = glm::max(hi, vec(sm.point(v)));
    }
    const double tiny = 1e-5 * glm::length(hi - lo);
    std::vector<Face> nearCuts;  // faces with a vertex off the float grid: a point made by the cut
    for (Face f : sm.faces())
        for (Vertex v : CGAL::vertices_around_face(sm.halfedge(f), sm))
            if (!onFloatGrid(sm.point(v))) {
                nearCuts.push_back(f);
                break;
            }
    if (nearCuts.empty()) return;
    PMP::experimental::remove_almost_degenerate_faces(nearCuts, sm, std::cos(175.0 * 3.14159265358979 / 180.0), 10.0,
                                                      tiny, CGAL::parameters::flip_triangle_height_threshold(tiny));
    sm.collect_garbage();
}

std::uint64_t splitmix64(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

// Moves the vertices of the triangles that intersect by a tiny step in a pseudo-random
// (but reproducible) direction: a ten-thousandth of their longest edge, at least 64 float
// steps. Returns the number moved.
std::size_t nudgeIntersectingVertices(SurfaceMesh& sm, int round) {
    std::vector<std::pair<Face, Face>> pairs;
    PMP::self_intersections(sm, std::back_inserter(pairs));
    std::vector<bool> marked(sm.number_of_vertices() + sm.number_of_removed_vertices(), false);
    for (const auto& [f, g] : pairs)
        for (Face face : {f, g})
            for (Vertex v : CGAL::vertices_around_face(sm.halfedge(face), sm)) marked[v] = true;
    std::size_t moved = 0;
    for (Vertex v : sm.vertices()) {
        if (!marked[v]) continue;
        const glm::dvec3 p = vec(sm.point(v));
        double longest = 0.0;
        for (Halfedge h : CGAL::halfedges_around_target(sm.halfedge(v), sm))
            longest = std::max(longest, glm::length(vec(sm.point(sm.source(h))) - p));
        glm::dvec3 d;
        for (int k = 0; k < 3; ++k)
            d[k] = double(splitmix64(4 * std::uint64_t(std::size_t(v)) + k + 1000003ull * std::uint64_t(round)) >> 11) *
                       0x1.0p-53 * 2.0 -
                   1.0;
        const double length = glm::length(d);
        sm.point(v) = stepFrom(p, length > 0.0 ? d / length : glm::dvec3(0.0), 1e-4 * longest);
        ++moved;
    }
    return moved;
}

// Rounds the points to float, as the result will store them. Returns whether any moved.
// (Written with a float vector on purpose: GCC 12 at -O2 compiled the plain form,
// Point(double(float(p.x())), ...) of a point read by reference, into a copy of p.)
bool roundToFloat(SurfaceMesh& sm) {
    bool moved = false;
    for (Vertex v : sm.vertices()) {
        const Point p = sm.point(v);
        const glm::vec3 f(p.x(), p.y(), p.z());
        if (double(f.x) != p.x() || double(f.y) != p.y() || double(f.z) != p.z()) {
            sm.point(v) = Point(f.x, f.y, f.z);
            moved = true;
        }
    }
    return moved;
}

// Vertices where several fans of triangles meet (two solids touching at a point or along
// an edge, after welding by position) get one copy per fan, each moved a thousandth of
// its longest edge into its own fan (intoOwnFan()) so that the copies no longer coincide. Returns the number of such
// points.
std::size_t separatePinches(Soup& soup) {
    const Topology topo = analyse(soup.polygons, soup.points.size());
    if (topo.nonManifoldVertices == 0) return 0;
    struct FanSum {
        glm::dvec3 normal{0.0}, ring{0.0};
        double edge = 0.0, count = 0.0;
        std::size_t copy = kNone;
    };
    std::vector<std::pair<std::uint32_t, FanSum>> fans;  // per fan root corner of a pinched point
    std::vector<std::size_t> fanIndex(topo.fan.size(), kNone);
    for (std::uint32_t c = 0; c < topo.fan.size(); ++c) {
        const Polygon& p = soup.polygons[c / 3];
        const std::size_t v = p[c % 3];
        if (!topo.pinched[v]) continue;
        const std::uint32_t root = topo.fan[c];
        if (fanIndex[root] == kNone) {
            fanIndex[root] = fans.size();
            fans.push_back({root, {}});
        }
        FanSum& sum = fans[fanIndex[root]].second;
        const glm::dvec3 a = vec(soup.points[p[0]]), b = vec(soup.points[p[1]]), d = vec(soup.points[p[2]]);
        sum.normal += glm::cross(b - a, d - a);
        const glm::dvec3 here = vec(soup.points[v]), next = vec(soup.points[p[(c + 1) % 3]]),
                         prev = vec(soup.points[p[(c + 2) % 3]]);
        sum.edge = std::max({sum.edge, glm::length(next - here), glm::length(prev - here)});
        sum.ring += next + prev;
        sum.count += 2.0;
    }
    for (auto& [root, sum] : fans) {
        const glm::dvec3 p = vec(soup.points[soup.polygons[root / 3][root % 3]]);
        sum.copy = soup.points.size();
        soup.points.push_back(stepFrom(p, intoOwnFan(p, sum.ring / sum.count, sum.normal, sum.edge), 1e-3 * sum.edge));
    }
    for (std::uint32_t c = 0; c < topo.fan.size(); ++c) {
        const std::size_t v = soup.polygons[c / 3][c % 3];
        if (topo.pinched[v]) soup.polygons[c / 3][c % 3] = fans[fanIndex[topo.fan[c]]].second.copy;
    }
    return topo.nonManifoldVertices;
}

// inspectMesh(); `selfIntersecting`, when given, is already known and not checked again.
MeshReport inspect(const Mesh& mesh, std::optional<bool> selfIntersecting) {
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

    const Topology topo = analyse(soup.polygons, soup.points.size());
    for (const auto& [a, b] : topo.openEdges) r.openEdges.emplace_back(vec(soup.points[a]), vec(soup.points[b]));
    r.boundaryEdges = topo.boundaryEdges;
    r.nonManifoldEdges = topo.nonManifoldEdges;
    r.nonManifoldVertices = topo.nonManifoldVertices;
    r.components = topo.components;
    r.closed = !soup.polygons.empty() && topo.closed();
    r.manifold = topo.manifold();
    r.consistentlyOriented = r.manifold && topo.consistentlyOriented;

    try {
        if (r.manifold && r.consistentlyOriented) {
            SurfaceMesh sm = toSurfaceMesh(soup, "the triangles do not form a manifold surface", true);
            r.selfIntersecting =
                selfIntersecting ? *selfIntersecting : PMP::does_self_intersect<CGAL::Parallel_if_available_tag>(sm);
            if (r.closed) {
                r.volume = signedVolume(soup, centre(soup.points));
                const std::vector<bool> reverse = shellsToReverse(findShells(sm));
                r.outwardOriented = std::find(reverse.begin(), reverse.end(), true) == reverse.end();
            }
        } else {
            // Split non-manifold vertices and fix orientation so that CGAL can build a
            // mesh; faces meeting only at a split vertex or edge then count as touching.
            PMP::orient_polygon_soup(soup.points, soup.polygons);
            r.selfIntersecting = PMP::does_self_intersect(toSurfaceMesh(soup));
        }
    } catch (const std::exception& e) {
        throw InputError(format("the geometric checks failed on this mesh: {}", inOurWords(e)));
    }
    return r;
}

// What is wrong with a mesh that should bound a volume, as one clause; empty when nothing.
std::string whatIsWrong(const MeshReport& r) {
    std::vector<std::string> wrong;
    if (r.boundaryEdges > 0)
        wrong.push_back(format("it is open ({})", counted(r.boundaryEdges, "boundary edge", "boundary edges")));
    if (r.nonManifoldEdges > 0)
        wrong.push_back(
            format("{} shared by three or more triangles", counted(r.nonManifoldEdges, "edge is", "edges are")));
    if (r.nonManifoldVertices > 0)
        wrong.push_back(format("{} where separate parts touch",
                               counted(r.nonManifoldVertices, "vertex is a point", "vertices are points")));
    if (r.selfIntersecting) wrong.push_back("it still intersects itself");
    if (r.manifold && r.closed && !r.consistentlyOriented) wrong.push_back("its orientation is inconsistent");
    if (r.manifold && r.closed && r.consistentlyOriented && !r.outwardOriented)
        wrong.push_back("some shells face the wrong way");
    std::string out;
    for (std::size_t i = 0; i < wrong.size(); ++i)
        out += (i == 0 ? "" : i + 1 == wrong.size() ? " and " : ", ") + wrong[i];
    return out;
}

// The mesh as a soup of its triangles; the volume it had, if it bounded one.
Soup startRepair(const Mesh& mesh, RepairReport& rep) {
    {
        const Soup welded = weldedSoup(mesh, nullptr);
        const Topology topo = analyse(welded.polygons, welded.points.size());
        if (topo.closed() && topo.manifold() && topo.consistentlyOriented && !welded.polygons.empty())
            rep.volumeBefore = signedVolume(welded, centre(welded.points));
    }
    Soup soup;
    soup.points.reserve(mesh.positions.size());
    for (const glm::vec3& p : mesh.positions) soup.points.emplace_back(p.x, p.y, p.z);
    soup.polygons.reserve(mesh.triangleCount());
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t)
        soup.polygons.push_back({mesh.indices[3 * t], mesh.indices[3 * t + 1], mesh.indices[3 * t + 2]});
    if (const Flatness f = flatness(soup.points); f != Flatness::Solid) throw InputError(flatMessage(f));
    return soup;
}

// Duplicate points and degenerate, duplicate and coincident opposite triangles go.
void cleanSoup(Soup& soup, RepairReport& rep) {
    const std::size_t pointsBefore = soup.points.size(), polygonsBefore = soup.polygons.size();
    PMP::repair_polygon_soup(soup.points, soup.polygons, CGAL::parameters::require_same_orientation(true));
    if (soup.points.size() != pointsBefore)
        rep.actions.push_back(format(
            "merged or removed {}",
            counted(pointsBefore - soup.points.size(), "duplicate or unused point", "duplicate or unused points")));
    if (soup.polygons.size() != polygonsBefore)
        rep.actions.push_back(
            format("removed {}", counted(polygonsBefore - soup.polygons.size(), "degenerate or duplicate triangle",
                                         "degenerate or duplicate triangles")));
    if (const std::size_t pairs = removeOppositePairs(soup.polygons))
        rep.actions.push_back(
            format("removed {} of coincident opposite triangles (inner walls)", counted(pairs, "pair", "pairs")));
    if (soup.polygons.empty())
        throw InputError("the mesh has no volume: no triangles are left after removing degenerate and coincident ones");

}

// The soup oriented consistently as a mesh; "f:dawnforge_intent" says which way each face
// was meant to face (-1: CGAL reversed it).
SurfaceMesh orientSoup(Soup& soup, RepairReport& rep) {
    std::vector<bool> reversed(soup.polygons.size(), false);
    const std::size_t beforeOrient = soup.points.size();
    ReversalRecorder recorder;
    recorder.reversed = &reversed;
    PMP::orient_polygon_soup(soup.points, soup.polygons, CGAL::parameters::visitor(recorder));
    if (soup.points.size() != beforeOrient)
        rep.actions.push_back(format("split {} where the surface is not manifold",
                                     counted(soup.points.size() - beforeOrient, "point", "points")));
    SurfaceMesh sm = toSurfaceMesh(soup, "the repair failed: CGAL could not orient the triangles consistently");
    auto intent = sm.add_property_map<Face, std::int8_t>("f:dawnforge_intent", 0).first;
    for (std::size_t i = 0; i < soup.polygons.size(); ++i)
        intent[Face(static_cast<SurfaceMesh::size_type>(i))] = reversed[i] ? -1 : 1;
    return sm;
}

// Borders stitched, pinches split, degenerate and flat parts removed, holes filled, the
// shells oriented as the faces were meant to face.
void closeSurface(SurfaceMesh& sm, RepairReport& rep, const char*& stage) {
    auto intent = sm.property_map<Face, std::int8_t>("f:dawnforge_intent").first;
    stage = "stitching borders";
    if (const std::size_t stitched = PMP::stitch_borders(sm))
        rep.actions.push_back(
            format("stitched {}", counted(stitched, "pair of border edges", "pairs of border edges")));
    sm.collect_garbage();
    if (const std::size_t pinched = PMP::duplicate_non_manifold_vertices(sm))
        rep.actions.push_back(format("split {} where separate parts touched", counted(pinched, "vertex", "vertices")));
    stage = "removing degenerate triangles";
    if (const std::size_t degenerate = countDegenerateFaces(sm)) {
        PMP::remove_degenerate_faces(sm);
        sm.collect_garbage();
        rep.actions.push_back(
            format("collapsed {}", counted(degenerate, "degenerate triangle", "degenerate triangles")));
    }
    if (const std::size_t flat = removeFlatComponents(sm))
        rep.actions.push_back(format("removed {} with no volume", counted(flat, "flat piece", "flat pieces")));
    if (sm.number_of_faces() == 0) throw InputError(flatMessage(Flatness::Plane));

    if (!CGAL::is_closed(sm)) {
        stage = "filling holes";
        const bool intersectedBefore = PMP::does_self_intersect(sm);
        const std::size_t holes = fillHoles(sm);
        rep.actions.push_back(format("filled {}", counted(holes, "hole", "holes")));
        if (!intersectedBefore && PMP::does_self_intersect(sm))
            rep.actions.push_back("a filled hole cut through the surface (resolved below as a self-intersection)");
        if (!CGAL::is_closed(sm)) throw InputError("the repair failed: some holes could not be filled");
    }
    stage = "orienting the shells";
    orientAsIntended(sm, intent);
    sm.remove_property_map(intent);
}

struct Resolution {
    bool intersecting = false;  // after the last round (false when it succeeded)
    bool resolved = false;      // autorefinement ran
    std::size_t removed = 0;    // faces of shells removed as enclosing nothing more
};

// Resolve the self-intersections: split the triangles along them (autorefinement), keep
// the faces that bound the solid, merge the two sides of each cut. The result is
// rounded to float, as it will be stored; should that make triangles cross again,
// resolve again. Without self-intersections, shells nested inside the solid still go.
Resolution resolveSelfIntersections(SurfaceMesh& sm, RepairReport& rep) {
    roundToFloat(sm);  // collapsing degenerate triangles and filling holes may place points off the grid
    Resolution res;
    bool& intersecting = res.intersecting;
    bool& resolved = res.resolved;
    std::size_t& removed = res.removed;
    intersecting = PMP::does_self_intersect(sm);
    if (intersecting || countShells(sm) > 1) {
        const std::size_t facesBefore = sm.number_of_faces();
        std::size_t nudged = 0, cracks = 0, parted = 0;
        constexpr int kRounds = 6;
        for (int round = 0; round < kRounds; ++round) {
            SurfaceMesh before;
            if (intersecting) before = sm;
            auto cut = sm.add_property_map<Edge, bool>("e:dawnforge_cut", false).first;
            if (intersecting) {
                try {
                    PMP::experimental::autorefine(sm, CGAL::parameters::edge_is_constrained_map(cut));
                } catch (const std::exception&) {
                    // CGAL 5.5's autorefinement fails where distinct vertices share a
                    // position (parts that touch at a point) and where intersections meet
                    // exactly at a vertex or along an edge: move the former apart, nudge
                    // the vertices of the latter, and try again.
                    if (round + 1 == kRounds) throw;
                    sm = std::move(before);
                    if (const std::size_t shared = parted == 0 ? separateCoincidentVertices(sm) : 0)
                        parted += shared;
                    else
                        nudged += nudgeIntersectingVertices(sm, round);
                    continue;
                }
                resolved = true;
            }
            removed += removeEnclosedFaces(sm, cut);
            sm.remove_property_map(cut);
            if (intersecting) {
                rebuild(sm);
                // Where the faces kept on the two sides of a cut do not quite meet (a face
                // judged wrongly, or kept because it could not be judged), close the crack.
                if (!CGAL::is_closed(sm)) cracks += fillHoles(sm, kMaxCrackEdges);
            }
            if (!roundToFloat(sm) && !intersecting) break;
            // Rounding can flatten a sliver; collapsing it can place a vertex off the grid.
            for (int pass = 0; pass < 3 && countDegenerateFaces(sm) > 0; ++pass) {
                PMP::remove_degenerate_faces(sm);
                sm.collect_garbage();
                roundToFloat(sm);
            }
            intersecting = PMP::does_self_intersect(sm);
            if (!intersecting) break;
        }
        if (parted > 0)
            rep.actions.push_back(format("moved apart the vertices at {} where separate parts touched",
                                         counted(parted, "point", "points")));
        if (nudged > 0)
            rep.actions.push_back(format("nudged {} by a ten-thousandth of an edge where intersections met exactly",
                                         counted(nudged, "vertex", "vertices")));
        if (resolved)
            rep.actions.push_back(
                format("resolved the self-intersections, keeping the union of what the surface encloses "
                       "({} → {})",
                       counted(facesBefore, "triangle", "triangles"), thousands(sm.number_of_faces())));
        else if (removed > 0)
            rep.actions.push_back(format("removed {} of shells inside the solid (they enclosed nothing more)",
                                         counted(removed, "triangle", "triangles")));
        if (cracks > 0)
            rep.actions.push_back(format("closed {} left along the cuts", counted(cracks, "crack", "cracks")));
    }

    return res;
}

// The repaired mesh, checked: it must bound a volume, and without a reason to, keep the
// input's.
Mesh checkedResult(const SurfaceMesh& sm, const Mesh& mesh, const Resolution& res, RepairReport& rep) {
    Mesh out = toMesh(toSoup(sm), mesh.name);
    // When welding changes nothing, the result is the mesh just checked for
    // self-intersections (its points are floats already): no need to check again.
    std::optional<bool> known = res.intersecting;
    {
        std::size_t repeated = 0;
        Soup welded = weldedSoup(out, &repeated);
        if (repeated > 0 || welded.points.size() != out.positions.size()) known.reset();
        if (const std::size_t pinches = separatePinches(welded)) {
            rep.actions.push_back(
                format("moved apart {} where separate parts touched", counted(pinches, "point", "points")));
            out = toMesh(welded, mesh.name);
            known.reset();
        }
    }
    const MeshReport r = inspect(out, known);
    if (const std::string wrong = whatIsWrong(r); !wrong.empty())
        throw InputError(format("the repair failed: {}", wrong));
    const double size = glm::length(r.bounds.max - r.bounds.min);
    if (!r.volume || *r.volume <= 0.0 || 2.0 * *r.volume / r.area < kFlatThickness * size)
        throw InputError("the mesh has no volume: what it encloses is flat (thinner than a millionth of its size)");
    rep.closed = true;
    rep.volumeAfter = *r.volume;
    if (rep.volumeBefore) {
        const double before = std::abs(*rep.volumeBefore);
        const double change = (rep.volumeAfter - before) / before;
        // Without self-intersections or nested shells, the solid is the input's: its volume
        // may only move by the collapse of degenerate triangles and the parting of touching
        // parts. Anything more is a bug, not a repair.
        if (!res.resolved && res.removed == 0 && std::abs(change) > 1e-4)
            throw InputError(format("the repair failed: it would change the volume by {}% without a reason",
                                    std::round(change * 1e4) / 1e2));
        if (std::abs(change) > 1e-6)
            rep.actions.push_back(format("the volume changed by {}% (from {} to {})", std::round(change * 1e4) / 1e2,
                                         before, rep.volumeAfter));
    }
    return out;
}

// The repair proper; `stage` says what it is doing, for the message should CGAL fail.
Mesh repair(const Mesh& mesh, RepairReport& rep, const char*& stage) {
    stage = "reading the mesh";
    Soup soup = startRepair(mesh, rep);
    stage = "cleaning the triangle soup";
    cleanSoup(soup, rep);
    stage = "orienting the triangles";
    SurfaceMesh sm = orientSoup(soup, rep);
    closeSurface(sm, rep, stage);
    stage = "resolving self-intersections";
    const Resolution res = resolveSelfIntersections(sm, rep);
    stage = "checking the result";
    return checkedResult(sm, mesh, res, rep);
}

}  // namespace

MeshReport inspectMesh(const Mesh& mesh) { return inspect(mesh, std::nullopt); }

std::vector<std::string> orientMesh(Mesh& mesh) {
    std::vector<std::uint32_t> source;
    Soup soup = weldedSoup(mesh, nullptr, &source);
    const Topology topo = analyse(soup.polygons, soup.points.size());
    if (soup.polygons.empty() || !topo.closed() || !topo.manifold()) return {};

    std::vector<bool> flip;
    orientConsistently(soup, topo, flip);
    for (std::size_t f = 0; f < flip.size(); ++f)
        if (flip[f]) std::swap(soup.polygons[f][1], soup.polygons[f][2]);
    std::vector<bool> reverseShell;
    Shells shells;
    try {
        SurfaceMesh sm = toSurfaceMesh(soup);
        shells = findShells(sm);
        reverseShell = shellsToReverse(shells);
    } catch (const std::exception& e) {
        throw InputError(format("orienting the mesh failed: {}", inOurWords(e)));
    }

    // What changed, per shell: a shell turned as a whole faced the wrong way; triangles
    // flipped within a shell that stays disagreed with their neighbours.
    std::size_t turnedOut = 0, turnedIn = 0, cavities = 0, disagreeing = 0;
    std::vector<std::size_t> flippedIn(shells.size(), 0);
    for (std::size_t f = 0; f < flip.size(); ++f)
        if (flip[f]) ++flippedIn[shells.ofFace[f]];
    for (std::size_t s = 0; s < shells.size(); ++s) {
        if (!reverseShell[s]) {
            disagreeing += flippedIn[s];
        } else if (shells.level[s] % 2 == 0) {
            turnedOut += shells.faces[s] - flippedIn[s];
        } else {
            turnedIn += shells.faces[s] - flippedIn[s];
            ++cavities;
        }
    }
    std::vector<bool> flipped(mesh.triangleCount(), false);
    std::size_t changed = 0;
    for (std::size_t f = 0; f < flip.size(); ++f)
        if (flip[f] != reverseShell[shells.ofFace[f]]) {
            flipped[source[f]] = true;
            ++changed;
        }
    if (changed == 0) return {};

    for (std::size_t t = 0; t < flipped.size(); ++t)
        if (flipped[t]) std::swap(mesh.indices[3 * t + 1], mesh.indices[3 * t + 2]);
    // Normals: a vertex normal usually follows the winding, so a shell that was inside out
    // carries inward normals too, but exporters that mirror a mesh sometimes fix the normals
    // and forget the winding. So rather than negating blindly, each normal of a vertex used
    // by a flipped triangle is compared with the (area-weighted) normal of its triangles as
    // now wound, and negated only if it points away from them. Vertices of unflipped
    // triangles keep their normals whatever they are: a mesh that already bounds its volume
    // is not touched.
    if (!mesh.normals.empty()) {
        std::vector<glm::dvec3> faceSum(mesh.vertexCount(), glm::dvec3(0.0));
        std::vector<bool> touched(mesh.vertexCount(), false);
        for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
            const std::uint32_t a = mesh.indices[3 * t], b = mesh.indices[3 * t + 1], c = mesh.indices[3 * t + 2];
            const glm::dvec3 pa = mesh.positions[a], pb = mesh.positions[b], pc = mesh.positions[c];
            const glm::dvec3 n = glm::cross(pb - pa, pc - pa);
            for (std::uint32_t v : {a, b, c}) {
                faceSum[v] += n;
                if (flipped[t]) touched[v] = true;
            }
        }
        for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
            if (touched[v] && glm::dot(glm::dvec3(mesh.normals[v]), faceSum[v]) < 0.0)
                mesh.normals[v] = -mesh.normals[v];
    }

    std::vector<std::string> said;
    if (turnedOut > 0)
        said.push_back(
            format("turned {} outward", counted(turnedOut, "inward-facing triangle", "inward-facing triangles")));
    if (turnedIn > 0)
        said.push_back(format("turned {} of {} to face into the cavity", counted(turnedIn, "triangle", "triangles"),
                              counted(cavities, "inner shell", "inner shells")));
    if (disagreeing > 0)
        said.push_back(
            format("flipped {} to agree with their neighbours", counted(disagreeing, "triangle", "triangles")));
    return said;
}

Mesh repairMesh(const Mesh& mesh, RepairReport* report) {
    RepairReport local;
    RepairReport& rep = report ? *report : local;
    const char* stage = "starting";
    try {
        return repair(mesh, rep, stage);
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        throw InputError(format("the repair failed while {}: {}", stage, inOurWords(e)));
    }
}

}  // namespace dawnforge
