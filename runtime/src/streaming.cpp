#include "streaming.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/read_file.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <set>

namespace dawnforge::runtime {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }
constexpr std::size_t kMB = 1024u * 1024u;

}  // namespace

namespace {

// What a node's content will hold on the GPU, until it is known: about twice its GLB (vertices
// grow to 64 bytes) and, for a tile, about four times its bake's PNGs (decoded to RGBA, two
// levels, in shelves with some room left).
std::size_t estimateBytes(const TileNode& node) {
    if (node.file.empty()) return 0;
    std::error_code ec;
    std::size_t bytes = 2 * std::size_t(std::filesystem::file_size(node.file, ec));
    if (ec) return 0;
    if (node.hlod) return bytes;
    for (const auto& e : std::filesystem::directory_iterator(node.file.parent_path() / "bake", ec))
        if (e.path().extension() == ".png") bytes += 4 * std::size_t(e.file_size(ec));
    return bytes;
}

}  // namespace

std::optional<std::set<std::uint32_t>> worldBuildings(const std::filesystem::path& worldDir) {
    const std::filesystem::path file = worldDir / "plan.json";
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) return std::nullopt;
    try {
        const nlohmann::json plan = nlohmann::json::parse(readTextFile(file));
        std::set<std::uint32_t> ids;
        for (const nlohmann::json& tile : plan.at("tiles"))
            for (const nlohmann::json& id : tile.at("buildings")) ids.insert(id.get<std::uint32_t>());
        return ids;
    } catch (const nlohmann::json::exception& e) {
        throw InputError(format("{}: not a world plan ({})", file.string(), oneLine(e.what())));
    }
}

TileStreamer::~TileStreamer() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
        queue_.clear();
    }
    wake_.notify_all();
    for (std::thread& t : workers_) t.join();
}

void TileStreamer::open(const std::filesystem::path& worldDir, const StreamingOptions& options,
                        std::map<std::uint32_t, double> until, bool proxies) {
    tiles_ = readTileset(worldDir);
    proxies_ = proxies;
    options_ = options;
    until_ = std::move(until);
    entries_.resize(tiles_.nodes.size());
    for (std::size_t i = 0; i < entries_.size(); ++i) entries_[i].estimate = estimateBytes(tiles_.nodes[i]);
    const int workers = std::clamp(options.workers, 1, 16);
    for (int k = 0; k < workers; ++k) workers_.emplace_back([this] { work(); });
}

// A worker: takes the most urgent request, reads and parses its file, hands the result back.
void TileStreamer::work() {
    for (;;) {
        int node = -1;
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [this] { return stop_ || !queue_.empty(); });
            if (stop_) return;
            node = queue_.front();
            queue_.pop_front();
            ++busy_;  // the node stays Queued until its result is collected
        }
        Result r = loadNode(node);
        {
            std::lock_guard lock(mutex_);
            results_.push_back(std::move(r));
            --busy_;
        }
        done_.notify_all();
    }
}

TileStreamer::Result TileStreamer::loadNode(int node) const {
    const TileNode& n = tiles_.nodes[std::size_t(node)];
    Result r{node, std::nullopt, {}, {}, {}};
    try {
        // A tile's city folder (its city.glb with its bake, lamps and proxies), or any other GLB
        // as it is (an HLOD node's carries its bake in its vertices).
        if (n.hlod || n.file.filename() != "city.glb") {
            r.city = buildCityCpu(loadMeshNodes(n.file, ReadIn::thisProcess), std::nullopt, n.hlod, until_);
        } else {
            const std::filesystem::path dir = n.file.parent_path();
            r.city = loadCityCpu(dir, until_);
            r.lamps = readStreetLamps(dir);
            const std::filesystem::path proxies = dir / "bake" / "proxies.json";
            std::error_code ec;
            if (proxies_ && std::filesystem::is_regular_file(proxies, ec)) r.proxies = parseProbeBoxes(readTextFile(proxies), proxies.string());
        }
    } catch (const std::exception& e) {
        r.error = oneLine(e.what());
        r.city.reset();
    }
    return r;
}

