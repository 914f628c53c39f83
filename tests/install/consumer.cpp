// Uses the installed dawnforge package from outside the project: one real call into each
// of sim, exporters and runtime, so that the link pulls in their third-party libraries
// (CGAL, OpenVDB and Bullet for sim; tinygltf, OpenEXR and stb for exporters; Assimp for core;
// epoxy, EGL and GLFW for runtime). Exits 0 and prints one line when all is well.
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/core/scene.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/runtime/context.hpp>
#include <dawnforge/runtime/sky.hpp>
#include <dawnforge/sim/fracture.hpp>
#include <dawnforge/sim/rigidbody.hpp>

#include <cstdio>
#include <cstring>

namespace {

int fail(const char* what) {
    std::fprintf(stderr, "consumer: %s\n", what);
    return 1;
}

}  // namespace

int main() {
    using namespace dawnforge;
    // sim: a unit icosphere in 6 pieces, then a few frames of them falling.
    sim::FractureSettings fracture;
    fracture.pieces = 6;
    const sim::FractureResult pieces = sim::fractureMesh(makeIcosphere(1.0f, 2), fracture);
    if (pieces.pieces.size() < 2) return fail("the icosphere did not break");
    sim::SimulationSettings simulation;
    simulation.frames = 3;
    const sim::SimulationResult motion = sim::simulate(sim::rigidPieces(pieces), pieces.bonds, simulation);
    if (motion.frames != 3) return fail("the simulation did not run three frames");

    // exporters: the pieces as a GLB in memory.
    Scene scene;
    for (const sim::FracturePiece& p : pieces.pieces) scene.addMeshNode(p.mesh, glm::vec3(p.mass.centerOfMass));
    const std::vector<std::byte> glb = exporters::encodeGlb(scene);
    if (glb.size() < 12 || std::memcmp(glb.data(), "glTF", 4) != 0) return fail("encodeGlb did not write a GLB");

    // runtime: the sky at noon needs no GL context. The context functions are only
    // referenced, which links the GL side (context, epoxy, EGL, GLFW) without running it.
    const runtime::Lighting noon = runtime::lightingAt(12.0);
    if (!(noon.elevation > 0.0)) return fail("the sun is not up at noon");
    auto* volatile makeHeadless = &runtime::GlContext::headless;
    if (makeHeadless == nullptr) return fail("no headless context function");

    std::printf("consumer: %zu pieces, %zu-byte GLB, sun %.1f degrees high at noon\n", pieces.pieces.size(),
                glb.size(), noon.elevation * 57.29577951308232);
    return 0;
}
