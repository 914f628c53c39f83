// Roofs are closed, outward solids over their footprint, with the volumes of their
// textbook shapes.
#include <dawnforge/procgen/roof.hpp>

#include <dawnforge/core/validate.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace dawnforge::procgen {
namespace {

// w x l rectangle: edge 0 runs along l, edge 1 along w.
Polygon2 rectangle(double l, double w, glm::dvec2 at = glm::dvec2(0.0)) {
    return {at, at + glm::dvec2(l, 0), at + glm::dvec2(l, w), at + glm::dvec2(0, w)};
}
const Polygon2 kTrapezoid{{0, 0}, {20, 0}, {16, 10}, {4, 10}};  // ends slanted 22 degrees
const Polygon2 kParallelogram{{0, 0}, {20, 0}, {24, 10}, {4, 10}};
const Polygon2 kSkewedQuad{{0, 0}, {18, -2}, {21, 9}, {2, 12}};
const Polygon2 kPentagon{{0, 0}, {12, 0}, {14, 7}, {6, 12}, {-2, 7}};
const Polygon2 kLShape{{0, 0}, {20, 0}, {20, 8}, {8, 8}, {8, 18}, {0, 18}};
const Polygon2 kUShape{{0, 0}, {24, 0}, {24, 16}, {16, 16}, {16, 6}, {8, 6}, {8, 16}, {0, 16}};

// A 20-vertex footprint: a circle with a wobble (convex) or a star-like outline.
Polygon2 twentyGon(bool convex) {
    Polygon2 out;
    for (int i = 0; i < 20; ++i) {
        const double a = 2.0 * std::numbers::pi * i / 20.0;
        const double r = convex ? 10.0 + 0.3 * std::cos(3.0 * a) : (i % 2 == 0 ? 10.0 : 6.5);
        out.push_back({r * std::cos(a), r * std::sin(a)});
    }
    return out;
}

RoofSettings settingsFor(RoofType type, std::size_t frontEdge = 0) {
    RoofSettings s;
    s.type = type;
    s.frontEdge = frontEdge;
    return s;
}

std::string describe(const RoofSettings& s) {
    return std::string(roofTypeName(s.type)) + " roof, front edge " + std::to_string(s.frontEdge);
}

// The properties every roof has; returns the inspection for further checks.
MeshReport checkRoof(const Roof& roof, std::span<const glm::dvec2> footprint, double baseHeight,
                     const RoofSettings& s) {
    SCOPED_TRACE(describe(s));
    const Mesh& mesh = roof.mesh;
    EXPECT_NO_THROW(validateMeshData(mesh, "roof"));
    EXPECT_EQ(mesh.normals.size(), mesh.positions.size());
    EXPECT_EQ(mesh.uv0.size(), mesh.positions.size());
    EXPECT_EQ(mesh.materialIds.size(), mesh.positions.size());
    const MeshReport report = inspectMesh(mesh);
    EXPECT_TRUE(report.closed);
    EXPECT_TRUE(report.manifold);
    EXPECT_TRUE(report.consistentlyOriented);
    EXPECT_TRUE(report.outwardOriented);
    EXPECT_FALSE(report.selfIntersecting);
    EXPECT_EQ(report.degenerateTriangles, 0u);
    EXPECT_EQ(report.components, 1u);
    EXPECT_TRUE(report.volume && *report.volume > 0.0);

    glm::dvec2 lo(INFINITY), hi(-INFINITY);
    for (glm::dvec2 p : footprint) lo = glm::min(lo, p), hi = glm::max(hi, p);
    const double slack = 1e-6 * std::max({1.0, std::abs(lo.x), std::abs(lo.y), std::abs(hi.x), std::abs(hi.y)});
    double top = -INFINITY;
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        const glm::vec3 p = mesh.positions[i];
        EXPECT_GE(p.x, lo.x - slack);
        EXPECT_LE(p.x, hi.x + slack);
        EXPECT_GE(-p.z, lo.y - slack);
        EXPECT_LE(-p.z, hi.y + slack);
        EXPECT_GE(p.y, baseHeight - 1e-5);
        top = std::max(top, static_cast<double>(p.y));
        const std::uint8_t m = mesh.materialIds[i];
        EXPECT_TRUE(m == s.roofMaterial || m == s.flatMaterial || m == s.wallMaterial || m == s.trimMaterial);
        EXPECT_TRUE(std::isfinite(mesh.uv0[i].x) && std::isfinite(mesh.uv0[i].y));
        EXPECT_NEAR(glm::length(mesh.normals[i]), 1.0f, 1e-5f);
        if (s.type != RoofType::Flat && m == s.roofMaterial) {
            EXPECT_GT(mesh.normals[i].y, 0.0f);
        }
    }
    EXPECT_NEAR(top, baseHeight + roof.height, 1e-5 * std::max(1.0, std::abs(baseHeight) + roof.height));

