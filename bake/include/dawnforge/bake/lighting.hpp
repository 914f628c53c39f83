#pragma once
// The four lightmap channels (Dentro: "Baking for Dynamic lighting", the seed talk), baked with
// Embree rays over any set of receivers; bake.hpp feeds it a city.
//
//   R  sky: irradiance from a uniform sky of radiance 1/π over the upper hemisphere (so an
//      unobstructed horizontal surface gets exactly 1), direct (the cosine-weighted fraction
//      of rays that escape upwards) plus its bounces. The runtime multiplies it by the time of
//      day's sky colour.
//   G  sun bounce: light of a unit directional sun (irradiance 1 on a surface facing it),
//      averaged over the daytime path (06:00 to 18:00, uniform in time; sunDirection()), after
//      one or more bounces; the direct sun is not in it (the runtime draws the sun with its
//      shadow map). The runtime multiplies it by the sun's colour.
//   B  ambient occlusion: the cosine-weighted fraction of rays that travel kAoRadius (1 m by
//      default) without hitting anything.
//   A  artificial light: the ceiling lamps of lit rooms (roomLampLit(): the runtime's hash for
//      lit windows), direct with occlusion plus bounces. The runtime multiplies it by the lamp
//      colour and the night factor.
//
// Bounces gather: each bounce casts `samples` cosine rays per texel and reads the previous
// bounce's irradiance where they land (bilinear in the hit surface's lightmap), times the hit
// material's albedo: E_k+1(x) = mean(albedo(y) · E_k(y)). The texel's own sample point lies on
// its triangle (charts.hpp); texels whose rays see back faces more than a quarter of the time
// lie inside something and are filled by dilation.
//
// Determinism: every texel's random numbers come from (seed, pass, receiver, texel); work is
// cut into fixed chunks of texels whose results go to the texel's own slot; sums run in a
// fixed order; so the result does not depend on the thread count.
#include <dawnforge/bake/charts.hpp>

#include <dawnforge/core/progress.hpp>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace dawnforge::bake {

enum Channel : int { kSkyChannel = 0, kSunChannel = 1, kAoChannel = 2, kLampChannel = 3 };

// Greyscale albedo (luminance of materialMeanColour, core/materials.hpp) per material ID.
std::array<float, 16> defaultAlbedo();

// The sun's unit direction (towards it) at `hours`, glTF axes: rises in the east (+x) at
// 6:00, 55° high in the south (+z) at noon, sets in the west at 18:00 (runtime/src/sky.cpp).
glm::dvec3 sunDirection(double hours);

// Ceiling lamps: a point of intensity kLampIntensity below its own height (smoothstep from
// -0.2 to 0.2 in the sine of the angle below the horizontal), inverse-square with a softening
// radius kLampSoftening, windowed to zero at kLampRange by (1 - (d/range)^4)^2:
//   E = I · s(dir.y) · max(0, n·dir) · window(d) / (d² + r²), dir = unit (lamp - point).
inline constexpr double kLampIntensity = 7.5;  // a floor 2.74 m below gets irradiance 0.97
inline constexpr double kLampSoftening = 0.1;
inline constexpr double kLampRange = 8.0;
inline constexpr double kLampBelowCeiling = 0.3;  // lamps hang this far under the ceiling
double lampIrradiance(glm::dvec3 lamp, glm::dvec3 point, glm::dvec3 normal);

// Whether room `room` of building `building` has its lamp on at night: the runtime's lit-window
// hash (interior.glsl, roomLampLit()), bit for bit.
bool roomLampLit(std::uint32_t building, std::uint32_t room);

// Street lamps (city.json's "lamps") are the same kind of light, this many times brighter:
// the pavement under a lamp head 5.4 m up gets an irradiance of about 0.6.
inline constexpr float kStreetLampIntensity = 4.0f;

struct Lamp {
    glm::vec3 position{0.0f};
    std::uint32_t receiver = 0;  // lights only this receiver's texels (its building, or a street lamp's neighbours)
    float intensity = 1.0f;      // × kLampIntensity
};

// A window of a room: a glass triangle and the direction into the room. The room's values
// (room table) are the irradiance of the surfaces seen from its windows.
struct RoomWindow {
    std::uint32_t receiver = 0;
    std::uint32_t slot = 0;  // the room's slot in the receiver's room table
    glm::vec3 a{0.0f}, b{0.0f}, c{0.0f};
    glm::vec3 inward{0.0f};
};

