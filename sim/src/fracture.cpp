// Voronoi fracture with CGAL: Delaunay neighbours -> bisector half-spaces ->
// halfspace_intersection_3 (the cell) -> corefine_and_compute_intersection with the mesh.
// Measured approach and pitfalls: ../shared/notes/measured.md (clipping plane by plane
// was slower and less robust than one corefinement per cell).
//
// Every face carries an "origin" through the corefinements (a CGAL corefinement
// visitor): the input triangle it came from, or the cell plane that cut it. Output
// attributes are rebuilt from that: input triangles give their normals, UVs and
// material by barycentric interpolation; cut faces get the plane's normal, planar UVs
// in metres and the interior material; cut planes give the bond graph.
//
// This is the only translation unit of sim that includes CGAL.
#include "part_contact.hpp"
#include "part_plan.hpp"
#include "piece_surface.hpp"
#include "pieces.hpp"
#include "rough.hpp"
#include "rvd.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/seed.hpp>
#include <dawnforge/core/validate.hpp>
#include <dawnforge/sim/fracture.hpp>
#include <dawnforge/sim/fracture_parts.hpp>

#include <CGAL/Convex_hull_3/dual/halfspace_intersection_3.h>
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cstdio>
#include <atomic>
#include <functional>
#include <map>
#include <mutex>
#include <numeric>
#include <set>

namespace dawnforge::sim {

namespace PMP = CGAL::Polygon_mesh_processing;
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Plane = K::Plane_3;
using SM = CGAL::Surface_mesh<Point>;
using Face = SM::Face_index;
using Vertex = SM::Vertex_index;

namespace {

// Where a face came from: >= 0, an input triangle; kBoxOrigin, a hierarchy box (never
// part of a piece); otherwise -1 - plane, for the plane-th cut plane of this fracture.
using Origin = std::int64_t;
constexpr Origin kBoxOrigin = std::numeric_limits<Origin>::min();
constexpr const char* kOriginMap = "f:origin";

SM::Property_map<Face, Origin> origins(SM& m) { return m.add_property_map<Face, Origin>(kOriginMap, kBoxOrigin).first; }
SM::Property_map<Face, Origin> origins(const SM& m) { return m.property_map<Face, Origin>(kOriginMap).first; }

// Carries face origins through a corefinement. Copies of the visitor share `current`.
struct OriginVisitor : PMP::Corefinement::Default_visitor<SM> {
    Origin* current;
    explicit OriginVisitor(Origin* c) : current(c) {}
    void before_subface_creations(Face f, SM& tm) { *current = origins(tm)[f]; }
    void after_subface_created(Face f, SM& tm) { origins(tm)[f] = *current; }
    void after_face_copy(Face src, const SM& tmSrc, Face tgt, SM& tmTgt) { origins(tmTgt)[tgt] = origins(tmSrc)[src]; }
};

glm::dvec3 toGlm(const Point& p) { return {p.x(), p.y(), p.z()}; }
Point toPoint(const glm::dvec3& p) { return {p.x, p.y, p.z}; }

// A cut plane: the half-space on its negative side is kept; its outward normal is the
// plane's normal. `neighbour` is the global cell on the other side (-1 for a bounding plane).
struct CutPlane {
    Plane plane;
    glm::dvec3 normal;  // unit
    std::int64_t neighbour;
};

// Intersects `a` with `b` in place (a := a ∩ b), keeping face origins. Returns false when
// CGAL finds self-intersecting triangles near the intersection: chained Epick corefinements
// can leave such rounding artefacts, and corefinement can loop forever on them, so it is
// asked to check and throw instead (throw_on_self_intersection). `a` is then unusable.
bool tryIntersectInPlace(SM& a, SM& b, const char* what, std::size_t id) {
    Origin current = 0;
    OriginVisitor visitor(&current);
    bool ok = false;
    try {
        ok = PMP::corefine_and_compute_intersection(
            a, b, a, CGAL::parameters::visitor(visitor).throw_on_self_intersection(true),
            CGAL::parameters::throw_on_self_intersection(true));
    } catch (const PMP::Corefinement::Self_intersection_exception&) {
        return false;
    } catch (const std::exception& e) {
        throw InputError(format("fracture: CGAL failed on {} {}: {}", what, id, e.what()));
    }
    if (!ok)
        throw InputError(format("fracture: the intersection with {} {} is not a manifold (a cut passes exactly "
                                "through an edge or corner of the mesh); try another seed",
                                what, id));
    return true;
}

// The convex polyhedron of half-spaces (negative sides), with face origins set to the
// plane each face lies on. `inside` must be strictly inside.
SM convexCell(const std::vector<CutPlane>& planes, Origin firstOrigin, const Point& inside, std::size_t id) {
    std::vector<Plane> ps;
    ps.reserve(planes.size());
    for (const CutPlane& c : planes) ps.push_back(c.plane);
    SM cell;
    CGAL::halfspace_intersection_3(ps.begin(), ps.end(), cell, boost::make_optional(inside));
    if (cell.number_of_faces() == 0 || !PMP::triangulate_faces(cell))
        throw InputError(format("fracture: cell {} is degenerate (seeds too close together?)", id));
    auto o = origins(cell);
    for (Face f : cell.faces()) {
        // The plane all three corners lie on (closest by summed distance).
        double best = std::numeric_limits<double>::max();
        std::size_t bestPlane = 0;
        for (std::size_t k = 0; k < planes.size(); ++k) {
            double d = 0;
            for (Vertex v : CGAL::vertices_around_face(cell.halfedge(f), cell)) {
                const Plane& p = planes[k].plane;
                const Point& q = cell.point(v);
                d += std::abs(p.a() * q.x() + p.b() * q.y() + p.c() * q.z() + p.d());
            }
            if (d < best) {
                best = d;
                bestPlane = k;
            }
        }
        o[f] = firstOrigin == kBoxOrigin ? kBoxOrigin : firstOrigin - static_cast<Origin>(bestPlane);
    }
    return cell;
}

std::vector<CutPlane> boxPlanes(const CGAL::Bbox_3& b) {
    auto plane = [](double a, double bb, double c, double d) {
        return CutPlane{Plane(a, bb, c, d), glm::dvec3(a, bb, c), -1};
    };
    return {plane(1, 0, 0, -b.xmax()), plane(-1, 0, 0, b.xmin()), plane(0, 1, 0, -b.ymax()),
            plane(0, -1, 0, b.ymin()), plane(0, 0, 1, -b.zmax()), plane(0, 0, -1, b.zmin())};
}

CGAL::Bbox_3 expanded(const CGAL::Bbox_3& b, double m) {
    return {b.xmin() - m, b.ymin() - m, b.zmin() - m, b.xmax() + m, b.ymax() + m, b.zmax() + m};
}

// The input surface of one fracture call: welded positions and the triangles' attributes.
struct Input {
    const Mesh* mesh;
    const std::vector<detail::PlaneKey>* planes;  // per input triangle: the cut plane it lies on, or none
    SM sm;
    CGAL::Bbox_3 bbox;
    std::optional<CGAL::Side_of_triangle_mesh<SM, K>> inside{};  // made where the Input stays (it refers to sm)
};

// `exact`: the vertices' positions in double (a re-fractured piece's grid points), or empty
// for the mesh's own float positions.
Input makeInput(const Mesh& mesh, const std::vector<detail::PlaneKey>* planes, std::span<const glm::dvec3> exact) {
    Input in{&mesh, planes, {}, {}};
    std::map<std::array<double, 3>, Vertex> welded;
    std::vector<Vertex> vertexOf(mesh.positions.size());
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        const glm::dvec3 p = exact.empty() ? glm::dvec3(mesh.positions[i]) : exact[i];
        const auto [it, inserted] = welded.try_emplace({p.x, p.y, p.z}, Vertex());
        if (inserted) it->second = in.sm.add_vertex(toPoint(p));
        vertexOf[i] = it->second;
    }
    auto o = origins(in.sm);
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const Vertex a = vertexOf[mesh.indices[3 * t]], b = vertexOf[mesh.indices[3 * t + 1]],
                     c = vertexOf[mesh.indices[3 * t + 2]];
        if (a == b || b == c || a == c) continue;
        const Face f = in.sm.add_face(a, b, c);
        if (f == SM::null_face()) throw InputError("fracture: the mesh is not manifold");
        o[f] = static_cast<Origin>(t);
    }
    in.bbox = PMP::bbox(in.sm);
    return in;
}

// ---------------------------------------------------------------- seeds

// Where seeds may fall: a grid over the bounding box whose cells are known to lie inside the
// volume, or to meet the surface (conservatively: a cell overlapping a triangle's bounding
// box). Cells neither inside nor meeting the surface lie outside and are never sampled, so
// thin and sparse shapes cost no more tests than solid ones.
struct SeedGrid {
    glm::dvec3 lo{0.0}, cell{0.0};
    glm::ivec3 n{1};
    std::vector<std::uint32_t> candidates;  // cell indices, inside or boundary
    std::vector<char> boundary;             // per cell

