// Buildings: sections (a base and an optional setback tower), storeys, facades, interiors,
// roofs, LOD0 and LOD1. All footprints are convex (lots are convex; insets of convex
// polygons are convex), which the floor layout relies on.
//
// Floor layout (the same cuts on every floor, so the stairs core lines up): the frame's
// u axis runs along the footprint's front edge (the street), v into the building. A corridor
// runs from the entrance in the middle of the front to the back; rooms line both sides,
// cut across the corridor every `roomWidth`; one slot next to the corridor is the stairs.
// Every room has a door onto the corridor; the corridor has the entrance; stairs join the
// floors. Too narrow for rooms on both sides: rooms on one side; narrower still: rooms in
// a row, each opening into the next (an enfilade), the first one onto the street.
//
// Walls are closed solids: each storey's exterior wall is one ring (outer face, inner face,
// caps, and a reveal around each opening); every face of a ring uses the same rows (the
// heights of all its openings) and each wall segment's columns are its openings' edges, so
// faces meet vertex to vertex, corners included.
#include <dawnforge/procgen/building.hpp>
#include "mesh_builder.hpp"
#include <dawnforge/core/materials.hpp>

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/seed.hpp>

#include <algorithm>
#include <cmath>
#include <optional>

namespace dawnforge::procgen {

const char* partKindName(PartKind kind) {
    switch (kind) {
        case PartKind::Wall: return "wall";
        case PartKind::Trim: return "trim";
        case PartKind::Slab: return "slab";
        case PartKind::InteriorWall: return "interior_wall";
        case PartKind::Stairs: return "stairs";
        case PartKind::Balcony: return "balcony";
        case PartKind::Railing: return "railing";
        case PartKind::Window: return "window";
        case PartKind::Door: return "door";
        case PartKind::Roof: return "roof";
    }
    return "wall";
}

std::optional<PartKind> partKindFromName(std::string_view name) {
    for (int k = 0; k <= static_cast<int>(PartKind::Roof); ++k)
        if (name == partKindName(static_cast<PartKind>(k))) return static_cast<PartKind>(k);
    return std::nullopt;
}

Mesh partMesh(const Mesh& lod0, const BuildingPart& part) {
    const std::size_t first = part.firstTriangle, count = part.triangles;
    if (first + count > lod0.triangleCount())
        throw InputError(format("part {} ({} triangles from {}) runs past the mesh's {} triangles",
                                partKindName(part.kind), count, first, lod0.triangleCount()));
    Mesh out;
    out.name = partKindName(part.kind);
    std::vector<std::uint32_t> index(lod0.positions.size(), UINT32_MAX);
    auto copy = [](const auto& from, auto& to, std::uint32_t v) {
        if (!from.empty()) to.push_back(from[v]);
    };
    for (std::size_t i = 3 * first; i < 3 * (first + count); ++i) {
        const std::uint32_t v = lod0.indices[i];
        if (index[v] == UINT32_MAX) {
            index[v] = static_cast<std::uint32_t>(out.positions.size());
            out.positions.push_back(lod0.positions[v]);
            copy(lod0.normals, out.normals, v);
            copy(lod0.uv0, out.uv0, v);
            copy(lod0.uv1, out.uv1, v);
            copy(lod0.uv2, out.uv2, v);
            copy(lod0.uv3, out.uv3, v);
            copy(lod0.materialIds, out.materialIds, v);
            copy(lod0.pieceIds, out.pieceIds, v);
        }
        out.indices.push_back(index[v]);
    }
    return out;
}

const char* roomKindName(RoomKind kind) {
    switch (kind) {
        case RoomKind::Room: return "room";
        case RoomKind::Corridor: return "corridor";
        case RoomKind::Stairs: return "stairs";
    }
    return "room";
}

namespace {

constexpr double kRiser = 0.2;          // stairs: target step height
constexpr double kMinTread = 0.23;      // with kRiser: about 41 degrees, steep but a stair
constexpr double kHeadroom = 2.0;       // stairs: clear height under the slab above a step
constexpr double kStairWidth = 1.1;
constexpr double kGlassRecess = 0.08;   // glass sits this far behind the outer face
constexpr double kGlassThickness = 0.02;
constexpr double kDoorThickness = 0.05;
constexpr double kRailing = 0.06;       // balcony railings: this thick, 1 m high
constexpr double kBandHeight = 0.25;    // floor band and cornice
constexpr double kMinEdge = 1.5;        // footprints lose vertices until every edge is this long
constexpr double kMaxShedRise = 3.0;    // metres from the low to the high side of a shed roof
constexpr double kMinInnerWidth = 2.4;  // metres inside the walls, along and across the footprint's first edge

// A wall segment between an outer line (o0 -> o1) and an inner line (i0 -> i1) parallel to
// it at distance `thickness` on the left (inside). Positions along the wall are distances s
// from o0 along `dir`; the ends use the given corner points exactly so that neighbouring
// segments of a ring share them.
struct WallLine {
    glm::dvec2 o0, o1, i0, i1;
    glm::dvec2 dir, inward;
    double length = 0, thickness = 0;
    double uOffset = 0;  // outer face u at o0 (the perimeter run so far)

    static WallLine between(glm::dvec2 o0, glm::dvec2 o1, glm::dvec2 i0, glm::dvec2 i1, double thickness) {
        WallLine w{o0, o1, i0, i1, {}, {}, glm::distance(o0, o1), thickness, 0.0};
        w.dir = (o1 - o0) / w.length;
        w.inward = {-w.dir.y, w.dir.x};
        return w;
    }
    // Centred on the segment a -> b (an interior wall), with square ends.
    static WallLine centred(glm::dvec2 a, glm::dvec2 b, double thickness) {
        const glm::dvec2 dir = glm::normalize(b - a), inward{-dir.y, dir.x};
        const glm::dvec2 half = inward * (0.5 * thickness);
        return between(a - half, b - half, a + half, b + half, thickness);
    }
    double innerStart() const { return glm::dot(i0 - o0, dir); }
    double innerEnd() const { return glm::dot(i1 - o0, dir); }
};

struct Opening {
    double s0 = 0, s1 = 0, z0 = 0, z1 = 0;  // along the wall; heights
    bool leaf = true;  // a pane or door leaf in the opening (interior doorways have none)
    std::optional<MeshBuilder::Glass> glass;  // windows: interior-mapping data
};

// Breakpoints along a wall: index 0 and the last are the segment's ends.
struct Columns {
    std::vector<double> s;      // s[0] = 0, s.back() = length
    std::vector<int> opening;   // per column (between s[k] and s[k+1]): index into openings or -1
};

Columns columnsOf(const WallLine& w, std::span<const Opening> openings) {
    Columns c;
    c.s.push_back(0.0);
    for (std::size_t i = 0; i < openings.size(); ++i) {
        c.opening.push_back(-1);
        c.s.push_back(openings[i].s0);
        c.opening.push_back(static_cast<int>(i));
        c.s.push_back(openings[i].s1);
    }
    c.opening.push_back(-1);
    c.s.push_back(w.length);
    return c;
}

glm::dvec2 outerAt(const WallLine& w, const Columns& c, std::size_t k) {
    if (k == 0) return w.o0;
    if (k + 1 == c.s.size()) return w.o1;
    return w.o0 + w.dir * c.s[k];
}
glm::dvec2 innerAt(const WallLine& w, const Columns& c, std::size_t k) {
    if (k == 0) return w.i0;
    if (k + 1 == c.s.size()) return w.i1;
    return w.o0 + w.dir * c.s[k] + w.inward * w.thickness;
}

struct WallMaterials {
    std::uint8_t outer = kBrick, inner = kInteriorWall, caps = kBrick, reveal = kTrim;
};

// LOD0 as it is built: what one call of part() appends is one closed solid, recorded as a
// BuildingPart (the fracture of a building takes them one by one).
class Lod0 {
public:
    Lod0(Mesh& mesh, std::vector<BuildingPart>& parts) : mb(mesh), mesh_(mesh), parts_(parts) {}
    template <class Build>
    void part(PartKind kind, std::uint8_t material, Build&& build) {
        const auto first = static_cast<std::uint32_t>(mesh_.triangleCount());
        build(mb);
        const auto count = static_cast<std::uint32_t>(mesh_.triangleCount()) - first;
        if (count > 0) parts_.push_back({kind, material, first, count});
    }

