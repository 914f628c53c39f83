#include <dawnforge/core/seed.hpp>

#include <gtest/gtest.h>

#include <array>
#include <set>

using namespace dawnforge;

TEST(Seed, Mix64IsSplitMix64) {
    // The first output of the reference SplitMix64 seeded with 0 (Vigna, splitmix64.c).
    EXPECT_EQ(mix64(0), 0xe220a8397b1dcdafull);
}

TEST(Seed, DerivedSeedsDependOnSeedPurposeAndId) {
    const std::uint64_t base = deriveSeed(42, "lot-split", 7);
    EXPECT_EQ(base, deriveSeed(42, "lot-split", 7));
    EXPECT_NE(base, deriveSeed(43, "lot-split", 7));
    EXPECT_NE(base, deriveSeed(42, "lot-splits", 7));
    EXPECT_NE(base, deriveSeed(42, "lot-split", 8));
    std::set<std::uint64_t> seen;
    for (std::uint64_t id = 0; id < 10000; ++id) seen.insert(deriveSeed(1, "piece", id));
    EXPECT_EQ(seen.size(), 10000u);
}

TEST(Rng, SameSeedSameSequence) {
    Rng a(123), b(123), c(124);
    bool differs = false;
    for (int i = 0; i < 1000; ++i) {
        const std::uint64_t x = a.next();
        EXPECT_EQ(x, b.next());
        differs |= x != c.next();
    }
    EXPECT_TRUE(differs);
}

TEST(Rng, UniformIsInRangeWithTheRightMean) {
    Rng rng(7);
    double sum = 0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        const double u = rng.uniform();
        ASSERT_GE(u, 0.0);
        ASSERT_LT(u, 1.0);
        sum += u;
    }
    // Standard error of the mean is sqrt(1/12/n) ~ 0.00065: 0.003 is over four of them.
    EXPECT_NEAR(sum / n, 0.5, 0.003);
    for (int i = 0; i < 1000; ++i) {
        const double v = rng.uniform(-2.0, 3.0);
        ASSERT_GE(v, -2.0);
        ASSERT_LT(v, 3.0);
    }
}

TEST(Rng, BelowAndRangeAreUnbiasedAndInclusive) {
    Rng rng(99);
    std::array<int, 6> counts{};
    const int n = 60000;
    for (int i = 0; i < n; ++i) ++counts[rng.below(6)];
    // Expected 10000 per bucket, standard deviation ~91: allow five of them.
    for (int c : counts) EXPECT_NEAR(c, 10000, 460);
    bool sawLo = false, sawHi = false;
    for (int i = 0; i < 1000; ++i) {
        const int r = rng.range(-3, 3);
        ASSERT_GE(r, -3);
        ASSERT_LE(r, 3);
        sawLo |= r == -3;
        sawHi |= r == 3;
    }
    EXPECT_TRUE(sawLo && sawHi);
}
