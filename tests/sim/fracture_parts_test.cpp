// Fracture of an assembly of touching parts, each broken by its material (fracture_parts.hpp):
// a slab, a brick wall standing on it, a glass pane and a wooden door against the wall.
#include "test_support.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/materials.hpp>
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/core/validate.hpp>
#include <dawnforge/sim/fracture_io.hpp>
#include <dawnforge/sim/fracture_parts.hpp>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <set>

using namespace dawnforge;
using namespace dawnforge::sim;

namespace {

// Part indices: 0 slab, 1 wall (on the slab), 2 pane and 3 door (against the wall's front).
std::vector<FracturePart> smallAssembly() {
    return {
        {"slab", kConcrete, makeBox({0, 0, 0}, {4, 0.2f, 2}, kFloor)},
        {"wall", kBrick, makeBox({0, 0.2f, 0}, {4, 3, 0.25f}, kBrick)},
        {"window", kGlass, makeBox({0.5f, 1, 0.25f}, {1.5f, 2, 0.27f}, kGlass)},
        {"door", kWood, makeBox({2.5f, 0.2f, 0.25f}, {3.4f, 2.2f, 0.3f}, kWood)},
    };
}

PartsFractureSettings smallSettings() {
    PartsFractureSettings s;
    s.common.pieces = 12;
    s.shardSize = 0.3;
    s.splinterWidth = 0.15;
    s.splinterLength = 0.9;
    return s;
}

bool bonded(const FractureResult& r, std::int32_t partA, std::int32_t partB) {
    for (const Bond& b : r.bonds) {
        const std::int32_t pa = r.pieces[b.a].part, pb = r.pieces[b.b].part;
        if ((pa == partA && pb == partB) || (pa == partB && pb == partA)) return true;
    }
    return false;
}

}  // namespace

TEST(FractureParts, PiecesAreClosedAndAddUpToEachPart) {
    const std::vector<FracturePart> parts = smallAssembly();
    const FractureResult r = fractureParts(parts, smallSettings());
    ASSERT_EQ(r.parts.size(), parts.size());
    std::vector<double> volume(parts.size(), 0.0);
    for (const FracturePiece& p : r.pieces) {
        const MeshReport report = inspectMesh(p.mesh);
        EXPECT_TRUE(report.closed && report.manifold) << p.name;
        EXPECT_EQ(report.degenerateTriangles, 0u) << p.name;
        ASSERT_GE(p.part, 0);
        EXPECT_EQ(p.material, parts[std::size_t(p.part)].material) << p.name;
        volume[std::size_t(p.part)] += p.mass.volume;
    }
    for (std::size_t i = 0; i < parts.size(); ++i) {
        EXPECT_NEAR(volume[i], r.parts[i].volume, 1e-6 * r.parts[i].volume) << parts[i].kind;
        EXPECT_GT(r.parts[i].pieces, 1u) << parts[i].kind;
    }
    EXPECT_EQ(r.parts[2].style, BreakStyle::Shards);
    EXPECT_EQ(r.parts[3].style, BreakStyle::Splinters);
    EXPECT_GE(r.parts[2].pieces, 8u);  // a 1 m² pane in 0.3 m shards
}

TEST(FractureParts, GlassShardsDrawNoWindowAndCutFacesAreRubble) {
    const FractureResult r = fractureParts(smallAssembly(), smallSettings());
    std::set<int> glassSurface;
    for (const FracturePiece& p : r.pieces) {
        EXPECT_TRUE(p.mesh.uv1.empty() && p.mesh.uv2.empty()) << p.name << ": no interior-mapping attributes";
        for (std::uint8_t m : p.mesh.materialIds)
            if (p.part == 2) glassSurface.insert(m);
    }
    EXPECT_EQ(glassSurface, (std::set<int>{kGlass, kRubble}));
}

TEST(FractureParts, SplintersRunAlongTheGrain) {
    const FractureResult r = fractureParts(smallAssembly(), smallSettings());
    int along = 0, across = 0;
    for (const FracturePiece& p : r.pieces) {
        if (p.part != 3) continue;
        const Bounds b = computeBounds(p.mesh.positions);
        const glm::dvec3 size = b.max - b.min;
        (size.y > size.x ? along : across) += 1;
    }
    EXPECT_GT(along, 3 * across) << "door splinters should be longer up the grain (+Y) than across";
}

TEST(FractureParts, EveryPairOfTouchingPartsIsBondedAndGlassIsWeakest) {
    const FractureResult r = fractureParts(smallAssembly(), smallSettings());
    EXPECT_TRUE(bonded(r, 0, 1)) << "wall on slab";
    EXPECT_TRUE(bonded(r, 1, 2)) << "pane against the wall";
    EXPECT_TRUE(bonded(r, 1, 3)) << "door against the wall";
    EXPECT_TRUE(bonded(r, 0, 3)) << "door on the slab";
    EXPECT_FALSE(bonded(r, 2, 3)) << "pane and door do not touch";
    double glass = 1e300, concrete = 0.0;
    for (const Bond& b : r.bonds) {
        const std::int32_t pa = r.pieces[b.a].part, pb = r.pieces[b.b].part;
        EXPECT_GT(b.strength, 0.0);
        if (pa == 2 || pb == 2) glass = std::min(glass, b.strength);
        if (pa == 0 && pb == 0) concrete = std::max(concrete, b.strength);
    }
    EXPECT_LT(glass, concrete);
}

TEST(FractureParts, SameBytesOnOneAndTwoThreads) {
    std::string files[2];
    for (int threads : {1, 2}) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        const FractureResult r = fractureParts(smallAssembly(), smallSettings());
        files[threads - 1] = fractureJson(r, smallSettings().common, "assembly", 0);
    }
    EXPECT_EQ(files[0], files[1]);
}

TEST(FractureParts, BadPartsAreNamed) {
    std::vector<FracturePart> parts = smallAssembly();
    parts[2].mesh.indices.resize(parts[2].mesh.indices.size() - 3);  // an open pane
    EXPECT_NE(test::inputErrorOf([&] { fractureParts(parts, smallSettings()); }).find("part 2 (window)"), std::string::npos);
    EXPECT_NE(test::inputErrorOf([] { fractureParts({}, PartsFractureSettings()); }).find("no parts"), std::string::npos);
}