    const Roof again = buildRoof(footprint, baseHeight, s);
    EXPECT_EQ(again.height, roof.height);
    EXPECT_TRUE(again.mesh.positions == mesh.positions && again.mesh.indices == mesh.indices &&
                again.mesh.normals == mesh.normals && again.mesh.uv0 == mesh.uv0 &&
                again.mesh.materialIds == mesh.materialIds);
    return report;
}

void expectVolume(const MeshReport& report, double expected) {
    ASSERT_TRUE(report.volume);
    EXPECT_NEAR(*report.volume, expected, 1e-6 * expected);
}

// The largest offset at which the footprint's inset is not empty (the hip's top time).
void expectTopTime(std::span<const glm::dvec2> footprint, double time) {
    EXPECT_FALSE(insetPolygon(footprint, time * (1.0 - 1e-3)).empty());
    EXPECT_TRUE(insetPolygon(footprint, time * (1.0 + 1e-3)).empty());
}

bool hasMaterial(const Mesh& mesh, std::uint8_t id) {
    return std::find(mesh.materialIds.begin(), mesh.materialIds.end(), id) != mesh.materialIds.end();
}

// Gable ends and shed sides: vertical faces of the wall material (the bottom face, hidden
// on the building, also takes the wall material but faces down).
bool hasVerticalWall(const Mesh& mesh, std::uint8_t wall) {
    for (std::size_t i = 0; i < mesh.positions.size(); ++i)
        if (mesh.materialIds[i] == wall && std::abs(mesh.normals[i].y) < 1e-6f) return true;
    return false;
}

TEST(Roof, TypeNames) {
    EXPECT_STREQ(roofTypeName(RoofType::Flat), "flat");
    EXPECT_STREQ(roofTypeName(RoofType::Hip), "hip");
    EXPECT_STREQ(roofTypeName(RoofType::Gable), "gable");
    EXPECT_STREQ(roofTypeName(RoofType::Shed), "shed");
}

TEST(Roof, EveryTypeIsAClosedSolidOnEveryFootprint) {
    const std::vector<Polygon2> convex{rectangle(20, 10), rectangle(10, 10), kTrapezoid, kParallelogram,
                                       kSkewedQuad, kPentagon, twentyGon(true)};
    const std::vector<Polygon2> nonConvex{kLShape, kUShape, twentyGon(false)};
    for (RoofType type : {RoofType::Flat, RoofType::Hip, RoofType::Gable, RoofType::Shed}) {
        for (const std::vector<Polygon2>* set : {&convex, &nonConvex})
            for (std::size_t f = 0; f < set->size(); ++f) {
                const Polygon2& footprint = (*set)[f];
                // Flat and hip roofs ignore the front edge.
                const bool fronted = type == RoofType::Gable || type == RoofType::Shed;
                const std::size_t step = !fronted ? footprint.size() : footprint.size() > 6 ? 7 : 1;
                for (std::size_t front = 0; front < footprint.size(); front += step) {
                    SCOPED_TRACE("footprint " + std::to_string(f) + (set == &convex ? " (convex)" : " (non-convex)"));
                    const RoofSettings s = settingsFor(type, front);
                    const Roof roof = buildRoof(footprint, 6.0, s);
                    checkRoof(roof, footprint, 6.0, s);
                    if (type == RoofType::Hip) expectTopTime(footprint, roof.height / s.pitch);
                    // Convex footprints with gable ends (edges across the front) get them.
                    if (type == RoofType::Gable && set == &convex) {
                        const std::size_t n = footprint.size();
                        const glm::dvec2 frontDir = glm::normalize(footprint[(front + 1) % n] - footprint[front]);
                        bool ends = false;
                        for (std::size_t i = 0; i < n; ++i)
                            ends |= std::abs(glm::dot(glm::normalize(footprint[(i + 1) % n] - footprint[i]), frontDir)) < 0.5;
                        EXPECT_EQ(hasVerticalWall(roof.mesh, s.wallMaterial), ends);
                    }
                }
            }
    }
}

TEST(Roof, HipHasThePyramidalVolume) {
    const double p = 0.6;
    for (auto [l, w] : {std::pair{20.0, 10.0}, std::pair{10.0, 10.0}, std::pair{31.0, 7.5}}) {
        const Polygon2 footprint = rectangle(l, w);
        const RoofSettings s = settingsFor(RoofType::Hip);
        const Roof roof = buildRoof(footprint, 0.0, s);
        expectVolume(checkRoof(roof, footprint, 0.0, s), p * w * w * (3 * l - w) / 12.0);
        EXPECT_NEAR(roof.height, p * w / 2.0, 1e-9);
        EXPECT_FALSE(hasVerticalWall(roof.mesh, s.wallMaterial));
    }
}

