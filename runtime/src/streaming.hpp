#pragma once
// A world's tiles streamed around the camera (private to the renderer; ARCHITECTURE.md 7,
// Streaming). Each frame: the selection by screen-space error (tiles.hpp), the loads it wants
// handed to worker threads (file reading and parsing never happen on the frame's thread), the
// finished ones uploaded within a per-frame byte budget, and what nobody used lately evicted
// under the resident budget. `render` waits until its camera's selection is resident.
#include "city_gpu.hpp"
#include "flares.hpp"

#include <dawnforge/runtime/probe_placement.hpp>
#include <dawnforge/runtime/renderer.hpp>
#include <dawnforge/runtime/tiles.hpp>

#include <condition_variable>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <thread>
#include <vector>

namespace dawnforge::runtime {

// The ids of the buildings a world's plan.json gives its tiles; none when it has no plan.json.
std::optional<std::set<std::uint32_t>> worldBuildings(const std::filesystem::path& worldDir);

class TileStreamer {
public:
    TileStreamer() = default;
    ~TileStreamer();
    TileStreamer(const TileStreamer&) = delete;
    TileStreamer& operator=(const TileStreamer&) = delete;

    // Reads the manifest (InputError when it is missing or broken) and starts the workers.
    // `until`: building id → the scene time a destruction replaces it.
    // `proxies`: also read each tile's bake/proxies.json (the probes').
    void open(const std::filesystem::path& worldDir, const StreamingOptions& options, std::map<std::uint32_t, double> until,
              bool proxies);
    const Tileset& tiles() const { return tiles_; }

    // One frame's streaming for `camera` (and, ahead of it, `prefetch` when given).
    void update(const SelectionCamera& camera, const SelectionCamera* prefetch, StreamingStats& stats);

    struct Drawn {
        CityGpu* city;
        glm::dvec3 offset;  // its frame, runtime coordinates
        bool hlod;
        const std::vector<StreetLamp>* lamps;  // in its frame
        const std::vector<ProbeBox>* proxies;  // in its frame (empty unless asked for)
        int node;
    };
    // What the last update selected, in drawing order.
    std::vector<Drawn> drawn();

private:
    enum class State { Absent, Queued, Loaded, Resident, Failed };  // Queued: asked for or in a worker's hands
    struct Entry {
        State state = State::Absent;
        std::optional<CityGpu> gpu;
        std::vector<StreetLamp> lamps;
        std::vector<ProbeBox> proxies;
        std::uint64_t lastUsed = 0;
        std::size_t estimate = 0;  // bytes it will hold once loaded (estimateBytes)
    };
    struct Result {
        int node;
        std::optional<CityCpu> city;
        std::vector<StreetLamp> lamps;
        std::vector<ProbeBox> proxies;
        std::string error;
    };

    void work();
    Result loadNode(int node) const;
    void collect(StreamingStats& stats);
    void request(const std::vector<int>& wanted);
    std::size_t uploadSome(const std::vector<int>& wanted, std::size_t budget);
    void evict(const std::vector<int>& wanted, StreamingStats& stats);
    TileSelection select(const SelectionCamera& camera) const;
    std::vector<int> nearestFirst(std::vector<int> nodes, glm::dvec3 camera) const;
    std::size_t residentBytes() const;
    bool pending() const;

    Tileset tiles_;
    StreamingOptions options_;
    std::map<std::uint32_t, double> until_;
    bool proxies_ = false;
    std::vector<Entry> entries_;
    std::vector<int> drawn_;
    std::uint64_t frame_ = 0;

    std::mutex mutex_;
    std::condition_variable wake_, done_;
    std::deque<int> queue_;         // guarded; the frame thread rewrites it every frame
    std::vector<Result> results_;   // guarded
    int busy_ = 0;                  // guarded: loads in a worker's hands
    bool stop_ = false;             // guarded
    std::vector<std::thread> workers_;
};

}  // namespace dawnforge::runtime
