// Perspective interior mapping: the one ray–box exit is the ray's only way out of the room, the
// picture mapping is a pinhole perspective and its inverse, the middle layer is hit only inside
// the room, room styles are a deterministic spread, and the generated pictures are the
// perspective they claim to be.
#include <dawnforge/runtime/interior.hpp>

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace dawnforge::runtime {
namespace {

using glm::dvec2;
using glm::dvec3;

// mt19937_64's sequence is fixed by the standard; the distributions are not, so convert by hand.
struct TestRng {
    std::mt19937_64 engine;
    explicit TestRng(std::uint64_t seed) : engine(seed) {}
    double uniform() { return static_cast<double>(engine() >> 11) * 0x1.0p-53; }
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
};

bool onFace(RoomFace face, dvec3 p, double tolerance) {
    switch (face) {
    case RoomFace::Back: return std::abs(p.z - 1.0) <= tolerance;
    case RoomFace::Left: return std::abs(p.x) <= tolerance;
    case RoomFace::Right: return std::abs(p.x - 1.0) <= tolerance;
    case RoomFace::Floor: return std::abs(p.y) <= tolerance;
    case RoomFace::Ceiling: return std::abs(p.y - 1.0) <= tolerance;
    }
    return false;
}
bool inBox(dvec3 p, double tolerance) {
    for (int i = 0; i < 3; ++i)
        if (p[i] < -tolerance || p[i] > 1.0 + tolerance) return false;
    return true;
}
int facesTouched(dvec3 p, double tolerance) {
    int n = 0;
    for (RoomFace f : {RoomFace::Back, RoomFace::Left, RoomFace::Right, RoomFace::Floor, RoomFace::Ceiling}) n += onFace(f, p, tolerance) ? 1 : 0;
    return n;
}

// Every point where the ray meets the box's surface for t > 0: all six planes, brute force,
// with hits that coincide (edges, corners) merged.
std::vector<dvec3> bruteForceSurfaceHits(dvec3 o, dvec3 d) {
    std::vector<dvec3> hits;
    for (int axis = 0; axis < 3; ++axis) {
        if (d[axis] == 0.0) continue;
        for (double plane : {0.0, 1.0}) {
            const double t = (plane - o[axis]) / d[axis];
            if (!(t > 0.0)) continue;
            dvec3 p = o + t * d;
            p[axis] = plane;
            if (!inBox(p, 1e-9)) continue;
            const bool seen = std::any_of(hits.begin(), hits.end(), [&](dvec3 q) { return glm::length(q - p) <= 1e-9; });
            if (!seen) hits.push_back(p);
        }
    }
    return hits;
}

void expectUniqueExit(dvec3 o, dvec3 d) {
    SCOPED_TRACE(::testing::Message() << "origin (" << o.x << ", " << o.y << ", " << o.z << ") direction (" << d.x << ", " << d.y
                                      << ", " << d.z << ")");
    const RoomHit exit = roomExit(o, d);
    const std::vector<dvec3> hits = bruteForceSurfaceHits(o, d);
    ASSERT_EQ(hits.size(), 1u) << "a ray from the glass going in leaves the box exactly once";
    EXPECT_LE(glm::length(hits[0] - exit.point), 1e-9);
    EXPECT_TRUE(onFace(exit.face, exit.point, 1e-9)) << "the exit lies on the face reported";
    EXPECT_TRUE(inBox(exit.point, 1e-9));
    EXPECT_LE(glm::length(o + exit.t * d - exit.point), 1e-9 * std::max(1.0, exit.t * glm::length(d)));
    ASSERT_GT(exit.t, 0.0);
    const double eps = 1e-6 * exit.t;
    EXPECT_TRUE(inBox(o + (exit.t - eps) * d, 1e-12)) << "just before the exit the ray is inside";
    EXPECT_FALSE(inBox(o + (exit.t + eps) * d, 0.0)) << "just after the exit the ray is outside";
}

TEST(RoomExit, RandomRaysLeaveTheBoxExactlyOnceWhereReported) {
    TestRng rng(0x1f2e3d4c);
    for (int i = 0; i < 20000; ++i) {
        const dvec3 o(rng.uniform(0.001, 0.999), rng.uniform(0.001, 0.999), 0.0);
        const double dz = i % 4 == 0 ? 1e-6 : (i % 4 == 1 ? rng.uniform(1e-4, 0.05) : rng.uniform(0.05, 2.0));
        const dvec3 d(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), dz);
        expectUniqueExit(o, d);
    }
}

TEST(RoomExit, AxisAlignedGrazingAndCornerRays) {
    const std::vector<dvec3> origins{{0.5, 0.5, 0.0}, {0.1, 0.9, 0.0}, {0.999, 0.001, 0.0}, {0.3, 0.7, 0.0}};
    const std::vector<dvec3> directions{
        {0, 0, 1},    {0, 0, 1e-6},  {1, 0, 1e-6},  {-1, 0, 1e-6}, {0, 1, 1e-6},  {0, -1, 1e-6}, {1, 0, 1},
        {-1, 0, 1},   {0, 1, 1},     {0, -1, 1},    {1, 1, 1},     {-1, -1, 1e-6}, {1e-6, 0, 1}, {0, -1e-9, 1},
        {3, -2, 1e-6}, {1e-12, 1e-12, 1}};
    for (dvec3 o : origins)
        for (dvec3 d : directions) expectUniqueExit(o, d);
    // Rays aimed exactly at the back corners and at points on the back edges.
    for (dvec3 o : origins)
        for (dvec3 target : {dvec3(0, 0, 1), dvec3(1, 0, 1), dvec3(0, 1, 1), dvec3(1, 1, 1), dvec3(0.5, 0, 1), dvec3(1, 0.5, 1)})
            expectUniqueExit(o, target - o);
}

TEST(RoomExit, FacesAndParameterOfSimpleRays) {
    EXPECT_EQ(roomExit({0.5, 0.5, 0}, {0, 0, 2}).face, RoomFace::Back);
    EXPECT_DOUBLE_EQ(roomExit({0.5, 0.5, 0}, {0, 0, 2}).t, 0.5);
    EXPECT_EQ(roomExit({0.5, 0.5, 0}, {-1, 0, 0.1}).face, RoomFace::Left);
    EXPECT_EQ(roomExit({0.5, 0.5, 0}, {1, 0, 0.1}).face, RoomFace::Right);
    EXPECT_EQ(roomExit({0.5, 0.5, 0}, {0, -1, 0.1}).face, RoomFace::Floor);
    EXPECT_EQ(roomExit({0.5, 0.5, 0}, {0, 1, 0.1}).face, RoomFace::Ceiling);
    const RoomHit corner = roomExit({0, 0, 0}, {1, 1, 1});
    EXPECT_EQ(corner.face, RoomFace::Right) << "ties go to x, then y, then z";
    EXPECT_EQ(corner.point, dvec3(1.0));
    // A ray from the glass's edge that heads straight out leaves at once.
    EXPECT_EQ(roomExit({0, 0.5, 0}, {-1, 0, 1}).t, 0.0);
}

TEST(RoomRay, MapsTheWorldToRoomSpace) {
    // Glass facing +Z (viewer at +Z looking -Z): right is +X, in is -Z.
    const dvec3 size(4.0, 3.0, 6.0);
    const dvec3 d = roomRay(glm::normalize(dvec3(1.0, -0.5, -2.0)), {0, 0, 1}, size);
    const dvec3 expected = dvec3(1.0, -0.5, 2.0) / glm::length(dvec3(1.0, -0.5, -2.0)) / size;
    EXPECT_NEAR(glm::length(d - expected), 0.0, 1e-15);
    // Glass facing +X: in is -X, right is cross(-X, +Y) = -Z.
    const dvec3 e = roomRay({-1.0, 0.0, -1.0}, {1, 0, 0}, dvec3(1.0));
    EXPECT_NEAR(glm::length(e - dvec3(1.0, 0.0, 1.0)), 0.0, 1e-15);
    // A world ray's exit, taken back to the world, lies on the world ray.
    const dvec3 eye(1.0, 1.7, 9.0), glassAt(1.5, 1.2, 0.0);  // glass at z = 0, room from x = 0, y = 0
    const RoomHit exit = roomExit({glassAt.x / size.x, glassAt.y / size.y, 0.0}, roomRay(glm::normalize(glassAt - eye), {0, 0, 1}, size));
    const dvec3 world(exit.point.x * size.x, exit.point.y * size.y, -exit.point.z * size.z);
    EXPECT_NEAR(glm::length(glm::cross(glm::normalize(world - eye), glm::normalize(glassAt - eye))), 0.0, 1e-12);
}

// A random point on one of the five faces.
dvec3 pointOnFace(RoomFace face, TestRng& rng) {
    const double a = rng.uniform(), b = rng.uniform();
    switch (face) {
    case RoomFace::Back: return {a, b, 1.0};
    case RoomFace::Left: return {0.0, a, b};
    case RoomFace::Right: return {1.0, a, b};
    case RoomFace::Floor: return {a, 0.0, b};
    case RoomFace::Ceiling: return {a, 1.0, b};
    }
    return {};
}
constexpr std::array<RoomFace, 5> kFaces{RoomFace::Back, RoomFace::Left, RoomFace::Right, RoomFace::Floor, RoomFace::Ceiling};

TEST(RoomTextureUv, BackWallFillsTheCentralSquareAndTheGlassEdgesThePictureEdges) {
    for (double b : {0.3, kBackWallShare, 0.7}) {
        SCOPED_TRACE(b);
        const double lo = 0.5 - 0.5 * b, hi = 0.5 + 0.5 * b;
        const std::array<std::pair<dvec3, dvec2>, 8> corners{{{{0, 0, 1}, {lo, lo}},
                                                              {{1, 0, 1}, {hi, lo}},
                                                              {{0, 1, 1}, {lo, hi}},
                                                              {{1, 1, 1}, {hi, hi}},
                                                              {{0, 0, 0}, {0, 0}},
                                                              {{1, 0, 0}, {1, 0}},
                                                              {{0, 1, 0}, {0, 1}},
                                                              {{1, 1, 0}, {1, 1}}}};
        for (const auto& [p, uv] : corners) EXPECT_NEAR(glm::length(roomTextureUv(p, b) - uv), 0.0, 1e-12);
        TestRng rng(17);
        for (int i = 0; i < 2000; ++i) {
            const dvec2 uv = roomTextureUv(pointOnFace(RoomFace::Back, rng), b);
            EXPECT_TRUE(uv.x >= lo - 1e-12 && uv.x <= hi + 1e-12 && uv.y >= lo - 1e-12 && uv.y <= hi + 1e-12);
            for (RoomFace f : {RoomFace::Left, RoomFace::Right, RoomFace::Floor, RoomFace::Ceiling}) {
                const dvec2 side = roomTextureUv(pointOnFace(f, rng), b);
                EXPECT_TRUE(side.x >= 0.0 && side.x <= 1.0 && side.y >= 0.0 && side.y <= 1.0);
                EXPECT_GE(std::max(std::abs(side.x - 0.5), std::abs(side.y - 0.5)), 0.5 * b - 1e-12)
                    << "side faces lie outside the back wall's square";
            }
        }
    }
}

TEST(RoomTextureUv, RoundTripsThroughRoomPointAtUvOnAllFiveFaces) {
    TestRng rng(23);
    for (double b : {0.3, kBackWallShare, 0.7}) {
        for (RoomFace face : kFaces) {
            for (int i = 0; i < 3000; ++i) {
                const dvec3 p = pointOnFace(face, rng);
                const RoomHit back = roomPointAtUv(roomTextureUv(p, b), b);
                ASSERT_LE(glm::length(back.point - p), 1e-9) << "face " << static_cast<int>(face) << " b " << b;
                if (facesTouched(p, 1e-9) == 1) {
                    EXPECT_EQ(back.face, face);
                }
                EXPECT_TRUE(onFace(back.face, back.point, 0.0));
            }
        }
        // And the other way: every picture point is a room point that maps back onto it.
        for (int j = 0; j <= 64; ++j) {
            for (int i = 0; i <= 64; ++i) {
                const dvec2 uv(i / 64.0, j / 64.0);
                const RoomHit hit = roomPointAtUv(uv, b);
                EXPECT_TRUE(onFace(hit.face, hit.point, 0.0));
                EXPECT_TRUE(inBox(hit.point, 0.0));
                EXPECT_LE(glm::length(roomTextureUv(hit.point, b) - uv), 1e-12);
            }
        }
    }
}

TEST(RoomTextureUv, IsAOnePointPerspectiveThroughThePictureEye) {
    TestRng rng(29);
    const double b = kBackWallShare;
    const dvec3 eye(0.5, 0.5, -b / (1.0 - b));
    auto cross2 = [](dvec2 a, dvec2 c) { return a.x * c.y - a.y * c.x; };
    for (int i = 0; i < 2000; ++i) {
        // Straight lines on the floor, a side wall, and anywhere in the room stay straight.
        const RoomFace face = i % 3 == 0 ? RoomFace::Floor : RoomFace::Left;
        dvec3 a = pointOnFace(face, rng), c = pointOnFace(face, rng);
        if (i % 3 == 2) {
            a = {rng.uniform(), rng.uniform(), rng.uniform()};
            c = {rng.uniform(), rng.uniform(), rng.uniform()};
        }
        const dvec3 m = glm::mix(a, c, 0.37);
        const dvec2 ua = roomTextureUv(a), um = roomTextureUv(m), uc = roomTextureUv(c);
        const dvec2 e1 = um - ua, e2 = uc - ua;
        EXPECT_LE(std::abs(cross2(e1, e2)), 1e-12 + 1e-9 * glm::length(e1) * glm::length(e2));
        // The picture point is where the line from the eye to the room point crosses the glass.
        const dvec3 onGlass(ua, 0.0);
        EXPECT_LE(glm::length(glm::cross(onGlass - eye, a - eye)), 1e-12 * glm::length(a - eye) + 1e-12);
    }
    // The mapping is not affine on the floor: equal steps in depth shrink in the picture.
    const double v0 = roomTextureUv({0.5, 0.0, 0.0}).y, v1 = roomTextureUv({0.5, 0.0, 0.5}).y, v2 = roomTextureUv({0.5, 0.0, 1.0}).y;
    EXPECT_GT(v1 - v0, v2 - v1);
}

TEST(MiddleLayer, HitsThePlaneOnlyAheadAndInsideTheRoom) {
    TestRng rng(31);
    int reported = 0, missed = 0;
    for (int i = 0; i < 20000; ++i) {
        const dvec3 o(rng.uniform(), rng.uniform(), 0.0);
        const dvec3 d(rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0), i % 5 == 0 ? 1e-6 : rng.uniform(0.01, 1.0));
        const double depth = rng.uniform(0.05, 0.95);
        const std::optional<dvec3> hit = middleLayerHit(o, d, depth);
        const double t = (depth - o.z) / d.z;
        const dvec3 p = o + t * d;
        const RoomHit exit = roomExit(o, d);
        const bool inside = p.x >= 0.0 && p.x <= 1.0 && p.y >= 0.0 && p.y <= 1.0;
        ASSERT_EQ(hit.has_value(), inside);
        if (hit) {
            ++reported;
            EXPECT_EQ(hit->z, depth);
            EXPECT_LE(glm::length(*hit - p), 1e-12 * std::max(1.0, t));
            EXPECT_LE(t, exit.t * (1.0 + 1e-12)) << "a reported hit is in front of the box exit";
        } else {
            ++missed;
            EXPECT_GE(t, exit.t * (1.0 - 1e-12)) << "a missed plane lies beyond the box exit";
        }
    }
    EXPECT_GT(reported, 1000);
    EXPECT_GT(missed, 1000);
    EXPECT_FALSE(middleLayerHit({0.5, 0.5, 0.0}, {0.0, 0.0, -1.0}, 0.45).has_value()) << "behind the glass";
    EXPECT_FALSE(middleLayerHit({0.5, 0.5, 0.0}, {1.0, 0.0, 0.0}, 0.45).has_value()) << "parallel to the plane";
    EXPECT_FALSE(middleLayerHit({0.5, 0.5, 0.5}, {0.0, 0.0, 1.0}, 0.45).has_value()) << "already past the plane";
}