    MeshBuilder mb;

private:
    Mesh& mesh_;
    std::vector<BuildingPart>& parts_;
};

// A pane of glass or a door leaf filling an opening (from s0 to s1, z0 to z1) at `recess`
// behind the wall's outer face, `depth` thick.
struct Leaf {
    glm::dvec2 a{0.0}, b{0.0};  // front corners in plan (on the pane's outer face)
    glm::dvec2 inward{0.0};     // into the building
    double z0 = 0, z1 = 0, depth = 0;
    std::optional<MeshBuilder::Glass> glass;  // glass; a wooden door leaf without
    MeshBuilder::Uv uv;
};

// A leaf as a closed box. Every face of a pane carries the interior-mapping data of the room
// behind it (the front is what interior mapping draws; the others are hidden in the reveal).
void appendLeaf(MeshBuilder& mb, const Leaf& leaf) {
    using Uv = MeshBuilder::Uv;
    const glm::dvec2 a = leaf.a, b = leaf.b, c = b + leaf.inward * leaf.depth, d = a + leaf.inward * leaf.depth;
    const glm::dvec2 dir = glm::normalize(b - a);
    const glm::dvec3 out = MeshBuilder::planDir(-leaf.inward), along = MeshBuilder::planDir(dir);
    const std::uint8_t material = leaf.glass ? std::uint8_t{kGlass} : std::uint8_t{kWood};
    const MeshBuilder::Glass* glass = leaf.glass ? &*leaf.glass : nullptr;
    const Uv sideUv{Uv::Wall, leaf.inward, 0.0};
    const double z0 = leaf.z0, z1 = leaf.z1;
    mb.quad({a, z0}, {b, z0}, {b, z1}, {a, z1}, out, material, leaf.uv, glass);
    mb.quad({d, z0}, {c, z0}, {c, z1}, {d, z1}, -out, material, leaf.uv, glass);
    mb.quad({a, z0}, {d, z0}, {d, z1}, {a, z1}, -along, material, sideUv, glass);
    mb.quad({b, z0}, {c, z0}, {c, z1}, {b, z1}, along, material, sideUv, glass);
    mb.quad({a, z0}, {b, z0}, {c, z0}, {d, z0}, -MeshBuilder::up(), material, {}, glass);
    mb.quad({a, z1}, {b, z1}, {c, z1}, {d, z1}, MeshBuilder::up(), material, {}, glass);
}

// One wall segment as part of a closed solid: outer and inner faces on the rows `levels`,
// caps at the first and last level, reveals around the openings and (for free-standing
// walls) end caps. The panes and door leaves of its openings go to `leaves`: each is a solid
// of its own.
void appendWall(MeshBuilder& mb, const WallLine& w, std::span<const Opening> openings, std::span<const double> levels,
                bool endCaps, const WallMaterials& mat, std::vector<Leaf>* leaves = nullptr) {
    using Uv = MeshBuilder::Uv;
    const Columns cols = columnsOf(w, openings);
    const glm::dvec3 out = MeshBuilder::outward(w.dir), in = -out, along = MeshBuilder::planDir(w.dir);
    const Uv outerUv{Uv::Wall, w.dir, w.uOffset - glm::dot(w.o0, w.dir)}, wallUv{Uv::Wall, w.dir, 0.0};
    const Uv sideUv{Uv::Wall, w.inward, 0.0};
    const double y0 = levels.front(), y1 = levels.back();
    auto inOpening = [&](int o, std::size_t r) {
        return o >= 0 && levels[r] >= openings[o].z0 && levels[r + 1] <= openings[o].z1;
    };
    for (std::size_t k = 0; k + 1 < cols.s.size(); ++k) {
        const int o = cols.opening[k];
        const glm::dvec2 oa = outerAt(w, cols, k), ob = outerAt(w, cols, k + 1);
        const glm::dvec2 ia = innerAt(w, cols, k), ib = innerAt(w, cols, k + 1);
        for (std::size_t r = 0; r + 1 < levels.size(); ++r) {
            if (inOpening(o, r)) continue;
            const double za = levels[r], zb = levels[r + 1];
            mb.quad({oa, za}, {ob, za}, {ob, zb}, {oa, zb}, out, mat.outer, outerUv);
            mb.quad({ia, za}, {ib, za}, {ib, zb}, {ia, zb}, in, mat.inner, wallUv);
        }
        // An opening from the bottom level up is a notch: no cap and no sill under it.
        const bool notch = o >= 0 && openings[o].z0 <= y0;
        if (!notch) mb.quad({oa, y0}, {ob, y0}, {ib, y0}, {ia, y0}, -MeshBuilder::up(), mat.caps, {});
        mb.quad({oa, y1}, {ob, y1}, {ib, y1}, {ia, y1}, MeshBuilder::up(), mat.caps, {});
        if (o < 0) continue;
        const Opening& op = openings[o];
        for (std::size_t r = 0; r + 1 < levels.size(); ++r) {
            if (!inOpening(o, r)) continue;
            const double za = levels[r], zb = levels[r + 1];
            mb.quad({oa, za}, {ia, za}, {ia, zb}, {oa, zb}, along, mat.reveal, sideUv);
            mb.quad({ob, za}, {ib, za}, {ib, zb}, {ob, zb}, -along, mat.reveal, sideUv);
        }
        if (!notch) mb.quad({oa, op.z0}, {ob, op.z0}, {ib, op.z0}, {ia, op.z0}, MeshBuilder::up(), mat.reveal, {});
        mb.quad({oa, op.z1}, {ob, op.z1}, {ib, op.z1}, {ia, op.z1}, -MeshBuilder::up(), mat.reveal, {});
        // The pane (or door leaf), recessed from the outer face, filling the opening.
        if (!op.leaf || !leaves) continue;
        const double recess = std::min(kGlassRecess, w.thickness / 3.0);
        const double depth = std::min(op.glass ? kGlassThickness : kDoorThickness, w.thickness / 3.0);
        leaves->push_back({oa + w.inward * recess, ob + w.inward * recess, w.inward, op.z0, op.z1, depth, op.glass,
                           wallUv});
    }
    if (!endCaps) return;
    // The ends' normals: square ends face along the wall; an end cut along another wall's
    // face (an interior wall meeting the exterior wall at an angle) faces across that face.
    auto endNormal = [&](glm::dvec2 o, glm::dvec2 i, double sign) {
        glm::dvec2 n = glm::normalize(glm::dvec2(i.y - o.y, o.x - i.x));
        if (glm::dot(n, w.dir) * sign < 0.0) n = -n;
        return MeshBuilder::planDir(n);
    };
    const glm::dvec3 startNormal = endNormal(w.o0, w.i0, -1.0), endNormal1 = endNormal(w.o1, w.i1, 1.0);
    for (std::size_t r = 0; r + 1 < levels.size(); ++r) {
        const double za = levels[r], zb = levels[r + 1];
        mb.quad({w.o0, za}, {w.i0, za}, {w.i0, zb}, {w.o0, zb}, startNormal, mat.caps, sideUv);
        mb.quad({w.o1, za}, {w.i1, za}, {w.i1, zb}, {w.o1, zb}, endNormal1, mat.caps, sideUv);
    }
}

std::vector<double> levelsOf(double y0, double y1, std::span<const std::vector<Opening>> walls) {
    std::vector<double> levels{y0, y1};
    for (const auto& openings : walls)
        for (const Opening& o : openings) levels.insert(levels.end(), {o.z0, o.z1});
    std::sort(levels.begin(), levels.end());
    levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
    return levels;
}

// --- Floor layout -------------------------------------------------------------------------

enum class LayoutKind { DoubleLoaded, SingleLoaded, Enfilade };

// The cuts shared by every floor of a building, in frame coordinates (u along the front, v inward).
struct FloorLayout {
    LayoutKind kind = LayoutKind::Enfilade;
    double corridor0 = 0, corridor1 = 0;      // corridor strip u range (not Enfilade)
    std::vector<double> cutsLow, cutsHigh;     // v positions of the cuts on the low-u and high-u sides
    int stairsSide = 1;                        // 0: low side, 1: high side (Enfilade: the row)
    double stairs0 = 0, stairs1 = 0;           // v range of the stairs slot
    bool hasStairs = false;
};

struct Piece {
    RoomKind kind = RoomKind::Room;
    Polygon2 polygon;
    int side = -1;                  // 0 low, 1 high, -1 corridor / enfilade row
    double v0 = 0, v1 = 0;          // slot range
};

struct Section {
    Polygon2 footprint;  // outer face of the exterior wall
    Polygon2 inner;      // inner face
    int firstFloor = 0, floorCount = 0;
    double y0 = 0, y1 = 0;
};

struct StairFlight {
    double footV = 0, endV = 0, tread = 0;  // frame v of the flight's foot and top; step depth
    double openingV = 0;                    // the slab above is open from here to endV
};

struct BuildContext {
    const CityRecipe& recipe;
    PolygonFrame frame;         // from the base footprint's front edge
    FloorLayout layout;
    std::vector<double> floorY; // floor f's bottom; floorY[floors] = top of the last storey
};

double storeyHeightOf(const BuildingRecipe& r, int floor) {
    return floor == 0 ? r.groundStoreyHeight : r.storeyHeight;
}

// The flight from `floor` up to the next: it starts past the stairs room's door and fills
// the slot to a landing at its far end.
StairFlight stairFlight(const BuildContext& ctx, int floor) {
    const FloorLayout& L = ctx.layout;
    const InteriorRecipe& ir = ctx.recipe.interiors;
    const double rise = ctx.floorY[floor + 1] - ctx.floorY[floor];
    const int risers = std::max(2, static_cast<int>(std::round(rise / kRiser)));
    const double start = std::isinf(L.stairs0) ? ctx.recipe.buildings.wallThickness : L.stairs0;
    const double length = (std::isinf(L.stairs1) ? start + risers * kMinTread + ir.doorWidth + 1.0 : L.stairs1) - start;
    StairFlight flight;
    flight.footV = start + ir.doorWidth + 0.8;
    flight.tread = std::max(kMinTread, (length - ir.doorWidth - 1.0) / risers);
    flight.endV = flight.footV + risers * flight.tread;
    // The slab above opens only where a step has less than the headroom under it, so the
    // next flight's foot, right above this one's, stands on that slab (and is glued to it).
    const double clear = rise - ir.slabThickness - kHeadroom;
    flight.openingV = flight.footV + std::max(2, static_cast<int>(std::floor(clear / (rise / risers)))) * flight.tread;
    return flight;
}

// Cuts every `width` or so within [lo, hi], none closer than `margin` to either end.
std::vector<double> cutsWithin(double lo, double hi, double width, double margin) {
    std::vector<double> cuts;
    const double span = hi - lo;
    const int slots = static_cast<int>(std::floor(span / width));
    if (slots < 2) return cuts;
    for (int i = 1; i < slots; ++i) {
        const double v = lo + span * i / slots;
        if (v - lo >= margin && hi - v >= margin) cuts.push_back(v);
    }
    return cuts;
}

std::vector<Piece> splitSide(std::span<const glm::dvec2> poly, const PolygonFrame& f, glm::dvec2 sideAxis,
                             double sideLo, double sideHi, std::span<const double> cuts, int side,
                             const FloorLayout& layout) {
    std::vector<Piece> pieces;
    const Polygon2 strip = clipStrip(poly, sideAxis, sideLo, sideHi);
    if (strip.empty()) return pieces;
    std::vector<double> bounds{-INFINITY};
    bounds.insert(bounds.end(), cuts.begin(), cuts.end());
    bounds.push_back(INFINITY);
    const double vOrigin = glm::dot(f.origin, f.v);
    for (std::size_t i = 0; i + 1 < bounds.size(); ++i) {
        const double lo = bounds[i], hi = bounds[i + 1];
        const Polygon2 p =
            clipStrip(strip, f.v, std::isinf(lo) ? -1e30 : lo + vOrigin, std::isinf(hi) ? 1e30 : hi + vOrigin);
        if (p.size() < 3 || signedArea(p) < 1.0) continue;
        Piece piece;
        piece.polygon = p;
        piece.side = side;
        piece.v0 = lo;
        piece.v1 = hi;
        piece.kind = (layout.hasStairs && side == layout.stairsSide && lo == layout.stairs0 && hi == layout.stairs1)
                         ? RoomKind::Stairs
                         : RoomKind::Room;
        pieces.push_back(std::move(piece));
    }
    return pieces;
}

// The pieces of one floor of `section`.
std::vector<Piece> layoutPieces(const BuildContext& ctx, const Section& section) {
    const PolygonFrame& f = ctx.frame;
    const FloorLayout& L = ctx.layout;
    const double uOrigin = glm::dot(f.origin, f.u);
    std::vector<Piece> pieces;
    if (L.kind == LayoutKind::Enfilade) return splitSide(section.inner, f, f.u, -1e30, 1e30, L.cutsLow, -1, L);
    Piece corridor;
    corridor.kind = RoomKind::Corridor;
    corridor.polygon = clipStrip(section.inner, f.u, L.corridor0 + uOrigin, L.corridor1 + uOrigin);
    pieces.push_back(corridor);
    if (L.kind == LayoutKind::DoubleLoaded) {
        auto low = splitSide(section.inner, f, f.u, -1e30, L.corridor0 + uOrigin, L.cutsLow, 0, L);
        pieces.insert(pieces.end(), low.begin(), low.end());
    }
    auto high = splitSide(section.inner, f, f.u, L.corridor1 + uOrigin, 1e30, L.cutsHigh, 1, L);
    pieces.insert(pieces.end(), high.begin(), high.end());
    return pieces;
}

// Chooses the corridor, the room cuts and the stairs slot from the base section's inner polygon.
std::optional<FloorLayout> planLayout(const BuildContext& ctx, std::span<const glm::dvec2> inner, int floors,
                                      Rng& rng) {
    const InteriorRecipe& ir = ctx.recipe.interiors;
    const PolygonFrame& f = ctx.frame;
    FloorLayout L;
    // The inner polygon's extents in the frame.
    double u0 = INFINITY, u1 = -INFINITY, v0 = INFINITY, v1 = -INFINITY;
    for (glm::dvec2 p : inner) {
        const glm::dvec2 q = f.toFrame(p);
        u0 = std::min(u0, q.x), u1 = std::max(u1, q.x), v0 = std::min(v0, q.y), v1 = std::max(v1, q.y);
    }
    // The front edge of the inner polygon: the points within 1 cm of its lowest v.
    double f0 = INFINITY, f1 = -INFINITY;
    for (glm::dvec2 p : inner) {
        const glm::dvec2 q = f.toFrame(p);
        if (q.y < v0 + 0.01) f0 = std::min(f0, q.x), f1 = std::max(f1, q.x);
    }
    const double cw = ir.corridorWidth, minDepth = ir.minRoomDepth;
    const double margin = ir.doorWidth + ir.wallThickness + 0.6;
    const double uc = 0.5 * (f0 + f1);
    const double roomWidth = ir.roomWidth * rng.uniform(0.85, 1.2);
    const double vOrigin = glm::dot(f.origin, f.v), uOrigin = glm::dot(f.origin, f.u);
    if (f1 - f0 >= cw + 1.0 && uc - cw / 2 - u0 >= minDepth && u1 - (uc + cw / 2) >= minDepth) {
        L.kind = LayoutKind::DoubleLoaded;
        L.corridor0 = uc - cw / 2, L.corridor1 = uc + cw / 2;
    } else if (f1 - f0 >= cw + 1.0 && u1 - (u0 + cw) >= minDepth) {
        L.kind = LayoutKind::SingleLoaded;
        L.corridor0 = u0 - 1.0, L.corridor1 = std::max(u0 + cw, f0 + cw);
        if (u1 - L.corridor1 < minDepth) L.kind = LayoutKind::Enfilade;
    }
    // Cuts along each corridor line, within the range where that line crosses the polygon.
    auto sideCuts = [&](double uLine) -> std::pair<std::vector<double>, std::pair<double, double>> {
        const auto range = chord(inner, f.u, uLine + uOrigin, f.v);
        if (!range) return {{}, {0.0, 0.0}};
        const double lo = range->first - vOrigin, hi = range->second - vOrigin;
        return {cutsWithin(lo, hi, roomWidth, margin), {lo, hi}};
    };
    std::pair<double, double> rangeHigh{v0, v1};
    if (L.kind == LayoutKind::Enfilade) {
        L.cutsLow = cutsWithin(v0, v1, roomWidth, margin);
    } else {
        if (L.kind == LayoutKind::DoubleLoaded) L.cutsLow = sideCuts(L.corridor0).first;
        auto [cuts, range] = sideCuts(L.corridor1);
        L.cutsHigh = cuts;
        rangeHigh = range;
    }
    if (floors < 2) return L;
    // The stairs: a slot on the high side (the row for an enfilade) long enough for a flight
    // from the ground floor up (the tallest storey) with a landing and a door at its foot.
    const double tallest = std::max(ctx.recipe.buildings.groundStoreyHeight, ctx.recipe.buildings.storeyHeight);
    const int risers = static_cast<int>(std::ceil(tallest / kRiser));
    const double need = risers * kMinTread + ir.doorWidth + 1.0;
    std::vector<double>& cuts = L.kind == LayoutKind::Enfilade ? L.cutsLow : L.cutsHigh;
    const double lo = L.kind == LayoutKind::Enfilade ? v0 : rangeHigh.first;
    const double hi = L.kind == LayoutKind::Enfilade ? v1 : rangeHigh.second;
    if (hi - lo < need + 0.2) return std::nullopt;  // no room for stairs: the caller makes it one storey
    // Replace the cuts near the middle with a stairs slot of length `need`.
    const double mid = 0.5 * (lo + hi);
    double s0 = std::clamp(mid - need / 2, lo, hi - need), s1 = s0 + need;
    std::vector<double> kept;
    for (double c : cuts)
        if (c <= s0 - margin || c >= s1 + margin) kept.push_back(c);
    if (s0 - lo > 0.5) kept.push_back(s0); else s0 = -INFINITY;
    if (hi - s1 > 0.5) kept.push_back(s1); else s1 = INFINITY;
    std::sort(kept.begin(), kept.end());
    cuts = kept;
    L.hasStairs = true;
    L.stairsSide = L.kind == LayoutKind::Enfilade ? -1 : 1;
    L.stairs0 = s0, L.stairs1 = s1;
    return L;
}

// --- Meshes -------------------------------------------------------------------------------

// A straight flight from (foot, y0) up to y1 along `dir`, `width` wide to the left of the
// centre line through `foot`: one closed solid (two sawtooth sides and the step strips).
void appendStairs(MeshBuilder& mb, glm::dvec2 foot, glm::dvec2 dir, double width, double y0, double y1, double tread) {
    const int n = std::max(2, static_cast<int>(std::round((y1 - y0) / kRiser)));
    const double rise = (y1 - y0) / n;
    // Profile in (distance along dir, height), counter-clockwise seen from the left side.
    std::vector<glm::dvec2> profile{{0.0, 0.0}};
    for (int j = 0; j < n; ++j) {
        profile.push_back({j * tread, (j + 1) * rise});
        profile.push_back({(j + 1) * tread, (j + 1) * rise});
    }
    profile.push_back({n * tread, (n - 1) * rise});
    profile.push_back({tread, 0.0});
    // profile runs clockwise in (t, h) as listed; reverse to counter-clockwise.
    std::reverse(profile.begin(), profile.end());
    const glm::dvec2 left{-dir.y, dir.x};
    auto at = [&](glm::dvec2 q, double side) { return glm::dvec3(foot + dir * q.x + left * side, y0 + q.y); };
    const std::vector<std::uint32_t> tris = triangulatePolygon(profile);
    const glm::dvec3 leftW = MeshBuilder::planDir(left);
    MeshBuilder::Uv uv{MeshBuilder::Uv::Wall, dir, 0.0};
    for (std::size_t t = 0; t < tris.size(); t += 3) {
        const glm::dvec3 l[3] = {at(profile[tris[t]], width), at(profile[tris[t + 1]], width), at(profile[tris[t + 2]], width)};
        mb.polygon(l, leftW, kFloor, uv);
        const glm::dvec3 r[3] = {at(profile[tris[t]], 0.0), at(profile[tris[t + 1]], 0.0), at(profile[tris[t + 2]], 0.0)};
        mb.polygon(r, -leftW, kFloor, uv);
    }
    for (std::size_t i = 0; i < profile.size(); ++i) {
        const glm::dvec2 a = profile[i], b = profile[(i + 1) % profile.size()];
        // Outward normal of the profile edge (counter-clockwise: right of the edge), in the world.
        const glm::dvec2 e = b - a, n2{e.y, -e.x};
        const glm::dvec3 want = MeshBuilder::planDir(dir) * n2.x + MeshBuilder::up() * n2.y;
        mb.quad(at(a, 0.0), at(b, 0.0), at(b, width), at(a, width), want, kFloor, {});
    }
}

void appendBox(MeshBuilder& mb, glm::dvec2 origin, glm::dvec2 dir, double length, double depth, double y0, double y1,
               std::uint8_t material) {
    const glm::dvec2 left{-dir.y, dir.x};
    const Polygon2 poly{origin, origin + dir * length, origin + dir * length + left * depth, origin + left * depth};
    mb.prism(poly, y0, y1, material, material, material);
}

// A ring around convex `poly` from y0 to y1 sticking out by `depth` (floor bands, cornices).
void appendBand(MeshBuilder& mb, std::span<const glm::dvec2> poly, double depth, double y0, double y1) {
    const Polygon2 outer = mitreOffset(poly, -depth);
    const std::size_t n = poly.size();
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j = (i + 1) % n;
        const WallLine w = WallLine::between(outer[i], outer[j], poly[i], poly[j], depth);
        const double levels[2] = {y0, y1};
        appendWall(mb, w, {}, levels, false, {kTrim, kTrim, kTrim, kTrim});
    }
}

struct BuildingStyle {
    std::uint8_t wall = kBrick;
    bool shop = false, balconies = false;
};

// What every storey of a section shares: the rooms of each floor, the wall on the street, and
// the perimeter run at each corner (run[e] at corner e), so that facade u continues round corners.
struct SectionPlan {
    std::vector<Piece> pieces;
    std::size_t front = 0;
    std::vector<double> run;
};

// One storey of a section. Its rooms are the section's pieces, in order, from `firstRoom` on.
struct Storey {
    int floor = 0;
    double y0 = 0, y1 = 0;  // bottom and top
    double slabTop = 0;     // top of the floor slab
    int firstRoom = 0;
};

// Where one room meets exterior wall `edge`: from sa to sb along the wall, measured from the
// wall's outer corner `o`.
struct RoomOnWall {
    const Piece& piece;
    int roomId = 0;
    std::size_t edge = 0;
    glm::dvec2 o{0.0}, dir{0.0}, inward{0.0};
    double sa = 0, sb = 0;
};

// A balcony outside a balcony door: from `start` on the wall's outer face, `length` along it.
struct Balcony {
    glm::dvec2 start{0.0}, dir{0.0}, outward{0.0};
    double length = 0;
};

// The openings of one storey's exterior walls and what comes with them.
struct StoreyOpenings {
    std::vector<std::vector<Opening>> walls;  // per footprint edge, sorted along the wall
    std::vector<Window> windows;
    std::vector<Door> doors;  // the entrance
    std::vector<Balcony> balconies;
};

// How far balconies reach out: at most 1.2 m, within the setback and clear of the trims;
// buildings get none when that is 0.5 m or less.
double balconyDepthOf(const CityRecipe& recipe) {
    return std::min(1.2, recipe.lots.setback - recipe.buildings.trimDepth - 0.1);
}

// run[i]: the distance along the polygon's boundary from vertex 0 to vertex i (i = 0..n).
std::vector<double> perimeterRun(std::span<const glm::dvec2> polygon) {
    const std::size_t n = polygon.size();
    std::vector<double> run(n + 1, 0.0);
    for (std::size_t i = 0; i < n; ++i) run[i + 1] = run[i] + glm::distance(polygon[i], polygon[(i + 1) % n]);
    return run;
}

// Where `piece` meets exterior wall e of `sec` (its edges on the wall's inner face); nullopt
// when it does not.
std::optional<RoomOnWall> roomOnWall(const Section& sec, std::size_t e, const Piece& piece, int roomId) {
    const std::size_t n = sec.footprint.size(), m = piece.polygon.size();
    const glm::dvec2 a = sec.inner[e], c = sec.inner[(e + 1) % n];
    const glm::dvec2 dir = glm::normalize(c - a);
    RoomOnWall wall{piece, roomId, e, sec.footprint[e], dir, {-dir.y, dir.x}, INFINITY, -INFINITY};
    for (std::size_t k = 0; k < m; ++k) {
        const glm::dvec2 p = piece.polygon[k], q = piece.polygon[(k + 1) % m];
        if (std::abs(cross(dir, p - a)) > 1e-6 || std::abs(cross(dir, q - a)) > 1e-6) continue;
        if (glm::dot(q - p, dir) <= 0.0) continue;
        wall.sa = std::min(wall.sa, glm::dot(p - wall.o, dir));
        wall.sb = std::max(wall.sb, glm::dot(q - wall.o, dir));
    }
    if (!(wall.sb > wall.sa)) return std::nullopt;
    return wall;
}

// The stretch of a room's wall where openings may go: clear of the interior walls at its ends.
std::pair<double, double> openingRange(const InteriorRecipe& ir, const RoomOnWall& wall) {
    const double endMargin = ir.wallThickness / 2 + 0.3;
    return {wall.sa + endMargin, wall.sb - endMargin};
}

void placeEntrance(const BuildContext& ctx, const Storey& storey, const RoomOnWall& wall, StoreyOpenings& out) {
    const BuildingRecipe& br = ctx.recipe.buildings;
    const auto [lo, hi] = openingRange(ctx.recipe.interiors, wall);
    const double w = std::min(br.doorWidth, hi - lo);
    if (w < 0.8) return;
    Opening door;
    door.s0 = 0.5 * (lo + hi) - w / 2, door.s1 = door.s0 + w;
    door.z0 = storey.slabTop, door.z1 = std::min(storey.y0 + br.doorHeight, storey.y1 - 0.3);
    out.walls[wall.edge].push_back(door);
    out.doors.push_back({wall.roomId, -1, false, wall.o + wall.dir * (0.5 * (lo + hi))});
}

// A window centred `centre` along the wall, or a balcony door (then with its balcony); the
// glass carries the room's interior-mapping box.
void placeWindow(const BuildContext& ctx, const Storey& storey, const RoomOnWall& wall, double centre, double width,
                 double sill, double height, bool balconyDoor, StoreyOpenings& out) {
    Opening op;
    op.s0 = centre - width / 2, op.s1 = centre + width / 2;
    op.z0 = sill, op.z1 = sill + height;
    const glm::dvec2 mid = wall.o + wall.dir * centre + wall.inward * ctx.recipe.buildings.wallThickness;
    const double depth = rayExit(wall.piece.polygon, mid, wall.inward);
    MeshBuilder::Glass g;
    g.origin = wall.o + wall.dir * wall.sa;
    g.floorY = storey.slabTop;
    g.dir = wall.dir;
    g.depthIndex = {static_cast<float>(depth), static_cast<float>(wall.roomId)};
    g.size = {static_cast<float>(wall.sb - wall.sa), static_cast<float>(storey.y1 - storey.slabTop)};
    op.glass = g;
    out.walls[wall.edge].push_back(op);
    out.windows.push_back({wall.roomId, storey.floor, mid, wall.inward, width, sill, height, depth, balconyDoor});
    if (balconyDoor)
        out.balconies.push_back({wall.o + wall.dir * (op.s0 - 0.4), wall.dir, -wall.inward, op.s1 - op.s0 + 0.8});
}

// A shop front: the whole stretch in bays of glass from near the floor up.
void placeShopWindows(const BuildContext& ctx, const Storey& storey, const RoomOnWall& wall, StoreyOpenings& out) {
    const auto [lo, hi] = openingRange(ctx.recipe.interiors, wall);
    const double avail = hi - lo, slabTop = storey.slabTop;
    const int k = std::max(1, static_cast<int>(std::floor(avail / ctx.recipe.buildings.bayWidth)));
    const double bay = avail / k, w = bay - 0.5;
    if (w < 0.8) return;
    const double height = std::min(storey.y1 - 0.5, slabTop + 2.8) - slabTop - 0.3;
    for (int i = 0; i < k; ++i)
        placeWindow(ctx, storey, wall, lo + bay * (i + 0.5), w, slabTop + 0.3, height, false, out);
}

// Windows in bays centred on the stretch; with `balcony`, the first is a balcony door.
void placeWindows(const BuildContext& ctx, const Storey& storey, const RoomOnWall& wall, bool balcony,
                  StoreyOpenings& out) {
    const BuildingRecipe& br = ctx.recipe.buildings;
    const auto [lo, hi] = openingRange(ctx.recipe.interiors, wall);
    const double w = br.windowWidth;
    const int k = static_cast<int>(std::floor((hi - lo + br.bayWidth - w) / br.bayWidth));
    if (k < 1) return;
    const double sill = storey.y0 + std::max(br.sillHeight, ctx.recipe.interiors.slabThickness + 0.05);
    const double wh = std::min(br.windowHeight, storey.y1 - 0.25 - sill);
    if (wh < 0.4) return;
    const double span = (k - 1) * br.bayWidth;
    for (int i = 0; i < k; ++i) {
        const double centre = 0.5 * (lo + hi) - span / 2 + i * br.bayWidth;
        if (balcony && i == 0)
            placeWindow(ctx, storey, wall, centre, w, storey.slabTop, std::min(2.3, storey.y1 - 0.25 - storey.slabTop),
                        true, out);
        else
            placeWindow(ctx, storey, wall, centre, w, sill, wh, false, out);
    }
}

// The openings of one storey's exterior walls, room by room: on the ground floor's front the
// entrance and (in a shop building) shop fronts; elsewhere windows, and balcony doors on the
// front of a balcony building's upper floors.
StoreyOpenings placeOpenings(const BuildContext& ctx, const Section& sec, const SectionPlan& plan,
                             const BuildingStyle& style, const Storey& storey) {
    const std::size_t n = sec.footprint.size();
    StoreyOpenings out;
    out.walls.resize(n);
    for (std::size_t pi = 0; pi < plan.pieces.size(); ++pi) {
        const Piece& piece = plan.pieces[pi];
        for (std::size_t e = 0; e < n; ++e) {
            const auto wall = roomOnWall(sec, e, piece, storey.firstRoom + static_cast<int>(pi));
            if (!wall) continue;
            const bool isFront = e == plan.front && storey.floor == 0;
            const bool entrance = isFront && (piece.kind == RoomKind::Corridor ||
                                              (ctx.layout.kind == LayoutKind::Enfilade && pi == 0));
            // No balconies on a tower's first storey: it stands on the terrace.
            const bool balcony = style.balconies && storey.floor > sec.firstFloor && e == plan.front &&
                                 piece.kind == RoomKind::Room && balconyDepthOf(ctx.recipe) > 0.5;
            if (entrance)
                placeEntrance(ctx, storey, *wall, out);
            else if (isFront && style.shop && piece.kind == RoomKind::Room)
                placeShopWindows(ctx, storey, *wall, out);
            else
                placeWindows(ctx, storey, *wall, balcony, out);
        }
    }
    for (auto& list : out.walls)
        std::sort(list.begin(), list.end(), [](const Opening& x, const Opening& y) { return x.s0 < y.s0; });
    return out;
}

// A slab `depth` deep and three railings, each a part. The slab rests on the floor band
// (its bottom at `bandTop`, or 0.2 m under the floor without one); the side railings stop
// at the front one.
void appendBalcony(Lod0& lod0, const Balcony& balcony, double depth, double slabTop, std::optional<double> bandTop) {
    const glm::dvec2 start = balcony.start, dir = balcony.dir, outward = balcony.outward;
    const double length = balcony.length;
    const glm::dvec2 outer = start + outward * depth;
    const double bottom = bandTop ? std::min(slabTop - 0.05, std::max(slabTop - 0.2, *bandTop)) : slabTop - 0.2;
    lod0.part(PartKind::Balcony, kConcrete,
              [&](MeshBuilder& mb) { appendBox(mb, outer, dir, length, depth, bottom, slabTop, kConcrete); });
    const double top = slabTop + 1.0;
    lod0.part(PartKind::Railing, kMetal,
              [&](MeshBuilder& mb) { appendBox(mb, outer, dir, length, kRailing, slabTop, top, kMetal); });
    lod0.part(PartKind::Railing, kMetal,
              [&](MeshBuilder& mb) { appendBox(mb, start, outward, depth - kRailing, kRailing, slabTop, top, kMetal); });
    lod0.part(PartKind::Railing, kMetal, [&](MeshBuilder& mb) {
        appendBox(mb, start + dir * (length - kRailing), outward, depth - kRailing, kRailing, slabTop, top, kMetal);
    });
}

// The exterior wall of one storey from `bottom` up: one closed solid, a ring of segments
// that all use the rows of all the storey's openings; then its panes and door leaves, a
// part each.
void appendExteriorRing(const BuildContext& ctx, const Section& sec, const SectionPlan& plan,
                        const BuildingStyle& style, const Storey& storey, double bottom,
                        std::span<const std::vector<Opening>> openings, Lod0& lod0) {
    const std::size_t n = sec.footprint.size();
    const std::vector<double> levels = levelsOf(bottom, storey.y1, openings);
    const std::uint8_t outer = storey.floor == 0 && style.shop ? std::uint8_t{kConcrete} : style.wall;
    std::vector<Leaf> leaves;
    lod0.part(PartKind::Wall, outer, [&](MeshBuilder& mb) {
        for (std::size_t e = 0; e < n; ++e) {
            WallLine w = WallLine::between(sec.footprint[e], sec.footprint[(e + 1) % n], sec.inner[e],
                                           sec.inner[(e + 1) % n], ctx.recipe.buildings.wallThickness);
            w.uOffset = plan.run[e];
            appendWall(mb, w, openings[e], levels, false, {outer, kInteriorWall, style.wall, kTrim}, &leaves);
        }
    });
    for (const Leaf& leaf : leaves)
        lod0.part(leaf.glass ? PartKind::Window : PartKind::Door, leaf.glass ? kGlass : kWood,
                  [&](MeshBuilder& mb) { appendLeaf(mb, leaf); });
}

// Floor slabs. Above the ground the stairs room has a floor at its door and a landing where
// the flight from below arrives; the rest is the stairwell.
void appendFloorSlabs(const BuildContext& ctx, const Storey& storey, std::span<const Piece> pieces, Lod0& lod0) {
    const PolygonFrame& f = ctx.frame;
    const double vOrigin = glm::dot(f.origin, f.v);
    auto slab = [&](const Polygon2& polygon) {
        lod0.part(PartKind::Slab, kConcrete,
                  [&](MeshBuilder& mb) { mb.prism(polygon, storey.y0, storey.slabTop, kFloor, kFloor, kFloor); });
    };
    for (const Piece& piece : pieces) {
        if (piece.kind != RoomKind::Stairs || storey.floor == 0) {
            slab(piece.polygon);
            continue;
        }
        const StairFlight below = stairFlight(ctx, storey.floor - 1);
        for (const Polygon2& part : {clipStrip(piece.polygon, f.v, -1e30, vOrigin + below.openingV),
                                     clipStrip(piece.polygon, f.v, vOrigin + below.endV, 1e30)})
            if (part.size() >= 3 && signedArea(part) > 0.05) slab(part);
    }
}

// Where an interior wall meets the exterior wall: an end on the inner face `inner` (a convex
// polygon) is cut along it, whatever the angle, so that the two touch and do not overlap.
struct WallEnds {
    bool start = false, end = false;  // cut along `inner` at o0/i0, at o1/i1
};

// An interior wall a -> c on the storey's slab up to its ceiling, with a doorway centred
// `doorAt` (from a) along it where one fits; true when it got the doorway.
bool appendInteriorWall(Lod0& lod0, const InteriorRecipe& ir, const Storey& storey, std::span<const glm::dvec2> inner,
                        glm::dvec2 a, glm::dvec2 c, WallEnds ends, std::optional<double> doorAt) {
    WallLine w = WallLine::centred(a, c, ir.wallThickness);
    const glm::dvec2 o0 = w.o0;
    auto cut = [&](glm::dvec2& p, bool atStart) {
        const auto range = chord(inner, w.inward, glm::dot(w.inward, p), w.dir);
        if (range) p += w.dir * ((atStart ? range->first : range->second) - glm::dot(w.dir, p));
    };
    if (ends.start) cut(w.o0, true), cut(w.i0, true);
    if (ends.end) cut(w.o1, false), cut(w.i1, false);
    w.length = glm::dot(w.o1 - w.o0, w.dir);
    const double shift = glm::dot(w.o0 - o0, w.dir);  // positions along w start at its o0
    std::vector<Opening> ops;
    if (doorAt) {
        Opening d;
        d.s0 = *doorAt - shift - ir.doorWidth / 2, d.s1 = d.s0 + ir.doorWidth;
        // A notch from the wall's bottom: the slabs on both sides are the floor.
        d.z0 = storey.slabTop, d.z1 = std::min(storey.slabTop + ir.doorHeight, storey.y1 - 0.1);
        d.leaf = false;
        if (d.s0 > 0.05 + std::max(0.0, w.innerStart()) && d.s1 < std::min(w.length, w.innerEnd()) - 0.05)
            ops.push_back(d);
    }
    const std::vector<double> levels =
        levelsOf(storey.slabTop, storey.y1, std::span<const std::vector<Opening>>(&ops, 1));
    lod0.part(PartKind::InteriorWall, kPlaster, [&](MeshBuilder& mb) {
        appendWall(mb, w, ops, levels, true, {kInteriorWall, kInteriorWall, kInteriorWall, kInteriorWall});
    });
    return !ops.empty();
}

// Each room's wall on the corridor, with its door, and the cut at its far end (v1), shared
// with the next room of its side; an enfilade's cuts have a door into the next room.
void appendRoomWalls(const BuildContext& ctx, const Section& sec, const Storey& storey, std::span<const Piece> pieces,
                     Building& b, Lod0& lod0) {
    const InteriorRecipe& ir = ctx.recipe.interiors;
    const double half = 0.5 * ir.wallThickness;
    const PolygonFrame& f = ctx.frame;
    const FloorLayout& L = ctx.layout;
    const double uOrigin = glm::dot(f.origin, f.u), vOrigin = glm::dot(f.origin, f.v);
    const bool enfilade = L.kind == LayoutKind::Enfilade;
    for (std::size_t pi = 0; pi < pieces.size(); ++pi) {
        const Piece& piece = pieces[pi];
        const int roomId = storey.firstRoom + static_cast<int>(pi);
        if (piece.kind == RoomKind::Corridor) continue;
        if (!enfilade) {
            // A room with no wall on the corridor gets no cut either.
            const double uLine = piece.side == 0 ? L.corridor0 : L.corridor1;
            const auto range = chord(piece.polygon, f.u, uLine + uOrigin, f.v);
            if (!range) continue;
            const double a = range->first - vOrigin, c = range->second - vOrigin;
            if (c - a < 0.3) continue;
            const double doorAt = piece.kind == RoomKind::Stairs
                                      ? std::min(c - a - ir.doorWidth, ir.doorWidth / 2 + 0.3)
                                      : 0.5 * (c - a);
            // Along v: the first and last rooms' walls end on the front and back walls.
            const WallEnds ends{std::isinf(piece.v0), std::isinf(piece.v1)};
            if (appendInteriorWall(lod0, ir, storey, sec.inner, f.toPlan(uLine, a), f.toPlan(uLine, c), ends, doorAt))
                b.doors.push_back({roomId, storey.firstRoom, false, f.toPlan(uLine, a + doorAt)});
        }
        if (std::isinf(piece.v1)) continue;
        const auto range = chord(piece.polygon, f.v, piece.v1 + vOrigin, f.u);
        if (!range) continue;
        double a = range->first - uOrigin, c = range->second - uOrigin;
        // Cut walls run from low u to high u, from the corridor wall's face (not its middle)
        // to the exterior wall; an enfilade's from one exterior wall to the other.
        if (!enfilade) (piece.side == 0 ? c : a) += piece.side == 0 ? -half : half;
        if (c - a < 0.3) continue;
        const WallEnds ends{enfilade || piece.side == 0, enfilade || piece.side != 0};
        const bool door = appendInteriorWall(lod0, ir, storey, sec.inner, f.toPlan(a, piece.v1), f.toPlan(c, piece.v1),
                                             ends, enfilade ? std::optional<double>(0.5 * (c - a)) : std::nullopt);
        if (enfilade && door && pi + 1 < pieces.size())
            b.doors.push_back({roomId, roomId + 1, false, f.toPlan(0.5 * (a + c), piece.v1)});
    }
}

// The flight from this storey's slab up to the next one's, in the stairs room.
void appendFlights(const BuildContext& ctx, const Storey& storey, std::span<const Piece> pieces, Lod0& lod0) {
    const InteriorRecipe& ir = ctx.recipe.interiors;
    const PolygonFrame& f = ctx.frame;
    const FloorLayout& L = ctx.layout;
    for (const Piece& piece : pieces) {
        if (piece.kind != RoomKind::Stairs) continue;
        const StairFlight flight = stairFlight(ctx, storey.floor);
        double uSide = L.corridor1 + ir.wallThickness / 2 + 0.05;
        if (L.kind == LayoutKind::Enfilade) {
            uSide = INFINITY;
            for (glm::dvec2 p : piece.polygon) uSide = std::min(uSide, f.toFrame(p).x + 0.1);
        }
        lod0.part(PartKind::Stairs, kConcrete, [&](MeshBuilder& mb) {
            appendStairs(mb, f.toPlan(uSide + kStairWidth, flight.footV), f.v, kStairWidth, storey.slabTop,
                         ctx.floorY[storey.floor + 1] + ir.slabThickness, flight.tread);
        });
    }
}

// One storey of a section: its rooms, exterior openings and wall, the floor band under it
// (none on a section's first storey: the ground, or the terrace below a tower) and its
// interiors. Returns the openings of each exterior wall, for the LOD1 shell.
std::vector<std::vector<Opening>> buildStorey(const BuildContext& ctx, const Section& sec, const SectionPlan& plan,
                                              const BuildingStyle& style, int floor, Building& b, Lod0& lod0) {
    const double y0 = ctx.floorY[floor];
    const Storey storey{floor, y0, ctx.floorY[floor + 1], y0 + ctx.recipe.interiors.slabThickness,
                        static_cast<int>(b.rooms.size())};
    for (const Piece& p : plan.pieces) b.rooms.push_back({static_cast<int>(b.rooms.size()), floor, p.kind, p.polygon});
    b.roomsPerFloor.push_back(static_cast<int>(plan.pieces.size()));

    StoreyOpenings openings = placeOpenings(ctx, sec, plan, style, storey);
    b.windows.insert(b.windows.end(), openings.windows.begin(), openings.windows.end());
    b.doors.insert(b.doors.end(), openings.doors.begin(), openings.doors.end());
    const bool hasBand = floor > sec.firstFloor;
    for (const Balcony& balcony : openings.balconies)
        appendBalcony(lod0, balcony, balconyDepthOf(ctx.recipe), storey.slabTop,
                      hasBand ? std::optional<double>(y0 + kBandHeight / 2) : std::nullopt);
    // A tower's first storey stands on the terrace slab, which is as thick as a floor slab.
    const bool onTerrace = floor == sec.firstFloor && floor > 0;
    appendExteriorRing(ctx, sec, plan, style, storey, onTerrace ? storey.slabTop : y0, openings.walls, lod0);
    const double band = ctx.recipe.buildings.trimDepth;
    if (hasBand)
        lod0.part(PartKind::Trim, kTrim, [&](MeshBuilder& mb) {
            appendBand(mb, sec.footprint, band, y0 - kBandHeight / 2, y0 + kBandHeight / 2);
        });

    if (ctx.recipe.interiors.enabled) {
        appendFloorSlabs(ctx, storey, plan.pieces, lod0);
        appendRoomWalls(ctx, sec, storey, plan.pieces, b, lod0);
        if (floor + 1 < b.floors && ctx.layout.hasStairs) appendFlights(ctx, storey, plan.pieces, lod0);
    }
    return std::move(openings.walls);
}

// One wall of the LOD1 shell, storey by storey: a quad per column and row, glass or a door
// leaf where an opening is. `columns`: the opening edges of every storey on this wall.
void appendShellWall(const Section& sec, const SectionPlan& plan, const BuildingStyle& style, std::size_t e,
                     std::span<const double> columns, std::span<const std::vector<std::vector<Opening>>> storeys,
                     std::span<const std::vector<double>> storeyLevels, MeshBuilder& lod1) {
    const glm::dvec2 a = sec.footprint[e], c = sec.footprint[(e + 1) % sec.footprint.size()];
    const glm::dvec2 dir = glm::normalize(c - a);
    std::vector<double> cols{0.0};
    cols.insert(cols.end(), columns.begin(), columns.end());
    cols.push_back(glm::distance(a, c));
    auto point = [&](std::size_t k) { return k == 0 ? a : k + 1 == cols.size() ? c : a + dir * cols[k]; };
    const glm::dvec3 out = MeshBuilder::outward(dir);
    const MeshBuilder::Uv uv{MeshBuilder::Uv::Wall, dir, plan.run[e] - glm::dot(a, dir)};
    for (std::size_t storey = 0; storey < storeys.size(); ++storey) {
        const int floor = sec.firstFloor + static_cast<int>(storey);
        const std::vector<Opening>& ops = storeys[storey][e];
        const std::vector<double>& levels = storeyLevels[storey];
        const std::uint8_t wall = floor == 0 && style.shop ? std::uint8_t{kConcrete} : style.wall;
        for (std::size_t k = 0; k + 1 < cols.size(); ++k) {
            const double sm = 0.5 * (cols[k] + cols[k + 1]);
            const Opening* hit = nullptr;
            for (const Opening& op : ops)
                if (sm > op.s0 && sm < op.s1) hit = &op;
            for (std::size_t r = 0; r + 1 < levels.size(); ++r) {
                const double za = levels[r], zb = levels[r + 1];
                const bool inside = hit && za >= hit->z0 && zb <= hit->z1;
                const MeshBuilder::Glass* glass = inside && hit->glass ? &*hit->glass : nullptr;
                lod1.quad({point(k), za}, {point(k + 1), za}, {point(k + 1), zb}, {point(k), zb}, out,
                          inside ? std::uint8_t{glass ? kGlass : kWood} : wall, uv, glass);
            }
        }
    }
}

// The bottom and top caps of the LOD1 shell, with every column point on their boundary.
void appendShellCaps(const Section& sec, std::span<const std::vector<double>> edgeColumns, MeshBuilder& lod1) {
    const std::size_t n = sec.footprint.size();
    for (double y : {sec.y0, sec.y1}) {
        std::vector<glm::dvec2> ring;
        for (std::size_t e = 0; e < n; ++e) {
            const glm::dvec2 a = sec.footprint[e], c = sec.footprint[(e + 1) % n];
            const glm::dvec2 dir = glm::normalize(c - a);
            ring.push_back(a);
            for (double s : edgeColumns[e]) ring.push_back(a + dir * s);
        }
        const glm::dvec2 mid = centroid(sec.footprint);
        for (std::size_t i = 0; i < ring.size(); ++i) {
            const glm::dvec3 tri[3] = {{ring[i], y}, {ring[(i + 1) % ring.size()], y}, {mid, y}};
            const bool bottom = y == sec.y0;
            lod1.polygon(tri, bottom ? -MeshBuilder::up() : MeshBuilder::up(), bottom ? kConcrete : kRoofFlat, {});
        }
    }
}

// LOD1: the facade shell of a section, one closed prism. Every storey uses the union of all
// storeys' opening edges on its wall as columns, and every wall of a storey uses the rows of
// all that storey's openings, so storeys and corners meet vertex to vertex.
void appendShell(const BuildContext& ctx, const Section& sec, const SectionPlan& plan, const BuildingStyle& style,
                 std::span<const std::vector<std::vector<Opening>>> storeys, MeshBuilder& lod1) {
    const std::size_t n = sec.footprint.size();
    std::vector<std::vector<double>> storeyLevels;
    for (std::size_t storey = 0; storey < storeys.size(); ++storey) {
        const int floor = sec.firstFloor + static_cast<int>(storey);
        storeyLevels.push_back(levelsOf(ctx.floorY[floor], ctx.floorY[floor + 1], storeys[storey]));
    }
    std::vector<std::vector<double>> edgeColumns(n);  // opening edges along each wall, sorted
    for (std::size_t e = 0; e < n; ++e) {
        std::vector<double>& cols = edgeColumns[e];
        for (const auto& walls : storeys)
            for (const Opening& op : walls[e]) cols.insert(cols.end(), {op.s0, op.s1});
        std::sort(cols.begin(), cols.end());
        cols.erase(std::unique(cols.begin(), cols.end()), cols.end());
    }
    for (std::size_t e = 0; e < n; ++e)
        appendShellWall(sec, plan, style, e, edgeColumns[e], storeys, storeyLevels, lod1);
    appendShellCaps(sec, edgeColumns, lod1);
}

// Everything of one section's storeys: exterior walls with openings, interiors, the LOD1
// shell, and a cornice on top of a section that is not the building's top.
void buildSection(const BuildContext& ctx, const Section& sec, const BuildingStyle& style, bool isTop, Building& b,
                  Lod0& lod0, MeshBuilder& lod1) {
    SectionPlan plan;
    plan.pieces = layoutPieces(ctx, sec);
    // The front: of the edges along the frame's u, the one nearest the street.
    plan.front = bestEdge(sec.footprint, [&](glm::dvec2 p, glm::dvec2 q, glm::dvec2 dir) {
        return glm::dot(dir, ctx.frame.u) < 0.9 ? -INFINITY : -glm::dot(0.5 * (p + q) - ctx.frame.origin, ctx.frame.v);
    });
    plan.run = perimeterRun(sec.footprint);
    std::vector<std::vector<std::vector<Opening>>> storeys;  // per storey, per wall
    for (int floor = sec.firstFloor; floor < sec.firstFloor + sec.floorCount; ++floor)
        storeys.push_back(buildStorey(ctx, sec, plan, style, floor, b, lod0));
    appendShell(ctx, sec, plan, style, storeys, lod1);
    if (!isTop)
        lod0.part(PartKind::Trim, kTrim, [&](MeshBuilder& mb) {
            appendBand(mb, sec.footprint, ctx.recipe.buildings.trimDepth, sec.y1 - kBandHeight, sec.y1);
        });
}

// Convex pieces covering `a` outside `b` (both convex, counter-clockwise): piece k lies
// outside b's edge k and inside its edges before k. Slivers are left out.
std::vector<Polygon2> convexDifference(std::span<const glm::dvec2> a, std::span<const glm::dvec2> b) {
    std::vector<Polygon2> pieces;
    Polygon2 rest(a.begin(), a.end());
    for (std::size_t k = 0; k < b.size() && rest.size() >= 3; ++k) {
        const glm::dvec2 p = b[k], q = b[(k + 1) % b.size()];
        const glm::dvec2 m = inwardNormal(p, q);
        Polygon2 outside = simplifyPolygon(clipHalfPlane(rest, m, glm::dot(m, p)), 1e-9);
        if (outside.size() >= 3 && signedArea(outside) > 1e-3) pieces.push_back(std::move(outside));
        rest = clipHalfPlane(rest, -m, -glm::dot(m, p));
    }
    return pieces;
}

// The terrace on a base under its tower (LOD0): slabs covering the base's footprint outside
// the tower's inner wall face (the tower's walls stand on them, its rooms have their own
// floor slabs), each a part, and the parapet along the edge, a ring.
void appendTerrace(const BuildContext& ctx, std::span<const glm::dvec2> footprint, const Section& tower,
                   const RoofSettings& rs, Lod0& lod0) {
    const double y0 = tower.y0, top = y0 + ctx.recipe.interiors.slabThickness;
    for (const Polygon2& piece : convexDifference(footprint, tower.inner))
        lod0.part(PartKind::Roof, kConcrete,
                  [&](MeshBuilder& mb) { mb.prism(piece, y0, top, rs.wallMaterial, rs.flatMaterial, rs.wallMaterial); });
    if (!(rs.parapetHeight > 0.0)) return;
    const Polygon2 inner = mitreOffset(footprint, rs.parapetWidth);
    lod0.part(PartKind::Roof, kConcrete, [&](MeshBuilder& mb) {
        const double levels[2] = {top, top + rs.parapetHeight};
        for (std::size_t i = 0, n = footprint.size(); i < n; ++i) {
            const std::size_t j = (i + 1) % n;
            const WallLine w = WallLine::between(footprint[i], footprint[j], inner[i], inner[j], rs.parapetWidth);
            appendWall(mb, w, {}, levels, false, {rs.wallMaterial, rs.wallMaterial, rs.trimMaterial, rs.trimMaterial});
        }
    });
}

std::uint8_t pick(Rng& rng, std::initializer_list<std::uint8_t> options) {
    return *(options.begin() + static_cast<std::ptrdiff_t>(rng.below(options.size())));
}

// The outer face (the footprint) and the inner face of a section's exterior wall.
struct WallOutline {
    Polygon2 footprint, inner;
};

// The base's wall on `lot`, set back by `setback`; nullopt when the lot is too small or too
// thin for a building.
std::optional<WallOutline> baseOutline(const Lot& lot, const CityRecipe& recipe, double setback) {
    const Polygon2 footprint = dropShortEdges(simplifyPolygon(insetPolygon(lot.polygon, setback), 0.01), kMinEdge);
    if (footprint.size() < 3 || signedArea(footprint) < recipe.lots.minArea * 0.25 || !isConvex(footprint))
        return std::nullopt;
    const Polygon2 inner = mitreOffset(footprint, recipe.buildings.wallThickness);
    if (!isConvex(inner) || signedArea(inner) < 4.0) return std::nullopt;
    // No slivers: a building is at least kMinInnerWidth wide inside its walls both ways.
    const PolygonFrame extent = edgeFrame(inner, 0);
    if (extent.uMax - extent.uMin < kMinInnerWidth || extent.vMax - extent.vMin < kMinInnerWidth) return std::nullopt;
    return WallOutline{footprint, inner};
}

// A building's random choices, drawn from its generator in this order.
struct BuildingDraw {
    BuildingStyle style;
    int floors = 0;       // of the base
    int towerFloors = 0;  // 0: no tower
    RoofType roof = RoofType::Flat;
};

BuildingDraw drawBuilding(const CityRecipe& recipe, Rng& rng) {
    const BuildingRecipe& br = recipe.buildings;
    BuildingDraw draw;
    draw.style.wall = pick(rng, {kBrick, kConcrete, kPlaster});
    draw.style.shop = rng.uniform() < br.shopChance;
    draw.style.balconies = rng.uniform() < br.balconyChance;
    // Floors: skewed towards the low end.
    const double x = rng.uniform();
    const int floors = br.minFloors + static_cast<int>(std::floor(x * x * (br.maxFloors - br.minFloors + 1)));
    draw.floors = std::clamp(floors, br.minFloors, br.maxFloors);
    if (rng.uniform() < br.towerChance && br.towerExtraFloors > 0)
        draw.towerFloors = rng.range(std::min(2, br.towerExtraFloors), br.towerExtraFloors);
    // Roof type by weight.
    const double weights[4] = {recipe.roofs.flat, recipe.roofs.hip, recipe.roofs.gable, recipe.roofs.shed};
    double pickW = rng.uniform() * (weights[0] + weights[1] + weights[2] + weights[3]);
    int roofIndex = 0;
    while (roofIndex < 3 && pickW >= weights[roofIndex]) pickW -= weights[roofIndex++];
    draw.roof = static_cast<RoofType>(roofIndex);
    return draw;
}

// Lays the floors out from the street edge. Too shallow behind it for a flight of stairs:
// from a side edge instead (the entrance then opens on that side); failing that, as one
// storey without a tower. Sets ctx.frame and ctx.layout.
void chooseLayout(BuildContext& ctx, const WallOutline& base, std::size_t frontEdge, BuildingDraw& draw, Rng& rng) {
    const std::size_t n = base.footprint.size();
    std::optional<FloorLayout> layout = planLayout(ctx, base.inner, draw.floors + draw.towerFloors, rng);
    for (std::size_t side : {(frontEdge + 1) % n, (frontEdge + n - 1) % n}) {
        if (layout) break;
        ctx.frame = edgeFrame(base.footprint, side);
        layout = planLayout(ctx, base.inner, draw.floors + draw.towerFloors, rng);
    }
    if (!layout) {
        draw.floors = 1, draw.towerFloors = 0;
        ctx.frame = edgeFrame(base.footprint, frontEdge);
        layout = planLayout(ctx, base.inner, 1, rng);
    }
    ctx.layout = *layout;
}

// The tower's wall, set back from the base's; nullopt when the base's floors cannot carry
// one: a tower needs a corridor with rooms on both sides whose stairs survive the setback.
std::optional<WallOutline> towerOutline(const BuildContext& ctx, std::span<const glm::dvec2> footprint) {
    const BuildingRecipe& br = ctx.recipe.buildings;
    const FloorLayout& L = ctx.layout;
    const Polygon2 tower = dropShortEdges(simplifyPolygon(insetPolygon(footprint, br.towerSetback), 0.01), kMinEdge);
    if (L.kind != LayoutKind::DoubleLoaded || !L.hasStairs || tower.size() < 3 || !isConvex(tower)) return std::nullopt;
    const Polygon2 inner = mitreOffset(tower, br.wallThickness);
    if (!isConvex(inner)) return std::nullopt;
    const PolygonFrame& f = ctx.frame;
    const double uOrigin = glm::dot(f.origin, f.u), vOrigin = glm::dot(f.origin, f.v);
    const auto high = chord(inner, f.u, L.corridor1 + uOrigin, f.v);
    const bool stairsFit = high && high->first - vOrigin < L.stairs0 - 0.5 &&
                           high->second - vOrigin > L.stairs1 + 0.5 && !std::isinf(L.stairs0) && !std::isinf(L.stairs1);
    const auto low = chord(inner, f.u, L.corridor0 + uOrigin, f.v);
    if (!stairsFit || !low || !(low->second - low->first > 2.0)) return std::nullopt;
    return WallOutline{tower, inner};
}

// Roof settings from the recipe, in the building's wall material.
RoofSettings roofSettings(const CityRecipe& recipe, RoofType type, const BuildingStyle& style) {
    RoofSettings rs;
    rs.type = type;
    rs.parapetHeight = recipe.roofs.parapetHeight;
    rs.parapetWidth = recipe.roofs.parapetWidth;
    rs.slabThickness = recipe.interiors.slabThickness;
    rs.wallMaterial = style.wall;
    return rs;
}

// The roof over the top section `top`. A gable's ridge runs along the street and a shed rises
// towards it (the street's direction, not the layout's frame: floors may be laid out from a
// side edge); a shed rises over the whole depth, so its pitch keeps it a lean-to, not a wedge.
RoofSettings topRoofSettings(const CityRecipe& recipe, const BuildingStyle& style, RoofType type,
                             std::span<const glm::dvec2> top, glm::dvec2 streetDir) {
    RoofSettings rs = roofSettings(recipe, type, style);
    rs.pitch = recipe.roofs.pitch;
    rs.frontEdge = bestEdge(top, [&](glm::dvec2, glm::dvec2, glm::dvec2 dir) {
        return glm::dot(dir, streetDir) > 0.99 ? 0.0 : -INFINITY;  // the first edge along the street
    });
    if (rs.type == RoofType::Shed) {
        const PolygonFrame depth = edgeFrame(top, rs.frontEdge);
        rs.pitch = std::min(rs.pitch, kMaxShedRise / std::max(1.0, depth.vMax - depth.vMin));
    }
    return rs;
}

void addRoof(Building& b, const Roof& roof, bool pitched) {
    b.parts.push_back({PartKind::Roof, pitched ? std::uint8_t{kRoofTiles} : std::uint8_t{kConcrete},
                       static_cast<std::uint32_t>(b.lod0.triangleCount()),
                       static_cast<std::uint32_t>(roof.mesh.triangleCount())});
    appendMesh(b.lod0, roof.mesh);
    appendMesh(b.lod1, roof.mesh);
}

// Stairs join the stairs rooms of consecutive floors.
void joinStairs(Building& b) {
    for (std::size_t i = 0; i < b.rooms.size(); ++i) {
        if (b.rooms[i].kind != RoomKind::Stairs) continue;
        for (std::size_t j = i + 1; j < b.rooms.size(); ++j)
            if (b.rooms[j].kind == RoomKind::Stairs && b.rooms[j].floor == b.rooms[i].floor + 1) {
                b.doors.push_back({b.rooms[i].id, b.rooms[j].id, true, centroid(b.rooms[i].polygon)});
                break;
            }
    }
}

}  // namespace

