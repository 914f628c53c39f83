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
    bool outwardOriented = false;        // closed, and the normals point out of the volume
    std::optional<double> volume;        // signed; only for closed, manifold, oriented meshes
    double area = 0.0;
    Bounds bounds;
    std::vector<std::pair<glm::dvec3, glm::dvec3>> openEdges;  // the first few boundary edges, to name in errors
};

// Topology and geometry checks on a mesh that passed validateMeshData().
MeshReport inspectMesh(const Mesh& mesh);

struct RepairReport {
    std::vector<std::string> actions;  // what was changed, one sentence each
    bool closed = false;               // the result is closed
};

// Merges duplicate points, drops degenerate and duplicate triangles, makes the
// orientation consistent, stitches borders, fills holes and orients the result
// outward. The result carries positions and indices only (attributes are dropped).
Mesh repairMesh(const Mesh& mesh, RepairReport* report = nullptr);

}  // namespace dawnforge