TEST(RoomStyle, DeterministicInRangeAndSpread) {
    constexpr int kStyles = 8;
    std::array<int, kStyles> counts{};
    for (std::uint32_t building = 0; building < 100; ++building) {
        for (std::uint32_t room = 0; room < 10; ++room) {
            const int s = roomStyle(building, room, kStyles);
            ASSERT_GE(s, 0);
            ASSERT_LT(s, kStyles);
            EXPECT_EQ(s, roomStyle(building, room, kStyles));
            ++counts[static_cast<std::size_t>(s)];
        }
    }
    for (int c : counts) EXPECT_GT(c, 1000 / kStyles / 2) << "every style is used, roughly evenly";
    // Neighbouring rooms of one building do not all share a style.
    std::set<int> ofOneBuilding;
    for (std::uint32_t room = 0; room < 12; ++room) ofOneBuilding.insert(roomStyle(7, room, kStyles));
    EXPECT_GE(ofOneBuilding.size(), 4u);
    EXPECT_EQ(roomStyle(123, 4, 1), 0);
}

// The shader mirrors the C++: the same picture constant and the same hash.
TEST(InteriorShader, SharesConstantsWithTheCpuReference) {
    // From the test data folder (absolute), not __FILE__, which ccache's base_dir makes relative.
    const std::filesystem::path glsl = test::dataFile("../../runtime/shaders/interior.glsl");
    ASSERT_TRUE(std::filesystem::exists(glsl)) << glsl;
    std::ifstream in(glsl);
    std::stringstream text;
    text << in.rdbuf();
    const std::string source = text.str();
    std::ostringstream share;
    share << "const float kInteriorBackWallShare = " << kBackWallShare << ";";
    EXPECT_NE(source.find(share.str()), std::string::npos) << "interior.glsl must use runtime::kBackWallShare";
    for (const char* constant : {"0x7feb352du", "0x846ca68bu", "0x9e3779b9u", "x ^= x >> 16;", "x ^= x >> 15;"})
        EXPECT_NE(source.find(constant), std::string::npos) << constant;
}

