#pragma once
// Where irradiance probes go (issue 14, items 1, 5 and 8), on the CPU: the seed's quality
// presets, probes on a world-aligned lattice around the camera ordered near to far, empty
// space culled with a sparse grid of the proxy boxes, positions inside a box rejected, and
// the cache that keeps probes while the camera wanders.
//
// Probes sit at lattice points spacing · (i + ½, j + ½, k + ½): the same point has the same
// key from any camera position, so a probe captured once is reused when the camera returns.
#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace dawnforge::runtime {

enum class ProbeBasis { AmbientCube, Sh };

// The seed's table: low (ambient cube, 150 probes/s, 256² cache, 4 m), mid (ambient cube,
// 300/s, 512², 2 m), high (SH with PRT, 600/s, 256², 1 m).
struct ProbePreset {
    std::string_view name;
    ProbeBasis basis = ProbeBasis::AmbientCube;
    double probesPerSecond = 300.0;
    int cacheTexels = 512;  // the cache texture is cacheTexels² texels, 5 × 5 per probe
    double spacing = 2.0;   // metres between probes
    int cacheProbes() const { return (cacheTexels / 5) * (cacheTexels / 5); }
};
// "low", "mid" or "high"; nullopt for anything else ("off" is the caller's).
std::optional<ProbePreset> probePreset(std::string_view name);

// An oriented box of the scene (the bake's flat-coloured proxies): centre, unit horizontal
// axes u and w, half sizes along u, +Y and w. Destruction pieces (capture only, never placed
// around) may turn any way: their `up` is then not +Y.
struct ProbeBox {
    glm::dvec3 centre{0.0};
    glm::dvec3 u{1, 0, 0}, w{0, 0, 1};
    glm::dvec3 up{0, 1, 0};
    glm::dvec3 halfSize{0.0};
    bool ground = false;  // terrain, kerbs, streets: everything under the box is solid too
    std::array<glm::vec3, 6> colours{};  // linear albedo of the faces +u, -u, +y, -y, +w, -w
    int building = -1;                   // the city building it stands for ("building_NNNNN"), or -1
};

// The boxes of a bake's proxies.json (bake/proxies.hpp); "ground", "kerb" and "street" boxes
// are ground. A malformed document is an InputError naming `source`.
std::vector<ProbeBox> parseProbeBoxes(const std::string& json, const std::string& source);

using ProbeKey = std::uint64_t;  // a lattice point, packed (21 bits per axis, offset)
ProbeKey probeKey(glm::ivec3 lattice);
glm::ivec3 probeLattice(ProbeKey key);

struct PlacedProbe {
    ProbeKey key = 0;
    glm::dvec3 position{0.0};
    int slot = -1;  // its tile in the cache texture, once the cache holds it
};

// The probe field's geometry: boxes bucketed in a sparse grid of `cell`-metre columns.
class ProbeField {
public:
    explicit ProbeField(std::vector<ProbeBox> boxes, double cell = 8.0);
    // Whether p is inside a box, or under a ground box (a probe there would see only insides).
    bool inside(glm::dvec3 p) const;
    // Whether a box comes within `reach` metres of p (a probe is worth placing there).
    bool near(glm::dvec3 p, double reach) const;

    // Lattice probes in the box `halfExtent` around `camera` that are near a box (within one
    // spacing) and inside none, nearest first (ties by key).
    std::vector<PlacedProbe> place(glm::dvec3 camera, glm::dvec3 halfExtent, double spacing) const;

private:
    std::vector<ProbeBox> boxes_;
    double cell_;
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> columns_;  // (x, z) cell → boxes overlapping it
    std::vector<std::uint32_t> candidates(glm::dvec3 p, double reach) const;
};

// The probes kept: those of the lighting area first (the player's surroundings, high
// priority), then the caching area (kept while there is room, perhaps outdated). When full, the
// probe farthest from the camera goes. Each held probe owns one slot (a tile of the cache
// texture) in [0, capacity); a slot freed by an evicted probe is given to the next one.
class ProbeCache {
public:
    explicit ProbeCache(int capacity);
    // Makes room for `wanted` (nearest first): returns the ones not yet held, in order, at
    // most `budget` of them (the frame's capture budget), and holds them, with their slots.
    std::vector<PlacedProbe> admit(std::span<const PlacedProbe> wanted, glm::dvec3 camera, int budget);
    bool holds(ProbeKey key) const { return held_.count(key) != 0; }
    // The slot of a held probe, or -1.
    int slotOf(ProbeKey key) const;
    std::size_t size() const { return held_.size(); }

private:
    struct Held {
        glm::dvec3 position;
        int slot;
    };
    int capacity_;
    std::unordered_map<ProbeKey, Held> held_;
    std::vector<int> free_;  // free slots, the lowest last
};

}  // namespace dawnforge::runtime
