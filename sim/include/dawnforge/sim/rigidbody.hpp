#pragma once
// Rigid-body destruction with Bullet 3.24: each set of pieces glued by unbroken bonds is
// one body (a compound of the pieces' convex hulls, exact mass and inertia), fixed where it
// rests on the ground or a support; contacts load the bond graph, and a body splits where
// its bonds fail (the Blast model). A trigger (projectile, explosion or collapse), a ground
// plane and static colliders. Fixed time step with substeps; the same inputs give the same
// transforms.
#include <dawnforge/core/mesh.hpp>
#include <dawnforge/core/progress.hpp>
#include <dawnforge/sim/debris.hpp>
#include <dawnforge/sim/fracture.hpp>

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace dawnforge::sim {

// A piece as fracture.json and fragments.glb describe it.
struct RigidPiece {
    std::string name;
    Mesh mesh;                     // relative to the centre of mass (the pivot)
    double mass = 0.0;             // kg
    glm::dvec3 centerOfMass{0.0};  // rest position of the pivot, world (m)
    glm::dmat3 inertia{0.0};       // kg·m^2 about the centre of mass, world axes
};

// The pieces of a fracture result as bodies: the same meshes, masses and inertia.
std::vector<RigidPiece> rigidPieces(const FractureResult& fracture);

// A ball thrown at `target`: it appears outside the pieces' bounds at the trigger time,
// on the line through `target` along `direction`, moving at `speed`.
struct Projectile {
    glm::dvec3 target{0.0};
    glm::dvec3 direction{-1.0, 0.0, 0.0};  // of travel; normalised by the simulation
    double mass = 20000.0;                 // kg
    double speed = 40.0;                   // m/s
    double radius = 1.0;                   // m
};

// An outward push on every piece whose centre of mass is within `radius` of `center`, in
// units that mean the same for a vase and a tower: a piece of the pieces' mean mass m̄ at the
// centre is thrown at `speed`, a piece of mass m at d at speed · (1 - d/radius)^2 · (m̄ / m)^(1/3)
// (its impulse goes as the area it shows to the blast, (m / m̄)^(2/3)), and no piece faster than
// kFastestThrow: a sliver that would be is thrown at that speed (SimulationResult::clampedThrows).
struct Explosion {
    glm::dvec3 center{0.0};
    double radius = 5.0;   // m
    double speed = 25.0;   // m/s at the centre, of a piece of the mean mass; at most kFastestThrow
};
constexpr double kFastestThrow = 300.0;  // m/s

// A flat floor under part of the scene: a horizontal plane at `height` that holds the pieces
// whose centre of mass is over [min, max] (x, z), where the colliders let them through; over
// the rest, the colliders hold them and the plane lets them through. A building stands on
// it (a glued structure resting on a triangle mesh is shaken by its contacts), and its
// debris falls onto the city's ground around it.
struct Support {
    double height = 0.0;
    glm::dvec2 min{0.0}, max{0.0};  // x, z
};

struct SimulationSettings {
    int frames = 120;                 // frame 0 is the rest pose
    double fps = 30.0;
    int substeps = 4;                 // fixed Bullet steps per frame
    int solverIterations = 20;       // twice Bullet's default (contacts between bodies)
    std::uint64_t seed = 1;           // varies each bond's strength by ±strengthVariation
    glm::dvec3 gravity{0.0, -9.81, 0.0};
    bool ground = true;
    std::optional<double> groundHeight;  // default: the lowest point of the pieces
    double friction = 0.6;
    double restitution = 0.1;
    double strength = 1e6;            // glue, Pa, of bonds with none of their own: see impactTime, and a bond whose stress
                                      // under the weights exceeds its rest stress by this breaks; 0: no glue
    double strengthVariation = 0.2;   // relative, per bond, from the seed
    // Contact damage (sim/src/damage.hpp): a blow of J N·s breaks a bond as a force J / impactTime
    // held for impactTime would: it breaks when the damage it took exceeds strength · area · impactTime.
    double impactTime = 0.01;         // s
    double damageTransmission = 0.35; // of the impulse that reaches a piece, what it passes on to the next
    int damageHops = 3;               // bonds from the piece struck that a blow reaches
    double damageHalfLife = 1.0;      // s: accumulated damage halves in this time
    bool anchor = true;               // glued pieces resting on the ground or the support hold their set there
    bool sleep = true;                // bodies slower than 0.1 m/s and 0.2 rad/s for 0.4 s stop being simulated until hit
    int hullVertices = 48;            // collision hull vertex budget per piece
    double margin = 0.01;             // Bullet collision margin (m); hulls are shrunk by it first
    double linearDamping = 0.02;
    double angularDamping = 0.05;
    double triggerTime = 0.2;         // s, when the projectile / explosion / collapse happens
    std::optional<Projectile> projectile;
    std::optional<Explosion> explosion;
    bool collapse = false;            // every bond breaks at the trigger time
    std::vector<Mesh> colliders;      // static triangle meshes, world space
    std::optional<Support> support;   // a floor under part of the scene (the colliders give way there)
    DebrisSettings debris;            // chips where bonds break (off by default)
};

struct BondBreak {
    std::size_t bond = 0;
    double time = 0.0;  // s, the end of the substep in which it broke
};

struct SimulationResult {
    int frames = 0;
    double fps = 0.0;
    std::size_t pieces = 0;
    // frames × pieces × (px py pz qx qy qz qw): world pivot position and orientation,
    // the layout of transforms.bin. Frame 0 is the rest pose (identity orientations).
    std::vector<float> transforms;
    // frames × pieces: the rotation from frame k to k+1 along the simulated path, in turns,
    // negative when that path ends at the negated quaternion of frame k+1 as written
    // (turns.bin; the VAT rotation alpha). The last frame's are 0.
    std::vector<float> turns;
    // Per frame: kinetic + potential energy of every body (projectile included) minus the
    // energy the triggers put in so far (J). Without numerical gain it never rises above frame 0.
    std::vector<double> energy;
    double injectedEnergy = 0.0;      // J, by the projectile and the explosion
    double groundHeight = 0.0;        // m
    std::size_t bonds = 0;            // bonds glued (0 without glue)
    std::size_t brokenBonds = 0;      // of which broken by the end
    double maxSpeed = 0.0;            // m/s, fastest piece at any frame
    std::size_t clampedThrows = 0;    // pieces the explosion would have thrown faster than kFastestThrow
    std::vector<BondBreak> breaks;    // in the order they broke
    std::size_t actors = 0;           // bodies made for pieces: the first sets, then each split's
    std::size_t fixedActors = 0;      // of which fixed
    std::size_t overlappingHulls = 0; // pairs of pieces whose hulls overlap at rest: they never collide
    std::vector<int> hullVertices;    // per piece, after simplification
    // Debris (SimulationSettings::debris): chips emitted where bonds broke, after the pieces.
    // `pieces`, `transforms` and `turns` count them: chips[k] is piece pieces - chips.size() + k.
    // Each chip's mesh is relative to its pivot, which rests in its bond's crack at frame 0.
    std::vector<RigidPiece> chips;
    std::size_t chipBonds = 0;        // broken bonds that emitted chips
    // Dust (SimulationSettings::debris.dust): frames × dustPuffs × (x y z size opacity): each
    // puff's centre (m), diameter (m) and opacity (0 before it is emitted and once it has faded).
    std::vector<float> dust;
    std::size_t dustPuffs = 0;
};

// Simulates `pieces` glued by `bonds` (indices into pieces). Throws InputError on settings
// or data a user could get wrong (no pieces, zero frames, fps <= 0, a bond naming a piece
// that does not exist, a non-positive mass or inertia).
SimulationResult simulate(std::span<const RigidPiece> pieces, std::span<const Bond> bonds,
                          const SimulationSettings& settings, const ProgressFn& progress = noProgress);

// Principal axes of a symmetric inertia tensor: I = R · diag(moments) · Rᵀ with R a proper
// rotation (det +1). Jacobi iterations in double.
struct PrincipalInertia {
    glm::dvec3 moments{0.0};
    glm::dmat3 axes{1.0};  // columns are the principal axes
};
PrincipalInertia principalInertia(const glm::dmat3& inertia);

}  // namespace dawnforge::sim