void TileStreamer::collect(StreamingStats& stats) {
    std::vector<Result> results;
    {
        std::lock_guard lock(mutex_);
        results.swap(results_);
    }
    for (Result& r : results) {
        Entry& e = entries_[std::size_t(r.node)];
        if (!r.city) {
            e.state = State::Failed;
            ++stats.failed;
            const TileNode& n = tiles_.nodes[std::size_t(r.node)];
            bool standIn = false;  // an ancestor with content of its own
            for (int p = n.parent; p >= 0 && !standIn; p = tiles_.nodes[std::size_t(p)].parent) standIn = !tiles_.nodes[std::size_t(p)].file.empty();
            std::fprintf(stderr, "dawnforge: warning: %s (%s): %s; %s\n", n.file.string().c_str(), n.name.c_str(), r.error.c_str(),
                         standIn ? "its parent is drawn in its place" : "nothing is drawn in its place");
            continue;
        }
        e.gpu.emplace(std::move(*r.city));
        e.lamps = std::move(r.lamps);
        e.proxies = std::move(r.proxies);
        e.state = State::Loaded;
        ++stats.loads;
    }
}

std::size_t TileStreamer::residentBytes() const {
    std::size_t n = 0;
    for (const Entry& e : entries_)
        if (e.gpu) n += e.gpu->bytes();
    return n;
}

// The queue becomes the wanted nodes not yet loaded, most urgent first, while the resident
// bytes leave room; requests nobody wants any more go back to absent.
void TileStreamer::request(const std::vector<int>& wanted) {
    const std::size_t budget = options_.residentBudgetMB * kMB;
    std::size_t bytes = residentBytes();
    std::lock_guard lock(mutex_);
    for (int node : queue_) entries_[std::size_t(node)].state = State::Absent;
    queue_.clear();
    for (const Entry& e : entries_)
        if (e.state == State::Queued) bytes += e.estimate;  // in a worker's hands
    for (int node : wanted) {
        Entry& e = entries_[std::size_t(node)];
        if (e.state != State::Absent) continue;
        if (bytes + e.estimate > budget && bytes > 0) break;  // coarser content keeps standing in
        e.state = State::Queued;
        bytes += e.estimate;
        queue_.push_back(node);
    }
    if (!queue_.empty()) wake_.notify_all();
}

// Loaded content to the GPU, most wanted first, until the frame's budget is spent; returns the
// bytes copied.
std::size_t TileStreamer::uploadSome(const std::vector<int>& wanted, std::size_t budget) {
    std::size_t cost = 0, copied = 0;
    for (int node : wanted) {
        Entry& e = entries_[std::size_t(node)];
        if (e.state != State::Loaded) continue;
        if (cost >= budget) break;
        const UploadStep step = e.gpu->upload(budget - cost);
        cost += step.cost;
        copied += step.copied;
        if (e.gpu->done()) e.state = State::Resident;
    }
    return copied;
}

// Least recently used first, under the budget less what the wanted loads will need, so that
// what nobody uses makes room for them.
void TileStreamer::evict(const std::vector<int>& wanted, StreamingStats& stats) {
    std::size_t need = 0;
    for (int node : wanted)
        if (entries_[std::size_t(node)].state == State::Absent) need += entries_[std::size_t(node)].estimate;
    const std::size_t budget = options_.residentBudgetMB * kMB;
    std::vector<ResidentTile> held;
    for (std::size_t i = 0; i < entries_.size(); ++i)
        if (entries_[i].gpu) held.push_back({int(i), entries_[i].gpu->bytes(), entries_[i].lastUsed});
    for (int node : chooseEvictions(held, budget - std::min(need, budget), options_.lowWater, frame_, options_.keepFrames)) {
        Entry& e = entries_[std::size_t(node)];
        e.gpu.reset();
        e.lamps.clear();
        e.proxies.clear();
        e.state = State::Absent;
        ++stats.evictions;
    }
}

