// Example 2: build a scene in code and write it as glTF (GLB).
//
//   build/bin/example_02_write_scene out.glb
//
// Material IDs (0-15) travel in the _MATERIAL_ID attribute, and each material a mesh uses
// is a primitive with a glTF material of its own (plain colours here: see GltfSettings for
// pictures); UVs are in metres so the runtime's atlas tiles at a known density.
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/exporters/gltf.hpp>

#include <cstdio>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s OUT.glb\n", argv[0]);
        return 2;
    }
    dawnforge::Scene scene;
    // A 6-storey tower: storeys alternate between material 2 (wall) and 3 (window band).
    scene.addMeshNode(dawnforge::makeTower(6, 3.0f, 10.0f, 10.0f));
    // A sphere beside it, wearing material 7 everywhere, placed by its node's translation.
    dawnforge::Mesh sphere = dawnforge::makeIcosphere(3.0f, 3);
    sphere.materialIds.assign(sphere.vertexCount(), 7);
    scene.addMeshNode(sphere, {12.0f, 3.0f, 0.0f});
    // Anything JSON can go into the glTF extras of the scene or of a node.
    scene.extrasJson = R"({"example": 2})";
    try {
        dawnforge::exporters::writeGlb(scene, argv[1]);  // atomic: a temporary file, then a rename
    } catch (const dawnforge::InputError& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 2;
    }
    std::printf("wrote %s\n", argv[1]);
    return 0;
}
