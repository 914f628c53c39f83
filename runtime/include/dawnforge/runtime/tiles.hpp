#pragma once
// The CPU half of streaming a world (ARCHITECTURE.md 7, Streaming): a world's tileset.json (OGC
// 3D Tiles 1.1 as `dawnforge world build` writes it) read into a tree of nodes in the runtime's
// coordinates, the per-frame selection of what to draw by screen-space error (REPLACE
// refinement, never a hole), and the choice of what leaves the resident set.
//
// Coordinates: 3D Tiles is z-up in plan metres (x east, y north); the runtime is y-up with
// (x, h, −y). Transforms are translations (the only ones dawnforge writes); the content of a
// node is in its own frame, `offset` from the runtime's origin, so its vertices stay small.
#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace dawnforge::runtime {

struct TileNode {
    std::string name;             // "tile 1_2", "hlod 2_0_0" or "root": for messages
    std::filesystem::path file;   // the content (a GLB); empty: none
    bool hlod = false;            // an HLOD mesh (the bake in its vertices) rather than a tile's city folder
    double geometricError = 0.0;  // metres
    glm::dvec3 offset{0.0};       // the content's frame, runtime coordinates
    glm::dvec3 boxMin{0.0}, boxMax{0.0};    // bounding volume, runtime coordinates (culling)
    glm::dvec3 areaMin{0.0}, areaMax{0.0};  // the box less the far land (extras.area, in its frame): what error is measured from
    int parent = -1, depth = 0;
    std::vector<int> children;
};

struct Tileset {
    std::filesystem::path dir;
    std::vector<TileNode> nodes;  // nodes[0] is the root; parents before children
    glm::dvec3 boundsMin{0.0}, boundsMax{0.0};  // the root's box without far land
};

// Reads DIR/tileset.json. InputError (naming the file) when it is missing, not JSON, not 3D
// Tiles 1.x, uses a transform other than a translation, a bounding volume other than a box,
// additive refinement, or content other than a GLB; a content file that is missing is not an
// error here (the streamer skips it with a warning and draws its parent).
Tileset readTileset(const std::filesystem::path& dir);
Tileset parseTileset(const std::string& json, const std::filesystem::path& dir, const std::string& file);

struct SelectionCamera {
    glm::dvec3 position{0.0};
    glm::dmat4 viewProj{1.0};  // runtime coordinates (culling)
    double screenHeight = 720.0;
    double fovYRadians = 0.87;
};

// 3D Tiles' screen-space error: geometricError × height / (2 d tan(fov/2)), d the distance
// from the camera to the node's area box (infinite at d = 0).
double screenSpaceError(const TileNode& node, const SelectionCamera& camera);

struct TileSelection {
    std::vector<int> draw;    // nodes to draw: each point the camera sees is covered exactly once
    std::vector<int> wanted;  // nodes whose content the frame needs, coarse before fine, near before far
    bool complete = true;     // every wanted node is resident and drawn: nothing stands in for its children
};

// Walks the tree from the root: a node in the frustum whose error on screen exceeds
// `maxScreenError` pixels refines into its children, but only when every child's subtree
// can be drawn from resident content; until then the node draws itself (when resident), so a
// parent stays until all its children are there and the picture never has a hole.
// `unavailable` nodes (content missing or broken) count as drawn by their parent.
TileSelection selectTiles(const Tileset& tiles, const SelectionCamera& camera, double maxScreenError,
                          const std::function<bool(int)>& resident, const std::function<bool(int)>& unavailable);

struct ResidentTile {
    int node = -1;
    std::size_t bytes = 0;
    std::uint64_t lastUsed = 0;  // the last frame that wanted or drew it
};

// What leaves when the resident bytes exceed `budget`: least recently used first (ties by node),
// never a node used within the last `keepFrames` frames, until the total is at most
// lowWater × budget. The gap between the budget and the low water is the hysteresis: a camera
// at a border does not load and evict the same tiles frame after frame.
std::vector<int> chooseEvictions(std::span<const ResidentTile> resident, std::size_t budget, double lowWater,
                                 std::uint64_t frame, std::uint64_t keepFrames);

}  // namespace dawnforge::runtime
