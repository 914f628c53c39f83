// Debris (dawnforge/sim/debris.hpp): chips come out of the bonds that broke, when they broke,
// as many as their area and material give; they ride hidden in their crack until then, fly
// out, land on the ground and come to rest; the pieces move exactly as they would without
// them; dust appears at the breaks, rises, grows and fades; the same bytes on any thread count.
#include "debris.hpp"
#include "test_support.hpp"
#include "tower_fixture.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/sim/fracture.hpp>
#include <dawnforge/sim/mass_properties.hpp>
#include <dawnforge/sim/rigidbody.hpp>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <map>

using namespace dawnforge;
using namespace dawnforge::sim;

namespace {

using test::smallTower;

// Every bond breaks at 0.2 s (frame 6 at 30 fps); chips on.
SimulationSettings collapsing(bool chips) {
    SimulationSettings s;
    s.frames = 90;
    s.collapse = true;
    s.debris.chips = chips;
    return s;
}

struct Pose {
    glm::dvec3 x;
    glm::dquat q;
};
Pose poseAt(const SimulationResult& r, int frame, std::size_t piece) {
    const float* t = r.transforms.data() + (std::size_t(frame) * r.pieces + piece) * 7;
    return {{t[0], t[1], t[2]}, glm::dquat(t[6], t[3], t[4], t[5])};
}

}  // namespace

// Each chip comes from a bond that broke, rests at its crack's centroid (within a chip's
// length), leaves at the first frame after the break, and is a closed octahedron as dense as
// its piece; no bond gives more than its area's worth (rounded up) or the cap.
TEST(Debris, ChipsComeOutOfTheBondsThatBrokeWhenTheyBroke) {
    const std::vector<RigidPiece> pieces = rigidPieces(smallTower());
    const std::vector<Bond>& bonds = smallTower().bonds;
    const SimulationSettings s = collapsing(true);
    const SimulationResult r = simulate(pieces, bonds, collapsing(false));
    ASSERT_EQ(r.breaks.size(), bonds.size());
    const std::vector<ChipSeed> chips = emitChips(pieces, bonds, r, s);
    ASSERT_GE(chips.size(), 10u);
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::size_t> bondOf;
    for (std::size_t b = 0; b < bonds.size(); ++b) bondOf[{bonds[b].a, bonds[b].b}] = b;
    std::map<std::size_t, int> perBond;
    for (const ChipSeed& chip : chips) {
        const auto it = bondOf.find(std::minmax(chip.parent, chip.other));
        ASSERT_NE(it, bondOf.end()) << chip.piece.name << " is not from a bond";
        const Bond& bond = bonds[it->second];
        ++perBond[it->second];
        EXPECT_EQ(chip.releaseFrame, 6);  // broke in the substep ending at 0.2 s
        const double length = 2.0 * std::max({chip.radii.x, chip.radii.y, chip.radii.z});
        EXPECT_LE(length, 1.4 * s.debris.chipSize + 1e-9);
        EXPECT_LT(glm::length(chip.piece.centerOfMass - bond.centroid), length);
        std::vector<glm::dvec3> positions(chip.piece.mesh.positions.begin(), chip.piece.mesh.positions.end());
        const MassProperties mp = computeMassProperties(positions, chip.piece.mesh.indices, 1.0);
        EXPECT_NEAR(mp.volume, 4.0 / 3.0 * chip.radii.x * chip.radii.y * chip.radii.z, 1e-6 * length * length * length);
        EXPECT_LT(glm::length(mp.centerOfMass), 1e-5);
        const RigidPiece& parent = pieces[chip.parent];
        std::vector<glm::dvec3> p(parent.mesh.positions.begin(), parent.mesh.positions.end());
        const double density = parent.mass / computeMassProperties(p, parent.mesh.indices, 1.0).volume;
        EXPECT_NEAR(chip.piece.mass, density * mp.volume, 1e-6 * chip.piece.mass);
        EXPECT_GT(glm::length(chip.spray), 0.0);
    }
    for (const auto& [b, n] : perBond) {
        EXPECT_LE(n, s.debris.maxChipsPerBond);
        EXPECT_LE(n, int(std::floor(bonds[b].area * s.debris.chipsPerSquareMetre)) + 1) << "bond " << b;
    }
    SimulationSettings few = s;
    few.debris.maxChips = 5;
    EXPECT_EQ(emitChips(pieces, bonds, r, few).size(), 5u);
    few.debris.chipsPerSquareMetre = 0.0;
    EXPECT_TRUE(emitChips(pieces, bonds, r, few).empty());
}

