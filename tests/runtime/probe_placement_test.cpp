// Probe placement and cache: the seed's presets, probes near geometry but never inside a box,
// on the world lattice, nearest first, none in empty space, and a cache that keeps what the
// camera comes back to.
#include <dawnforge/runtime/probe_placement.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <set>

namespace dawnforge::runtime {
namespace {

// A street: a 100 m ground slab (10 cm thick, top at 0; solid under it) and a house turned 30°.
std::vector<ProbeBox> street() {
    ProbeBox ground;
    ground.centre = {0.0, -0.05, 0.0};
    ground.halfSize = {50.0, 0.05, 50.0};
    ground.ground = true;
    ProbeBox house;
    const double a = std::acos(-1.0) / 6.0;
    house.centre = {5.0, 6.0, 3.0};
    house.u = {std::cos(a), 0.0, -std::sin(a)};
    house.w = {std::sin(a), 0.0, std::cos(a)};
    house.halfSize = {4.0, 6.0, 3.0};
    return {ground, house};
}

// The test's own containment: p in the box's frame, against its half sizes.
bool inBox(const ProbeBox& b, glm::dvec3 p) {
    const glm::dvec3 d = p - b.centre;
    const bool level = b.ground ? d.y < b.halfSize.y : std::abs(d.y) < b.halfSize.y;  // under the ground is inside it
    return std::abs(d.x * b.u.x + d.z * b.u.z) < b.halfSize.x && level && std::abs(d.x * b.w.x + d.z * b.w.z) < b.halfSize.z;
}

TEST(ProbePlacement, PresetsAreTheSeedsTable) {
    const ProbePreset low = *probePreset("low"), mid = *probePreset("mid"), high = *probePreset("high");
    EXPECT_EQ(low.basis, ProbeBasis::AmbientCube);
    EXPECT_EQ(low.probesPerSecond, 150.0);
    EXPECT_EQ(low.cacheTexels, 256);
    EXPECT_EQ(low.spacing, 4.0);
    EXPECT_EQ(mid.probesPerSecond, 300.0);
    EXPECT_EQ(mid.cacheTexels, 512);
    EXPECT_EQ(mid.spacing, 2.0);
    EXPECT_EQ(high.basis, ProbeBasis::Sh);
    EXPECT_EQ(high.probesPerSecond, 600.0);
    EXPECT_EQ(high.spacing, 1.0);
    EXPECT_EQ(mid.cacheProbes(), 102 * 102);
    for (const char* bad : {"off", "ultra", "", "MID"}) EXPECT_FALSE(probePreset(bad)) << bad;
}

TEST(ProbePlacement, KeysRoundTrip) {
    for (glm::ivec3 l : {glm::ivec3(0), glm::ivec3(-1, 2, -3), glm::ivec3(1048575, -1048576, 12345)})
        EXPECT_EQ(probeLattice(probeKey(l)), l);
    EXPECT_NE(probeKey({1, 0, 0}), probeKey({0, 1, 0}));
}

TEST(ProbePlacement, NearGeometryNeverInsideABoxNearestFirst) {
    const std::vector<ProbeBox> boxes = street();
    const ProbeField field(boxes);
    const glm::dvec3 camera(4.0, 1.7, 6.0), half(7.5, 4.0, 7.5);
    for (double spacing : {1.0, 2.0, 4.0}) {
        const std::vector<PlacedProbe> probes = field.place(camera, half, spacing);
        ASSERT_GT(probes.size(), spacing > 2.0 ? 5u : 20u) << spacing;
        std::set<ProbeKey> keys;
        double last = 0.0;
        for (const PlacedProbe& p : probes) {
            for (const ProbeBox& b : boxes) EXPECT_FALSE(inBox(b, p.position)) << "inside a box at spacing " << spacing;
            const glm::dvec3 lattice = p.position / spacing - 0.5;
            EXPECT_LT(glm::length(lattice - glm::round(lattice)), 1e-9) << "off the lattice";
            EXPECT_EQ(glm::dvec3(probeLattice(p.key)), glm::round(lattice));
            EXPECT_TRUE(glm::all(glm::lessThanEqual(glm::abs(p.position - camera), half)));
            const double d = glm::length(p.position - camera);
            EXPECT_GE(d, last - 1e-12);
            last = d;
            EXPECT_TRUE(keys.insert(p.key).second);
        }
    }
}

TEST(ProbePlacement, OpenGroundGetsOneLayerAndEmptySpaceNone) {
    const ProbeField field(street());
    // 30 m from the house: the layer 1 m over the ground, 8 x 8 probes at 2 m.
    const std::vector<PlacedProbe> open = field.place({-30.0, 1.7, -30.0}, {7.5, 4.0, 7.5}, 2.0);
    EXPECT_EQ(open.size(), 64u);
    for (const PlacedProbe& p : open) EXPECT_DOUBLE_EQ(p.position.y, 1.0);
    EXPECT_TRUE(field.place({0.0, 100.0, 0.0}, {7.5, 4.0, 7.5}, 2.0).empty()) << "high in the air";
    EXPECT_TRUE(field.place({500.0, 1.0, 0.0}, {7.5, 4.0, 7.5}, 2.0).empty()) << "beyond the ground";
}

TEST(ProbePlacement, TheCacheKeepsWhatTheCameraComesBackTo) {
    const ProbeField field(street());
    const glm::dvec3 home(-30.0, 1.7, -30.0), away(30.0, 1.7, 30.0), half(7.5, 4.0, 7.5);
    ProbeCache cache(100);
    const std::vector<PlacedProbe> here = field.place(home, half, 2.0);
    ASSERT_EQ(here.size(), 64u);
    // The frame's budget: 30 probes, nearest first.
    const std::vector<PlacedProbe> first = cache.admit(here, home, 30);
    ASSERT_EQ(first.size(), 30u);
    EXPECT_EQ(first.front().key, here.front().key);
    EXPECT_EQ(cache.admit(here, home, 100).size(), 34u);
    EXPECT_TRUE(cache.admit(here, home, 100).empty()) << "nothing new to capture";
    // Away: 64 more need room; the farthest of home's go.
    const std::vector<PlacedProbe> there = field.place(away, half, 2.0);
    EXPECT_EQ(cache.admit(there, away, 1000).size(), there.size());
    EXPECT_EQ(cache.size(), 100u);
    std::size_t kept = 0;
    for (const PlacedProbe& p : here) kept += cache.holds(p.key);
    EXPECT_EQ(kept, 36u);
    // Back home: only the 28 dropped are captured again.
    EXPECT_EQ(cache.admit(here, home, 1000).size(), 28u);
}

}  // namespace
}  // namespace dawnforge::runtime
