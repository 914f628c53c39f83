#pragma once
// One building on one lot: floors, facades split into floors and bays (walls with
// thickness, windows, doors, balconies, trims), a roof, and interiors (rooms off a
// corridor, interior walls with doors, floor slabs, a stairs core). LOD0 carries
// everything; LOD1 is the facade shell whose windows carry the interior-mapping
// attributes, so a far view shows rooms without geometry.
//
// Window glass vertices (material kGlass) carry, for interior mapping:
//   TEXCOORD_0 (uv0): position on the room's front face in metres from its lower-left corner
//   TEXCOORD_1 (uv1): (room depth in metres, room index within the building)
//   TEXCOORD_2 (uv2): (room width, room height) in metres
// Every other vertex has uv1 = uv2 = (0, 0) and uv0 in metres for atlas tiling.
#include <dawnforge/core/mesh.hpp>
#include <dawnforge/procgen/geometry2d.hpp>
#include <dawnforge/procgen/plan.hpp>
#include <dawnforge/procgen/recipe.hpp>
#include <dawnforge/procgen/roof.hpp>

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

namespace dawnforge::procgen {

enum class RoomKind { Room, Corridor, Stairs };
const char* roomKindName(RoomKind kind);  // "room", "corridor", "stairs"

struct Room {
    int id = 0;          // index in Building::rooms
    int floor = 0;
    RoomKind kind = RoomKind::Room;
    Polygon2 polygon;    // convex, inside the exterior walls' inner face
};

// A passage between two rooms (`to` = -1: the outside, i.e. the entrance). Stairs join the
// stairs rooms of consecutive floors.
struct Door {
    int from = 0;
    int to = -1;
    bool stairs = false;
    glm::dvec2 position{0.0};  // plan position (the stairs' foot for stairs)
};

struct Window {
    int room = 0;            // the room behind it
    int floor = 0;
    glm::dvec2 centre{0.0};  // plan point on the wall's inner face, at the window's middle
    glm::dvec2 inward{0.0};  // unit normal into the building
    double width = 0, sill = 0, height = 0;  // sill: height of the bottom above the ground
    double roomDepth = 0;    // from the inner face to the room's far wall along `inward`
    bool door = false;       // a balcony door
};

// What a closed solid of LOD0 is: fracture breaks each part its own way (by material) and
// glues the parts where they touch.
enum class PartKind : std::uint8_t { Wall, Trim, Slab, InteriorWall, Stairs, Balcony, Railing, Window, Door, Roof };
const char* partKindName(PartKind kind);  // "wall", "trim", "slab", "interior_wall", "stairs", "balcony", "railing", "window", "door", "roof"
std::optional<PartKind> partKindFromName(std::string_view name);

// One closed solid of LOD0: triangles [firstTriangle, firstTriangle + triangles) of
// Building::lod0. Parts touch (share faces) but never overlap.
struct BuildingPart {
    PartKind kind = PartKind::Wall;
    std::uint8_t material = 0;  // what it is made of (core/materials.hpp), not its surface: a slab is concrete
    std::uint32_t firstTriangle = 0, triangles = 0;
};

struct Building {
    int id = 0;                 // = its lot's id
    int lot = 0;
    Polygon2 footprint;         // the base section
    Polygon2 towerFootprint;    // empty without a tower
    int floors = 0;             // all sections
    int baseFloors = 0;         // floors of the base section
    double height = 0;          // top of the roof above the ground
    RoofType roof = RoofType::Flat;
    std::uint8_t wallMaterial = 0;
    std::vector<Room> rooms;    // floor by floor
    std::vector<Door> doors;
    std::vector<Window> windows;
    std::vector<int> roomsPerFloor;
    Mesh lod0;                  // walls, windows, doors, balconies, trims, roof, interiors
    std::vector<BuildingPart> parts;  // LOD0 as closed solids, in triangle order, every triangle in one
    Mesh lod1;                  // facades and roof only
};

// Part `part` of `lod0` on its own: its triangles, and the vertices they use with all their
// attributes, in order. Throws InputError when the part's triangles are not in the mesh.
Mesh partMesh(const Mesh& lod0, const BuildingPart& part);

// The building on `lot`, or std::nullopt-like empty building (floors == 0) when the lot
// cannot hold one (too small once set back). Deterministic in (lot, recipe, seed).
Building buildBuilding(const Lot& lot, const CityRecipe& recipe, std::uint64_t seed);
// Whether buildBuilding() puts a building on `lot`, without building it (a world's plan).
bool lotHoldsBuilding(const Lot& lot, const CityRecipe& recipe, std::uint64_t seed);

}  // namespace dawnforge::procgen