// The pieces never feel the chips: their transforms and turns are the same bytes with and
// without; the chips follow them in every frame, named, and the result counts them.
TEST(Debris, ThePiecesMoveTheSameWithOrWithoutChips) {
    const std::vector<RigidPiece> pieces = rigidPieces(smallTower());
    const SimulationResult plain = simulate(pieces, smallTower().bonds, collapsing(false));
    const SimulationResult r = simulate(pieces, smallTower().bonds, collapsing(true));
    const std::size_t n = pieces.size(), c = r.chips.size();
    ASSERT_GT(c, 0u);
    EXPECT_EQ(r.pieces, n + c);
    EXPECT_GT(r.chipBonds, 0u);
    EXPECT_LE(r.chipBonds, r.brokenBonds);
    ASSERT_EQ(r.transforms.size(), std::size_t(r.frames) * (n + c) * 7);
    ASSERT_EQ(r.turns.size(), std::size_t(r.frames) * (n + c));
    for (int f = 0; f < r.frames; ++f)
        for (std::size_t i = 0; i < n * 7; ++i)
            ASSERT_EQ(r.transforms[std::size_t(f) * (n + c) * 7 + i], plain.transforms[std::size_t(f) * n * 7 + i])
                << "frame " << f;
    for (int f = 0; f < r.frames; ++f)
        for (std::size_t i = 0; i < n; ++i)
            ASSERT_EQ(r.turns[std::size_t(f) * (n + c) + i], plain.turns[std::size_t(f) * n + i]);
    const std::string last = std::to_string(c - 1);
    EXPECT_EQ(r.chips.front().name, "chip_" + std::string(last.size(), '0'));
    EXPECT_EQ(r.chips.back().name, "chip_" + last);
    for (std::size_t k = 0; k < c; ++k) {
        const Pose rest = poseAt(r, 0, n + k);
        EXPECT_LT(glm::length(rest.x - r.chips[k].centerOfMass), 1e-5);  // frame 0 is the rest pose
        EXPECT_EQ(rest.q, glm::dquat(1.0, 0.0, 0.0, 0.0));
    }
}

// Until its bond breaks a chip rides in its parent (its place relative to it does not change);
// then it flies out, tumbling no faster than 25 rad/s, never through the ground, and once the tower has settled nearly all have
// come to rest.
TEST(Debris, ChipsRideHiddenThenFlyOutAndComeToRestOnTheGround) {
    const std::vector<RigidPiece> pieces = rigidPieces(smallTower());
    SimulationSettings s = collapsing(true);
    s.frames = 240;
    SimulationSettings without = s;
    without.debris.chips = false;
    const SimulationResult plain = simulate(pieces, smallTower().bonds, without);
    const std::vector<ChipSeed> seeds = emitChips(pieces, smallTower().bonds, plain, s);
    const SimulationResult r = simulate(pieces, smallTower().bonds, s);
    const std::size_t n = pieces.size();
    ASSERT_EQ(r.chips.size(), seeds.size());
    std::size_t left = 0, resting = 0;
    double lowest = 1e9;
    for (std::size_t k = 0; k < seeds.size(); ++k) {
        const ChipSeed& chip = seeds[k];
        const glm::dvec3 offset = chip.piece.centerOfMass - pieces[chip.parent].centerOfMass;
        for (int f = 0; f <= chip.releaseFrame; ++f) {
            const Pose parent = poseAt(r, f, chip.parent), me = poseAt(r, f, n + k);
            EXPECT_LT(glm::length(parent.x + parent.q * offset - me.x), 1e-4) << chip.piece.name << " frame " << f;
        }
        const Pose end = poseAt(r, r.frames - 1, n + k), parentEnd = poseAt(r, r.frames - 1, chip.parent);
        left += glm::length(parentEnd.x + parentEnd.q * offset - end.x) > 0.1;
        resting += glm::length(end.x - poseAt(r, r.frames - 2, n + k).x) < 0.005;
        for (int f = 0; f < r.frames; ++f) lowest = std::min(lowest, poseAt(r, f, n + k).x.y);
        // Free, it tumbles at most 25 rad/s, and turns.bin holds at least the turn between frames.
        for (int f = chip.releaseFrame; f + 1 < r.frames; ++f) {
            const double turns = std::abs(r.turns[std::size_t(f) * r.pieces + n + k]);
            const double net = std::acos(std::min(1.0, std::abs(glm::dot(poseAt(r, f, n + k).q, poseAt(r, f + 1, n + k).q)))) / glm::pi<double>();
            EXPECT_LE(turns, 25.0 / s.fps / glm::two_pi<double>() + 1e-4) << chip.piece.name << " frame " << f;
            EXPECT_GE(turns, net - 1e-3) << chip.piece.name << " frame " << f;  // float quaternions: 1e-4 turns of noise
        }
    }
    std::size_t piecesResting = 0;
    for (std::size_t i = 0; i < n; ++i)
        piecesResting += glm::length(poseAt(r, r.frames - 1, i).x - poseAt(r, r.frames - 2, i).x) < 0.005;
    ASSERT_EQ(piecesResting, n) << "the tower has not settled: the test needs more frames";
    EXPECT_GT(lowest, r.groundHeight - 0.1);  // none fell through; a piece lying on one presses it in a little
    EXPECT_GE(left, seeds.size() * 9 / 10);
    EXPECT_GE(resting, seeds.size() * 9 / 10);
}

