// Example 3: from a closed mesh to vertex animation textures, in code: fracture, glue,
// knock it over, bake for Unity.
//
//   build/bin/example_03_destruction_vat OUT_DIR
//
// The library calls are the three stages of the command line (fracture, sim::simulate, vat);
// each takes a plain settings struct and returns plain data, so a tool can keep the
// pieces in memory between them instead of going through files.
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/exporters/vat.hpp>
#include <dawnforge/sim/fracture.hpp>
#include <dawnforge/sim/rigidbody.hpp>

#include <cstdio>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s OUT_DIR\n", argv[0]);
        return 2;
    }
    using namespace dawnforge;
    // A 4 × 6 × 4 m pillar in 60 pieces, smaller ones near where it will be hit.
    sim::FractureSettings fracture;
    fracture.pieces = 60;
    fracture.density = 600.0;
    fracture.impact = glm::dvec3(2.0, 3.0, 0.0);
    fracture.impactRadius = 2.0;
    const sim::FractureResult pieces = sim::fractureMesh(makeBox({-2, 0, -2}, {2, 6, 2}), fracture);

    // Bodies are the pieces as fracture describes them: mesh about the centre of mass.
    const std::vector<sim::RigidPiece> bodies = sim::rigidPieces(pieces);
    std::vector<Mesh> meshes;
    for (const sim::RigidPiece& b : bodies) meshes.push_back(b.mesh);
    // The bonds glue neighbours; a 2 t ball at 30 m/s breaks the ones it loads too much.
    sim::SimulationSettings sim;
    sim.frames = 90;
    sim.projectile = sim::Projectile{{2.0, 3.0, 0.0}, {-1.0, 0.0, 0.0}, 2000.0, 30.0, 0.5};
    const sim::SimulationResult motion = sim::simulate(bodies, pieces.bonds, sim);

    // Bake for the SideFX Labs Unity shaders, in half floats (RGBA16F).
    exporters::VatSettings vat;
    vat.preset = exporters::VatPreset::Unity;
    vat.half = true;
    vat.name = "pillar";
    try {
        const exporters::Vat textures = exporters::encodeVat({meshes, motion.transforms, motion.frames, motion.fps}, vat);
        exporters::writeVat(textures, vat, argv[1]);
        std::printf("%zu pieces, %zu of %zu bonds broke; %d×%d textures, worst vertex error %.2g m (half)\n",
                    motion.pieces, motion.brokenBonds, motion.bonds, textures.layout.width, textures.layout.height,
                    textures.maxVertexError);
    } catch (const InputError& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 2;
    }
    return 0;
}