int slotDifference(const std::vector<std::uint8_t>& image, int roomSize, int styles, int a, int c) {
    const std::size_t width = static_cast<std::size_t>(roomSize) * styles;
    long long sum = 0;
    for (int j = 0; j < roomSize; ++j)
        for (int i = 0; i < roomSize; ++i)
            for (int ch = 0; ch < 3; ++ch)
                sum += std::abs(image[(j * width + static_cast<std::size_t>(a) * roomSize + i) * 4 + ch] -
                                image[(j * width + static_cast<std::size_t>(c) * roomSize + i) * 4 + ch]);
    return static_cast<int>(sum / (roomSize * roomSize * 3));
}

TEST(GenerateInteriors, DeterministicDistinctStylesAndCutouts) {
    const InteriorTextures a = generateInteriors(64, 8), b = generateInteriors(64, 8);
    EXPECT_EQ(a.rooms, b.rooms);
    EXPECT_EQ(a.middle, b.middle);
    ASSERT_EQ(a.roomSize, 64);
    ASSERT_EQ(a.styles, 8);
    ASSERT_EQ(a.rooms.size(), std::size_t{64} * 64 * 8 * 4);
    ASSERT_EQ(a.middle.size(), a.rooms.size());
    for (std::size_t k = 3; k < a.rooms.size(); k += 4) ASSERT_EQ(a.rooms[k], 255);
    for (int s = 0; s < 8; ++s)
        for (int t = s + 1; t < 8; ++t) EXPECT_GE(slotDifference(a.rooms, 64, 8, s, t), 4) << "styles " << s << " and " << t;
    // Every style has cut-outs and clear space.
    const std::size_t width = 64 * 8;
    for (int s = 0; s < 8; ++s) {
        int clear = 0, solid = 0;
        for (std::size_t j = 0; j < 64; ++j)
            for (std::size_t i = 0; i < 64; ++i) {
                const std::uint8_t alpha = a.middle[(j * width + static_cast<std::size_t>(s) * 64 + i) * 4 + 3];
                clear += alpha == 0 ? 1 : 0;
                solid += alpha == 255 ? 1 : 0;
            }
        EXPECT_GT(clear, 64 * 64 / 2) << "style " << s;
        EXPECT_GT(solid, 64) << "style " << s;
    }
}

