// BondStressModel: the largest principal stress of each bond of a glued structure, from a
// linear model of the bond graph, checked on structures small enough to solve by hand.
#include "bond_stress.hpp"

#include <dawnforge/core/error.hpp>

#include <glm/gtc/constants.hpp>
#include <gtest/gtest.h>

#include <cmath>

using namespace dawnforge::sim;

namespace {

// Node 0 held at the origin, node 1 a metre above it, one bond between them at half height
// with the normal from 0 to 1 (+y) and the given area; `load` on node 1.
std::vector<double> column(double area, glm::dvec3 force, glm::dvec3 torque = glm::dvec3(0.0)) {
    BondStressModel model({{{0, 0, 0}, 10.0, true}, {{0, 1, 0}, 10.0, false}}, {{0, 1, {0, 0.5, 0}, {0, 1, 0}, area}});
    return model.stresses({{glm::dvec3(0.0), force}, {glm::dvec3(0.0), torque}});
}

}  // namespace

TEST(BondStress, APulledBondCarriesForceOverAreaAndAPressedOneNothing) {
    EXPECT_NEAR(column(0.5, {0, 1000, 0})[0], 2000.0, 1e-3);
    EXPECT_NEAR(column(0.5, {0, -1000, 0})[0], 0.0, 1e-3);
}

// σ = 0, τ = F/A: the principal stress is τ. Node 1's load acts 0.5 m from the bond, so it
// also bends it: σ = 4·M/(A·r) with M = 0.5·F.
TEST(BondStress, ShearAndBendingGiveTheirPrincipalStress) {
    const double area = 0.5, force = 1000.0, r = std::sqrt(area / glm::pi<double>());
    const double sigma = 4.0 * 0.5 * force / (area * r), tau = force / area;
    EXPECT_NEAR(column(area, {force, 0, 0})[0], 0.5 * sigma + std::sqrt(0.25 * sigma * sigma + tau * tau), 1e-2);
    // A pure twist about the normal: τ = 2·T/(A·r).
    EXPECT_NEAR(column(area, glm::dvec3(0.0), {0, 100, 0})[0], 2.0 * 100.0 / (area * r), 1e-3);
}

// Two bonds side by side carry a load in proportion to their areas: the same stress.
TEST(BondStress, ParallelBondsShareALoadByTheirAreas) {
    BondStressModel model({{{0, 0, 0}, 10.0, true}, {{0, 1, 0}, 10.0, false}},
                          {{0, 1, {-1, 0.5, 0}, {0, 1, 0}, 0.1}, {0, 1, {1, 0.5, 0}, {0, 1, 0}, 0.1}, {0, 1, {0, 0.5, 0}, {0, 1, 0}, 0.3}});
    const std::vector<double> s = model.stresses({{glm::dvec3(0.0), {0, 5000, 0}}, {glm::dvec3(0.0), glm::dvec3(0.0)}});
    for (double v : s) EXPECT_NEAR(v, 5000.0 / 0.5, 1e-2);
}

// A glued pair with nothing held falls as one: its weight stresses nothing. A broken bond
// carries nothing, and the rest of the structure takes its load.
TEST(BondStress, AFallingGroupCarriesNoWeightAndABrokenBondNothing) {
    const glm::dvec3 g(0, -9.81, 0);
    BondStressModel falling({{{0, 0, 0}, 10.0, false}, {{0, 1, 0}, 30.0, false}}, {{0, 1, {0, 0.5, 0}, {0, 1, 0}, 0.1}});
    EXPECT_NEAR(falling.stresses({{10.0 * g, 30.0 * g}, {glm::dvec3(0.0), glm::dvec3(0.0)}})[0], 0.0, 1e-6);

    BondStressModel pair({{{0, 0, 0}, 10.0, true}, {{0, 1, 0}, 10.0, false}},
                         {{0, 1, {-1, 0.5, 0}, {0, 1, 0}, 0.2}, {0, 1, {1, 0.5, 0}, {0, 1, 0}, 0.2}});
    const NodeLoads pull{{glm::dvec3(0.0), {0, 4000, 0}}, {glm::dvec3(0.0), glm::dvec3(0.0)}};
    EXPECT_NEAR(pair.stresses(pull)[1], 4000.0 / 0.4, 1e-2);
    pair.breakLink(0);
    const std::vector<double> after = pair.stresses(pull);
    EXPECT_EQ(after[0], 0.0);
    EXPECT_GT(after[1], 4000.0 / 0.2);  // all the pull, and the bending of carrying it off-centre
}