// Puffs appear at the first frame after the collapse, never below the ground, grow, rise,
// and have faded out once their life (5 s ± 30 %) is over; none before.
TEST(Debris, DustAppearsAtTheBreaksRisesGrowsAndFades) {
    const std::vector<RigidPiece> pieces = rigidPieces(smallTower());
    SimulationSettings s = collapsing(false);
    s.frames = 240;
    s.debris.dust = true;
    const SimulationResult r = simulate(pieces, smallTower().bonds, s);
    const std::size_t p = r.dustPuffs;
    ASSERT_GT(p, 5u);
    EXPECT_LE(p, s.debris.maxPuffs);
    ASSERT_EQ(r.dust.size(), std::size_t(r.frames) * p * 5);
    EXPECT_TRUE(r.chips.empty());
    const auto at = [&](int frame, std::size_t puff, int c) { return r.dust[(std::size_t(frame) * p + puff) * 5 + std::size_t(c)]; };
    double risen = 0.0;
    for (std::size_t i = 0; i < p; ++i) {
        for (int f = 0; f <= 6; ++f) EXPECT_EQ(at(f, i, 4), 0.0f) << "puff " << i << " before the break, frame " << f;
        EXPECT_GT(at(9, i, 4), 0.1f) << "puff " << i;
        EXPECT_EQ(at(r.frames - 1, i, 4), 0.0f) << "puff " << i << " outlived 6.5 s";
        for (int f = 7; f < r.frames; ++f) {
            EXPECT_GE(at(f, i, 3), at(f - 1, i, 3));
            EXPECT_GE(at(f, i, 1), r.groundHeight + 0.5 * at(f, i, 3) - 1e-4);
            EXPECT_LE(at(f, i, 4), 0.55f + 1e-6f);
        }
        EXPECT_NEAR(at(r.frames - 1, i, 3), 4.0 * at(6, i, 3), 0.02 * at(6, i, 3));  // four times its size by then
        risen += at(150, i, 1) - at(30, i, 1);
    }
    EXPECT_GT(risen / double(p), 0.5);  // 0.3 m/s for 4 s, less what the ground holds down
    SimulationSettings none = s;
    none.debris.puffsPerSquareMetre = 0.0;
    const SimulationResult still = simulate(pieces, smallTower().bonds, none);
    EXPECT_EQ(still.dustPuffs, 0u);
    EXPECT_TRUE(still.dust.empty());
    EXPECT_EQ(still.transforms, r.transforms);  // dust never moves a piece
}

TEST(Debris, SameChipsOnAnyThreadCount) {
    const std::vector<RigidPiece> pieces = rigidPieces(smallTower());
    SimulationSettings s = collapsing(true);
    s.debris.dust = true;
    s.frames = 40;
    SimulationResult one;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = simulate(pieces, smallTower().bonds, s);
    }
    const SimulationResult two = simulate(pieces, smallTower().bonds, s);
    ASSERT_GT(one.chips.size(), 0u);
    EXPECT_EQ(one.transforms, two.transforms);
    EXPECT_EQ(one.turns, two.turns);
    ASSERT_GT(one.dustPuffs, 0u);
    EXPECT_EQ(one.dust, two.dust);
    s.seed = 9;  // another seed, other chips
    EXPECT_NE(simulate(pieces, smallTower().bonds, s).transforms, two.transforms);
}

TEST(Debris, NoBreaksNoChipsAndBadSettingsAreInputErrors) {
    const std::vector<RigidPiece> pieces = rigidPieces(smallTower());
    SimulationSettings s = collapsing(true);
    s.collapse = false;
    s.frames = 20;
    const SimulationResult standing = simulate(pieces, smallTower().bonds, s);
    EXPECT_EQ(standing.brokenBonds, 0u);
    EXPECT_TRUE(standing.chips.empty());
    EXPECT_EQ(standing.pieces, pieces.size());
    s.debris.chipSize = 0.0;
    EXPECT_THROW(simulate(pieces, smallTower().bonds, s), InputError);
    s.debris.chipSize = 0.1;
    s.debris.spraySpeed = -1.0;
    EXPECT_THROW(simulate(pieces, smallTower().bonds, s), InputError);
    s.debris.spraySpeed = 1.0;
    s.debris.puffLife = 0.0;
    EXPECT_THROW(simulate(pieces, smallTower().bonds, s), InputError);
}