TEST(Roof, GableRidgeRunsAlongTheFrontEdge) {
    const double p = 0.6;
    // Rectangle 20 x 10: front edge long (ridge along 20) or short (ridge along 10), square.
    struct Case {
        Polygon2 footprint;
        std::size_t front;
        double run, ridge;  // slope run (half the span) and ridge length
    };
    for (const Case& c : {Case{rectangle(20, 10), 0, 5, 20}, Case{rectangle(20, 10), 1, 10, 10},
                          Case{rectangle(20, 10), 2, 5, 20}, Case{rectangle(10, 10), 0, 5, 10},
                          Case{rectangle(10, 10), 3, 5, 10}}) {
        const RoofSettings s = settingsFor(RoofType::Gable, c.front);
        const Roof roof = buildRoof(c.footprint, 0.0, s);
        const MeshReport report = checkRoof(roof, c.footprint, 0.0, s);
        // V = p * w^2 * l / 4 with w the span (2 * run) and l the ridge.
        expectVolume(report, p * 4 * c.run * c.run * c.ridge / 4.0);
        EXPECT_NEAR(roof.height, p * c.run, 1e-9);
        EXPECT_TRUE(hasVerticalWall(roof.mesh, s.wallMaterial));
        // The ridge: the top vertices run parallel to the front edge.
        const glm::dvec2 front = c.footprint[(c.front + 1) % 4] - c.footprint[c.front];
        glm::dvec2 first(NAN), last(NAN);
        for (glm::vec3 q : roof.mesh.positions)
            if (std::abs(q.y - roof.height) < 1e-5) {
                const glm::dvec2 plan(q.x, -q.z);
                if (std::isnan(first.x)) first = plan;
                last = plan;
                EXPECT_NEAR(std::abs(glm::dot(glm::normalize(front), plan - first)), glm::distance(plan, first), 1e-5);
            }
        EXPECT_NEAR(glm::distance(first, last), c.ridge, 1e-5);
    }
    // Trapezoid with slanted gable ends: the integral of p * min(y, 10 - y) over it.
    const RoofSettings s = settingsFor(RoofType::Gable, 0);
    const Roof roof = buildRoof(kTrapezoid, 0.0, s);
    expectVolume(checkRoof(roof, kTrapezoid, 0.0, s), 0.6 * 400.0);
    EXPECT_NEAR(roof.height, 3.0, 1e-9);
}

TEST(Roof, GableFallsBackToHipOnNonConvexFootprints) {
    const RoofSettings gable = settingsFor(RoofType::Gable, 0), hip = settingsFor(RoofType::Hip, 0);
    const Roof a = buildRoof(kLShape, 0.0, gable), b = buildRoof(kLShape, 0.0, hip);
    EXPECT_TRUE(a.mesh.positions == b.mesh.positions);
    EXPECT_EQ(a.height, b.height);
}

TEST(Roof, ShedRisesToTheFrontEdge) {
    const double p = 0.6;
    for (auto [front, w, l] : {std::tuple{std::size_t{0}, 10.0, 20.0}, std::tuple{std::size_t{1}, 20.0, 10.0},
                               std::tuple{std::size_t{3}, 20.0, 10.0}}) {
        const Polygon2 footprint = rectangle(20, 10);
        const RoofSettings s = settingsFor(RoofType::Shed, front);
        const Roof roof = buildRoof(footprint, 0.0, s);
        // V = p * w^2 * l / 2 with w the run across the slope.
        expectVolume(checkRoof(roof, footprint, 0.0, s), p * w * w * l / 2.0);
        EXPECT_NEAR(roof.height, p * w, 1e-9);
        // The front edge carries the top.
        const glm::dvec2 a = footprint[front], b = footprint[(front + 1) % 4];
        for (glm::vec3 q : roof.mesh.positions) {
            const glm::dvec2 plan(q.x, -q.z);
            if (glm::length(plan - a) < 1e-6 || glm::length(plan - b) < 1e-6) {
                EXPECT_TRUE(q.y < 1e-6 || std::abs(q.y - roof.height) < 1e-5);
            }
        }
    }
    const RoofSettings s = settingsFor(RoofType::Shed, 0);
    const Roof roof = buildRoof(kTrapezoid, 0.0, s);
    expectVolume(checkRoof(roof, kTrapezoid, 0.0, s), 0.6 * 2600.0 / 3.0);
}

