// Buildings: closed walls, reachable rooms, windows that belong to rooms and carry what
// interior mapping needs, and everything inside the lot.
#include <dawnforge/core/validate.hpp>
#include <dawnforge/procgen/building.hpp>
#include <dawnforge/core/materials.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <queue>
#include <set>
#include <tuple>

namespace dawnforge::procgen {
namespace {

Lot makeLot(Polygon2 polygon, int front = 0, int id = 7) {
    Lot lot;
    lot.id = id;
    lot.polygon = std::move(polygon);
    lot.streetEdge.assign(lot.polygon.size(), false);
    lot.streetEdge[static_cast<std::size_t>(front)] = true;
    lot.frontEdge = front;
    return lot;
}

// Lots of several shapes and sizes: narrow and wide, rectangular and not.
std::vector<Lot> testLots() {
    return {
        makeLot({{0, 0}, {24, 0}, {24, 30}, {0, 30}}),                      // wide: corridor with rooms both sides
        makeLot({{100, 0}, {111, 0}, {111, 25}, {100, 25}}),               // narrow: rooms on one side
        makeLot({{200, 0}, {208.5, 0}, {208.5, 22}, {200, 22}}),           // very narrow: rooms in a row
        makeLot({{300, 0}, {330, 4}, {326, 34}, {298, 28}}),               // skewed quad
        makeLot({{400, 10}, {430, 0}, {445, 20}, {425, 45}, {400, 35}}, 1), // pentagon, front not edge 0
        makeLot({{500, 0}, {540, 0}, {532, 26}, {508, 26}}),               // trapezoid
    };
}

CityRecipe tallRecipe() {
    CityRecipe r;
    r.buildings.minFloors = 6;
    r.buildings.maxFloors = 9;
    r.buildings.towerChance = 1.0;
    r.buildings.towerExtraFloors = 6;
    r.buildings.balconyChance = 1.0;
    r.lots.setback = 2.0;
    return r;
}

std::vector<Building> testBuildings() {
    std::vector<Building> out;
    const CityRecipe recipes[2] = {CityRecipe{}, tallRecipe()};
    for (const CityRecipe& recipe : recipes)
        for (const Lot& lot : testLots())
            for (std::uint64_t seed : {1u, 2u, 3u}) {
                Building b = buildBuilding(lot, recipe, seed);
                if (b.floors > 0) out.push_back(std::move(b));
            }
    return out;
}

const std::vector<Building>& buildings() {
    static const std::vector<Building> all = testBuildings();
    return all;
}

// Whether p lies inside the closed mesh `m` (ray parity along a skewed direction, so that
// the ray does not run along the axis-aligned faces buildings are full of).
bool inside(const Mesh& m, const glm::dvec3& p) {
    const glm::dvec3 dir = glm::normalize(glm::dvec3(0.5773, 0.6123, 0.5402));
    int crossings = 0;
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
        const glm::dvec3 a(m.positions[m.indices[t]]), b(m.positions[m.indices[t + 1]]), c(m.positions[m.indices[t + 2]]);
        const glm::dvec3 e1 = b - a, e2 = c - a, q = glm::cross(dir, e2);
        const double det = glm::dot(e1, q);
        if (std::abs(det) < 1e-15) continue;
        const glm::dvec3 s = p - a;
        const double u = glm::dot(s, q) / det;
        const glm::dvec3 r = glm::cross(s, e1);
        const double v = glm::dot(dir, r) / det, t1 = glm::dot(e2, r) / det;
        if (u >= 0 && v >= 0 && u + v <= 1 && t1 > 0) ++crossings;
    }
    return crossings % 2 == 1;
}

double distanceToTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    // Ericson, Real-Time Collision Detection, 5.1.5.
    const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return glm::length(ap);
    const glm::dvec3 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return glm::length(bp);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return glm::length(p - (a + ab * (d1 / (d1 - d3))));
    const glm::dvec3 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return glm::length(cp);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return glm::length(p - (a + ac * (d2 / (d2 - d6))));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return glm::length(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
    const double denom = 1.0 / (va + vb + vc);
    return glm::length(p - (a + ab * (vb * denom) + ac * (vc * denom)));
}

double distanceToSurface(const Mesh& m, const glm::dvec3& p) {
    double best = INFINITY;
    for (std::size_t t = 0; t < m.indices.size(); t += 3)
        best = std::min(best, distanceToTriangle(p, glm::dvec3(m.positions[m.indices[t]]),
                                                 glm::dvec3(m.positions[m.indices[t + 1]]),
                                                 glm::dvec3(m.positions[m.indices[t + 2]])));
    return best;
}

TEST(Building, EveryLotShapeGetsABuilding) {
    const CityRecipe recipe;
    for (const Lot& lot : testLots()) {
        const Building b = buildBuilding(lot, recipe, 1);
        EXPECT_GT(b.floors, 0) << "lot at " << lot.polygon[0].x;
        EXPECT_GT(b.lod0.triangleCount(), b.lod1.triangleCount());
        EXPECT_GT(b.height, recipe.buildings.groundStoreyHeight);
    }
    // The tall recipe builds towers where the footprint allows.
    int towers = 0;
    for (const Building& b : buildings()) towers += b.towerFootprint.empty() ? 0 : 1;
    EXPECT_GT(towers, 0);
}

TEST(Building, WallsSlabsStairsAndRoofsAreClosed) {
    for (const Building& b : buildings()) {
        validateMeshData(b.lod0, "lod0");
        validateMeshData(b.lod1, "lod1");
        const MeshReport r0 = inspectMesh(b.lod0);
        EXPECT_EQ(r0.boundaryEdges, 0u) << "building on lot " << b.lot << " floors " << b.floors;
        if (r0.boundaryEdges && !r0.openEdges.empty())
            ADD_FAILURE() << "open edge at " << r0.openEdges[0].first.x << "," << r0.openEdges[0].first.y << ","
                          << r0.openEdges[0].first.z;
        // LOD1 is a closed shell with its glass and doors in it.
        Mesh shell = b.lod1;
        const MeshReport r1 = inspectMesh(shell);
        EXPECT_EQ(r1.boundaryEdges, 0u) << "LOD1 of building on lot " << b.lot;
        EXPECT_EQ(r1.degenerateTriangles, 0u);
    }
}

// Every triangle of LOD0 is in one part, in order; each part is one closed, manifold,
// outward solid of the material its kind says.
TEST(Building, LodZeroIsMadeOfClosedParts) {
    for (const Building& b : buildings()) {
        std::uint32_t next = 0;
        std::set<PartKind> kinds;
        for (const BuildingPart& part : b.parts) {
            ASSERT_EQ(part.firstTriangle, next) << "building on lot " << b.lot;
            next += part.triangles;
            kinds.insert(part.kind);
            const Mesh mesh = partMesh(b.lod0, part);
            const MeshReport r = inspectMesh(mesh);
            EXPECT_TRUE(r.closed && r.manifold && r.outwardOriented && !r.selfIntersecting)
                << partKindName(part.kind) << " from triangle " << part.firstTriangle << " of building on lot " << b.lot;
            EXPECT_EQ(r.degenerateTriangles, 0u);
            EXPECT_EQ(r.components, 1u) << partKindName(part.kind) << " from triangle " << part.firstTriangle;
            ASSERT_TRUE(r.volume);
            EXPECT_GT(*r.volume, 0.0);
            if (part.kind == PartKind::Window) EXPECT_EQ(part.material, kGlass);
            if (part.kind == PartKind::Door) EXPECT_EQ(part.material, kWood);
        }
        EXPECT_EQ(next, b.lod0.triangleCount()) << "building on lot " << b.lot;
        for (PartKind k : {PartKind::Wall, PartKind::Slab, PartKind::InteriorWall, PartKind::Window, PartKind::Door,
                           PartKind::Roof})
            EXPECT_TRUE(kinds.count(k)) << partKindName(k) << " missing in building on lot " << b.lot;
        EXPECT_EQ(kinds.count(PartKind::Stairs), b.floors > 1 ? 1u : 0u);
        EXPECT_EQ(partKindFromName(partKindName(PartKind::InteriorWall)), PartKind::InteriorWall);
    }
}

// Parts touch but never overlap: no corner of a part lies inside another one by more than
// 1 mm. (Every overlap buildings ever had shows this way: a wall through a slab, a balcony
// through a band, railings crossing, a tower's walls in its terrace, an interior wall's end
// through the exterior wall.)
TEST(Building, PartsTouchButNeverOverlap) {
    for (const Building& b : buildings()) {
        std::vector<Mesh> parts;
        std::vector<Bounds> bounds;
        std::vector<std::set<std::tuple<float, float, float>>> corners;
        for (const BuildingPart& part : b.parts) {
            parts.push_back(partMesh(b.lod0, part));
            bounds.push_back(computeBounds(parts.back().positions));
            corners.emplace_back();
            for (const glm::vec3& v : parts.back().positions) corners.back().emplace(v.x, v.y, v.z);
        }
        int reported = 0;
        for (std::size_t i = 0; i < parts.size() && reported < 5; ++i)
            for (std::size_t j = 0; j < parts.size() && reported < 5; ++j) {
                if (i == j) continue;
                const Bounds& bi = bounds[i];
                const Bounds& bj = bounds[j];
                if (glm::any(glm::lessThan(bi.max, bj.min)) || glm::any(glm::lessThan(bj.max, bi.min))) continue;
                for (const auto& [x, y, z] : corners[i]) {
                    const glm::dvec3 p(x, y, z);
                    if (glm::any(glm::lessThan(p, bj.min + 1e-3)) || glm::any(glm::greaterThan(p, bj.max - 1e-3))) continue;
                    if (!inside(parts[j], p) || distanceToSurface(parts[j], p) < 1e-3) continue;
                    ADD_FAILURE() << partKindName(b.parts[i].kind) << " " << i << " has a corner at " << p.x << ","
                                  << p.y << "," << p.z << " inside " << partKindName(b.parts[j].kind) << " " << j
                                  << " of building on lot " << b.lot << " (" << b.floors << " floors)";
                    ++reported;
                    break;
                }
            }
    }
}

TEST(Building, EveryRoomIsReachableFromTheEntrance) {
    for (const Building& b : buildings()) {
        std::vector<std::vector<int>> next(b.rooms.size());
        std::queue<int> open;
        std::vector<bool> seen(b.rooms.size(), false);
        int entrances = 0;
        for (const Door& d : b.doors) {
            ASSERT_GE(d.from, 0);
            ASSERT_LT(d.from, static_cast<int>(b.rooms.size()));
            if (d.to < 0) {
                ++entrances;
                EXPECT_EQ(b.rooms[d.from].floor, 0);
                if (!seen[d.from]) seen[d.from] = true, open.push(d.from);
                continue;
            }
            ASSERT_LT(d.to, static_cast<int>(b.rooms.size()));
            EXPECT_EQ(d.stairs, b.rooms[d.from].floor != b.rooms[d.to].floor);
            next[d.from].push_back(d.to);
            next[d.to].push_back(d.from);
        }
        EXPECT_EQ(entrances, 1) << "lot " << b.lot;
        while (!open.empty()) {
            const int r = open.front();
            open.pop();
            for (int n : next[r])
                if (!seen[n]) seen[n] = true, open.push(n);
        }
        for (const Room& room : b.rooms)
            EXPECT_TRUE(seen[room.id]) << "lot " << b.lot << ": room " << room.id << " (" << roomKindName(room.kind)
                                       << ") on floor " << room.floor << " is not reachable";
        // Rooms per floor add up, and every floor above the ground has stairs.
        int sum = 0;
        for (int n : b.roomsPerFloor) sum += n;
        EXPECT_EQ(sum, static_cast<int>(b.rooms.size()));
        EXPECT_EQ(static_cast<int>(b.roomsPerFloor.size()), b.floors);
    }
}

TEST(Building, EveryWindowBelongsToARoomBehindIt) {
    for (const Building& b : buildings()) {
        EXPECT_FALSE(b.windows.empty());
        for (const Window& w : b.windows) {
            ASSERT_GE(w.room, 0);
            ASSERT_LT(w.room, static_cast<int>(b.rooms.size()));
            const Room& room = b.rooms[w.room];
            EXPECT_EQ(room.floor, w.floor);
            EXPECT_TRUE(containsPoint(room.polygon, w.centre + w.inward * 0.05))
                << "lot " << b.lot << " window at " << w.centre.x << "," << w.centre.y;
            // The room depth is where a ray from the window leaves the room.
            EXPECT_GT(w.roomDepth, 0.5);
            EXPECT_FALSE(containsPoint(room.polygon, w.centre + w.inward * (w.roomDepth + 0.01)));
            EXPECT_TRUE(containsPoint(room.polygon, w.centre + w.inward * (w.roomDepth - 0.01)));
        }
    }
}

TEST(Building, GlassCarriesRoomDepthIndexAndSize) {
    for (const Building& b : buildings()) {
        for (const Mesh* mesh : {&b.lod0, &b.lod1}) {
            ASSERT_EQ(mesh->uv1.size(), mesh->positions.size());
            ASSERT_EQ(mesh->uv2.size(), mesh->positions.size());
            std::size_t glass = 0;
            std::set<int> roomsSeen;
            for (std::size_t v = 0; v < mesh->positions.size(); ++v) {
                if (mesh->materialIds[v] != kGlass) continue;
                ++glass;
                const glm::vec2 depthIndex = mesh->uv1[v], size = mesh->uv2[v];
                EXPECT_GT(depthIndex.x, 0.5f);
                EXPECT_EQ(depthIndex.y, std::floor(depthIndex.y));
                ASSERT_LT(depthIndex.y, static_cast<float>(b.rooms.size()));
                roomsSeen.insert(static_cast<int>(depthIndex.y));
                EXPECT_GT(size.x, 0.5f);
                EXPECT_GT(size.y, 1.5f);
                // The pane lies on the room's front face.
                EXPECT_GE(mesh->uv0[v].x, -1e-3f);
                EXPECT_LE(mesh->uv0[v].x, size.x + 1e-3f);
                EXPECT_GE(mesh->uv0[v].y, -1e-3f);
                EXPECT_LE(mesh->uv0[v].y, size.y + 1e-3f);
            }
            EXPECT_GT(glass, 0u);
            EXPECT_GT(roomsSeen.size(), 1u);
        }
    }
}

TEST(Building, GableRidgesRunAlongTheStreet) {
    // The rise of a gable over its footprint's depth behind the street, never over its length
    // along it, also where the floors are laid out from a side edge (the thin lot last).
    CityRecipe recipe;
    recipe.roofs.flat = recipe.roofs.hip = recipe.roofs.shed = 0.0;
    recipe.roofs.gable = 1.0;
    std::vector<Lot> lots = testLots();
    lots.push_back(makeLot({{60.32, 90.966}, {68.412, 90.637}, {65.853, 129.072}, {61.675, 129.059}}, 1));
    int gables = 0;
    for (const Lot& lot : lots)
        for (std::uint64_t seed : {1u, 2u, 3u}) {
            const Building b = buildBuilding(lot, recipe, seed);
            if (b.floors == 0 || b.roof != RoofType::Gable) continue;
            ++gables;
            const std::size_t f = static_cast<std::size_t>(lot.frontEdge);
            const PolygonFrame across = edgeFrame(lot.polygon, f);
            const double depth = across.vMax - across.vMin;
            const double top = recipe.buildings.groundStoreyHeight + (b.floors - 1) * recipe.buildings.storeyHeight;
            EXPECT_LE(b.height - top, recipe.roofs.pitch * 0.75 * depth) << "lot at " << lot.polygon[0].x << " seed " << seed;
        }
    EXPECT_GT(gables, 6);
}

TEST(Building, StaysInsideItsLotAndIsDeterministic) {
    const CityRecipe recipes[2] = {CityRecipe{}, tallRecipe()};
    for (const CityRecipe& recipe : recipes)
        for (const Lot& lot : testLots()) {
            const Building a = buildBuilding(lot, recipe, 5), b = buildBuilding(lot, recipe, 5);
            EXPECT_EQ(a.lod0.positions, b.lod0.positions);
            EXPECT_EQ(a.lod0.indices, b.lod0.indices);
            EXPECT_EQ(a.lod1.uv1, b.lod1.uv1);
            for (const glm::vec3& p : a.lod0.positions) {
                const glm::dvec2 plan{p.x, -p.z};
                EXPECT_TRUE(containsPoint(lot.polygon, plan) || distanceToBoundary(lot.polygon, plan) < 1e-3)
                    << "vertex " << plan.x << "," << plan.y << " outside lot " << lot.polygon[0].x;
                EXPECT_GE(p.y, 0.0f);
            }
            for (std::uint8_t m : a.lod0.materialIds) EXPECT_LT(m, 16);
        }
}

}  // namespace
}  // namespace dawnforge::procgen
