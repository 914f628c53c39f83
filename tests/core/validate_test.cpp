#include "test_support.hpp"

#include <dawnforge/core/import.hpp>
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/core/validate.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace dawnforge;

namespace {

Mesh boxWithCavity() {
    Mesh m = makeBox({-1, -1, -1}, {1, 1, 1});
    Mesh cavity = makeBox({-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f});
    flipOrientation(cavity);  // the cavity's faces point into the hole
    appendMesh(m, cavity);
    return m;
}

// Two cubes meeting at a single corner: closed, but the shared vertex is a pinch.
Mesh cubesTouchingAtACorner() {
    Mesh m = makeBox({0, 0, 0}, {1, 1, 1});
    appendMesh(m, makeBox({1, 1, 1}, {2, 2, 2}));
    return m;
}

}  // namespace

TEST(Inspect, UnitIcosahedronMatchesTheAnalyticVolume) {
    const Mesh ico = makeIcosphere(1.0f, 0);
    const MeshReport r = inspectMesh(ico);
    // Regular icosahedron with circumradius 1: edge a = 4 / sqrt(10 + 2 sqrt 5), V = 5/12 (3 + sqrt 5) a^3.
    const double a = 4.0 / std::sqrt(10.0 + 2.0 * std::sqrt(5.0));
    const double expected = 5.0 / 12.0 * (3.0 + std::sqrt(5.0)) * a * a * a;
    ASSERT_TRUE(r.volume.has_value());
    EXPECT_NEAR(*r.volume / expected, 1.0, 1e-6);
    EXPECT_EQ(r.triangles, 20u);
    EXPECT_EQ(r.vertices, 12u);
    EXPECT_TRUE(r.closed);
    EXPECT_TRUE(r.manifold);
    EXPECT_TRUE(r.consistentlyOriented);
    EXPECT_TRUE(r.outwardOriented);
    EXPECT_FALSE(r.selfIntersecting);
    EXPECT_EQ(r.components, 1u);
}

TEST(Inspect, SubdividedSphereMatchesAnIndependentVolume) {
    const Mesh sphere = makeIcosphere(1.0f, 4);  // 5,120 triangles
    const MeshReport r = inspectMesh(sphere);
    ASSERT_TRUE(r.volume.has_value());
    EXPECT_NEAR(*r.volume / test::referenceVolume(sphere), 1.0, 1e-6);
    EXPECT_LT(*r.volume, 4.0 / 3.0 * std::numbers::pi);
    EXPECT_GT(*r.volume, 0.99 * 4.0 / 3.0 * std::numbers::pi);
    EXPECT_NEAR(r.bounds.max.y, 1.0, 1e-6);
    EXPECT_EQ(r.triangles, 5120u);
    EXPECT_EQ(r.vertices, 2562u);  // Euler: V = F/2 + 2
}

TEST(Inspect, BoxWithCavityIsOuterMinusInner) {
    const MeshReport r = inspectMesh(boxWithCavity());
    ASSERT_TRUE(r.volume.has_value());
    EXPECT_NEAR(*r.volume, 8.0 - 1.0, 1e-9);
    EXPECT_TRUE(r.closed);
    EXPECT_TRUE(r.manifold);
    EXPECT_TRUE(r.outwardOriented);
    EXPECT_FALSE(r.selfIntersecting);
    EXPECT_EQ(r.components, 2u);
    EXPECT_EQ(r.vertices, 16u);  // welded: 24-vertex boxes share their corners
}

TEST(Inspect, OpenMeshIsReportedNotRejected) {
    const MeshReport r = inspectMesh(loadMesh(test::dataFile("open_box.obj")));
    EXPECT_FALSE(r.closed);
    EXPECT_TRUE(r.manifold);
    EXPECT_EQ(r.boundaryEdges, 4u);
    EXPECT_FALSE(r.volume.has_value());
}

