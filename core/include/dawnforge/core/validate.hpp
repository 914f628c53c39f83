#pragma once
// Mesh validation and repair (CGAL Polygon Mesh Processing inside; plain data outside).
#include <dawnforge/core/mesh.hpp>

#include <optional>
#include <utility>
#include <string>
#include <vector>

namespace dawnforge {

struct MeshReport {
    std::size_t triangles = 0;
    std::size_t vertices = 0;            // distinct positions (vertices welded by position)
    std::size_t attributeVertices = 0;   // vertices as stored, with their attributes
    std::size_t boundaryEdges = 0;       // edges used by one triangle
    std::size_t nonManifoldEdges = 0;    // edges used by three or more triangles
    std::size_t nonManifoldVertices = 0; // vertices whose triangles form several fans
    std::size_t degenerateTriangles = 0; // collinear corners or a repeated index
    std::size_t components = 0;          // connected by shared edges
    bool closed = false;                 // no boundary edge
    bool manifold = false;               // no non-manifold edge or vertex
    bool consistentlyOriented = false;   // every interior edge used once in each direction
    bool selfIntersecting = false;       // some triangles intersect other than at shared edges/corners
    bool outwardOriented = false;        // closed, and every shell faces away from the solid (a cavity's inward)
    std::optional<double> volume;        // signed; only for closed, manifold, oriented meshes
    double area = 0.0;
    Bounds bounds;
    std::vector<std::pair<glm::dvec3, glm::dvec3>> openEdges;  // the first few boundary edges, to name in errors
};

// Topology and geometry checks on a mesh that passed validateMeshData().
MeshReport inspectMesh(const Mesh& mesh);

// Turns a closed, manifold mesh so that it bounds its volume, as CGAL's
// orient_to_bound_a_volume() defines it: triangles that disagree with their neighbours
// are flipped (the larger area of each shell keeps its winding), then every shell faces
// away from the solid, so an outer shell points out and a shell nested in it (a cavity)
// points into the cavity, alternating with depth. Only the winding of triangles changes
// (and the sign of normals that then face the wrong way); vertices, their attributes and
// the order of triangles are kept. Returns what it did, one sentence each; nothing when
// the mesh already bounds its volume. An open or non-manifold mesh is left as it is
// (inspectMesh() says why; repairMesh() fixes it). Throws RepairableMeshError when a shell
// is one-sided (it then intersects itself) and cannot be oriented.
std::vector<std::string> orientMesh(Mesh& mesh);

struct RepairReport {
    std::vector<std::string> actions;    // what was changed, one sentence each
    bool closed = false;                 // the result is closed (always, when repairMesh returns)
    std::optional<double> volumeBefore;  // the input's signed volume, where it had one (closed, manifold, oriented)
    double volumeAfter = 0.0;            // the result's volume
};

// Makes a mesh that bounds a volume: closed, manifold, outward and not self-intersecting.
// Merges duplicate points, drops degenerate and duplicate triangles (a pair of opposite
// coincident triangles is an inner wall and goes), orients, stitches borders, fills holes,
// splits non-manifold edges and vertices, removes pieces that are flat, resolves
// self-intersections so that the result bounds the union of what the surface encloses
// (CGAL's autorefinement), drops shells that enclose nothing new (a shell inside the solid
// facing the same way as the one around it), and orients the shells as orientMesh() does.
// The result carries positions and indices only (attributes are dropped). Throws
// InputError when the mesh has no volume (it is flat), or with what is left wrong when
// the repair cannot make it bound a volume.
Mesh repairMesh(const Mesh& mesh, RepairReport* report = nullptr);

}  // namespace dawnforge
