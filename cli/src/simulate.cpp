#include "commands.hpp"
#include "folders.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/procgen/city_building.hpp>
#include <dawnforge/sim/rigidbody.hpp>
#include <dawnforge/sim/rigidbody_io.hpp>

#include <chrono>
#include <cstdio>
#include <memory>

namespace dawnforge::cli {

namespace {

// What only the command line has; everything else is the library's SimulationSettings.
// The projectile and explosion options fill their own structs (with the library's
// defaults) and take effect when --projectile or --explosion names a point.
struct SimulateOptions {
    std::filesystem::path fractureDir;
    std::filesystem::path outputDir;
    std::vector<std::filesystem::path> colliders;
    bool noGround = false;
    std::filesystem::path city;  // a building's city folder; empty: the one fracture.json names
    bool noCity = false;
    std::optional<glm::dvec3> projectileTarget, projectileDirection, explosionCenter;
    sim::Projectile projectile;
    sim::Explosion explosion;
    sim::SimulationSettings settings;
};

sim::SimulationSettings settingsOf(const SimulateOptions& o) {
    sim::SimulationSettings s = o.settings;
    s.ground = !o.noGround;
    if (o.projectileTarget) {
        s.projectile = o.projectile;
        s.projectile->target = *o.projectileTarget;
        if (o.projectileDirection) s.projectile->direction = *o.projectileDirection;
    }
    if (o.explosionCenter) {
        s.explosion = o.explosion;
        s.explosion->center = *o.explosionCenter;
    }
    for (const std::filesystem::path& file : o.colliders) s.colliders.push_back(loadMesh(file));
    return s;
}

// A city building's fracture falls into its city (placeInCity). Returns the neighbours added.
std::size_t addCityColliders(const SimulateOptions& options, const sim::FractureFolder& fracture,
                             sim::SimulationSettings& settings) {
    if (fracture.building < 0 || options.noCity) return 0;
    const std::filesystem::path city = options.city.empty() ? std::filesystem::path(fracture.input) : options.city;
    if (!std::filesystem::is_directory(city))
        throw InputError(format("{}: the fractured building's city folder {} is not there; give it with --city DIR, or "
                                "--no-city", (options.fractureDir / "fracture.json").string(), city.string()));
    procgen::CityBuilding building = procgen::loadCityBuilding(city, fracture.building);
    const std::size_t neighbours = building.neighbours.size();
    placeInCity(std::move(building), settings);
    return neighbours;
}

int runSimulate(const SimulateOptions& options, const CommonOptions& common) {
    const auto start = std::chrono::steady_clock::now();
    sim::SimulationSettings settings = settingsOf(options);
    const sim::FractureFolder fracture = sim::loadFracture(options.fractureDir);
    if (fracture.building < 0 && (!options.city.empty() || options.noCity))
        throw InputError(format("{}: --city and --no-city are for a building's fracture (fracture --building)",
                                options.fractureDir.string()));
    const std::size_t neighbours = addCityColliders(options, fracture, settings);
    sim::SimulationResult result;
    {
        StderrProgress progress = progressFor("simulate", common);
        result = sim::simulate(fracture.pieces, fracture.bonds, settings, progress.callback());
    }
    writeSimulationFolder(result, settings, fracture.pieces, options.fractureDir, options.outputDir);
    if (result.clampedThrows > 0)
        std::fprintf(stderr, "warning: the explosion would have thrown %zu pieces faster than %g m/s; they were thrown at %g m/s\n",
                     result.clampedThrows, sim::kFastestThrow, sim::kFastestThrow);

    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("simulated %zu pieces for %d frames at %g fps (%d substeps) in %.2f s\n", result.pieces,
                result.frames, result.fps, settings.substeps, seconds);
    std::printf("  %zu of %zu bonds broke; %zu bodies (%zu fixed where they stood); fastest piece %.2f m/s\n",
                result.brokenBonds, result.bonds, result.actors, result.fixedActors, result.maxSpeed);
    if (fracture.building >= 0 && !options.noCity)
        std::printf("  in its city: the ground and %zu neighbouring buildings as colliders\n", neighbours);
    if (settings.debris.chips)
        std::printf("  debris: %zu chips from %zu of the broken bonds%s\n", result.chips.size(), result.chipBonds,
                    result.chips.empty() ? "" : " (debris.glb)");
    if (settings.debris.dust)
        std::printf("  dust: %zu puffs%s\n", result.dustPuffs, result.dustPuffs == 0 ? "" : " (dust.bin)");
    std::printf("  wrote %s, transforms.bin, turns.bin and a copy of fragments.glb\n",
                (options.outputDir / "sim.json").string().c_str());
    return 0;
}

void addSolverOptions(CLI::App& cmd, sim::SimulationSettings& s) {
    cmd.add_option("--frames", s.frames, "Frames to write; frame 0 is the rest pose")
        ->check(CLI::Range(1, 100000))->capture_default_str();
    cmd.add_option("--fps", s.fps, "Frames per second")->check(CLI::PositiveNumber)->capture_default_str();
    cmd.add_option("--substeps", s.substeps, "Fixed simulation steps per frame")
        ->check(CLI::Range(1, 100))->capture_default_str();
    cmd.add_option("--iterations", s.solverIterations, "Constraint solver iterations per step")
        ->check(CLI::Range(1, 1000))->capture_default_str();
    cmd.add_option("--seed", s.seed, "Random seed (varies each bond's strength)")->capture_default_str();
    cmd.add_option("--strength", s.strength,
                   "Glue strength (Pa) of bonds with none of their own: a bond breaks when its largest principal stress (pull, bending, shear) above what it carries at rest "
                   "exceeds this; 0: no glue")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    cmd.add_option("--strength-variation", s.strengthVariation, "Relative spread of bond strengths, from the seed")
        ->check(CLI::Range(0.0, 0.99))->capture_default_str();
    cmd.add_option("--impact-time", s.impactTime,
                   "Contact damage: a blow of J N·s breaks a bond as a force J / this held for this long would (s): a "
                   "bond breaks when the impulse that crossed it exceeds strength x area x this")
        ->check(CLI::PositiveNumber)->capture_default_str();
    cmd.add_option("--damage-transmission", s.damageTransmission,
                   "Contact damage: the part of a blow that a piece passes on to its bonds further away")
        ->check(CLI::Range(0.0, 1.0))->capture_default_str();
    cmd.add_option("--damage-hops", s.damageHops, "Contact damage: how many bonds away from the piece struck a blow reaches")
        ->check(CLI::Range(1, 100))->capture_default_str();
    cmd.add_option("--damage-half-life", s.damageHalfLife, "Contact damage: accumulated damage halves in this time (s)")
        ->check(CLI::PositiveNumber)->capture_default_str();
    cmd.add_option("--friction", s.friction, "Friction coefficient of pieces, ground and colliders")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    cmd.add_option("--restitution", s.restitution, "Bounciness (0: none, 1: elastic)")
        ->check(CLI::Range(0.0, 1.0))->capture_default_str();
    cmd.add_option("--hull-vertices", s.hullVertices, "Collision hull vertex budget per piece")
        ->check(CLI::Range(4, 1000))->capture_default_str();
    cmd.add_option("--margin", s.margin, "Collision margin (m)")->check(CLI::PositiveNumber)->capture_default_str();
    cmd.add_flag("!--no-sleep", s.sleep,
                 "Simulate every body to the last frame; by default one slower than 0.1 m/s and 0.2 rad/s for 0.4 s "
                 "sleeps until something touches it");
}

void addDebrisOptions(CLI::App& cmd, sim::DebrisSettings& d) {
    d.chips = true;
    cmd.add_flag("!--no-debris", d.chips, "No chips where bonds break (by default they fly out of the cracks: debris.glb)");
    cmd.add_option("--chips-per-m2", d.chipsPerSquareMetre,
                   "Chips per square metre of broken bond, for masonry (glass 2x, wood 0.5x, metal 0.2x)")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    cmd.add_option("--chips-per-bond", d.maxChipsPerBond, "At most this many chips from one bond")
        ->check(CLI::Range(0, 100))->capture_default_str();
    cmd.add_option("--max-chips", d.maxChips, "At most this many chips in all; the earliest breaks emit first")
        ->check(CLI::Range(0, 100000))->capture_default_str();
    cmd.add_option("--chip-size", d.chipSize, "A chip's mean length (m); no chip is thicker than 70 % of its piece")
        ->check(CLI::PositiveNumber)->capture_default_str();
    cmd.add_option("--spray-speed", d.spraySpeed, "A chip's mean speed out of its crack, over its piece's (m/s)")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    d.dust = true;
    cmd.add_flag("!--no-dust", d.dust, "No dust where bonds break (by default puffs rise, spread and fade: dust.bin)");
    cmd.add_option("--puffs-per-m2", d.puffsPerSquareMetre,
                   "Puffs of dust per square metre of broken bond, for masonry (wood 0.5x, glass 0.2x, metal none)")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    cmd.add_option("--max-puffs", d.maxPuffs, "At most this many puffs in all; the earliest breaks emit first")
        ->check(CLI::Range(0, 4096))->capture_default_str();
    cmd.add_option("--puff-size", d.puffSize, "A puff's diameter as it leaves the crack (m); it grows to four times that")
        ->check(CLI::PositiveNumber)->capture_default_str();
    cmd.add_option("--puff-life", d.puffLife, "A puff's mean time until it has faded out (s)")
        ->check(CLI::PositiveNumber)->capture_default_str();
}

void addTriggerOptions(CLI::App& cmd, SimulateOptions& o) {
    cmd.add_option("--trigger-time", o.settings.triggerTime, "When the projectile, explosion or collapse happens (s)")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    addPointOption(cmd, "--projectile", o.projectileTarget, "Throw a ball at this point X,Y,Z (m)");
    addPointOption(cmd, "--projectile-dir", o.projectileDirection, "Direction of travel DX,DY,DZ (default -1,0,0)");
    cmd.add_option("--projectile-mass", o.projectile.mass, "kg")->check(CLI::PositiveNumber)->capture_default_str();
    cmd.add_option("--projectile-speed", o.projectile.speed, "m/s")->check(CLI::NonNegativeNumber)->capture_default_str();
    cmd.add_option("--projectile-radius", o.projectile.radius, "m")->check(CLI::PositiveNumber)->capture_default_str();
    addPointOption(cmd, "--explosion", o.explosionCenter, "Push pieces away from this point X,Y,Z (m)");
    cmd.add_option("--explosion-radius", o.explosion.radius, "m")->check(CLI::PositiveNumber)->capture_default_str();
    cmd.add_option("--explosion-speed", o.explosion.speed,
                   "m/s given to a piece of the mean mass at the centre, falling off as (1 - d/r)^2 and as "
                   "(mean / m)^(1/3) for a piece of mass m; no piece is thrown faster than 300 m/s")
        ->check(CLI::Range(0.0, sim::kFastestThrow))->capture_default_str();
    cmd.add_flag("--collapse", o.settings.collapse, "Every bond breaks at the trigger time (gravity collapse)");
}

}  // namespace

Command addSimulate(CLI::App& app, CommonOptions& common) {
    auto o = std::make_shared<SimulateOptions>();
    CLI::App* cmd = app.add_subcommand("simulate", "Simulate fractured pieces with Bullet: DIR/sim.json, "
                                                   "DIR/transforms.bin, DIR/turns.bin, DIR/debris.glb, DIR/dust.bin (+ a copy of fragments.glb)");
    cmd->add_option("FRACTURE_DIR", o->fractureDir, "Folder written by 'dawnforge fracture'")->required();
    cmd->add_option("-o,--output", o->outputDir, "Output folder")->required();
    addSolverOptions(*cmd, o->settings);
    addTriggerOptions(*cmd, *o);
    addDebrisOptions(*cmd, o->settings.debris);
    cmd->add_flag("--no-ground", o->noGround, "No ground plane");
    cmd->add_flag("!--no-anchor", o->settings.anchor,
                  "Glued pieces resting on the ground or the support do not hold their cluster there: it rests as one "
                  "moving body");
    cmd->add_option("--ground-height", o->settings.groundHeight,
                    "Ground plane height (m); default the lowest point of the pieces");
    cmd->add_option("--collider", o->colliders, "Static collider mesh (any format inspect reads), world space; repeatable");
    cmd->add_option("--city", o->city,
                    "A building's fracture: the city folder it stands in (default: the one fracture.json names); its "
                    "ground and neighbouring buildings become colliders");
    cmd->add_flag("--no-city", o->noCity, "A building's fracture: simulate it without its city around it");
    addThreadsOption(*cmd, common);
    return {cmd, [o, &common] { return runSimulate(*o, common); }};
}

}  // namespace dawnforge::cli
