// Properties of Voronoi fracture: volume is conserved, pieces are watertight and do not
// overlap, the output does not depend on the thread count, on convex, non-convex and
// hollow inputs.
#include "test_support.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/core/seed.hpp>
#include <dawnforge/core/validate.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/sim/fracture.hpp>
#include <dawnforge/sim/fracture_io.hpp>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <numeric>

using namespace dawnforge;
using namespace dawnforge::exporters;
using namespace dawnforge::sim;

namespace {

Mesh boxWithCavity() {
    Mesh m = makeBox({-1, -1, -1}, {1, 1, 1}, 4);
    Mesh cavity = makeBox({-0.5f, -0.4f, -0.3f}, {0.5f, 0.4f, 0.3f}, 4);
    flipOrientation(cavity);
    appendMesh(m, cavity);
    return m;
}

double totalVolume(const FractureResult& r) {
    double v = 0.0;
    for (const FracturePiece& p : r.pieces) v += p.mass.volume;
    return v;
}

// The piece in world space (its mesh is relative to the centre of mass).
Mesh worldMesh(const FracturePiece& p) {
    Mesh m = p.mesh;
    for (glm::vec3& q : m.positions) q = glm::vec3(glm::dvec3(q) + p.mass.centerOfMass);
    return m;
}

// Every piece closed and manifold, volumes add up, pieces do not overlap.
void expectSoundPieces(const Mesh& input, const FractureResult& r, double expectedVolume) {
    ASSERT_FALSE(r.pieces.empty());
    EXPECT_NEAR(r.inputVolume / expectedVolume, 1.0, 1e-6);
    EXPECT_NEAR(totalVolume(r) / r.inputVolume, 1.0, 1e-6);
    for (const FracturePiece& p : r.pieces) {
        const MeshReport report = inspectMesh(p.mesh);
        EXPECT_TRUE(report.closed) << p.name;
        EXPECT_TRUE(report.manifold) << p.name;
        EXPECT_GT(p.mass.volume, 0.0) << p.name;
        EXPECT_TRUE(p.closed) << p.name;
    }
    // Sample points: each lies inside at most one piece, and inside one iff inside the input.
    std::vector<Mesh> world;
    for (const FracturePiece& p : r.pieces) world.push_back(worldMesh(p));
    const Bounds b = computeBounds(input.positions);
    Rng rng(3);
    int insideInput = 0;
    for (int i = 0; i < 150; ++i) {
        const glm::dvec3 q(rng.uniform(b.min.x, b.max.x), rng.uniform(b.min.y, b.max.y), rng.uniform(b.min.z, b.max.z));
        const bool in = test::windingNumber(input, q) > 0.5;
        int containing = 0;
        for (const Mesh& m : world) containing += test::windingNumber(m, q) > 0.5 ? 1 : 0;
        EXPECT_LE(containing, 1) << "point inside several pieces";
        EXPECT_EQ(containing, in ? 1 : 0) << "point " << q.x << " " << q.y << " " << q.z;
        insideInput += in;
    }
    EXPECT_GT(insideInput, 10);  // the sampling did look inside
}

}  // namespace

TEST(Fracture, SphereIntoExactlyThePiecesAsked) {
    Mesh sphere = makeIcosphere(1.0f, 3);
    sphere.materialIds.assign(sphere.vertexCount(), 3);
    FractureSettings s;
    s.pieces = 30;
    s.interiorMaterial = 14;
    const FractureResult r = fractureMesh(sphere, s);
    EXPECT_EQ(r.pieces.size(), 30u);  // convex input: one piece per cell
    expectSoundPieces(sphere, r, test::referenceVolume(sphere));

    // Node/pivot convention: each mesh is centred on its centre of mass, a float point (the
    // node translation), in every build (GCC 12's vectorizer once dropped that rounding).
    std::set<std::uint8_t> materials;
    for (const FracturePiece& p : r.pieces) {
        for (int a = 0; a < 3; ++a) EXPECT_EQ(double(float(p.mass.centerOfMass[a])), p.mass.centerOfMass[a]) << p.name;
        const std::vector<glm::dvec3> pts(p.mesh.positions.begin(), p.mesh.positions.end());
        EXPECT_NEAR(glm::length(computeMassProperties(pts, p.mesh.indices, 1.0).centerOfMass), 0.0, 1e-5) << p.name;
        for (std::uint32_t id : p.mesh.pieceIds) EXPECT_EQ(&p - r.pieces.data(), std::ptrdiff_t(id));
        materials.insert(p.mesh.materialIds.begin(), p.mesh.materialIds.end());
        EXPECT_EQ(p.mesh.normals.size(), p.mesh.vertexCount());
        EXPECT_EQ(p.mesh.uv0.size(), p.mesh.vertexCount());
    }
    EXPECT_EQ(materials, (std::set<std::uint8_t>{3, 14}));  // outer surface keeps its material; cuts are interior
}

