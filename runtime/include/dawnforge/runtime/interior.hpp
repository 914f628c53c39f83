#pragma once
// Perspective interior mapping for window glass ("Perspective Interior Mapping" and its extended
// form with a middle and a front layer, Undawn, GDC 2024; see shared/seed): a room behind the glass
// from one ray–box exit and one 2D picture per room style instead of a cubemap. These are the CPU
// reference of runtime/shaders/interior.glsl, which mirrors them formula for formula, and the
// generator of the textures that shader samples.
//
// Room space: x = right as seen from outside / room width, y = up from the floor / room height,
// z = depth behind the glass / room depth; the room is [0,1]³ and the glass is its z = 0 face.
//
// The picture: the room seen from a pinhole at (0.5, 0.5, -b/(1-b)) through the glass, so a room
// point p lands at uv = 0.5 + (p.xy - 0.5) * s(p.z), s(z) = 1 / (1 + z*(1/b - 1)). The glass's
// edges are the picture's edges, the back wall fills the central b×b square and the side walls,
// floor and ceiling are the four trapezoids around it; uv is continuous across the faces.
#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <vector>

namespace dawnforge::runtime {

enum class RoomFace { Back = 0, Left = 1, Right = 2, Floor = 3, Ceiling = 4 };

struct RoomHit {
    RoomFace face;
    glm::dvec3 point;  // room space, on `face`
    double t;          // roomExit(): ray parameter; roomPointAtUv(): 1/s(z), the parameter along
                       // the picture's pinhole ray (1 on the glass, 1/b on the back wall)
};

// The view direction in room space: (dot(V,T)/width, dot(V,Up)/height, dot(V,-N)/depth) with
// T = normalize(cross(-N, +Y)) (right as seen from outside) and Up = cross(T, -N) (+Y for vertical
// glass). `normal` is the glass's outward normal; roomSize = (width, height, depth) in metres.
glm::dvec3 roomRay(glm::dvec3 viewDir, glm::dvec3 normal, glm::dvec3 roomSize);

// Where a ray from the glass (origin in [0,1]³, normally z = 0) going inwards (direction.z > 0,
// any length) leaves the room box: one exit, t = min over the axes of the distance to the wall the
// ray heads for over |d_i| (axes with d_i = 0 never bound it). Ties go to x, then y, then z.
RoomHit roomExit(glm::dvec3 origin, glm::dvec3 direction);

inline constexpr double kBackWallShare = 0.5;  // b: the back wall's share of the picture's side

// Where a room point on one of the five faces appears in the picture; inside [0,1]².
glm::dvec2 roomTextureUv(glm::dvec3 roomPoint, double backShare = kBackWallShare);

// The inverse, used to paint the picture: the face and room point seen at picture uv
// (clamped into [0,1]²). Diagonals of the picture are room edges; they go to the side walls.
RoomHit roomPointAtUv(glm::dvec2 uv, double backShare = kBackWallShare);

// Middle layer: the ray's hit with the plane z = depth (0 < depth < 1), if it is ahead (t > 0)
// and inside the room box (so in front of the box exit). Returns the room-space point.
std::optional<glm::dvec3> middleLayerHit(glm::dvec3 origin, glm::dvec3 direction, double depth);

// The room style of a window, from the building instance id and the room index: a 32-bit hash
// (lowbias32) that interior.glsl's roomStyle() reproduces bit for bit. styles > 0.
int roomStyle(std::uint32_t building, std::uint32_t room, int styles);

struct InteriorTextures {
    int roomSize = 256;  // each style's picture is roomSize² texels
    int styles = 8;      // pictures side by side in a row: width = roomSize*styles, height = roomSize
    // RGBA8 sRGB, row 0 first and row 0 is v = 0 (the floor side: upload as is, no flip), alpha 255.
    std::vector<std::uint8_t> rooms;
    // Same layout: cut-outs seen square-on at the middle plane (u = room x, v = room y), straight
    // alpha, 0 outside them; transparent texels carry the nearest cut-out's colour so that
    // filtering and mipmaps do not darken the silhouettes' edges.
    std::vector<std::uint8_t> middle;
};

// Each style: walls (paint, stripes or dots, a skirting board), a floor (planks, tiles or
// carpet), a ceiling with a lamp that lights the room, a window, door or picture on some walls,
// painted per texel (2×2 samples) through roomPointAtUv() with the default kBackWallShare, so the
// picture is the perspective the shader expects. Deterministic: a function of the arguments only.
// roomSize: a power of two >= 16; styles >= 1.
InteriorTextures generateInteriors(int roomSize = 256, int styles = 8);

}  // namespace dawnforge::runtime