    std::size_t index(glm::ivec3 c) const { return (std::size_t(c.z) * std::size_t(n.y) + std::size_t(c.y)) * std::size_t(n.x) + std::size_t(c.x); }
    glm::ivec3 coords(std::size_t i) const {
        return {int(i % std::size_t(n.x)), int(i / std::size_t(n.x) % std::size_t(n.y)), int(i / (std::size_t(n.x) * std::size_t(n.y)))};
    }
    glm::ivec3 cellOf(const glm::dvec3& p) const {
        return glm::clamp(glm::ivec3(glm::floor((p - lo) / cell)), glm::ivec3(0), n - 1);
    }
};

// Marks every cell overlapping a triangle's bounding box as boundary.
void markSurfaceCells(const Input& in, SeedGrid& g) {
    for (Face f : in.sm.faces()) {
        const CGAL::Bbox_3 b = PMP::face_bbox(f, in.sm);
        const glm::ivec3 a = g.cellOf({b.xmin(), b.ymin(), b.zmin()}), c = g.cellOf({b.xmax(), b.ymax(), b.zmax()});
        for (int z = a.z; z <= c.z; ++z)
            for (int y = a.y; y <= c.y; ++y)
                for (int x = a.x; x <= c.x; ++x) g.boundary[g.index({x, y, z})] = 1;
    }
}

// Sorts the cells that meet no triangle into regions (6-connected); each region is wholly
// inside or wholly outside, so one exact test of its first cell's centre decides it.
void addInsideRegions(SeedGrid& g, const CGAL::Side_of_triangle_mesh<SM, K>& inside) {
    std::vector<char> seen(g.boundary.begin(), g.boundary.end());
    std::vector<std::uint32_t> region, stack;
    for (std::size_t start = 0; start < seen.size(); ++start) {
        if (seen[start]) continue;
        region.clear();
        stack.assign(1, std::uint32_t(start));
        seen[start] = 1;
        while (!stack.empty()) {
            const std::uint32_t i = stack.back();
            stack.pop_back();
            region.push_back(i);
            const glm::ivec3 c = g.coords(i);
            for (int axis = 0; axis < 3; ++axis)
                for (int step : {-1, 1}) {
                    glm::ivec3 d = c;
                    d[axis] += step;
                    if (d[axis] < 0 || d[axis] >= g.n[axis] || seen[g.index(d)]) continue;
                    seen[g.index(d)] = 1;
                    stack.push_back(std::uint32_t(g.index(d)));
                }
        }
        const glm::dvec3 centre = g.lo + (glm::dvec3(g.coords(region.front())) + 0.5) * g.cell;
        if (inside(toPoint(centre)) == CGAL::ON_BOUNDED_SIDE) g.candidates.insert(g.candidates.end(), region.begin(), region.end());
    }
    for (std::size_t i = 0; i < g.boundary.size(); ++i)
        if (g.boundary[i]) g.candidates.push_back(std::uint32_t(i));
    std::sort(g.candidates.begin(), g.candidates.end());
}

SeedGrid seedGrid(const Input& in, const CGAL::Side_of_triangle_mesh<SM, K>& inside) {
    SeedGrid g;
    const glm::dvec3 lo(in.bbox.xmin(), in.bbox.ymin(), in.bbox.zmin()), hi(in.bbox.xmax(), in.bbox.ymax(), in.bbox.zmax());
    const glm::dvec3 extent = glm::max(hi - lo, glm::dvec3(1e-12));
    constexpr double kCellsAlongLongest = 32.0;
    const double longest = std::max({extent.x, extent.y, extent.z});
    g.n = glm::max(glm::ivec3(glm::ceil(extent / longest * kCellsAlongLongest)), glm::ivec3(1));
    g.lo = lo;
    g.cell = extent / glm::dvec3(g.n);
    g.boundary.assign(std::size_t(g.n.x) * std::size_t(g.n.y) * std::size_t(g.n.z), 0);
    markSurfaceCells(in, g);
    addInsideRegions(g, inside);
    return g;
}

// Seeds uniform in the volume (denser near the impact when given): points drawn uniformly in
// the candidate cells, kept when the exact inside test says so (always, in a cell that meets
// no triangle). Rejection keeps exactly the points of the volume, so the density is uniform.
std::vector<glm::dvec3> sampleSeeds(const Input& in, int count, std::uint64_t seed,
                                    const std::optional<glm::dvec3>& impact, double radius, double boost) {
    const CGAL::Side_of_triangle_mesh<SM, K>& inside = *in.inside;
    const SeedGrid grid = seedGrid(in, inside);
    if (grid.candidates.empty()) throw InputError("fracture: the mesh has no interior volume to place seeds in");
    Rng rng(deriveSeed(seed, "fracture-seeds"));
    std::vector<glm::dvec3> seeds;
    seeds.reserve(std::size_t(count));
    const double maxWeight = 1.0 + (impact ? boost : 0.0);
    for (std::size_t attempt = 0; int(seeds.size()) < count; ++attempt) {
        if (attempt > 1000u * std::size_t(count) + 100000u)
            throw InputError("fracture: could not place the seeds (is the impact far outside the mesh, or the mesh flat?)");
        const std::uint32_t cell = grid.candidates[rng.below(grid.candidates.size())];
        const glm::dvec3 u(rng.uniform(), rng.uniform(), rng.uniform());
        const glm::dvec3 p = grid.lo + (glm::dvec3(grid.coords(cell)) + u) * grid.cell;
        if (grid.boundary[cell] && inside(toPoint(p)) != CGAL::ON_BOUNDED_SIDE) continue;
        if (impact) {  // rejection: density 1 + boost·exp(-(d/r)^2)
            const double d = glm::length(p - *impact) / std::max(radius, 1e-9);
            if (rng.uniform() * maxWeight > 1.0 + boost * std::exp(-d * d)) continue;
        }
        seeds.push_back(p);
    }
    return seeds;
}

// ---------------------------------------------------------------- cells

using DelaunayVb = CGAL::Triangulation_vertex_base_with_info_3<std::uint32_t, K>;
using DelaunayTds = CGAL::Triangulation_data_structure_3<DelaunayVb>;
using Delaunay = CGAL::Delaunay_triangulation_3<K, DelaunayTds>;

struct Cells {
    std::vector<std::vector<std::uint32_t>> neighbours;  // per cell, sorted: its Delaunay neighbours
    std::vector<std::vector<CutPlane>> planes;           // per cell: the neighbours' bisectors, then the box
    std::vector<SM> meshes;                              // per cell, made by buildCellMeshes (corefinement only)
    std::vector<CGAL::Bbox_3> boxes;
};

using detail::Metric;

// Every other seed is a neighbour: a superset of the Delaunay neighbours, for few seeds.
std::vector<std::vector<std::uint32_t>> allNeighbours(std::size_t n) {
    std::vector<std::vector<std::uint32_t>> neighbours(n);
    for (std::uint32_t i = 0; i < n; ++i)
        for (std::uint32_t j = 0; j < n; ++j)
            if (i != j) neighbours[i].push_back(j);
    return neighbours;
}

std::vector<std::vector<std::uint32_t>> delaunayNeighbours(const std::vector<glm::dvec3>& seeds, const Metric& metric) {
    const std::size_t n = seeds.size();
    if (n <= 8) return allNeighbours(n);
    std::vector<std::vector<std::uint32_t>> neighbours(n);
    std::vector<std::pair<Point, std::uint32_t>> points;
    for (std::uint32_t i = 0; i < n; ++i) points.emplace_back(toPoint(metric.squeeze(seeds[i])), i);
    Delaunay dt(points.begin(), points.end());
    if (dt.number_of_vertices() != n) {
        std::vector<std::uint32_t> order(n);
        std::iota(order.begin(), order.end(), 0u);
        std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
            return std::tie(seeds[a].x, seeds[a].y, seeds[a].z, a) < std::tie(seeds[b].x, seeds[b].y, seeds[b].z, b);
        });
        for (std::size_t k = 1; k < n; ++k)
            if (seeds[order[k]] == seeds[order[k - 1]])
                throw InputError(format("fracture: seeds {} and {} are at the same point", order[k - 1], order[k]));
        throw InputError("fracture: the seeds are repeated");
    }
    if (dt.dimension() < 3) return allNeighbours(n);  // coplanar or collinear seeds
    for (auto v = dt.finite_vertices_begin(); v != dt.finite_vertices_end(); ++v) {
        std::vector<Delaunay::Vertex_handle> adjacent;
        dt.finite_adjacent_vertices(v, std::back_inserter(adjacent));
        for (const auto& w : adjacent) neighbours[v->info()].push_back(w->info());
        std::sort(neighbours[v->info()].begin(), neighbours[v->info()].end());
    }
    return neighbours;
}

