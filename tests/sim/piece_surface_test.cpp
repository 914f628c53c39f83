// cleanSurface(): what rounding does to a piece's surface, mended on exact grid points.
#include "piece_surface.hpp"

#include <gtest/gtest.h>

#include <map>
#include <utility>

using namespace dawnforge::sim::detail;
using P = glm::i64vec3;

namespace {

// A box from lo to hi as 12 outward triangles over 8 new points appended to `points`.
std::vector<GridTriangle> box(std::vector<P>& points, P lo, P hi, bool inward = false) {
    const auto base = std::uint32_t(points.size());
    for (int i = 0; i < 8; ++i) points.push_back({i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z});
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    std::vector<GridTriangle> tris;
    for (const auto& q : quads) {
        std::array<std::uint32_t, 4> v{};
        for (int k = 0; k < 4; ++k) v[std::size_t(k)] = base + std::uint32_t(q[k]);
        tris.push_back({{v[0], v[1], v[2]}, 0});
        tris.push_back({{v[0], v[2], v[3]}, 0});
    }
    if (inward)
        for (GridTriangle& t : tris) std::swap(t.v[1], t.v[2]);
    return tris;
}

// Every directed edge is used once and its reverse once: closed, manifold, consistent.
bool closedAndConsistent(const std::vector<GridTriangle>& tris) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> used;
    for (const GridTriangle& t : tris)
        for (int k = 0; k < 3; ++k) ++used[{t.v[k], t.v[(k + 1) % 3]}];
    for (const auto& [e, n] : used)
        if (n != 1 || used.count({e.second, e.first}) == 0 || used.at({e.second, e.first}) != 1) return false;
    return true;
}

std::int64_t volume6(const std::vector<P>& p, const std::vector<GridTriangle>& tris) {
    std::int64_t v = 0;
    for (const GridTriangle& t : tris) {
        const P a = p[t.v[0]], b = p[t.v[1]], c = p[t.v[2]];
        v += a.x * (b.y * c.z - b.z * c.y) - a.y * (b.x * c.z - b.z * c.x) + a.z * (b.x * c.y - b.y * c.x);
    }
    return v;
}

}  // namespace

TEST(PieceSurface, CollapsedTrianglesAreDropped) {
    std::vector<P> points;
    std::vector<GridTriangle> tris = box(points, {0, 0, 0}, {4, 4, 4});
    tris.push_back({{0, 0, 5}, 0});
    const CleanSurface clean = cleanSurface(points, tris);
    EXPECT_EQ(clean.collapsed, 1u);
    ASSERT_EQ(clean.parts.size(), 1u);
    EXPECT_EQ(clean.parts[0].size(), 12u);
    EXPECT_TRUE(closedAndConsistent(clean.parts[0]));
}

TEST(PieceSurface, AZeroAreaTriangleIsFlippedIntoItsNeighbour) {
    // A box whose bottom edge 0-1 carries point c at its middle: the bottom face keeps the
    // plain edge, the front face is split at c, and the zero-area triangle (0, 1, c) closes
    // the T-junction, as rounding leaves it.
    std::vector<P> points;
    std::vector<GridTriangle> tris = box(points, {0, 0, 0}, {4, 4, 4});
    const auto c = std::uint32_t(points.size());
    points.push_back({2, 0, 0});
    // The front face (y = 0) is {0, 1, 5, 4}: (0,1,5) and (0,5,4). Split (0,1,5) at c on 0-1.
    std::erase_if(tris, [](const GridTriangle& t) { return t.v == std::array<std::uint32_t, 3>{0, 1, 5}; });
    tris.push_back({{0, c, 5}, 0});
    tris.push_back({{c, 1, 5}, 0});
    tris.push_back({{0, 1, c}, 0});  // zero area: its 0 -> 1 pairs with the bottom face's 1 -> 0
    ASSERT_TRUE(closedAndConsistent(tris));
    const std::int64_t before = volume6(points, tris);

    const CleanSurface clean = cleanSurface(points, tris);
    EXPECT_EQ(clean.flattened, 1u);
    EXPECT_EQ(clean.unmended, 0u);
    ASSERT_EQ(clean.parts.size(), 1u);
    EXPECT_TRUE(closedAndConsistent(clean.parts[0]));
    EXPECT_EQ(volume6(points, clean.parts[0]), before);
    for (const GridTriangle& t : clean.parts[0]) {
        const P a = points[t.v[0]], b = points[t.v[1]], d = points[t.v[2]];
        const P e1 = b - a, e2 = d - a;
        EXPECT_NE(P(e1.y * e2.z - e1.z * e2.y, e1.z * e2.x - e1.x * e2.z, e1.x * e2.y - e1.y * e2.x), P(0));
    }
}

TEST(PieceSurface, AFlattenedSliverPairCancels) {
    std::vector<P> points;
    std::vector<GridTriangle> tris = box(points, {0, 0, 0}, {4, 4, 4});
    tris.push_back({{0, 1, 3}, 7});
    tris.push_back({{1, 0, 3}, 7});
    const CleanSurface clean = cleanSurface(points, tris);
    EXPECT_EQ(clean.cancelled, 2u);
    ASSERT_EQ(clean.parts.size(), 1u);
    EXPECT_EQ(clean.parts[0].size(), 12u);
    EXPECT_TRUE(closedAndConsistent(clean.parts[0]));
}

TEST(PieceSurface, BoxesTouchingAlongAnEdgeOrAtACornerBecomeSeparateParts) {
    for (const P offset : {P(4, 4, 0), P(4, 4, 4)}) {  // edge contact, corner contact
        std::vector<P> points;
        std::vector<GridTriangle> a = box(points, {0, 0, 0}, {4, 4, 4});
        std::vector<GridTriangle> b = box(points, offset, offset + P(4, 4, 4));
        // Weld the shared points, as the fracture does by grid position.
        std::map<std::array<std::int64_t, 3>, std::uint32_t> id;
        std::vector<std::uint32_t> remap(points.size());
        for (std::uint32_t i = 0; i < points.size(); ++i)
            remap[i] = id.try_emplace({points[i].x, points[i].y, points[i].z}, i).first->second;
        a.insert(a.end(), b.begin(), b.end());
        for (GridTriangle& t : a)
            for (std::uint32_t& v : t.v) v = remap[v];
        const CleanSurface clean = cleanSurface(points, a);
        ASSERT_EQ(clean.parts.size(), 2u) << offset.z;
        for (const auto& part : clean.parts) {
            EXPECT_EQ(part.size(), 12u);
            EXPECT_TRUE(closedAndConsistent(part));
        }
        EXPECT_EQ(points[clean.parts[0][0].v[0]].x, 0);  // ordered by smallest point
    }
}

TEST(PieceSurface, ACavityStaysWithTheShellAroundIt) {
    std::vector<P> points;
    std::vector<GridTriangle> tris = box(points, {0, 0, 0}, {10, 10, 10});
    const std::vector<GridTriangle> cavity = box(points, {3, 3, 3}, {6, 6, 6}, true);
    const std::vector<GridTriangle> other = box(points, {20, 0, 0}, {30, 10, 10});
    tris.insert(tris.end(), other.begin(), other.end());
    tris.insert(tris.end(), cavity.begin(), cavity.end());
    const CleanSurface clean = cleanSurface(points, tris);
    ASSERT_EQ(clean.parts.size(), 2u);
    EXPECT_EQ(clean.parts[0].size(), 24u);  // the box at the origin with its cavity
    EXPECT_EQ(clean.parts[1].size(), 12u);
    EXPECT_EQ(volume6(points, clean.parts[0]), 6 * (1000 - 27));
}
