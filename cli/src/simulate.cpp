#include "commands.hpp"

#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/sim/rigidbody.hpp>
#include <dawnforge/sim/rigidbody_io.hpp>

#include <chrono>
#include <cstring>
#include <cstdio>
#include <fstream>
#include <iterator>

namespace dawnforge::cli {

namespace {

glm::dvec3 point(const std::vector<double>& v) { return {v[0], v[1], v[2]}; }

std::vector<std::byte> readBytes(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::vector<char> chars((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in.eof() && !in) throw InputError(format("{}: cannot be read", file.string()));
    std::vector<std::byte> bytes(chars.size());
    std::memcpy(bytes.data(), chars.data(), chars.size());
    return bytes;
}

sim::SimulationSettings simulationSettings(const SimulateOptions& o) {
    sim::SimulationSettings s;
    s.frames = o.frames;
    s.fps = o.fps;
    s.substeps = o.substeps;
    s.solverIterations = o.iterations;
    s.seed = o.seed;
    s.strength = o.strength;
    s.strengthVariation = o.strengthVariation;
    s.triggerTime = o.triggerTime;
    s.friction = o.friction;
    s.restitution = o.restitution;
    s.hullVertices = o.hullVertices;
    s.margin = o.margin;
    s.ground = !o.noGround;
    if (o.groundHeight) s.groundHeight = *o.groundHeight;
    if (!o.projectile.empty()) {
        sim::Projectile p;
        p.target = point(o.projectile);
        if (!o.projectileDirection.empty()) p.direction = point(o.projectileDirection);
        p.mass = o.projectileMass;
        p.speed = o.projectileSpeed;
        p.radius = o.projectileRadius;
        s.projectile = p;
    }
    if (!o.explosion.empty()) s.explosion = sim::Explosion{point(o.explosion), o.explosionRadius, o.explosionImpulse};
    s.collapse = o.collapse;
    for (const std::filesystem::path& file : o.colliders) s.colliders.push_back(loadMesh(file));
    return s;
}

}  // namespace

int runSimulate(const SimulateOptions& options, const CommonOptions& common) {
    const auto start = std::chrono::steady_clock::now();
    const sim::SimulationSettings settings = simulationSettings(options);
    const sim::FractureFolder fracture = sim::loadFracture(options.fractureDir);
    sim::SimulationResult result;
    {
        StderrProgress progress("simulate", !common.quiet && stderrIsTerminal());
        result = sim::simulate(fracture.pieces, fracture.bonds, settings, progress.callback());
    }
    const std::vector<std::byte> fragments = readBytes(options.fractureDir / "fragments.glb");

    sim::writeSimulation(options.outputDir, result, settings, fracture.pieces, options.fractureDir.string());
    writeFileAtomically(options.outputDir / "fragments.glb", fragments);

    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("simulated %zu pieces for %d frames at %g fps (%d substeps) in %.2f s\n", result.pieces,
                result.frames, result.fps, settings.substeps, seconds);
    std::printf("  %zu of %zu bonds broke; fastest piece %.2f m/s\n", result.brokenBonds, result.bonds, result.maxSpeed);
    std::printf("  wrote %s, transforms.bin, turns.bin and a copy of fragments.glb\n",
                (options.outputDir / "sim.json").string().c_str());
    return 0;
}

}  // namespace dawnforge::cli