TEST(Roof, FlatHasAParapetRing) {
    const RoofSettings s = settingsFor(RoofType::Flat);
    const double height = s.slabThickness + s.parapetHeight;
    {
        const Polygon2 footprint = rectangle(20, 10);
        const Roof roof = buildRoof(footprint, 0.0, s);
        const double d = s.parapetWidth;
        expectVolume(checkRoof(roof, footprint, 0.0, s), 200.0 * height - (20 - 2 * d) * (10 - 2 * d) * s.parapetHeight);
        EXPECT_DOUBLE_EQ(roof.height, height);
        EXPECT_TRUE(hasMaterial(roof.mesh, s.trimMaterial));
        EXPECT_TRUE(hasMaterial(roof.mesh, s.flatMaterial));
    }
    for (const Polygon2& footprint : {kPentagon, kSkewedQuad, kLShape, kUShape}) {
        const Roof roof = buildRoof(footprint, 0.0, s);
        const double inner = signedArea(insetPolygon(footprint, s.parapetWidth));
        expectVolume(checkRoof(roof, footprint, 0.0, s), signedArea(footprint) * height - inner * s.parapetHeight);
        EXPECT_TRUE(hasMaterial(roof.mesh, s.trimMaterial));
    }
}

TEST(Roof, FlatWithoutAMatchingInsetIsASlab) {
    // The 0.14 m chamfer vanishes in the 0.5 m inset: no per-edge ring, a plain slab.
    const Polygon2 chamfered{{0, 0}, {10, 0}, {10, 9.9}, {9.9, 10}, {0, 10}};
    RoofSettings s = settingsFor(RoofType::Flat);
    s.parapetWidth = 0.5;
    for (double width : {0.5, 0.0}) {
        s.parapetWidth = width;
        const Roof roof = buildRoof(chamfered, 0.0, s);
        expectVolume(checkRoof(roof, chamfered, 0.0, s), signedArea(chamfered) * s.slabThickness);
        EXPECT_DOUBLE_EQ(roof.height, s.slabThickness);
        EXPECT_FALSE(hasMaterial(roof.mesh, s.trimMaterial));
    }
}

TEST(Roof, FarFromTheOriginStaysClosed) {
    const Polygon2 footprint = rectangle(20, 10, {4000.0, -2500.0});
    for (RoofType type : {RoofType::Flat, RoofType::Hip, RoofType::Gable, RoofType::Shed}) {
        const RoofSettings s = settingsFor(type, 1);
        const Roof roof = buildRoof(footprint, 30.0, s);
        const MeshReport report = checkRoof(roof, footprint, 30.0, s);
        const Roof near = buildRoof(rectangle(20, 10), 30.0, s);
        ASSERT_TRUE(report.volume);
        EXPECT_NEAR(*report.volume, *inspectMesh(near.mesh).volume, 1e-3 * *report.volume);
        EXPECT_NEAR(roof.height, near.height, 1e-9);
    }
}

TEST(Roof, UvsAreMetres) {
    // On the hip's front slope, u runs along the eave and v up the slope: the ridge point
    // above (5, 5) is sqrt(1 + p^2) * 5 metres up the slope from the eave.
    const RoofSettings s = settingsFor(RoofType::Hip);
    const Roof roof = buildRoof(rectangle(20, 10), 0.0, s);
    bool found = false;
    for (std::size_t i = 0; i < roof.mesh.positions.size(); ++i) {
        const glm::vec3 q = roof.mesh.positions[i];
        const glm::vec3 n = roof.mesh.normals[i];
        if (std::abs(q.x - 5.0f) < 1e-5f && std::abs(q.z + 5.0f) < 1e-5f && n.z > 0.1f) {  // front slope faces -y
            EXPECT_NEAR(roof.mesh.uv0[i].x, 5.0f, 1e-5f);
            EXPECT_NEAR(roof.mesh.uv0[i].y, 5.0f * std::sqrt(1.0f + 0.36f), 1e-5f);
            found = true;
        }
    }
    EXPECT_TRUE(found);
}

TEST(RoofDeathTest, DegenerateFootprintsAreProgrammerErrors) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    const RoofSettings s = settingsFor(RoofType::Hip);
    const Polygon2 two{{0, 0}, {1, 0}};
    const Polygon2 flat{{0, 0}, {1, 0}, {2, 0}};
    const Polygon2 clockwise{{0, 0}, {0, 10}, {10, 10}, {10, 0}};
    EXPECT_DEATH(buildRoof(two, 0.0, s), "three vertices");
    EXPECT_DEATH(buildRoof(flat, 0.0, s), "counter-clockwise");
    EXPECT_DEATH(buildRoof(clockwise, 0.0, s), "counter-clockwise");
}

}  // namespace
}  // namespace dawnforge::procgen
