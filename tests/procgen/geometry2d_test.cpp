// Plan geometry (geometry2d.hpp): the small polygon helpers every procgen stage shares.
#include <dawnforge/procgen/geometry2d.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace dawnforge::procgen {
namespace {

const Polygon2 kSquare{{0, 0}, {4, 0}, {4, 4}, {0, 4}};
const Polygon2 kPentagon{{0, 0}, {12, 0}, {14, 7}, {6, 12}, {-2, 7}};
const Polygon2 kLShape{{0, 0}, {20, 0}, {20, 8}, {8, 8}, {8, 18}, {0, 18}};  // reflex at vertex 3

// Distance from p to the line through a and b.
double lineDistance(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
    return std::abs(cross(b - a, p - a)) / glm::distance(a, b);
}

TEST(Geometry2d, CrossAndInwardNormalFollowCounterClockwise) {
    EXPECT_EQ(cross({1, 0}, {0, 1}), 1.0);
    EXPECT_EQ(cross({0, 1}, {1, 0}), -1.0);
    EXPECT_EQ(cross({2, 3}, {4, 6}), 0.0);
    // Left of each edge of a counter-clockwise polygon is inside.
    for (std::size_t i = 0; i < kPentagon.size(); ++i) {
        const glm::dvec2 a = kPentagon[i], b = kPentagon[(i + 1) % kPentagon.size()];
        const glm::dvec2 n = inwardNormal(a, b);
        EXPECT_NEAR(glm::length(n), 1.0, 1e-15);
        EXPECT_NEAR(glm::dot(n, b - a), 0.0, 1e-12);
        EXPECT_TRUE(containsPoint(kPentagon, 0.5 * (a + b) + 0.01 * n));
    }
}

TEST(Geometry2d, ReflexVertexAndInteriorPoint) {
    EXPECT_EQ(reflexVertex(kSquare), kSquare.size());
    EXPECT_EQ(reflexVertex(kLShape), 3u);
    EXPECT_TRUE(isConvex(kPentagon));
    EXPECT_FALSE(isConvex(kLShape));
    EXPECT_FALSE(isConvex(Polygon2{{0, 0}, {1, 0}}));
    const glm::dvec2 inside = interiorPoint(kLShape);
    EXPECT_TRUE(containsPoint(kLShape, inside));
    EXPECT_GT(distanceToBoundary(kLShape, inside), 0.1);
}

TEST(Geometry2d, SegmentsCrossOnlyThroughEachOther) {
    EXPECT_TRUE(segmentsCross({0, 0}, {2, 2}, {0, 2}, {2, 0}));
    EXPECT_FALSE(segmentsCross({0, 0}, {1, 1}, {1, 1}, {2, 0}));  // a shared end
    EXPECT_FALSE(segmentsCross({0, 0}, {2, 0}, {1, 0}, {1, 1}));  // a T
    EXPECT_FALSE(segmentsCross({0, 0}, {2, 0}, {1, 0}, {3, 0}));  // overlapping, collinear
    EXPECT_FALSE(segmentsCross({0, 0}, {1, 0}, {2, -1}, {2, 1}));
}

TEST(Geometry2d, ClosestPointOnASegment) {
    EXPECT_EQ(closestOnSegment({1, 5}, {0, 0}, {4, 0}), glm::dvec2(1, 0));
    EXPECT_EQ(closestOnSegment({-3, 1}, {0, 0}, {4, 0}), glm::dvec2(0, 0));
    EXPECT_EQ(closestOnSegment({9, -1}, {0, 0}, {4, 0}), glm::dvec2(4, 0));
    EXPECT_EQ(closestOnSegment({9, -1}, {2, 2}, {2, 2}), glm::dvec2(2, 2));  // a point
    EXPECT_EQ(distanceToSegment({1, 5}, {0, 0}, {4, 0}), 5.0);
    EXPECT_EQ(distanceToSegment({7, 4}, {0, 0}, {4, 0}), 5.0);
}

TEST(Geometry2d, StripsCutAConvexPolygonIntoPiecesOfTheRightArea) {
    const glm::dvec2 axis = glm::normalize(glm::dvec2(1, 2));
    double lo = INFINITY, hi = -INFINITY;
    for (glm::dvec2 p : kPentagon) lo = std::min(lo, glm::dot(axis, p)), hi = std::max(hi, glm::dot(axis, p));
    double sum = 0.0;
    for (int k = 0; k < 5; ++k) {
        const Polygon2 strip = clipStrip(kPentagon, axis, lo + (hi - lo) * k / 5, lo + (hi - lo) * (k + 1) / 5);
        ASSERT_GE(strip.size(), 3u);
        EXPECT_TRUE(isConvex(strip));
        for (glm::dvec2 p : strip) {
            EXPECT_GE(glm::dot(axis, p), lo + (hi - lo) * k / 5 - 1e-9);
            EXPECT_LE(glm::dot(axis, p), lo + (hi - lo) * (k + 1) / 5 + 1e-9);
        }
        sum += signedArea(strip);
    }
    EXPECT_NEAR(sum, signedArea(kPentagon), 1e-9);
    EXPECT_TRUE(clipStrip(kPentagon, axis, hi + 1.0, hi + 2.0).empty());
}

TEST(Geometry2d, ChordIsWhereALineCrossesAConvexPolygon) {
    const auto across = chord(kSquare, {1, 0}, 1.0, {0, 1});  // x = 1, as a range of y
    ASSERT_TRUE(across.has_value());
    EXPECT_DOUBLE_EQ(across->first, 0.0);
    EXPECT_DOUBLE_EQ(across->second, 4.0);
    const auto diagonal = chord(kSquare, glm::normalize(glm::dvec2(1, 1)), std::sqrt(2.0), {1, 0});
    ASSERT_TRUE(diagonal.has_value());  // x + y = 2: from (0, 2) to (2, 0)
    EXPECT_NEAR(diagonal->first, 0.0, 1e-12);
    EXPECT_NEAR(diagonal->second, 2.0, 1e-12);
    EXPECT_FALSE(chord(kSquare, {1, 0}, 5.0, {0, 1}).has_value());  // misses
    EXPECT_FALSE(chord(kSquare, glm::normalize(glm::dvec2(1, 1)), 0.0, {1, 0}).has_value());  // a corner
}

TEST(Geometry2d, RayExitIsTheDistanceToTheBoundary) {
    EXPECT_DOUBLE_EQ(rayExit(kSquare, {1, 1}, {1, 0}), 3.0);
    EXPECT_DOUBLE_EQ(rayExit(kSquare, {1, 1}, {0, -1}), 1.0);
    EXPECT_NEAR(rayExit(kSquare, {1, 1}, glm::normalize(glm::dvec2(1, 1))), 3.0 * std::sqrt(2.0), 1e-12);
    EXPECT_EQ(rayExit(kSquare, {6, 1}, {1, 0}), 0.0);  // already past it
}

TEST(Geometry2d, MitreOffsetMovesEveryEdgeByTheDistance) {
    for (double d : {0.3, -0.5}) {
        const Polygon2 moved = mitreOffset(kPentagon, d);
        ASSERT_EQ(moved.size(), kPentagon.size());
        EXPECT_TRUE(isConvex(moved));
        const std::size_t n = moved.size();
        for (std::size_t i = 0; i < n; ++i) {
            const glm::dvec2 a = kPentagon[i], b = kPentagon[(i + 1) % n];
            for (glm::dvec2 p : {moved[i], moved[(i + 1) % n]}) {
                EXPECT_NEAR(lineDistance(p, a, b), std::abs(d), 1e-12);
                EXPECT_EQ(glm::dot(p - a, inwardNormal(a, b)) > 0.0, d > 0.0);  // inward when positive
            }
        }
    }
    const Polygon2 square = mitreOffset(kSquare, 1.0);
    EXPECT_NEAR(signedArea(square), 4.0, 1e-12);
}

TEST(Geometry2d, DropShortEdgesOnlyShrinksAConvexPolygon) {
    // A 24-gon of radius 5 has edges of about 1.3 m.
    Polygon2 round;
    for (int i = 0; i < 24; ++i) {
        const double a = 2.0 * std::numbers::pi * i / 24.0;
        round.push_back({5.0 * std::cos(a), 5.0 * std::sin(a)});
    }
    const Polygon2 dropped = dropShortEdges(round, 2.0);
    ASSERT_GE(dropped.size(), 3u);
    EXPECT_LT(dropped.size(), round.size());
    EXPECT_TRUE(isConvex(dropped));
    EXPECT_LE(signedArea(dropped), signedArea(round));
    for (std::size_t i = 0; i < dropped.size(); ++i) {
        EXPECT_GE(glm::distance(dropped[i], dropped[(i + 1) % dropped.size()]), 2.0);
        EXPECT_NE(std::find(round.begin(), round.end(), dropped[i]), round.end());  // a vertex of the input
    }
    EXPECT_EQ(dropShortEdges(kSquare, 2.0), kSquare);
    EXPECT_EQ(dropShortEdges(kSquare, 10.0).size(), 3u);  // never fewer than three
}

TEST(Geometry2d, BestEdgeIsTheFirstOfTheHighestScores) {
    // Edges of the square: 0 east, 1 north, 2 west, 3 south.
    const auto along = [](glm::dvec2 want) {
        return [want](glm::dvec2, glm::dvec2, glm::dvec2 dir) { return glm::dot(dir, want); };
    };
    EXPECT_EQ(bestEdge(kSquare, along({1, 0})), 0u);
    EXPECT_EQ(bestEdge(kSquare, along({0, 1})), 1u);
    EXPECT_EQ(bestEdge(kSquare, along({-1, 0})), 2u);
    EXPECT_EQ(bestEdge(kSquare, along({0, -1})), 3u);
    EXPECT_EQ(bestEdge(kSquare, [](glm::dvec2, glm::dvec2, glm::dvec2) { return 1.0; }), 0u);  // a tie
    const auto highest = [](glm::dvec2 a, glm::dvec2 b, glm::dvec2) { return std::min(a.y, b.y); };
    EXPECT_EQ(bestEdge(kSquare, highest), 2u);  // the north edge runs west: (4, 4) -> (0, 4)
    EXPECT_EQ(bestEdge(kSquare, [](glm::dvec2, glm::dvec2, glm::dvec2) { return -INFINITY; }), 0u);
}

}  // namespace
}  // namespace dawnforge::procgen
