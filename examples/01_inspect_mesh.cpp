// Example 1: load any mesh (OBJ, glTF, GLB) and ask whether it is fit for fracture.
//
//   build/bin/example_01_inspect_mesh some_mesh.obj
//
// Fracture and simulation need a closed, manifold, non-self-intersecting mesh: this is the
// check `dawnforge inspect` makes, through the same two library calls.
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/validate.hpp>

#include <cstdio>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s MESH_FILE\n", argv[0]);
        return 2;
    }
    try {
        // loadMesh flattens the whole file into one mesh in world space, and throws
        // dawnforge::InputError with a one-line message if the file is unusable.
        const dawnforge::Mesh mesh = dawnforge::loadMesh(argv[1]);
        // inspectMesh welds vertices by position (files split vertices at UV seams), then
        // counts boundary and non-manifold edges and asks CGAL about self-intersections.
        const dawnforge::MeshReport r = dawnforge::inspectMesh(mesh);
        std::printf("%zu triangles, %zu vertices\n", r.triangles, r.vertices);
        std::printf("closed %d, manifold %d, self-intersecting %d\n", r.closed, r.manifold, r.selfIntersecting);
        if (r.volume) std::printf("volume %.6g m^3\n", *r.volume);
        const bool fractureReady = r.closed && r.manifold && !r.selfIntersecting && r.outwardOriented;
        std::printf("%s\n", fractureReady ? "ready to fracture" : "needs repair first (dawnforge inspect --repair)");
        return 0;
    } catch (const dawnforge::InputError& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 2;
    }
}
