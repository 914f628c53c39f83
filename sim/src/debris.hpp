#pragma once
// Debris (dawnforge/sim/debris.hpp): chips emitted where bonds broke (debris.cpp) and moved
// among the simulated pieces (debris_motion.cpp, Bullet); dust (dust.cpp).
#include <dawnforge/core/seed.hpp>
#include <dawnforge/sim/rigidbody.hpp>

#include <glm/gtc/quaternion.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace dawnforge::sim {

// A chip as emitted: an octahedron with radii `radii` along the axes of `axes`, its mesh
// relative to its pivot (its centre of mass) in world axes at rest.
struct ChipSeed {
    RigidPiece piece;         // centerOfMass: its rest place, in its bond's crack
    glm::dvec3 radii{0.0};    // m, along its principal axes
    glm::dquat axes{1.0, 0.0, 0.0, 0.0};
    std::uint32_t parent = 0; // the bond's piece it rides in until it is released
    std::uint32_t other = 0;  // the bond's other piece; it collides with neither
    int releaseFrame = 0;     // the frame from which it moves on its own (the first frame after its bond broke)
    glm::dvec3 spray{0.0};    // m/s, added at release to its parent's velocity at its place
};

// A direction uniform on the unit sphere.
glm::dvec3 randomUnitVector(Rng& rng);

// The principal moments of inertia of an octahedron of `mass` with vertices at ±radii: m (b² + c²) / 10, ...
glm::dvec3 octahedronMoments(double mass, const glm::dvec3& radii);

// The material with the most area on a piece's surface: what it is made of.
std::uint8_t mainMaterial(const Mesh& mesh);

// The first frame after a bond that broke at `time` (s), from which its debris moves on its own.
int releaseFrame(double time, const SimulationSettings& settings);

// The dust of the bonds that broke (sim/src/dust.cpp): sets result.dust and dustPuffs. Reads
// the pieces' motion from result.transforms, so it runs before the chips are appended.
void addDust(std::span<const RigidPiece> pieces, std::span<const Bond> bonds, const SimulationSettings& settings,
             SimulationResult& result);

// The chips of the bonds that broke, in the order they broke, at most settings.debris.maxChips.
std::vector<ChipSeed> emitChips(std::span<const RigidPiece> pieces, std::span<const Bond> bonds,
                                const SimulationResult& result, const SimulationSettings& settings);

// Moves the chips among the pieces as result's transforms move them and appends them to result
// (chips, pieces, transforms, turns).
void moveChips(std::span<const RigidPiece> pieces, std::vector<ChipSeed> chips, const SimulationSettings& settings,
               SimulationResult& result);

}  // namespace dawnforge::sim