TEST(Fracture, BondsCoverEveryCutFaceOnce) {
    const Mesh sphere = makeIcosphere(1.0f, 3);
    FractureSettings s;
    s.pieces = 25;
    s.interiorMaterial = 15;
    const FractureResult r = fractureMesh(sphere, s);
    ASSERT_FALSE(r.bonds.empty());
    double bonded = 0.0;
    for (const Bond& b : r.bonds) {
        EXPECT_LT(b.a, b.b);
        EXPECT_LT(b.b, r.pieces.size());
        EXPECT_GT(b.area, 0.0);
        EXPECT_NEAR(glm::length(b.normal), 1.0, 1e-9);
        // The normal points from a towards b.
        EXPECT_GT(glm::dot(b.normal, r.pieces[b.b].mass.centerOfMass - r.pieces[b.a].mass.centerOfMass), 0.0);
        bonded += b.area;
    }
    // Inside a convex input, every cut face is shared by exactly two pieces.
    double cutArea = 0.0;
    for (const FracturePiece& p : r.pieces)
        for (std::size_t t = 0; t < p.mesh.triangleCount(); ++t) {
            const std::uint32_t* i = &p.mesh.indices[3 * t];
            if (p.mesh.materialIds[i[0]] != 15) continue;
            const glm::dvec3 a(p.mesh.positions[i[0]]), b(p.mesh.positions[i[1]]), c(p.mesh.positions[i[2]]);
            cutArea += 0.5 * glm::length(glm::cross(b - a, c - a));
        }
    EXPECT_NEAR(2.0 * bonded / cutArea, 1.0, 1e-5);
}

TEST(Fracture, NonConvexTorus) {
    const Mesh torus = test::makeTorus(1.0f, 0.35f, 32, 16);
    FractureSettings s;
    s.pieces = 16;
    s.seed = 5;
    const FractureResult r = fractureMesh(torus, s);
    EXPECT_GE(r.pieces.size(), 16u);  // a cell can cut the ring into two islands
    expectSoundPieces(torus, r, test::referenceVolume(torus));
}

TEST(Fracture, BoxWithInnerCavity) {
    const Mesh hollow = boxWithCavity();
    FractureSettings s;
    s.pieces = 12;
    const FractureResult r = fractureMesh(hollow, s);
    EXPECT_GE(r.pieces.size(), 12u);  // a cell around the cavity may split in two
    expectSoundPieces(hollow, r, 8.0 - 1.0 * 0.8 * 0.6);
}

TEST(Fracture, SameOutputOnOneAndTwoThreads) {
    const Mesh sphere = makeIcosphere(1.0f, 3);
    FractureSettings s;
    s.pieces = 40;
    auto run = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        const FractureResult r = fractureMesh(sphere, s);
        return std::make_pair(encodeGlb(fractureScene(r)), fractureJson(r, s, "sphere"));
    };
    const auto one = run(1), two = run(2), again = run(2);
    EXPECT_EQ(one.first, two.first);
    EXPECT_EQ(one.second, two.second);
    EXPECT_EQ(two.first, again.first);
    EXPECT_EQ(two.second, again.second);
}

TEST(Fracture, ImpactClustersTheSeeds) {
    const Mesh sphere = makeIcosphere(1.0f, 3);
    FractureSettings s;
    s.pieces = 200;
    const auto near = [](const std::vector<glm::dvec3>& seeds) {
        return std::count_if(seeds.begin(), seeds.end(),
                             [](const glm::dvec3& p) { return glm::distance(p, glm::dvec3(0.7, 0, 0)) < 0.3; });
    };
    const long uniform = near(sampleFractureSeeds(sphere, s));
    s.impact = glm::dvec3(0.7, 0, 0);
    s.impactRadius = 0.3;
    const std::vector<glm::dvec3> clustered = sampleFractureSeeds(sphere, s);
    EXPECT_EQ(clustered.size(), 200u);
    EXPECT_GT(near(clustered), 3 * std::max(uniform, 1L));
    for (const glm::dvec3& p : clustered) EXPECT_LT(glm::length(p), 1.0);  // all inside the volume
}