TileSelection TileStreamer::select(const SelectionCamera& camera) const {
    return selectTiles(
        tiles_, camera, options_.maxScreenError, [this](int i) { return entries_[std::size_t(i)].state == State::Resident; },
        [this](int i) { return entries_[std::size_t(i)].state == State::Failed; });
}

bool TileStreamer::pending() const {
    return busy_ > 0 || !queue_.empty() || !results_.empty();
}

void TileStreamer::update(const SelectionCamera& camera, const SelectionCamera* prefetch, StreamingStats& stats) {
    ++frame_;
    stats.on = true;
    const auto t0 = Clock::now();
    double uploadMs = 0.0;
    for (;;) {
        collect(stats);
        TileSelection sel = select(camera);
        std::vector<int> wanted = sel.wanted;
        if (prefetch) {
            const std::set<int> now(wanted.begin(), wanted.end());
            for (int i : select(*prefetch).wanted)
                if (!now.count(i)) wanted.push_back(i);
        }
        for (int i : wanted) entries_[std::size_t(i)].lastUsed = frame_;
        for (int i : sel.draw) entries_[std::size_t(i)].lastUsed = frame_;
        evict(wanted, stats);  // first: what nobody uses makes room for what is wanted
        request(wanted);
        const auto u0 = Clock::now();
        const std::size_t budget = options_.wait ? std::numeric_limits<std::size_t>::max() : options_.uploadBudgetMB * kMB;
        stats.uploadBytes += uploadSome(wanted, std::max<std::size_t>(budget, 1));
        uploadMs += msSince(u0);
        sel = select(camera);  // what was uploaded just now draws this frame
        drawn_ = nearestFirst(sel.draw, camera.position);
        stats.wanted = int(sel.wanted.size());
        stats.complete = sel.complete;
        {
            std::unique_lock lock(mutex_);
            if (!options_.wait || sel.complete || !pending()) break;
            done_.wait_for(lock, std::chrono::milliseconds(50), [this] { return !results_.empty(); });
        }
        stats.waited = true;
    }
    stats.uploadMs = uploadMs;
    stats.waitMs = stats.waited ? msSince(t0) : 0.0;
    stats.drawn = int(drawn_.size());
    stats.nodes = int(tiles_.nodes.size());
    stats.resident = 0;
    stats.loading = 0;
    for (const Entry& e : entries_) {
        stats.resident += e.state == State::Resident;
        stats.loading += e.state == State::Queued || e.state == State::Loaded;
    }
    stats.residentMB = double(residentBytes()) / double(kMB);
}

// Nearest first: the depth test then rejects what they hide before it is shaded.
std::vector<int> TileStreamer::nearestFirst(std::vector<int> nodes, glm::dvec3 camera) const {
    const auto distance = [&](int i) {
        const TileNode& n = tiles_.nodes[std::size_t(i)];
        return glm::length(camera - glm::clamp(camera, n.areaMin, n.areaMax));
    };
    std::stable_sort(nodes.begin(), nodes.end(), [&](int a, int b) { return distance(a) < distance(b); });
    return nodes;
}

std::vector<TileStreamer::Drawn> TileStreamer::drawn() {
    std::vector<Drawn> out;
    for (int i : drawn_) {
        Entry& e = entries_[std::size_t(i)];
        if (e.state != State::Resident) continue;  // evicted since (never: what is drawn was used this frame)
        out.push_back({&*e.gpu, tiles_.nodes[std::size_t(i)].offset, tiles_.nodes[std::size_t(i)].hlod, &e.lamps, &e.proxies, i});
    }
    return out;
}

}  // namespace dawnforge::runtime