TEST(GenerateInteriors, TheLampIsWhereThePerspectivePutsIt) {
    constexpr int kSize = 128, kStyles = 3;
    const InteriorTextures tex = generateInteriors(kSize, kStyles);
    const std::size_t width = static_cast<std::size_t>(kSize) * kStyles;
    auto texel = [&](int s, dvec3 roomPoint) {
        const dvec2 uv = roomTextureUv(roomPoint);
        const std::size_t i = static_cast<std::size_t>(uv.x * kSize), j = static_cast<std::size_t>(uv.y * kSize);
        const std::uint8_t* p = &tex.rooms[(j * width + static_cast<std::size_t>(s) * kSize + i) * 4];
        return std::min({p[0], p[1], p[2]});
    };
    for (int s = 0; s < kStyles; ++s) {
        // The lamp is a warm white disc (its darkest channel, blue, encodes to ~223).
        EXPECT_GE(texel(s, {0.5, 1.0, 0.5}), 215) << "the lamp in the ceiling's middle is bright";
        EXPECT_LT(texel(s, {0.1, 1.0, 0.9}) + 40, texel(s, {0.5, 1.0, 0.5})) << "the ceiling's corner is not";
        EXPECT_LT(texel(s, {0.5, 1.0, 0.15}) + 40, texel(s, {0.5, 1.0, 0.5})) << "nor the ceiling by the glass";
    }
}

TEST(GenerateInteriors, DefaultLayout) {
    const InteriorTextures tex = generateInteriors();
    EXPECT_EQ(tex.roomSize, 256);
    EXPECT_EQ(tex.styles, 8);
    EXPECT_EQ(tex.rooms.size(), std::size_t{256} * 256 * 8 * 4);
    bool anyClear = false, anySolid = false;
    for (std::size_t k = 3; k < tex.middle.size(); k += 4) {
        anyClear = anyClear || tex.middle[k] == 0;
        anySolid = anySolid || tex.middle[k] == 255;
    }
    EXPECT_TRUE(anyClear);
    EXPECT_TRUE(anySolid);
}

}  // namespace
}  // namespace dawnforge::runtime