Cells buildCells(const std::vector<glm::dvec3>& seeds, const CGAL::Bbox_3& bounds, std::int64_t cellBase,
                 const Metric& metric) {
    const std::size_t n = seeds.size();
    Cells cells;
    cells.neighbours = delaunayNeighbours(seeds, metric);
    cells.planes.resize(n);
    cells.meshes.resize(n);
    cells.boxes.resize(n);
    const std::vector<CutPlane> bounding = boxPlanes(bounds);
    for (std::size_t i = 0; i < n; ++i) {
        std::vector<CutPlane>& planes = cells.planes[i];
        for (std::uint32_t j : cells.neighbours[i]) {
            const glm::dvec3 normal = metric.bisectorNormal(seeds[j] - seeds[i]);
            const double len = glm::length(normal);
            if (len == 0.0) throw InputError(format("fracture: seeds {} and {} are at the same point", i, j));
            const glm::dvec3 mid = 0.5 * (seeds[i] + seeds[j]);
            planes.push_back({Plane(normal.x, normal.y, normal.z, -glm::dot(normal, mid)), normal / len,
                              cellBase + std::int64_t(j)});
        }
        planes.insert(planes.end(), bounding.begin(), bounding.end());
    }
    return cells;
}

// The convex polyhedra of cells `ids` (for corefinement and the rough path).
void buildCellMeshes(Cells& cells, const std::vector<glm::dvec3>& seeds, std::span<const std::uint32_t> ids) {
    tbb::parallel_for(std::size_t(0), ids.size(), [&](std::size_t k) {
        const std::uint32_t i = ids[k];
        cells.meshes[i] = convexCell(cells.planes[i], -1, toPoint(seeds[i]), i);
        cells.boxes[i] = PMP::bbox(cells.meshes[i]);
    });
}

// ---------------------------------------------------------------- the hierarchy

struct Hierarchy {
    const SM& input;  // the clean input surface: the fallback when a chained cut fails
    const Cells& cells;
    const std::vector<glm::dvec3>& seeds;
    double margin;
    std::vector<SM>& results;
    const ProgressFn& progress;
    std::atomic<std::size_t> done{0};
    std::mutex progressMutex{};
    std::atomic<bool> cancelled{false};

    void cellDone() {
        const std::size_t d = ++done;
        std::lock_guard lock(progressMutex);
        if (!progress(double(d) / double(results.size()))) cancelled = true;
    }

    // The margin of a box at `depth` around its cells' bounding box. It shrinks with depth
    // so that a child box never shares a plane with its parent box (the parent's cut faces
    // have rounded corners: meeting them edge-on breaks corefinement), and stays above
    // half the first margin so that every cell stays strictly inside every box.
    double marginAt(int depth) const { return margin * (1.0 - std::min(depth, 32) / 64.0); }

    // nodeMesh equals the mesh inside a region that strictly contains every cell in `ids`.
    void process(const SM& nodeMesh, std::vector<std::uint32_t> ids, int depth = 0) {
        if (cancelled) throw Cancelled();
        if (nodeMesh.number_of_faces() == 0) {  // the region misses the mesh: no pieces here
            for (std::size_t k = 0; k < ids.size(); ++k) cellDone();
            return;
        }
        constexpr std::size_t kLeafCells = 20;
        if (ids.size() <= kLeafCells) {
            // A cell whose box meets no surface triangle lies wholly inside the mesh (the
            // piece is the cell itself) or wholly outside: no corefinement needed.
            std::vector<CGAL::Bbox_3> faceBoxes;
            faceBoxes.reserve(nodeMesh.number_of_faces());
            for (Face f : nodeMesh.faces()) faceBoxes.push_back(PMP::face_bbox(f, nodeMesh));
            std::vector<char> touches(ids.size(), 0);
            for (std::size_t k = 0; k < ids.size(); ++k)
                touches[k] = std::any_of(faceBoxes.begin(), faceBoxes.end(), [&](const CGAL::Bbox_3& b) {
                    return CGAL::do_overlap(b, cells.boxes[ids[k]]);
                });
            std::optional<CGAL::Side_of_triangle_mesh<SM, K>> inside;
            if (std::count(touches.begin(), touches.end(), 0) > 0) inside.emplace(nodeMesh);
            tbb::parallel_for(std::size_t(0), ids.size(), [&](std::size_t k) {
                const std::uint32_t id = ids[k];
                if (!touches[k]) {
                    if ((*inside)(toPoint(seeds[id])) == CGAL::ON_BOUNDED_SIDE) results[id] = cells.meshes[id];
                } else {
                    SM piece = nodeMesh;
                    SM cell = cells.meshes[id];
                    if (!tryIntersectInPlace(piece, cell, "cell", id)) {  // redo it on the clean input
                        piece = input;
                        cell = cells.meshes[id];
                        if (!tryIntersectInPlace(piece, cell, "cell", id))
                            throw InputError(format("fracture: cell {} meets a self-intersection of the mesh", id));
                    }
                    results[id] = std::move(piece);
                }
                cellDone();
            });
            return;
        }
        // Split the cells in two halves along the longest axis of their seeds.
        glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
        for (std::uint32_t id : ids) {
            lo = glm::min(lo, seeds[id]);
            hi = glm::max(hi, seeds[id]);
        }
        const glm::dvec3 extent = hi - lo;
        const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
        std::sort(ids.begin(), ids.end(), [&](std::uint32_t a, std::uint32_t b) {
            return seeds[a][axis] != seeds[b][axis] ? seeds[a][axis] < seeds[b][axis] : a < b;
        });
        const std::size_t half = ids.size() / 2;
        std::vector<std::uint32_t> left(ids.begin(), ids.begin() + std::ptrdiff_t(half));
        std::vector<std::uint32_t> right(ids.begin() + std::ptrdiff_t(half), ids.end());
        tbb::parallel_invoke([&] { child(nodeMesh, std::move(left), depth + 1); },
                             [&] { child(nodeMesh, std::move(right), depth + 1); });
    }

    void child(const SM& parentMesh, std::vector<std::uint32_t> ids, int depth) {
        CGAL::Bbox_3 box = cells.boxes[ids[0]];
        for (std::uint32_t id : ids) box += cells.boxes[id];
        box = expanded(box, marginAt(depth));
        const CGAL::Bbox_3 c = box;
        SM boxMesh = convexCell(boxPlanes(c), kBoxOrigin,
                                Point(0.5 * (c.xmin() + c.xmax()), 0.5 * (c.ymin() + c.ymax()), 0.5 * (c.zmin() + c.zmax())),
                                ids[0]);
        SM mesh = parentMesh;
        if (tryIntersectInPlace(mesh, boxMesh, "cell group of", ids[0]))
            process(mesh, std::move(ids), depth);
        else  // the box cut failed: its cells take the parent's mesh, which is also valid for them
            process(parentMesh, std::move(ids), depth);
    }
};

// ---------------------------------------------------------------- pieces

glm::dvec3 barycentric(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 v0 = b - a, v1 = c - a, v2 = p - a;
    const double d00 = glm::dot(v0, v0), d01 = glm::dot(v0, v1), d11 = glm::dot(v1, v1);
    const double d20 = glm::dot(v2, v0), d21 = glm::dot(v2, v1);
    const double denom = d00 * d11 - d01 * d01;
    if (denom == 0.0) return {1.0, 0.0, 0.0};
    const double v = (d11 * d20 - d01 * d21) / denom, w = (d00 * d21 - d01 * d20) / denom;
    return {1.0 - v - w, v, w};
}