TEST(Fracture, CallerSeedsGiveOnePieceEach) {
    FractureSettings s;
    s.points = {{-0.5, 0, 0}, {0.5, 0, 0}, {0, 0.5, 0}, {0, -0.5, 0.1}};
    const FractureResult r = fractureMesh(makeBox({-1, -1, -1}, {1, 1, 1}), s);
    ASSERT_EQ(r.pieces.size(), 4u);
    EXPECT_NEAR(totalVolume(r), 8.0, 1e-6);
    // Symmetric seeds along x: the two x pieces have equal volume.
    EXPECT_NEAR(r.pieces[0].mass.volume, r.pieces[1].mass.volume, 1e-6);
}

TEST(Fracture, SliversMergeIntoTheirNeighbours) {
    const Mesh sphere = makeIcosphere(1.0f, 3);
    FractureSettings s;
    s.pieces = 40;
    const FractureResult plain = fractureMesh(sphere, s);
    std::vector<double> volumes;
    for (const FracturePiece& p : plain.pieces) volumes.push_back(p.mass.volume);
    std::sort(volumes.begin(), volumes.end());
    s.minVolume = volumes[10];  // the ten smallest must go
    const FractureResult merged = fractureMesh(sphere, s);
    EXPECT_EQ(merged.merged, plain.pieces.size() - merged.pieces.size());
    EXPECT_GE(merged.merged, 5u);
    for (const FracturePiece& p : merged.pieces) EXPECT_GE(p.mass.volume, s.minVolume);
    EXPECT_NEAR(totalVolume(merged) / merged.inputVolume, 1.0, 1e-6);
    for (const FracturePiece& p : merged.pieces) EXPECT_TRUE(inspectMesh(p.mesh).closed);
}

TEST(Fracture, LevelsRefractureNearTheImpact) {
    const Mesh sphere = makeIcosphere(1.0f, 3);
    FractureSettings s;
    s.pieces = 10;
    s.impact = glm::dvec3(0.8, 0, 0);
    s.impactRadius = 0.6;
    s.levels = 1;
    s.levelPieces = 4;
    const FractureResult r = fractureMesh(sphere, s);
    const auto deeper = std::count_if(r.pieces.begin(), r.pieces.end(), [](const FracturePiece& p) { return p.level == 1; });
    EXPECT_GT(deeper, 0);
    EXPECT_GT(r.pieces.size(), 10u);
    expectSoundPieces(sphere, r, test::referenceVolume(sphere));
}

