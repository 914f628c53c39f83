// The leaf cards' picture (leaves.hpp): what the tree shaders cut the cards out with.
#include <dawnforge/core/leaves.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace dawnforge;

namespace {

const LeafImage& image() {
    static const LeafImage leaves = makeLeafImage();
    return leaves;
}

const std::uint8_t* texel(int level, int x, int y) {
    const int size = kLeafSize >> level;
    return &image().rgba[std::size_t(level)][(std::size_t(y) * std::size_t(size) + std::size_t(x)) * 4];
}

}  // namespace

TEST(Leaves, LevelsHaveTheirSizesAndTheSameBytesEveryTime) {
    for (int l = 0; l < kLeafLevels; ++l) EXPECT_EQ(image().rgba[std::size_t(l)].size(), std::size_t(kLeafSize >> l) * std::size_t(kLeafSize >> l) * 4);
    EXPECT_EQ(kLeafSize >> (kLeafLevels - 1), 1);
    const LeafImage again = makeLeafImage();
    for (int l = 0; l < kLeafLevels; ++l) EXPECT_EQ(again.rgba[std::size_t(l)], image().rgba[std::size_t(l)]) << "level " << l;
}

// A cluster, not a square: about a third of the card is leaf, and no leaf reaches its edge (a
// card's outline never shows).
TEST(Leaves, TheCardIsACutOutClusterWithAClearEdge) {
    const double coverage = leafCoverage(image(), 0);
    EXPECT_GT(coverage, 0.2);
    EXPECT_LT(coverage, 0.6);
    const int border = kLeafSize / 20;
    for (int y = 0; y < kLeafSize; ++y)
        for (int x = 0; x < kLeafSize; ++x)
            if (x < border || y < border || x >= kLeafSize - border || y >= kLeafSize - border) {
                ASSERT_EQ(texel(0, x, y)[3], 0) << x << ", " << y;
            }
    EXPECT_EQ(texel(0, kLeafSize / 2, kLeafSize / 2)[1] > texel(0, kLeafSize / 2, kLeafSize / 2)[0], true) << "green";
}

// Far crowns stay as dense: every level down to 8 × 8 passes the cutoff in about the share
// level 0 does (a plain box filter of the alpha thins them out as the levels shrink).
TEST(Leaves, MipLevelsKeepTheCoverage) {
    const double coverage = leafCoverage(image(), 0);
    for (int l = 1; l <= 5; ++l) EXPECT_NEAR(leafCoverage(image(), l), coverage, l <= 4 ? 0.04 : 0.1) << "level " << l;
}

// Where no leaf is, the colour is still the leaves' (green, not black): bilinear taps at a
// leaf's edge do not darken it.
TEST(Leaves, EmptyTexelsCarryTheLeavesColour) {
    for (int y = 0; y < kLeafSize; y += 7)
        for (int x = 0; x < kLeafSize; x += 7) {
            const std::uint8_t* t = texel(0, x, y);
            if (t[3] != 0) continue;
            EXPECT_GT(t[1], t[0]);
            EXPECT_GT(t[1], 40);
        }
}