// A free group's own inertia balances its loads, turning as well as moving: a dumbbell of two
// point masses struck across one end turns about the other end, and their bond carries
// nothing; three in a line struck across one end, each bond carries the force that moves
// the masses beyond it (F/6 across), and bends as much as it takes to turn them. Before the
// turning was taken out, the torque went through the bonds to the first node.
TEST(BondStress, AStruckFreeGroupTurnsAsWellAsMoves) {
    const NodeLoads strike{{glm::dvec3(0.0), {0, 600, 0}}, {glm::dvec3(0.0), glm::dvec3(0.0)}};
    BondStressModel dumbbell({{{-1, 0, 0}, 10.0, false}, {{1, 0, 0}, 10.0, false}}, {{0, 1, {0, 0, 0}, {1, 0, 0}, 0.1}});
    EXPECT_NEAR(dumbbell.stresses(strike)[0], 0.0, 1e-6 * 600.0 / 0.1);  // of F/A

    const double area = 0.1, r = std::sqrt(area / glm::pi<double>());
    BondStressModel bar({{{-2, 0, 0}, 10.0, false}, {{0, 0, 0}, 10.0, false}, {{2, 0, 0}, 10.0, false}},
                        {{0, 1, {-1, 0, 0}, {1, 0, 0}, area}, {1, 2, {1, 0, 0}, {1, 0, 0}, area}});
    const NodeLoads end{{glm::dvec3(0.0), glm::dvec3(0.0), {0, 600, 0}}, std::vector<glm::dvec3>(3, glm::dvec3(0.0))};
    const std::vector<double> s = bar.stresses(end);
    // a = F/3m, α = F·2/(m·8): the far mass accelerates by a − 2α = −F/6m, the middle by F/3m.
    // Bond 0 moves the far mass (shear F/6) 1 m away (moment F/6); bond 1 moves both (shear
    // F/6), their moment about its point is −F/6·3 + F/3·1 = −F/6.
    const double tau = 100.0 / area, sigma = 4.0 * 100.0 / (area * r);
    const double expected = 0.5 * sigma + std::sqrt(0.25 * sigma * sigma + tau * tau);
    EXPECT_NEAR(s[0], expected, 1e-6 * expected);
    EXPECT_NEAR(s[1], expected, 1e-6 * expected);
}

// Groups are separate systems: solving only the loaded one gives its bonds the same stresses
// as solving all, and the others read 0; a break in one group leaves the other's as they were.
TEST(BondStress, GroupsAreSolvedOnTheirOwnAndOnlyWhenActive) {
    // Two columns, each a held node with one above it, and a third node bonded to the second column.
    BondStressModel model({{{0, 0, 0}, 10.0, true}, {{0, 1, 0}, 10.0, false}, {{5, 0, 0}, 10.0, true}, {{5, 1, 0}, 10.0, false},
                           {{5, 2, 0}, 10.0, false}},
                          {{0, 1, {0, 0.5, 0}, {0, 1, 0}, 0.5}, {2, 3, {5, 0.5, 0}, {0, 1, 0}, 0.5}, {3, 4, {5, 1.5, 0}, {0, 1, 0}, 0.25}});
    const NodeLoads loads{{glm::dvec3(0.0), {0, 1000, 0}, glm::dvec3(0.0), {0, 2000, 0}, {0, 500, 0}}, std::vector<glm::dvec3>(5)};
    const std::vector<double> all = model.stresses(loads);
    EXPECT_NEAR(all[0], 2000.0, 1e-3);
    EXPECT_NEAR(all[1], 2500.0 / 0.5, 1e-3);
    EXPECT_NEAR(all[2], 500.0 / 0.25, 1e-3);
    const std::vector<bool> second{false, false, false, false, true};
    const std::vector<double> some = model.stresses(loads, &second);
    EXPECT_EQ(some[0], 0.0);
    EXPECT_EQ(some[1], all[1]);
    EXPECT_EQ(some[2], all[2]);
    model.breakLink(2);
    const std::vector<double> after = model.stresses(loads);
    EXPECT_EQ(after[0], all[0]);
    EXPECT_NEAR(after[1], 2000.0 / 0.5, 1e-3);  // node 4 no longer hangs on it
    EXPECT_EQ(after[2], 0.0);
}

TEST(BondStress, ABondToAMissingPieceIsAnInputError) {
    EXPECT_THROW(BondStressModel({{{0, 0, 0}, 1.0, true}}, {{0, 1, {0, 0, 0}, {0, 1, 0}, 1.0}}), dawnforge::InputError);
    EXPECT_THROW(BondStressModel({{{0, 0, 0}, 1.0, true}, {{0, 1, 0}, 1.0, false}}, {{0, 1, {0, 0, 0}, {0, 1, 0}, 0.0}}),
                 dawnforge::InputError);
}
