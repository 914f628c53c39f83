// The contact damage model alone (sim/src/damage.hpp): a blow damages the links next to the
// piece struck by what crosses them, split by area, less at every hop and not past the hops;
// damage adds up over blows and halves every half-life; a load the links hold is no damage; a
// link breaks past its force times the impact time.
#include "damage.hpp"

#include <gtest/gtest.h>

using namespace dawnforge::sim;

namespace {

// A chain 0 - 1 - 2 - ... - (n - 1), links of area 1 carrying `force`; node n is the ground.
DamageModel chain(std::uint32_t n, double force, DamageRules rules) {
    std::vector<DamageLink> links;
    for (std::uint32_t i = 0; i + 1 < n; ++i) links.push_back({i, i + 1, 1.0, force});
    return DamageModel(n + 1, n, std::move(links), rules);
}

}  // namespace

// Struck in the middle of a chain, the blow leaves through both links, half each, and each
// piece it reaches holds `transmission` of what crossed and splits it over its links by area,
// only the share that leads on going further: 50, 12.5, 3.125 of 100 on each side, then
// nothing. (A step of length 0 ages nothing and holds nothing back.)
TEST(Damage, ABlowCrossesTheLinksNextToItFirstAndLessAtEveryHop) {
    DamageModel m = chain(9, 1e12, {0.5, 3, 1e9, 1.0});
    m.strike(4, 100.0);
    EXPECT_TRUE(m.spread(0.0).empty());
    const double expected[] = {0.0, 3.125, 12.5, 50.0, 50.0, 12.5, 3.125, 0.0};
    for (std::size_t l = 0; l < 8; ++l) EXPECT_NEAR(m.damage(l), expected[l], 1e-9) << "link " << l;
    // Nothing is left to spread in the next step: a blow travels its hops in the step it lands.
    const std::vector<double> before = m.damages();
    m.spread(0.0);
    EXPECT_EQ(m.damages(), before);
}

// A piece's blow splits by area: the wide link takes three times what the narrow one does, and
// breaks no sooner for it, as it carries three times the force too.
TEST(Damage, ABlowSplitsByAreaAndAWideLinkIsNoWeakerForIt) {
    std::vector<DamageLink> links{{0, 1, 1.0, 30.0}, {0, 2, 3.0, 90.0}};
    DamageModel m(4, 3, links, {0.5, 1, 1e9, 1.0});
    m.strike(0, 100.0);
    EXPECT_TRUE(m.spread(0.0).empty());
    EXPECT_NEAR(m.damage(0), 25.0, 1e-9);
    EXPECT_NEAR(m.damage(1), 75.0, 1e-9);
    m.strike(0, 30.0);  // 25 + 7.5 > 30, 75 + 22.5 > 90: both go together
    EXPECT_EQ(m.spread(0.0), (std::vector<std::size_t>{0, 1}));
}

// Two blows that each break nothing break the link together, if the second comes before the
// first has healed; damage halves every half-life.
TEST(Damage, DamageAccumulatesAndHalvesEveryHalfLife) {
    DamageModel m = chain(2, 100.0, {0.5, 1, 0.5, 1.0});
    m.strike(0, 70.0);
    EXPECT_TRUE(m.spread(0.0).empty());
    EXPECT_NEAR(m.damage(0), 70.0, 1e-9);
    EXPECT_TRUE(m.spread(0.5).empty());
    EXPECT_NEAR(m.damage(0), 35.0, 1e-9);
    m.strike(0, 70.0);
    EXPECT_EQ(m.spread(0.0), (std::vector<std::size_t>{0}));  // 35 + 70 > 100

    DamageModel late = chain(2, 100.0, {0.5, 1, 0.5, 1.0});
    late.strike(0, 70.0);
    late.spread(0.0);
    late.spread(2.0);  // four half-lives: 4.4 left
    late.strike(0, 70.0);
    EXPECT_TRUE(late.spread(0.0).empty());
}

// What a piece's links carry over a step at their strength is a load, not a blow: a piece
// pushed with half of it every step for 10 s takes no damage; a blow of three times it, once,
// gives the link twice it as damage (2 · 1000 N · 1/120 s = 16.7 N·s, past 1000 N · 15 ms).
TEST(Damage, ALoadTheLinksHoldIsNoDamage) {
    const double dt = 1.0 / 120.0;
    DamageModel m = chain(2, 1000.0, {0.5, 1, 1.0, 0.015});
    for (int k = 0; k < 1200; ++k) {
        m.strike(0, 0.5 * 1000.0 * dt);
        ASSERT_TRUE(m.spread(dt).empty());
    }
    EXPECT_EQ(m.damage(0), 0.0);
    m.strike(0, 3.0 * 1000.0 * dt);
    EXPECT_EQ(m.spread(dt), (std::vector<std::size_t>{0}));
    EXPECT_NEAR(m.damage(0), 2.0 * 1000.0 * dt, 1e-9);
}

// A broken link takes nothing and passes nothing: a blow past it does not reach the far side,
// and the ground takes what crosses a ground link but passes nothing on.
TEST(Damage, ABrokenLinkAndTheGroundStopABlow) {
    std::vector<DamageLink> links{{0, 1, 1.0, 1e12}, {1, 2, 1.0, 1e12}, {0, 3, 1.0, 1e12}, {3, 2, 1.0, 1e12}};
    // 0 - 1 - 2 and 0 - ground(3) - 2: the ground does not carry the blow on to 2.
    DamageModel m(4, 3, links, {1.0, 4, 1e9, 1.0});
    m.breakLink(0);
    m.strike(0, 100.0);
    m.spread(0.0);
    EXPECT_EQ(m.damage(0), 0.0);
    EXPECT_NEAR(m.damage(2), 100.0, 1e-9);
    EXPECT_EQ(m.damage(1), 0.0);
    EXPECT_EQ(m.damage(3), 0.0);
}

// Two pieces struck side by side: their link takes both their shares, and neither passes the
// other's on (a ball on a seam breaks it, where only the outer links took damage before).
TEST(Damage, TheLinkBetweenTwoPiecesStruckTogetherTakesBothShares) {
    DamageModel m = chain(4, 1e12, {0.5, 2, 1e9, 1.0});
    m.strike(1, 100.0);
    m.strike(2, 100.0);
    m.spread(0.0);
    EXPECT_NEAR(m.damage(1), 100.0, 1e-9);  // 50 from each side
    EXPECT_NEAR(m.damage(0), 50.0, 1e-9);
    EXPECT_NEAR(m.damage(2), 50.0, 1e-9);
}

// Damage restored to what damages() gave is as if the step had not been taken (a substep taken
// again after a break).
TEST(Damage, RestoreTakesAStepBack) {
    DamageModel m = chain(3, 1e12, {0.5, 2, 1.0, 1.0});
    m.strike(1, 10.0);
    m.spread(0.0);
    const std::vector<double> saved = m.damages();
    m.strike(0, 50.0);
    m.spread(0.01);
    EXPECT_NE(m.damages(), saved);
    m.restore(saved);
    EXPECT_EQ(m.damages(), saved);
}