// Two unit vectors spanning the plane with normal n, chosen the same way for every piece
// so that cut-face UVs line up across neighbours.
void planeBasis(const glm::dvec3& n, glm::dvec3& u, glm::dvec3& v) {
    const glm::dvec3 a = std::abs(n.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
    u = glm::normalize(glm::cross(a, n));
    v = glm::cross(n, u);
}

struct Triangle {
    std::array<Vertex, 3> v;
    Origin origin;
};

// The grid the cutting rounds every corner to, per axis the power of two 2^-29 of the input's
// reach. Integer coordinates on it stay below 2^29, so cross and dot products of their
// differences are exact in 64-bit integers: the mending of each piece (detail::cleanSurface)
// decides collapses, flat triangles and contacts exactly, and shared faces of neighbouring
// pieces coincide corner for corner. The rounding also absorbs CGAL's run-to-run differences
// in the last bits of intersection points. It moves the input by about 1e-9 of its size; the
// files' float precision is applied afterwards, per piece (detail::roundForFiles).
struct Grid {
    glm::dvec3 h{1.0};
    glm::i64vec3 key(const glm::dvec3& p) const {
        return {std::llround(p.x / h.x), std::llround(p.y / h.y), std::llround(p.z / h.z)};
    }
    glm::dvec3 at(const glm::i64vec3& k) const { return glm::dvec3(k) * h; }
    glm::dvec3 snap(const glm::dvec3& p) const { return at(key(p)); }
};

Grid gridFor(const Bounds& b) {
    Grid g;
    for (int axis = 0; axis < 3; ++axis) {
        const double reach = std::max({std::abs(double(b.min[axis])), std::abs(double(b.max[axis])),
                                       double(b.max[axis]) - double(b.min[axis]), 1e-30});
        g.h[axis] = std::ldexp(1.0, std::ilogb(reach) + 1 - 29);
    }
    return g;
}

// A piece's corners rounded to the grid; everything downstream (order, flips, mass
// properties, the file) reads the rounded points.
struct Snapped {
    const SM& sm;
    const Grid& grid;
    Point operator()(Vertex v) const { return toPoint(grid.snap(toGlm(sm.point(v)))); }
};

// A triangle's corners, rotated so that the lexicographically smallest comes first
// (orientation kept): sorting by this orders triangles by geometry alone.
std::array<double, 9> triangleKey(const Snapped& point, const std::array<Vertex, 3>& v) {
    std::array<Point, 3> p{point(v[0]), point(v[1]), point(v[2])};
    const std::size_t first = std::size_t(std::min_element(p.begin(), p.end()) - p.begin());
    std::array<double, 9> key{};
    for (std::size_t i = 0; i < 3; ++i) {
        const Point& q = p[(first + i) % 3];
        key[3 * i] = q.x();
        key[3 * i + 1] = q.y();
        key[3 * i + 2] = q.z();
    }
    return key;
}

// CGAL 5.5's corefinement triangulates a split face differently from run to run (the
// result depends on memory addresses), though the vertices are the same. Each planar
// group of triangles (one origin: the part of one input triangle, or of one cut plane)
// is therefore brought to its constrained Delaunay triangulation by Lawson flips with
// exact predicates, co-circular ties going to the diagonal with the smallest vertex:
// that triangulation depends on the points and the group's boundary only.
void canonicalTriangulation(const Snapped& point, std::vector<Triangle>& tris) {
    using K2 = K;
    std::map<Origin, std::vector<std::size_t>> groups;
    for (std::size_t i = 0; i < tris.size(); ++i) groups[tris[i].origin].push_back(i);
    for (auto& [origin, members] : groups) {
        if (members.size() < 2) continue;
        // Project on the plane of the group's largest normal component.
        K::Vector_3 n(0, 0, 0);
        for (std::size_t i : members)
            n = n + CGAL::cross_product(point(tris[i].v[1]) - point(tris[i].v[0]),
                                        point(tris[i].v[2]) - point(tris[i].v[0]));
        const int axis = std::abs(n.x()) >= std::abs(n.y()) && std::abs(n.x()) >= std::abs(n.z()) ? 0
                         : std::abs(n.y()) >= std::abs(n.z())                                    ? 1
                                                                                                 : 2;
        const bool flipSign = (axis == 0 ? n.x() : axis == 1 ? n.y() : n.z()) < 0;
        auto project = [&](Vertex v) {
            const Point& p = point(v);
            const double a = axis == 0 ? p.y() : axis == 1 ? p.z() : p.x();
            const double b = axis == 0 ? p.z() : axis == 1 ? p.x() : p.y();
            return flipSign ? K2::Point_2(b, a) : K2::Point_2(a, b);  // keep counter-clockwise
        };
        auto before = [&](Vertex a, Vertex b) { return point(a) < point(b); };
        // Directed edge -> (triangle, corner opposite to it).
        std::map<std::pair<Vertex, Vertex>, std::pair<std::size_t, int>> edgeOf;
        auto index = [&](std::size_t t) {
            for (int k = 0; k < 3; ++k)
                edgeOf[{tris[t].v[std::size_t(k)], tris[t].v[std::size_t((k + 1) % 3)]}] = {t, (k + 2) % 3};
        };
        auto unindex = [&](std::size_t t) {
            for (int k = 0; k < 3; ++k) edgeOf.erase({tris[t].v[std::size_t(k)], tris[t].v[std::size_t((k + 1) % 3)]});
        };
        for (std::size_t t : members) index(t);
        std::vector<std::pair<Vertex, Vertex>> stack;
        for (const auto& [e, _] : edgeOf) stack.push_back(e);
        std::size_t flips = 0;
        const std::size_t maxFlips = 64 * members.size() * members.size() + 1000;
        while (!stack.empty() && flips < maxFlips) {
            const auto [a, b] = stack.back();
            stack.pop_back();
            const auto e1 = edgeOf.find({a, b}), e2 = edgeOf.find({b, a});
            if (e1 == edgeOf.end() || e2 == edgeOf.end()) continue;  // a boundary edge: constrained
            const std::size_t t1 = e1->second.first, t2 = e2->second.first;
            const Vertex c = tris[t1].v[std::size_t(e1->second.second)], d = tris[t2].v[std::size_t(e2->second.second)];
            const K2::Point_2 pa = project(a), pb = project(b), pc = project(c), pd = project(d);
            if (CGAL::orientation(pa, pb, pc) != CGAL::LEFT_TURN || CGAL::orientation(pb, pa, pd) != CGAL::LEFT_TURN)
                continue;
            if (CGAL::orientation(pa, pd, pc) != CGAL::LEFT_TURN || CGAL::orientation(pd, pb, pc) != CGAL::LEFT_TURN)
                continue;  // not strictly convex: the other diagonal would leave the quad
            const CGAL::Oriented_side side = CGAL::side_of_oriented_circle(pa, pb, pc, pd);
            const Vertex minOld = std::min(a, b, before), minNew = std::min(c, d, before);
            const bool flip = side == CGAL::ON_POSITIVE_SIDE ||
                              (side == CGAL::ON_ORIENTED_BOUNDARY && before(minNew, minOld));
            if (!flip) continue;
            unindex(t1);
            unindex(t2);
            tris[t1].v = {a, d, c};
            tris[t2].v = {d, b, c};
            index(t1);
            index(t2);
            ++flips;
            stack.insert(stack.end(), {{a, d}, {d, b}, {b, c}, {c, a}});
        }
    }
    std::vector<std::pair<std::array<double, 9>, Triangle>> keyed;
    keyed.reserve(tris.size());
    for (Triangle t : tris) {  // start each triangle at its smallest corner
        const auto first = std::min_element(t.v.begin(), t.v.end(),
                                            [&](Vertex a, Vertex b) { return point(a) < point(b); });
        std::rotate(t.v.begin(), first, t.v.end());
        keyed.emplace_back(triangleKey(point, t.v), t);
    }
    std::sort(keyed.begin(), keyed.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    for (std::size_t i = 0; i < tris.size(); ++i) tris[i] = keyed[i].second;
}

// The attributes of one corner of a piece's triangle: an input triangle's normal, UV and
// material interpolated at the corner; a cut face's plane normal, planar UVs in metres and
// the interior material.
struct Corner {
    glm::vec3 normal{0.0f};
    glm::vec2 uv{0.0f};
    std::uint8_t material = 0;
};

std::array<Corner, 3> cornerAttributes(const std::array<glm::dvec3, 3>& p, Origin origin, const Input& in,
                                       const std::vector<CutPlane>& planes, const FractureSettings& settings) {
    std::array<Corner, 3> out{};
    if (origin >= 0) {
        const Mesh& src = *in.mesh;
        const std::size_t t = std::size_t(origin);
        const std::uint32_t i0 = src.indices[3 * t], i1 = src.indices[3 * t + 1], i2 = src.indices[3 * t + 2];
        const glm::dvec3 a(src.positions[i0]), b(src.positions[i1]), c(src.positions[i2]);
        const glm::dvec3 flat = glm::normalize(glm::cross(b - a, c - a));
        for (std::size_t corner = 0; corner < 3; ++corner) {
            const glm::dvec3 w = barycentric(p[corner], a, b, c);
            out[corner].material = src.materialIds.empty() ? 0 : src.materialIds[i0];
            out[corner].normal = src.normals.empty() ? glm::vec3(flat)
                                                     : glm::vec3(glm::normalize(w.x * glm::dvec3(src.normals[i0]) +
                                                                                w.y * glm::dvec3(src.normals[i1]) +
                                                                                w.z * glm::dvec3(src.normals[i2])));
            if (!src.uv0.empty())
                out[corner].uv = glm::vec2(w.x * glm::dvec2(src.uv0[i0]) + w.y * glm::dvec2(src.uv0[i1]) +
                                           w.z * glm::dvec2(src.uv0[i2]));
        }
    } else {
        const CutPlane& plane = planes[std::size_t(-1 - origin)];
        glm::dvec3 u, v;
        planeBasis(plane.normal, u, v);
        for (std::size_t corner = 0; corner < 3; ++corner)
            out[corner] = {glm::vec3(plane.normal),
                           glm::vec2(glm::dot(p[corner], u), glm::dot(p[corner], v)) / float(settings.interiorUvScale),
                           settings.interiorMaterial};
    }
    return out;
}

// One piece from one part of a cell's surface, its corners on the grid.
detail::RawPiece buildPiece(const std::vector<detail::GridTriangle>& part, std::span<const glm::i64vec3> points,
                    const Grid& grid, const Input& in, const std::vector<CutPlane>& planes, std::int64_t ownCell,
                    const FractureSettings& settings) {
    detail::RawPiece piece;
    piece.cell = ownCell;
    piece.mesh.name = "piece";
    struct Key {
        std::uint32_t point;
        std::array<float, 5> attributes;  // normal, uv
        std::uint8_t material;
        bool operator<(const Key& k) const {
            return std::tie(point, attributes, material) < std::tie(k.point, k.attributes, k.material);
        }
    };
    std::map<Key, std::uint32_t> vertexOf;
    std::map<std::uint32_t, std::uint32_t> pointOf;
    for (const detail::GridTriangle& tri : part) {
        const std::array<glm::dvec3, 3> p{grid.at(points[tri.v[0]]), grid.at(points[tri.v[1]]), grid.at(points[tri.v[2]])};
        for (std::uint32_t v : tri.v) {
            auto [it, inserted] = pointOf.try_emplace(v, std::uint32_t(piece.points.size()));
            if (inserted) piece.points.push_back(grid.at(points[v]));
            piece.pointIndices.push_back(it->second);
        }
        const std::array<Corner, 3> corners = cornerAttributes(p, tri.origin, in, planes, settings);
        detail::PlaneKey plane = detail::kSurface;
        if (tri.origin >= 0) {
            if (in.planes) plane = (*in.planes)[std::size_t(tri.origin)];
        } else if (tri.origin != kBoxOrigin && planes[std::size_t(-1 - tri.origin)].neighbour >= 0) {
            plane = detail::planeKey(ownCell, planes[std::size_t(-1 - tri.origin)].neighbour);
        }
        piece.planes.push_back(plane);
        for (std::size_t corner = 0; corner < 3; ++corner) {
            const Corner& c = corners[corner];
            const Key vk{tri.v[corner], {c.normal.x, c.normal.y, c.normal.z, c.uv.x, c.uv.y}, c.material};
            auto [it, inserted] = vertexOf.try_emplace(vk, std::uint32_t(piece.mesh.positions.size()));
            if (inserted) {
                piece.mesh.positions.push_back(glm::vec3(p[corner]));
                piece.worldPositions.push_back(p[corner]);
                piece.mesh.normals.push_back(c.normal);
                piece.mesh.uv0.push_back(c.uv);
                piece.mesh.materialIds.push_back(c.material);
            }
            piece.mesh.indices.push_back(it->second);
        }
    }
    piece.mass = computeMassProperties(piece.points, piece.pointIndices, settings.density);
    return piece;
}

// The pieces of one cell from its triangles (three corners each, counter-clockwise from
// outside): corners on the grid, welded by grid point, mended (detail::cleanSurface) and split
// into closed parts: the volumes a cell cuts out of a non-convex mesh, and the parts that
// rounding left touching.
std::vector<detail::RawPiece> piecesOf(std::span<const glm::dvec3> corners, std::span<const Origin> triangleOrigins,
                                       const Grid& grid, const Input& in, const std::vector<CutPlane>& planes,
                                       std::int64_t ownCell, const FractureSettings& settings) {
    std::vector<glm::i64vec3> points;
    std::map<std::array<std::int64_t, 3>, std::uint32_t> idOf;
    std::vector<detail::GridTriangle> welded;
    welded.reserve(triangleOrigins.size());
    for (std::size_t t = 0; t < triangleOrigins.size(); ++t) {
        detail::GridTriangle g{{}, triangleOrigins[t]};
        for (std::size_t k = 0; k < 3; ++k) {
            const glm::i64vec3 q = grid.key(corners[3 * t + k]);
            const auto [it, inserted] = idOf.try_emplace({q.x, q.y, q.z}, std::uint32_t(points.size()));
            if (inserted) points.push_back(q);
            g.v[k] = it->second;
        }
        welded.push_back(g);
    }
    std::vector<detail::RawPiece> pieces;
    for (const auto& part : detail::cleanSurface(points, std::move(welded)).parts)
        pieces.push_back(buildPiece(part, points, grid, in, planes, ownCell, settings));
    return pieces;
}

// The pieces of one cell a corefinement cut, its triangles made canonical first.
std::vector<detail::RawPiece> extractPieces(const SM& sm, const Input& in, const Grid& grid, const std::vector<CutPlane>& planes,
                                    std::int64_t ownCell, const FractureSettings& settings) {
    const auto o = origins(sm);
    std::vector<Triangle> tris;
    tris.reserve(sm.number_of_faces());
    for (Face f : sm.faces()) {
        Triangle t{{}, o[f]};
        int k = 0;
        for (Vertex v : CGAL::vertices_around_face(sm.halfedge(f), sm)) t.v[std::size_t(k++)] = v;
        tris.push_back(t);
    }
    canonicalTriangulation(Snapped{sm, grid}, tris);
    std::vector<glm::dvec3> corners;
    std::vector<Origin> triangleOrigins;
    for (const Triangle& t : tris) {
        for (Vertex v : t.v) corners.push_back(toGlm(sm.point(v)));
        triangleOrigins.push_back(t.origin);
    }
    return piecesOf(corners, triangleOrigins, grid, in, planes, ownCell, settings);
}

// The pieces of one cell of the restricted Voronoi diagram: its caps name the seed across, which
// becomes that neighbour's cut plane.
std::vector<detail::RawPiece> rvdPieces(const detail::RvdCell& cell, std::span<const Origin> inputOrigins,
                                        const std::vector<std::uint32_t>& neighbours, const Grid& grid, const Input& in,
                                        const std::vector<CutPlane>& planes, std::int64_t ownCell,
                                        const FractureSettings& settings) {
    std::vector<glm::dvec3> corners;
    std::vector<Origin> triangleOrigins;
    for (const detail::RvdCell::Triangle& t : cell.triangles) {
        for (std::uint32_t v : t.v) corners.push_back(cell.points[v]);
        if (t.origin >= 0) {
            triangleOrigins.push_back(inputOrigins[std::size_t(t.origin)]);
        } else {
            const auto j = std::uint32_t(-1 - t.origin);
            const auto plane = std::lower_bound(neighbours.begin(), neighbours.end(), j) - neighbours.begin();
            triangleOrigins.push_back(-1 - Origin(plane));
        }
    }
    return piecesOf(corners, triangleOrigins, grid, in, planes, ownCell, settings);
}

// The pieces of the rough path (rough.cpp), as raw pieces with cut groups for bonds.
// Rough pieces re-mesh the whole surface, so their faces name only the cuts made here: a
// piece re-fractured by `levels` keeps bonds among its own sub-pieces, not outward.
std::vector<detail::RawPiece> roughFracture(const Mesh& mesh, const Cells& cells, const std::vector<glm::dvec3>& seeds,
                                    std::int64_t cellBase, double diagonal, const Grid& grid,
                                    const FractureSettings& settings) {
    std::vector<detail::RoughCell> rough(seeds.size());
    for (std::size_t i = 0; i < seeds.size(); ++i) {
        for (const CutPlane& c : cells.planes[i]) {
            const glm::dvec3 n(c.plane.a(), c.plane.b(), c.plane.c());
            const double len = glm::length(n);
            const std::int64_t own = cellBase + std::int64_t(i);
            rough[i].planes.push_back({n / len, c.plane.d() / len,
                                       c.neighbour < 0 ? 0.0 : (own < c.neighbour ? 1.0 : -1.0), c.neighbour});
        }
        const CGAL::Bbox_3& b = cells.boxes[i];
        rough[i].lo = {b.xmin(), b.ymin(), b.zmin()};
        rough[i].hi = {b.xmax(), b.ymax(), b.zmax()};
    }
    detail::RoughSettings rs;
    rs.amplitude = settings.roughness;
    rs.featureSize = settings.roughScale > 0.0 ? settings.roughScale : 4.0 * settings.roughness;
    rs.voxelSize = settings.voxelSize > 0.0 ? settings.voxelSize
                                            : std::clamp(0.5 * settings.roughness, diagonal / 400.0, diagonal / 50.0);
    rs.seed = deriveSeed(settings.seed, "fracture-roughness");
    rs.interiorMaterial = settings.interiorMaterial;
    rs.uvScale = settings.interiorUvScale;
    std::vector<std::vector<detail::RoughPiece>> perCell = detail::roughPieces(mesh, rough, rs);

    std::vector<detail::RawPiece> pieces;
    for (std::size_t i = 0; i < perCell.size(); ++i)
        for (detail::RoughPiece& rp : perCell[i]) {
            detail::RawPiece p;
            p.cell = cellBase + std::int64_t(i);
            p.mesh = std::move(rp.mesh);
            p.mesh.name = "piece";
            for (std::int64_t neighbour : rp.triangleKeys)
                p.planes.push_back(neighbour < 0 ? detail::kSurface : detail::planeKey(p.cell, neighbour));
            for (glm::vec3& q : p.mesh.positions) {
                p.worldPositions.push_back(grid.snap(glm::dvec3(q)));
                q = glm::vec3(p.worldPositions.back());
            }
            p.points = p.worldPositions;
            p.pointIndices = p.mesh.indices;
            p.mass = computeMassProperties(p.points, p.pointIndices, settings.density);
            pieces.push_back(std::move(p));
        }
    return pieces;
}

// Everything one fracture call's cells share.
struct CellJob {
    const Input& in;
    const Grid& grid;
    const FractureSettings& settings;
    std::int64_t cellBase;
    CGAL::Bbox_3 box;  // around every cell
    Metric metric;
    double diagonal;
    std::vector<glm::dvec3> seeds;
    Cells cells;
    std::vector<std::vector<detail::RawPiece>> perCell;  // per cell: its pieces, in the order of their smallest corner

    CellJob(const Input& input, const Grid& g, const FractureSettings& s, std::int64_t base, std::vector<glm::dvec3> seedPoints)
        : in(input), grid(g), settings(s), cellBase(base), metric{glm::normalize(s.grain), s.stretch},
          seeds(std::move(seedPoints)), perCell(seeds.size()) {
        const CGAL::Bbox_3& b = in.bbox;
        diagonal = std::sqrt(std::pow(b.xmax() - b.xmin(), 2) + std::pow(b.ymax() - b.ymin(), 2) +
                             std::pow(b.zmax() - b.zmin(), 2));
        box = expanded(b, 0.01 * diagonal + 1e-6);
        cells = buildCells(seeds, box, cellBase, metric);
    }
};

// Cuts cells `ids` by one corefinement each.
void corefineCells(CellJob& job, std::span<const std::uint32_t> ids, const ProgressFn& progress) {
    if (ids.empty()) return;
    buildCellMeshes(job.cells, job.seeds, ids);
    std::vector<SM> results(job.seeds.size());
    if (job.seeds.size() == 1) {  // one cell holds the whole mesh: nothing to cut
        results[0] = job.in.sm;
    } else {
        Hierarchy hierarchy{job.in.sm, job.cells, job.seeds, 1e-3 * job.diagonal + 1e-9, results, progress};
        hierarchy.process(job.in.sm, std::vector<std::uint32_t>(ids.begin(), ids.end()));
    }
    tbb::parallel_for(std::size_t(0), ids.size(), [&](std::size_t k) {
        const std::uint32_t i = ids[k];
        job.perCell[i] = extractPieces(results[i], job.in, job.grid, job.cells.planes[i], job.cellBase + std::int64_t(i),
                                       job.settings);
        results[i] = SM();
    });
}

// The input surface as plain arrays: its points (by SM vertex index), triangles and their origins.
struct SurfaceArrays {
    std::vector<glm::dvec3> points;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<Origin> origins;
};

SurfaceArrays surfaceArrays(const SM& sm) {
    SurfaceArrays s;
    for (Vertex v : sm.vertices()) s.points.push_back(toGlm(sm.point(v)));
    const auto o = origins(sm);
    for (Face f : sm.faces()) {
        std::array<std::uint32_t, 3> t{};
        std::size_t k = 0;
        for (Vertex v : CGAL::vertices_around_face(sm.halfedge(f), sm)) t[k++] = std::uint32_t(v);
        s.triangles.push_back(t);
        s.origins.push_back(o[f]);
    }
    return s;
}

// Cuts every cell through the restricted Voronoi diagram; returns the cells it could not close.
std::vector<std::uint32_t> rvdCells(CellJob& job, const SurfaceArrays& surface) {
    const CGAL::Bbox_3& b = job.box;
    const detail::RvdSeeds seeds{job.seeds, job.cells.neighbours, {b.xmin(), b.ymin(), b.zmin()},
                                 {b.xmax(), b.ymax(), b.zmax()}, job.metric};
    const CGAL::Side_of_triangle_mesh<SM, K>& side = *job.in.inside;
    const std::vector<detail::RvdCell> rvd =
        detail::restrictedVoronoi({surface.points, surface.triangles}, seeds,
                                  [&](const glm::dvec3& p) { return side(toPoint(p)) == CGAL::ON_BOUNDED_SIDE; });
    std::vector<std::uint32_t> failed;
    for (std::uint32_t i = 0; i < rvd.size(); ++i)
        if (!rvd[i].closed) failed.push_back(i);
    tbb::parallel_for(std::size_t(0), rvd.size(), [&](std::size_t i) {
        if (rvd[i].closed)
            job.perCell[i] = rvdPieces(rvd[i], surface.origins, job.cells.neighbours[i], job.grid, job.in,
                                       job.cells.planes[i], job.cellBase + std::int64_t(i), job.settings);
    });
    return failed;
}

// Whether the pieces' volumes add up to the surface's, up to what rounding the corners to the
// grid can move (the surface's area times a grid step).
bool volumesAddUp(const std::vector<std::vector<detail::RawPiece>>& perCell, const SurfaceArrays& surface,
                  const Grid& grid, double density) {
    std::vector<std::uint32_t> indices;
    double area = 0.0;
    for (const auto& t : surface.triangles) {
        indices.insert(indices.end(), t.begin(), t.end());
        const glm::dvec3 a = surface.points[t[0]];
        area += 0.5 * glm::length(glm::cross(surface.points[t[1]] - a, surface.points[t[2]] - a));
    }
    double sum = 0.0;
    for (const auto& list : perCell)
        for (const detail::RawPiece& p : list) sum += p.mass.mass / density;
    const double expected = computeMassProperties(surface.points, indices, 1.0).volume;
    return std::abs(sum - expected) <= 1e-9 * std::abs(expected) + area * std::max({grid.h.x, grid.h.y, grid.h.z});
}

struct Call {
    std::vector<detail::RawPiece> pieces;
    std::vector<glm::dvec3> seeds;
    std::size_t fallbackCells = 0;
};

// Seeds in a degenerate position (on a lattice: cells meeting four at an edge and eight at a
// corner, mesh edges on their bisectors) can leave cells the diagram cannot close by keys, and
// that CGAL's cell construction refuses as well. Moved by a millionth of the mesh's size, each
// its own way, they are in general position: cut again with the moved seeds.
void cutNudged(CellJob& job, const SurfaceArrays& surface) {
    Rng rng(deriveSeed(job.settings.seed, "fracture-nudge"));
    std::vector<glm::dvec3> moved = job.seeds;
    for (glm::dvec3& p : moved) p += 1e-6 * job.diagonal * glm::dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    CellJob again(job.in, job.grid, job.settings, job.cellBase, std::move(moved));
    const std::vector<std::uint32_t> failed = rvdCells(again, surface);
    corefineCells(again, failed, noProgress);
    job.seeds = std::move(again.seeds);
    job.cells = std::move(again.cells);
    job.perCell = std::move(again.perCell);
}

// The cells' pieces by the settings' method: the restricted Voronoi diagram, the cells it
// cannot close by corefinement (or all of them, from nudged seeds, if corefinement refuses
// one); and all of them by corefinement if the volumes do not add up. Returns how many cells
// corefinement cut.
std::size_t cutCells(CellJob& job, const ProgressFn& progress) {
    std::vector<std::uint32_t> all(job.seeds.size());
    std::iota(all.begin(), all.end(), 0u);
    if (job.settings.method == FractureMethod::Corefine) {
        corefineCells(job, all, progress);
        return 0;
    }
    const SurfaceArrays surface = surfaceArrays(job.in.sm);
    const std::vector<std::uint32_t> failed = rvdCells(job, surface);
    const double done = 1.0 - double(failed.size()) / double(all.size());
    if (!progress(done)) throw Cancelled();
    try {
        corefineCells(job, failed, [&](double f) { return progress(done + f); });
    } catch (const InputError&) {
        cutNudged(job, surface);
    }
    if (volumesAddUp(job.perCell, surface, job.grid, job.settings.density)) return failed.size();
    corefineCells(job, all, noProgress);
    return all.size();
}

// One fracture of one closed mesh into the cells of `seeds`, cells numbered from cellBase.
// Seeds are settings.points, or sampled from the surface this call builds anyway.
Call fractureOnce(const Mesh& mesh, const std::vector<detail::PlaneKey>* planes, std::span<const glm::dvec3> exact,
                  std::int64_t cellBase, const Grid& grid, const FractureSettings& settings, const ProgressFn& progress) {
    Input in = makeInput(mesh, planes, exact);
    in.inside.emplace(in.sm);
    Call call;
    call.seeds = !settings.points.empty() ? settings.points
                                          : sampleSeeds(in, settings.pieces, settings.seed, settings.impact,
                                                        settings.impactRadius, settings.impactDensity);
    CellJob job(in, grid, settings, cellBase, call.seeds);
    if (settings.roughness > 0.0) {
        std::vector<std::uint32_t> all(call.seeds.size());
        std::iota(all.begin(), all.end(), 0u);
        buildCellMeshes(job.cells, job.seeds, all);
        call.pieces = roughFracture(mesh, job.cells, job.seeds, cellBase, job.diagonal, grid, settings);
        return call;
    }
    call.fallbackCells = cutCells(job, progress);
    for (auto& list : job.perCell)
        for (detail::RawPiece& p : list) call.pieces.push_back(std::move(p));
    return call;
}

std::string pieceName(std::size_t i) {
    char name[32];
    std::snprintf(name, sizeof name, "piece_%04zu", i);
    return name;
}

double volumeOf(const Mesh& mesh) {
    const std::vector<glm::dvec3> points(mesh.positions.begin(), mesh.positions.end());
    return computeMassProperties(points, mesh.indices, 1.0).volume;
}

// Refuses a mesh that does not bound one volume, saying why.
void checkReport(const MeshReport& r) {
    if (!r.closed) {
        std::string where;
        for (const auto& [a, b] : r.openEdges)
            where += format("{}({} {} {})-({} {} {})", where.empty() ? ", open at " : ", ", a.x, a.y, a.z, b.x, b.y, b.z);
        throw RepairableMeshError(format("the mesh is not closed ({} boundary edges{}, {} non-manifold edges)",
                                         r.boundaryEdges, where, r.nonManifoldEdges));
    }
    if (!r.manifold)
        throw RepairableMeshError(format("the mesh is not manifold ({} non-manifold vertices)", r.nonManifoldVertices));
    if (r.selfIntersecting)
        throw RepairableMeshError("the mesh intersects itself; fracture needs a mesh that bounds one volume");
    if (!r.consistentlyOriented || !r.outwardOriented)
        throw RepairableMeshError("the mesh is inside out or inconsistently oriented");
    if (!r.volume || *r.volume <= 0.0) throw InputError("the mesh has no volume");
}

void checkInput(const Mesh& mesh) { checkReport(inspectMesh(mesh)); }

// Turns a closed mesh that is inside out outward (the notes say so), then checks that it bounds
// a volume. A mesh already outward is inspected once.
std::vector<std::string> orientAndCheck(Mesh& mesh) {
    MeshReport r = inspectMesh(mesh);
    std::vector<std::string> notes;
    if (!r.consistentlyOriented || !r.outwardOriented) {
        notes = orientMesh(mesh);
        if (!notes.empty()) r = inspectMesh(mesh);
    }
    checkReport(r);
    return notes;
}

}  // namespace

std::vector<glm::dvec3> sampleFractureSeeds(const Mesh& mesh, const FractureSettings& settings) {
    if (settings.pieces < 1) throw InputError(format("the number of pieces must be at least 1 (got {})", settings.pieces));
    Input in = makeInput(mesh, nullptr, {});
    in.inside.emplace(in.sm);
    return sampleSeeds(in, settings.pieces, settings.seed, settings.impact, settings.impactRadius,
                       settings.impactDensity);
}

namespace {

bool finite(const glm::dvec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

// Settings a user could get wrong, as sentences without the command line's names.
void checkSettings(const FractureSettings& s) {
    if (s.points.empty() && s.pieces < 1) throw InputError(format("the number of pieces must be at least 1 (got {})", s.pieces));
    if (s.impact && !finite(*s.impact)) throw InputError("the impact point is not finite");
    if (!(s.impactRadius > 0.0) || !std::isfinite(s.impactRadius))
        throw InputError(format("the impact radius must be positive (got {})", s.impactRadius));
    if (!(s.impactDensity >= 0.0)) throw InputError("the impact density boost must not be negative");
    for (const glm::dvec3& p : s.points)
        if (!finite(p)) throw InputError("a seed point is not finite");
    if (!(s.density > 0.0) || !std::isfinite(s.density))
        throw InputError(format("the density must be positive (got {})", s.density));
    if (s.interiorMaterial > 15) throw InputError(format("material IDs are 0 to 15 (got {})", int(s.interiorMaterial)));
    if (!(s.interiorUvScale > 0.0)) throw InputError("the UV scale of cut faces must be positive");
    if (!(s.minVolume >= 0.0)) throw InputError("the minimum piece volume must not be negative");
    if (s.levels < 0 || s.levels > 4) throw InputError(format("re-fracture levels are 0 to 4 (got {})", s.levels));
    if (s.levels > 0 && !s.impact)
        throw InputError("re-fracture levels need an impact point (the pieces near it are fractured again)");
    if (s.levelPieces < 2) throw InputError(format("a re-fractured piece needs at least 2 pieces (got {})", s.levelPieces));
    if (!finite(s.grain) || !(glm::length(s.grain) > 0.0)) throw InputError("the grain direction must not be zero");
    if (!(s.stretch >= 1.0) || !std::isfinite(s.stretch))
        throw InputError(format("the stretch of cells along the grain must be at least 1 (got {})", s.stretch));
    if (!(s.roughness >= 0.0) || !(s.roughScale >= 0.0) || !(s.voxelSize >= 0.0))
        throw InputError("roughness, its scale and the voxel size must not be negative");
}

// Fractures again, `levels` times, the pieces whose centre lies within the impact radius.
// A re-fractured piece's faces keep the cut plane they lay on, so its sub-pieces bond to
// the neighbours it had. A piece of part k is cut with partSettings[k] (its density, grain).
std::vector<detail::RawPiece> refracture(std::vector<detail::RawPiece> pieces, std::int64_t nextCell, const Grid& grid,
                                         const FractureSettings& settings,
                                         std::span<const FractureSettings> partSettings, FractureResult& result,
                                         const ProgressFn& progress) {
    for (int level = 1; level <= settings.levels && settings.impact; ++level) {
        std::vector<detail::RawPiece> next;
        for (std::size_t i = 0; i < pieces.size(); ++i) {
            detail::RawPiece& p = pieces[i];
            const bool near = glm::length(p.mass.centerOfMass - *settings.impact) <= settings.impactRadius;
            if (!near || p.level != std::uint32_t(level - 1)) {
                next.push_back(std::move(p));
                continue;
            }
            FractureSettings sub = p.part >= 0 ? partSettings[std::size_t(p.part)] : settings;
            sub.pieces = settings.levelPieces;
            sub.impact.reset();
            sub.points.clear();
            sub.seed = deriveSeed(settings.seed, "fracture-level", std::uint64_t(level) << 32 | i);
            Call call = fractureOnce(p.mesh, &p.planes, p.worldPositions, nextCell, grid, sub, noProgress);
            nextCell += std::int64_t(call.seeds.size());
            result.cells += call.seeds.size();
            result.fallbackCells += call.fallbackCells;
            for (detail::RawPiece& q : call.pieces) {
                q.level = std::uint32_t(level);
                q.part = p.part;
                next.push_back(std::move(q));
            }
        }
        pieces = std::move(next);
        if (!progress(double(level) / double(settings.levels))) throw Cancelled();
    }
    return pieces;
}

// Whether every edge of the mesh, its corners welded by position, is used by exactly one other
// triangle in the opposite direction: the mesh is closed as the file holds it.
bool closedByEdges(const Mesh& mesh) {
    std::map<std::array<float, 3>, std::uint32_t> id;
    std::vector<std::uint32_t> of;
    for (const glm::vec3& p : mesh.positions) of.push_back(id.try_emplace({p.x, p.y, p.z}, std::uint32_t(id.size())).first->second);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t)
        for (std::size_t k = 0; k < 3; ++k)
            edges.emplace_back(of[mesh.indices[3 * t + k]], of[mesh.indices[3 * t + (k + 1) % 3]]);
    std::sort(edges.begin(), edges.end());
    for (std::size_t k = 0; k < edges.size(); ++k) {
        const auto [a, b] = edges[k];
        if (a == b || (k + 1 < edges.size() && edges[k + 1] == edges[k])) return false;
        if (!std::binary_search(edges.begin(), edges.end(), std::pair{b, a})) return false;
    }
    return !edges.empty();
}

// The pieces as written: named in order, every vertex tagged with its piece; their meshes are
// already relative to their pivots (detail::roundForFiles).
std::vector<FracturePiece> finalPieces(std::vector<detail::RawPiece>& pieces) {
    std::vector<FracturePiece> out(pieces.size());
    tbb::parallel_for(std::size_t(0), pieces.size(), [&](std::size_t i) {
        detail::RawPiece& raw = pieces[i];
        FracturePiece& piece = out[i];
        piece.name = pieceName(i);
        piece.mass = raw.mass;
        piece.cell = std::uint32_t(raw.cell);
        piece.level = raw.level;
        piece.part = raw.part;
        piece.mesh = std::move(raw.mesh);
        piece.mesh.name = piece.name;
        piece.mesh.pieceIds.assign(piece.mesh.positions.size(), std::uint32_t(i));
        piece.closed = closedByEdges(piece.mesh);
    });
    return out;
}

FractureResult fractureChecked(const Mesh& input, const FractureSettings& settings, const ProgressFn& progress) {
    checkSettings(settings);
    if (input.triangleCount() > kMaxFractureTriangles)
        throw InputError(format("the mesh has {} triangles; fracture takes at most {} (about 5 KB of memory each): "
                                "simplify it first",
                                input.triangleCount(), kMaxFractureTriangles));
    FractureResult result;
    Mesh mesh = input;  // a closed mesh turned inside out is unambiguous: turn it outward
    result.notes = orientAndCheck(mesh);
    result.inputTriangles = mesh.triangleCount();
    result.inputVolume = volumeOf(mesh);
    const Grid grid = gridFor(computeBounds(mesh.positions));
    const Bounds bounds = computeBounds(mesh.positions);
    const double diagonal = glm::length(bounds.max - bounds.min);
    const double minArea = 1e-12 * diagonal * diagonal;  // contacts smaller than this are rounding

    // The first fracture and each re-fracture level take a share of the progress bar.
    const double share = 1.0 / double(1 + settings.levels);
    Call top = fractureOnce(mesh, nullptr, {}, 0, grid, settings, [&](double f) { return progress(f * share); });
    result.seeds = top.seeds;
    result.cells = top.seeds.size();
    result.fallbackCells = top.fallbackCells;
    std::vector<detail::RawPiece> pieces =
        refracture(std::move(top.pieces), std::int64_t(result.seeds.size()), grid, settings, {}, result,
                   [&](double f) { return progress(share + f * (1.0 - share)); });
    if (settings.minVolume > 0.0)
        result.merged = detail::mergeSmallPieces(pieces, settings.minVolume, settings.density, minArea);
    pieces = detail::roundForFiles(std::move(pieces), settings.density);
    result.bonds = detail::bondsBetween(pieces, minArea);
    result.pieces = finalPieces(pieces);
    progress(1.0);
    return result;
}

}  // namespace

FractureResult fractureMesh(const Mesh& mesh, const FractureSettings& settings, const ProgressFn& progress) {
    try {
        return fractureChecked(mesh, settings, progress);
    } catch (const CGAL::Failure_exception& e) {  // degenerate geometry CGAL gave up on
        throw InputError(format("fracture: CGAL could not handle the geometry: {}", e.message()));
    }
}


const char* fractureMethodName(FractureMethod method) {
    return method == FractureMethod::Rvd ? "rvd" : "corefine";
}

namespace {

void checkPartsSettings(std::span<const FracturePart> parts, const PartsFractureSettings& s) {
    if (parts.empty()) throw InputError("there are no parts to fracture");
    FractureSettings common = s.common;
    common.points.clear();
    checkSettings(common);
    if (!(s.shardSize > 0.0) || !std::isfinite(s.shardSize))
        throw InputError(format("the shard size must be positive (got {})", s.shardSize));
    if (!(s.splinterWidth > 0.0) || !(s.splinterLength >= s.splinterWidth) || !std::isfinite(s.splinterLength))
        throw InputError(format("splinters need a positive width and a length at least as large (got {} by {})",
                                s.splinterWidth, s.splinterLength));
    if (s.common.roughness > 0.0) throw InputError("rough cut surfaces are not available when fracturing parts");
    for (const MaterialBreak& m : s.materials) {
        if (!(m.density > 0.0) || !std::isfinite(m.density))
            throw InputError(format("a material's density must be positive (got {})", m.density));
        if (!(m.strength >= 0.0) || !std::isfinite(m.strength))
            throw InputError(format("a material's strength must not be negative (got {})", m.strength));
    }
    std::size_t triangles = 0;
    for (std::size_t i = 0; i < parts.size(); ++i) {
        const FracturePart& part = parts[i];
        if (part.material >= kMaterialCount)
            throw InputError(format("part {} ({}): material IDs are 0 to 15 (got {})", i, part.kind, int(part.material)));
        if (!finite(part.grain) || !(glm::length(part.grain) > 0.0))
            throw InputError(format("part {} ({}): the grain direction must not be zero", i, part.kind));
        triangles += part.mesh.triangleCount();
    }
    if (triangles > kMaxFractureTriangles)
        throw InputError(format("the parts have {} triangles; fracture takes at most {} (about 5 KB of memory each)",
                                triangles, kMaxFractureTriangles));
}

// Checks each part and records what it is (result.parts), with the bounds of them all.
Bounds describeParts(std::span<const FracturePart> parts, const PartsFractureSettings& settings, FractureResult& result) {
    result.parts.resize(parts.size());
    Bounds all{glm::dvec3(std::numeric_limits<double>::max()), glm::dvec3(std::numeric_limits<double>::lowest())};
    for (std::size_t i = 0; i < parts.size(); ++i) {
        const FracturePart& part = parts[i];
        try {
            checkInput(part.mesh);
        } catch (const RepairableMeshError& e) {
            throw RepairableMeshError(format("part {} ({}): {}", i, part.kind, e.what()));
        } catch (const InputError& e) {
            throw InputError(format("part {} ({}): {}", i, part.kind, e.what()));
        }
        PartResult& r = result.parts[i];
        r.kind = part.kind;
        r.material = part.material;
        r.style = settings.materials[part.material].style;
        r.volume = volumeOf(part.mesh);
        r.triangles = part.mesh.triangleCount();
        const Bounds b = computeBounds(part.mesh.positions);
        all.min = glm::min(all.min, b.min);
        all.max = glm::max(all.max, b.max);
        result.inputVolume += r.volume;
        result.inputTriangles += r.triangles;
    }
    return all;
}

// Level 0 of every part, in parallel, each into its own slot; pieces come part by part.
std::vector<detail::RawPiece> fractureEachPart(std::span<const FracturePart> parts,
                                               std::span<const FractureSettings> partSettings, const Grid& grid,
                                               double share, const ProgressFn& progress, FractureResult& result) {
    const std::size_t n = parts.size();
    std::vector<std::int64_t> cellBase(n + 1, 0);
    for (std::size_t i = 0; i < n; ++i) cellBase[i + 1] = cellBase[i] + partSettings[i].pieces;
    // Where parts touch: their faces there become contact faces, bonded like cut faces.
    std::vector<const Mesh*> meshes;
    for (const FracturePart& part : parts) meshes.push_back(&part.mesh);
    const detail::PartContacts contacts = detail::partContacts(meshes);
    std::vector<Call> calls(n);
    std::atomic<std::size_t> done{0};
    std::mutex progressMutex;
    std::atomic<bool> cancelled{false};
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
        if (cancelled) return;
        try {
            calls[i] = fractureOnce(parts[i].mesh, &contacts.planes[i], {}, cellBase[i], grid, partSettings[i], noProgress);
        } catch (const InputError& e) {
            throw InputError(format("part {} ({}): {}", i, parts[i].kind, e.what()));
        }
        for (detail::RawPiece& p : calls[i].pieces) p.part = std::int32_t(i);
        const std::size_t d = ++done;
        std::lock_guard lock(progressMutex);
        if (!progress(share * double(d) / double(n))) cancelled = true;
    });
    if (cancelled) throw Cancelled();
    std::vector<detail::RawPiece> pieces;
    for (Call& call : calls) {
        result.seeds.insert(result.seeds.end(), call.seeds.begin(), call.seeds.end());
        result.cells += call.seeds.size();
        result.fallbackCells += call.fallbackCells;
        for (detail::RawPiece& p : call.pieces) pieces.push_back(std::move(p));
    }
    return pieces;
}