// One lightmap atlas: a building (LOD0 and LOD1 together) or a ground tile.
struct ReceiverInput {
    std::string name;
    std::span<const glm::vec3> positions;       // world space
    std::span<const std::uint32_t> indices;
    std::span<const std::uint8_t> materials;    // per triangle
    std::span<const std::uint8_t> occluder;     // per triangle: 1 if rays hit it (LOD0, ground), 0 (LOD1, glass)
    std::span<const float> rayOffset;           // per triangle: how far samples start off the surface (m)
    LightmapLayout layout;                      // packLightmap() of its charts; room table = extra block 0
    std::uint32_t rooms = 0;                    // room table slots
};

// The room table: slot i is a kChartAlign² block of texels (exact at every kept mip level).
inline constexpr int kRoomTableColumns = 16;
glm::ivec2 roomTableSize(std::uint32_t rooms);                  // texels; (0,0) for no rooms
glm::ivec2 roomTexel(glm::ivec2 tableOrigin, std::uint32_t slot);  // the block's first texel

struct LightingSettings {
    int samples = 32;         // hemisphere rays per texel per pass (direct, each bounce)
    int sunSamples = 16;      // sun positions per texel along the day's path
    int bounces = 2;          // gathers after the direct pass
    int roomSamples = 256;    // rays per room for the room table
    double aoRadius = 1.0;    // metres
    std::array<float, 16> albedo = defaultAlbedo();
    std::uint64_t seed = 1;
};

struct ReceiverLighting {
    // width × height × 4 floats: R sky, G sun bounce, B AO, A lamp; every block dilated.
    std::vector<float> channels;
    std::vector<glm::vec3> rooms;  // per slot: sky, sun (direct + bounce), lamp of the room's surfaces
    std::size_t texels = 0;        // sampled texels
    std::size_t invalid = 0;       // of which inside geometry (filled by dilation)
};

struct LightingStats {
    std::size_t texels = 0;
    std::size_t rays = 0;          // all: hemisphere, sun, lamp, bounce and room rays
    double raySeconds = 0.0;       // wall time of the passes that trace (the bake's rays/s = rays / raySeconds)
    double dilateSeconds = 0.0;
};

struct Lighting {
    std::vector<ReceiverLighting> receivers;
    LightingStats stats;
};

class RayScene;

// The ray scene bakeLighting traces: geometry i holds receiver i's triangles with occluder = 1,
// in order.
std::unique_ptr<RayScene> occluderScene(std::span<const ReceiverInput> receivers);

// `scene`: occluderScene(receivers) when the caller has one already; null to build it.
Lighting bakeLighting(std::span<const ReceiverInput> receivers, std::span<const Lamp> lamps,
                      std::span<const RoomWindow> windows, const LightingSettings& settings,
                      const ProgressFn& progress = {}, const RayScene* scene = nullptr);

// Triangles of polygons that lie inside solids (caps between storeys, faces buried in walls):
// all but one of `probes` cosine rays from random points of the polygon (a patch: triangles
// sharing vertex indices) meet back faces. They need no lightmap texels. Per triangle, 1 = hidden;
// only occluders with texel size > 0 are probed (LOD1 shells are drawn alone, never hidden).
std::vector<std::vector<std::uint8_t>> hiddenTriangles(const RayScene& scene, std::span<const ReceiverInput> receivers,
                                                       std::span<const std::vector<float>> texelMetres, int probes = 8,
                                                       std::uint64_t seed = 1);

// Fills every unsampled texel of each block with the mean of its already-filled 8-neighbours in
// the same block, ring by ring outwards from the sampled texels (a block with none gets
// `empty`). `values` holds `channels` floats per texel; `filled` marks the sampled texels.
void dilate(std::span<float> values, int channels, std::span<const std::uint8_t> filled,
            std::span<const std::int32_t> owners, glm::ivec2 size, std::span<const float> empty);

// Stored bytes of a channel value: round(255 · sqrt(clamp(v / range, 0, 1))); the square root
// keeps dark interiors from banding. Ranges: R 2, G 2, B 1, A 4.
inline constexpr std::array<float, 4> kChannelRange{2.0f, 2.0f, 1.0f, 4.0f};
std::uint8_t encodeChannel(float value, int channel);
float decodeChannel(std::uint8_t stored, int channel);

}  // namespace dawnforge::bake