TEST(Fracture, RefusesMeshesThatBoundNoVolume) {
    FractureSettings s;
    s.pieces = 4;
    Mesh open = makeBox({0, 0, 0}, {1, 1, 1});
    open.indices.resize(open.indices.size() - 6);  // drop one face
    try {
        fractureMesh(open, s);
        ADD_FAILURE() << "an open mesh was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("not closed"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("open at ("), std::string::npos) << e.what();  // names the edges
    }
    Mesh overlapping = makeBox({0, 0, 0}, {1, 1, 1});
    appendMesh(overlapping, makeBox({0.5f, 0.5f, 0.5f}, {1.5f, 1.5f, 1.5f}));
    EXPECT_THROW(fractureMesh(overlapping, s), InputError);
}

TEST(Fracture, TurnsInsideOutAndInconsistentMeshesOutwardAndSaysSo) {
    FractureSettings s;
    s.pieces = 4;
    Mesh inside = makeBox({0, 0, 0}, {1, 2, 1});
    flipOrientation(inside);
    Mesh mixed = makeBox({0, 0, 0}, {1, 2, 1});
    for (std::size_t t = 0; t < mixed.indices.size(); t += 6) std::swap(mixed.indices[t + 1], mixed.indices[t + 2]);
    for (const Mesh& m : {inside, mixed}) {
        const FractureResult r = fractureMesh(m, s);
        EXPECT_FALSE(r.notes.empty());
        EXPECT_NEAR(r.inputVolume, 2.0, 1e-9);
        EXPECT_NEAR(totalVolume(r), 2.0, 1e-6);
    }
    EXPECT_TRUE(fractureMesh(makeBox({0, 0, 0}, {1, 2, 1}), s).notes.empty());
}

TEST(Fracture, RefusesMoreTrianglesThanFitInMemoryBeforeAnyWork) {
    Mesh huge = makeBox({0, 0, 0}, {1, 1, 1});
    const std::vector<std::uint32_t> box = huge.indices;
    while (huge.triangleCount() <= kMaxFractureTriangles) huge.indices.insert(huge.indices.end(), box.begin(), box.end());
    try {
        fractureMesh(huge, FractureSettings{});
        ADD_FAILURE() << "a mesh above the limit was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("at most 2000000"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("simplify"), std::string::npos) << e.what();
    }
}

TEST(Fracture, RoughCutsAreClosedNoisyAndTouching) {
    const Mesh sphere = makeIcosphere(1.0f, 3);
    FractureSettings s;
    s.pieces = 8;
    s.roughness = 0.08;
    s.interiorMaterial = 15;
    const FractureResult r = fractureMesh(sphere, s);
    ASSERT_GE(r.pieces.size(), 8u);
    // Level sets are meshed at a voxel of half the roughness: volume holds to about 2%.
    EXPECT_NEAR(totalVolume(r) / r.inputVolume, 1.0, 0.02);
    for (const FracturePiece& p : r.pieces) {
        const MeshReport report = inspectMesh(p.mesh);
        EXPECT_TRUE(report.closed) << p.name;
        EXPECT_TRUE(report.manifold) << p.name;
    }
    EXPECT_GE(r.bonds.size(), r.pieces.size());  // neighbours still touch
    // Noisy: the cut faces of one bond do not share one normal.
    double spread = 0.0;
    for (const FracturePiece& p : r.pieces)
        for (std::size_t t = 0; t < p.mesh.triangleCount(); ++t) {
            const std::uint32_t* i = &p.mesh.indices[3 * t];
            if (p.mesh.materialIds[i[0]] != 15) continue;
            for (const Bond& b : r.bonds)
                if (b.a == std::uint32_t(&p - r.pieces.data())) {
                    const glm::dvec3 n(p.mesh.normals[i[0]]);
                    spread = std::max(spread, 1.0 - std::abs(glm::dot(n, b.normal)));
                    break;
                }
        }
    EXPECT_GT(spread, 0.05);
    // Pieces barely overlap: few sample points fall in two of them (only within a voxel of a cut).
    std::vector<Mesh> world;
    for (const FracturePiece& p : r.pieces) world.push_back(worldMesh(p));
    Rng rng(9);
    int doubleCounted = 0, inside = 0;
    for (int i = 0; i < 200; ++i) {
        const glm::dvec3 q(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
        int containing = 0;
        for (const Mesh& m : world) containing += test::windingNumber(m, q) > 0.5 ? 1 : 0;
        doubleCounted += containing > 1;
        inside += containing > 0;
    }
    EXPECT_GT(inside, 50);
    EXPECT_LE(doubleCounted, 4);
}

TEST(Fracture, RoughCutsAreDeterministic) {
    const Mesh torus = test::makeTorus(1.0f, 0.35f, 24, 12);
    FractureSettings s;
    s.pieces = 6;
    s.roughness = 0.06;
    auto run = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        const FractureResult r = fractureMesh(torus, s);
        return std::make_pair(encodeGlb(fractureScene(r)), fractureJson(r, s, "torus"));
    };
    EXPECT_EQ(run(1), run(2));
}

// Regression: with this tower and seed, a second-level box cut met rounding
// self-intersections left by the first and CGAL's corefinement looped forever. Cuts now
// ask CGAL to throw on self-intersections and redo the cell on the clean input.
TEST(Fracture, AxisAlignedTowerDoesNotHang) {
    const Mesh tower = makeTower(6, 3.0f, 10.0f, 10.0f);
    FractureSettings s;
    s.pieces = 60;
    s.seed = 3;
    const FractureResult r = fractureMesh(tower, s);
    EXPECT_EQ(r.pieces.size(), 60u);
    expectSoundPieces(tower, r, 6 * 3.0 * 10.0 * 10.0);
}

// The restricted Voronoi diagram (the default) and one corefinement per cell are two ways to the
// same pieces: the same cells, volumes, bonds and bond areas, up to the grid's rounding.
TEST(Fracture, BothMethodsCutTheSamePieces) {
    const Mesh torus = test::makeTorus(1.0f, 0.35f, 32, 16);
    FractureSettings s;
    s.pieces = 30;
    s.seed = 11;
    const FractureResult rvd = fractureMesh(torus, s);
    s.method = FractureMethod::Corefine;
    const FractureResult corefine = fractureMesh(torus, s);
    EXPECT_EQ(rvd.fallbackCells, 0u);
    EXPECT_EQ(rvd.cells, 30u);
    ASSERT_EQ(rvd.pieces.size(), corefine.pieces.size());
    for (std::size_t i = 0; i < rvd.pieces.size(); ++i) {
        EXPECT_EQ(rvd.pieces[i].cell, corefine.pieces[i].cell);
        EXPECT_NEAR(rvd.pieces[i].mass.volume / corefine.pieces[i].mass.volume, 1.0, 1e-7) << rvd.pieces[i].name;
        EXPECT_LT(glm::distance(rvd.pieces[i].mass.centerOfMass, corefine.pieces[i].mass.centerOfMass), 1e-6);
    }
    ASSERT_EQ(rvd.bonds.size(), corefine.bonds.size());
    for (std::size_t k = 0; k < rvd.bonds.size(); ++k) {
        EXPECT_EQ(std::pair(rvd.bonds[k].a, rvd.bonds[k].b), std::pair(corefine.bonds[k].a, corefine.bonds[k].b));
        EXPECT_NEAR(rvd.bonds[k].area / corefine.bonds[k].area, 1.0, 1e-6);
    }
    expectSoundPieces(torus, rvd, test::referenceVolume(torus));
}

// Seeds no sampling would make: on a lattice (many cospherical, cells meeting 4 and 8 at an
// edge or corner), at a cube's corners, in one plane, and on the surface itself.
TEST(Fracture, DegenerateSeedsGiveSoundPieces) {
    const Mesh box = test::gridBox(4);
    std::vector<glm::dvec3> lattice, corners, plane, surface;
    for (int x = -1; x <= 1; ++x)
        for (int y = -1; y <= 1; ++y)
            for (int z = -1; z <= 1; ++z) lattice.push_back(0.6 * glm::dvec3(x, y, z));
    for (int k = 0; k < 8; ++k) corners.push_back({k & 1 ? 0.5 : -0.5, k & 2 ? 0.5 : -0.5, k & 4 ? 0.5 : -0.5});
    Rng rng(4);
    for (int k = 0; k < 12; ++k) plane.push_back({rng.uniform(-0.9, 0.9), rng.uniform(-0.9, 0.9), 0.25});
    for (int k = 0; k < 30; ++k) {
        glm::dvec3 p(rng.uniform(-0.9, 0.9), rng.uniform(-0.9, 0.9), rng.uniform(-0.9, 0.9));
        p[k % 3] = k % 2 ? 1.0 : -1.0;
        surface.push_back(p);
    }
    for (const auto& [name, seeds] : {std::pair{"lattice", lattice}, std::pair{"corners", corners},
                                      std::pair{"plane", plane}, std::pair{"surface", surface}}) {
        SCOPED_TRACE(name);
        FractureSettings s;
        s.points = seeds;
        const FractureResult r = fractureMesh(box, s);
        EXPECT_EQ(r.pieces.size(), seeds.size());
        EXPECT_LE(r.fallbackCells, r.cells);
        expectSoundPieces(box, r, 8.0);
    }
}

TEST(Fracture, RepeatedSeedsAreRefusedByIndex) {
    for (std::size_t n : {5u, 20u}) {
        FractureSettings s;
        for (std::size_t k = 0; k < n; ++k) s.points.push_back({0.05 * double(k) - 0.4, 0.01 * double(k * k % 7), 0.1});
        s.points[n - 2] = s.points[2];
        EXPECT_EQ(test::inputErrorOf([&] { fractureMesh(makeBox({-1, -1, -1}, {1, 1, 1}), s); }),
                  format("fracture: seeds 2 and {} are at the same point", n - 2));
    }
}

// Seeds at a cube's corners inside a box with vertices on every bisector: cells meet eight at
// the centre and four along each axis, which the diagram's keys cannot close; those cells are
// cut by corefinement, exactly as --method corefine cuts them.
TEST(Fracture, CellsTheDiagramCannotCloseAreCutByCorefinement) {
    const Mesh box = test::gridBox(4);
    FractureSettings s;
    for (int k = 0; k < 8; ++k) s.points.push_back({k & 1 ? 0.5 : -0.5, k & 2 ? 0.5 : -0.5, k & 4 ? 0.5 : -0.5});
    const FractureResult rvd = fractureMesh(box, s);
    EXPECT_GT(rvd.fallbackCells, 0u);
    EXPECT_EQ(rvd.cells, 8u);
    expectSoundPieces(box, rvd, 8.0);
    s.method = FractureMethod::Corefine;
    const FractureResult corefine = fractureMesh(box, s);
    EXPECT_EQ(corefine.fallbackCells, 0u);
    ASSERT_EQ(rvd.pieces.size(), corefine.pieces.size());
    if (rvd.fallbackCells == rvd.cells)
        for (std::size_t i = 0; i < rvd.pieces.size(); ++i) {
            EXPECT_EQ(rvd.pieces[i].mesh.positions, corefine.pieces[i].mesh.positions);
            EXPECT_EQ(rvd.pieces[i].mesh.indices, corefine.pieces[i].mesh.indices);
        }
}