namespace {

double drawSetback(const CityRecipe& recipe, Rng& rng) { return recipe.lots.setback + rng.uniform() * recipe.lots.setbackJitter; }

}  // namespace

bool lotHoldsBuilding(const Lot& lot, const CityRecipe& recipe, std::uint64_t seed) {
    Rng rng(deriveSeed(seed, "building", static_cast<std::uint64_t>(lot.id)));
    return baseOutline(lot, recipe, drawSetback(recipe, rng)).has_value();
}

Building buildBuilding(const Lot& lot, const CityRecipe& recipe, std::uint64_t seed) {
    Building b;
    b.id = b.lot = lot.id;
    Rng rng(deriveSeed(seed, "building", static_cast<std::uint64_t>(lot.id)));
    const double setback = drawSetback(recipe, rng);
    const std::optional<WallOutline> base = baseOutline(lot, recipe, setback);
    if (!base) return b;
    const Polygon2& footprint = base->footprint;

    // The footprint edge facing the lot's front street: parallel to it and nearest.
    const glm::dvec2 fa = lot.polygon[static_cast<std::size_t>(lot.frontEdge)];
    const glm::dvec2 fb = lot.polygon[(static_cast<std::size_t>(lot.frontEdge) + 1) % lot.polygon.size()];
    const glm::dvec2 frontDir = glm::normalize(fb - fa);
    const std::size_t frontEdge = bestEdge(footprint, [&](glm::dvec2 a, glm::dvec2, glm::dvec2 dir) {
        return glm::dot(dir, frontDir) * 100.0 - distanceToSegment(a, fa, fb);
    });

    BuildContext ctx{recipe, edgeFrame(footprint, frontEdge), {}, {}};
    BuildingDraw draw = drawBuilding(recipe, rng);
    chooseLayout(ctx, *base, frontEdge, draw, rng);
    const std::optional<WallOutline> tower = draw.towerFloors > 0 ? towerOutline(ctx, footprint) : std::nullopt;
    const int floors = draw.floors, towerFloors = tower ? draw.towerFloors : 0;
    b.floors = floors + towerFloors;
    b.baseFloors = floors;
    b.footprint = footprint;
    if (tower) b.towerFootprint = tower->footprint;
    b.wallMaterial = draw.style.wall;
    // The lot lies inside its block's kerb: the building stands on the kerb's top.
    const double ground = recipe.streets.curbHeight;
    ctx.floorY.resize(static_cast<std::size_t>(b.floors) + 1, ground);
    for (int fl = 0; fl < b.floors; ++fl) ctx.floorY[fl + 1] = ctx.floorY[fl] + storeyHeightOf(recipe.buildings, fl);

    Lod0 lod0(b.lod0, b.parts);
    MeshBuilder lod1(b.lod1);
    const Section baseSection{footprint, base->inner, 0, floors, ground, ctx.floorY[floors]};
    buildSection(ctx, baseSection, draw.style, !tower, b, lod0, lod1);
    if (tower) {
        // The base's roof: a flat terrace under the tower; in LOD0 slabs around the tower's
        // rooms and a parapet, so that nothing overlaps.
        const RoofSettings terrace = roofSettings(recipe, RoofType::Flat, draw.style);
        appendMesh(b.lod1, buildRoof(footprint, ctx.floorY[floors], terrace).mesh);
        const Section towerSection{tower->footprint, tower->inner, floors, towerFloors, ctx.floorY[floors],
                                   ctx.floorY[b.floors]};
        appendTerrace(ctx, footprint, towerSection, terrace, lod0);
        buildSection(ctx, towerSection, draw.style, true, b, lod0, lod1);
    }
    // Tall buildings and towers get flat roofs.
    const Polygon2& top = tower ? tower->footprint : footprint;
    const bool flat = b.floors > recipe.roofs.maxPitchedFloors || tower;
    const glm::dvec2 streetDir = glm::normalize(footprint[(frontEdge + 1) % footprint.size()] - footprint[frontEdge]);
    const RoofSettings rs = topRoofSettings(recipe, draw.style, flat ? RoofType::Flat : draw.roof, top, streetDir);
    const Roof roof = buildRoof(top, ctx.floorY[b.floors], rs);
    addRoof(b, roof, rs.type != RoofType::Flat);
    b.roof = rs.type;
    b.height = ctx.floorY[b.floors] - ground + roof.height;
    joinStairs(b);
    return b;
}

}  // namespace dawnforge::procgen