FractureResult fracturePartsChecked(std::span<const FracturePart> parts, const PartsFractureSettings& settings,
                                    const ProgressFn& progress) {
    checkPartsSettings(parts, settings);
    const FractureSettings& common = settings.common;
    FractureResult result;
    const Bounds all = describeParts(parts, settings, result);
    const std::vector<FractureSettings> partSettings = detail::planParts(parts, settings, result);
    const Grid grid = gridFor(all);  // one grid: touching faces of two parts stay on one plane
    const double diagonal = glm::length(all.max - all.min);
    const double minArea = 1e-12 * diagonal * diagonal;
    const double share = 1.0 / double(1 + common.levels);
    std::vector<detail::RawPiece> pieces = fractureEachPart(parts, partSettings, grid, share, progress, result);
    std::int64_t nextCell = 0;
    for (const FractureSettings& ps : partSettings) nextCell += ps.pieces;
    pieces = refracture(std::move(pieces), nextCell, grid, common, partSettings, result,
                        [&](double f) { return progress(share + f * (1.0 - share)); });
    if (common.minVolume > 0.0) result.merged = detail::mergeSmallPieces(pieces, common.minVolume, 1.0, minArea);
    // Rounded at unit density, then each piece weighed at its own part's density.
    pieces = detail::roundForFiles(std::move(pieces), 1.0);
    for (detail::RawPiece& p : pieces) {
        const double density = partSettings[std::size_t(p.part)].density;
        p.mass.mass *= density;
        p.mass.inertia *= density;
    }
    result.bonds = detail::bondsBetween(pieces, minArea);
    result.pieces = finalPieces(pieces);
    for (FracturePiece& p : result.pieces) {
        p.material = parts[std::size_t(p.part)].material;
        ++result.parts[std::size_t(p.part)].pieces;
    }
    for (Bond& b : result.bonds)
        b.strength = std::min(settings.materials[result.pieces[b.a].material].strength,
                              settings.materials[result.pieces[b.b].material].strength);
    progress(1.0);
    return result;
}

}  // namespace

FractureResult fractureParts(std::span<const FracturePart> parts, const PartsFractureSettings& settings,
                             const ProgressFn& progress) {
    try {
        return fracturePartsChecked(parts, settings, progress);
    } catch (const CGAL::Failure_exception& e) {
        throw InputError(format("fracture: CGAL could not handle the geometry: {}", e.message()));
    }
}

}  // namespace dawnforge::sim