TEST(Inspect, EdgeSharedByThreeTrianglesIsNonManifold) {
    const MeshReport r = inspectMesh(loadMesh(test::dataFile("fin.obj")));
    EXPECT_FALSE(r.manifold);
    EXPECT_EQ(r.nonManifoldEdges, 1u);
    EXPECT_FALSE(r.closed);
    EXPECT_FALSE(r.volume.has_value());
}

TEST(Inspect, PinchedVertexIsNonManifold) {
    const MeshReport r = inspectMesh(cubesTouchingAtACorner());
    EXPECT_EQ(r.nonManifoldEdges, 0u);
    EXPECT_EQ(r.nonManifoldVertices, 1u);
    EXPECT_FALSE(r.manifold);
    EXPECT_EQ(r.boundaryEdges, 0u);
}

TEST(Inspect, OverlappingBoxesSelfIntersect) {
    Mesh m = makeBox({0, 0, 0}, {1, 1, 1});
    appendMesh(m, makeBox({0.5f, 0.5f, 0.5f}, {1.5f, 1.5f, 1.5f}));
    const MeshReport r = inspectMesh(m);
    EXPECT_TRUE(r.selfIntersecting);
    EXPECT_TRUE(r.closed);
    EXPECT_FALSE(inspectMesh(makeBox({0, 0, 0}, {1, 1, 1})).selfIntersecting);
}

TEST(Inspect, OneFlippedTriangleBreaksOrientation) {
    Mesh m = makeBox({0, 0, 0}, {1, 1, 1});
    std::swap(m.indices[1], m.indices[2]);
    const MeshReport r = inspectMesh(m);
    EXPECT_FALSE(r.consistentlyOriented);
    EXPECT_TRUE(r.closed);
    EXPECT_FALSE(r.volume.has_value());
}

TEST(Inspect, DegenerateTrianglesAreCounted) {
    Mesh m = makeBox({0, 0, 0}, {1, 1, 1});
    m.positions.push_back({5, 5, 5});
    m.positions.push_back({6, 6, 6});
    m.positions.push_back({7, 7, 7});
    m.indices.insert(m.indices.end(), {24, 25, 26, 0, 0, 1});  // collinear, repeated corner
    EXPECT_EQ(inspectMesh(m).degenerateTriangles, 2u);
}

TEST(Inspect, TowerPrimitiveIsClosed) {
    const MeshReport r = inspectMesh(makeTower(7, 3.0f, 10.0f, 8.0f));
    EXPECT_TRUE(r.closed);
    EXPECT_TRUE(r.manifold);
    EXPECT_TRUE(r.outwardOriented);
    ASSERT_TRUE(r.volume.has_value());
    EXPECT_NEAR(*r.volume, 7 * 3.0 * 10.0 * 8.0, 1e-3);
}

TEST(Repair, FillsAHole) {
    RepairReport report;
    const Mesh fixed = repairMesh(loadMesh(test::dataFile("open_box.obj")), &report);
    const MeshReport r = inspectMesh(fixed);
    EXPECT_TRUE(report.closed);
    EXPECT_TRUE(r.closed);
    EXPECT_TRUE(r.manifold);
    ASSERT_TRUE(r.volume.has_value());
    EXPECT_NEAR(*r.volume, 1.0, 1e-9);
    EXPECT_FALSE(report.actions.empty());
}

TEST(Repair, FixesOrientationAndTurnsInsideOutMeshesOutward) {
    Mesh m = makeBox({0, 0, 0}, {2, 1, 1});
    flipOrientation(m);
    std::swap(m.indices[1], m.indices[2]);  // and one triangle inconsistent with the rest
    m.normals.clear();
    RepairReport report;
    const MeshReport r = inspectMesh(repairMesh(m, &report));
    EXPECT_TRUE(r.consistentlyOriented);
    EXPECT_TRUE(r.outwardOriented);
    ASSERT_TRUE(r.volume.has_value());
    EXPECT_NEAR(*r.volume, 2.0, 1e-9);
}
