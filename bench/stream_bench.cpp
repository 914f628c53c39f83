// A fly-through of a streamed world (issue 25's budgets), headless at 1280 × 720:
//   build/bin/stream_bench WORLD_DIR [--street X0,Z0,X1,Z1] [--city CITY_DIR] [--size WxH] [--frames N] [--fps F]
// The camera walks 1.7 m above a street at 1.5 m per frame (45 m/s at 30 frames a second: a
// fast fly-through that crosses tile borders), then climbs to 500 m over 90 frames looking down
// at the world's centre. The street: --street in runtime coordinates (x, −north), by default the
// longest major street of the world's centre tile (its city.json). Streaming as `view` streams:
// no frame waits; loads on two worker threads, uploads within the per-frame budget. Frames are
// paced at --fps (30; 0: as fast as they go): a frame that finishes sooner sleeps the rest, so
// on a fast GPU the camera moves at the speed it would in `view` and loading has its real time.
// Prints JSON: per phase (street, climb, all) the p50 / p95 / max frame time (CPU wall of the
// whole frame, finished with glFinish), triangles drawn, peak resident MB, upload ms, frames that
// drew a stand-in while tiles loaded ("waiting_frames"), loads and evictions; the process's peak
// memory. With --city, the same street and aerial views rendered from that city folder loaded
// whole (what `render` of one city.glb does today), for the ratio.
#include <dawnforge/core/read_file.hpp>
#include <dawnforge/runtime/context.hpp>
#include <dawnforge/runtime/renderer.hpp>
#include <dawnforge/runtime/scene_file.hpp>
#include <dawnforge/runtime/tiles.hpp>

#include <nlohmann/json.hpp>

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

using namespace dawnforge;
using namespace dawnforge::runtime;
namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

struct Options {
    fs::path world, city;
    glm::dvec4 street{0.0};
    bool haveStreet = false;
    glm::ivec2 size{1280, 720};
    int streetFrames = 240, climbFrames = 90;
    double fps = 30.0;
};

// The longest major street of the centre tile, in runtime coordinates.
glm::dvec4 defaultStreet(const fs::path& world) {
    const Json plan = Json::parse(readTextFile(world / "plan.json"));
    const glm::ivec2 tiles(plan["tile_count"][0].get<int>(), plan["tile_count"][1].get<int>());
    const std::string name = std::to_string(tiles.x / 2) + "_" + std::to_string(tiles.y / 2);
    const Json city = Json::parse(readTextFile(world / "tiles" / name / "city.json"));
    glm::dvec4 best(0.0);
    double longest = -1.0;
    for (const Json& s : city["streets"]) {
        if (!s["major"].get<bool>()) continue;
        const Json& line = s["polyline"];
        const glm::dvec2 a(line.front()[0].get<double>(), line.front()[1].get<double>());
        const glm::dvec2 b(line.back()[0].get<double>(), line.back()[1].get<double>());
        if (glm::length(b - a) > longest) longest = glm::length(b - a), best = glm::dvec4(a.x, -a.y, b.x, -b.y);
    }
    if (longest < 0.0) throw std::runtime_error("the centre tile " + name + " has no major street: give --street");
    return best;
}

struct Sample {
    double ms;
    std::size_t triangles;
    double residentMB, uploadMs;
    bool waiting;
    int loads, evictions;
};

Json summary(const std::vector<Sample>& s) {
    std::vector<double> ms;
    double resident = 0.0, upload = 0.0, uploadMax = 0.0;
    std::size_t triangles = 0, trianglesMax = 0;
    int waiting = 0, loads = 0, evictions = 0;
    for (const Sample& x : s) {
        ms.push_back(x.ms);
        resident = std::max(resident, x.residentMB);
        upload += x.uploadMs;
        uploadMax = std::max(uploadMax, x.uploadMs);
        triangles += x.triangles;
        trianglesMax = std::max(trianglesMax, x.triangles);
        waiting += x.waiting;
        loads += x.loads;
        evictions += x.evictions;
    }
    std::sort(ms.begin(), ms.end());
    const auto pct = [&](double p) { return ms.empty() ? 0.0 : ms[std::min(ms.size() - 1, std::size_t(p * double(ms.size())))]; };
    const auto r = [](double v) { return std::round(v * 10.0) / 10.0; };
    return {{"frames", s.size()},
            {"p50_ms", r(pct(0.5))},
            {"p95_ms", r(pct(0.95))},
            {"max_ms", r(ms.empty() ? 0.0 : ms.back())},
            {"triangles_mean", s.empty() ? 0 : triangles / s.size()},
            {"triangles_max", trianglesMax},
            {"resident_mb_peak", r(resident)},
            {"upload_ms_total", r(upload)},
            {"upload_ms_max", r(uploadMax)},
            {"waiting_frames", waiting},
            {"loads", loads},
            {"evictions", evictions}};
}

FrameSettings at(glm::dvec3 eye, glm::dvec3 target) {
    FrameSettings f;
    f.camera.position = eye;
    f.camera.forward = glm::normalize(target - eye);
    f.camera.fovYDegrees = 50.0;
    f.timeOfDay = 15.0;
    return f;
}

// The path: frame k's camera and velocity (m/s at 30 frames a second).
struct Path {
    glm::dvec3 start, direction, centre;
    int streetFrames, climbFrames;
    FrameSettings frame(int k) const {
        if (k < streetFrames) {
            const glm::dvec3 eye = start + direction * (1.5 * k);
            FrameSettings f = at(eye, eye + direction * 50.0);
            f.cameraVelocity = direction * 45.0;
            return f;
        }
        const double t = double(k - streetFrames + 1) / double(climbFrames);
        const glm::dvec3 base = start + direction * (1.5 * streetFrames);
        const glm::dvec3 eye = base + glm::dvec3(0.0, 500.0 * t * t, 0.0) - direction * (300.0 * t);
        FrameSettings f = at(eye, glm::mix(eye + direction * 50.0, centre, std::min(1.0, 2.0 * t)));
        f.cameraVelocity = (glm::dvec3(0.0, 1000.0 * t / climbFrames, 0.0) - direction * (300.0 / climbFrames)) * 30.0;
        return f;
    }
};

Options parse(int argc, char** argv) {
    if (argc < 2) throw std::invalid_argument("usage: stream_bench WORLD_DIR [--street X0,Z0,X1,Z1] [--city CITY_DIR] [--size WxH] [--frames N]");
    Options o;
    o.world = argv[1];
    for (int i = 2; i + 1 < argc; i += 2) {
        const std::string key = argv[i], value = argv[i + 1];
        if (key == "--street") {
            o.haveStreet = std::sscanf(value.c_str(), "%lf,%lf,%lf,%lf", &o.street.x, &o.street.y, &o.street.z, &o.street.w) == 4;
        } else if (key == "--city") {
            o.city = value;
        } else if (key == "--size") {
            std::sscanf(value.c_str(), "%dx%d", &o.size.x, &o.size.y);
        } else if (key == "--fps") {
            o.fps = std::atof(value.c_str());
        } else if (key == "--frames") {
            o.streetFrames = std::atoi(value.c_str());
        } else {
            throw std::invalid_argument("unknown option " + key);
        }
    }
    if (!o.haveStreet) o.street = defaultStreet(o.world);
    return o;
}

double peakRssMB() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_maxrss) / 1024.0;
}

// The median frame of three of a view, after one that loads what it needs.
double viewMs(Renderer& r, const FrameSettings& f, FrameStats* last) {
    r.render(f);
    std::vector<double> ms;
    for (int k = 0; k < 3; ++k) {
        *last = r.render(f);
        ms.push_back(last->frameMs);
    }
    std::sort(ms.begin(), ms.end());
    return ms[1];
}

}  // namespace

int main(int argc, char** argv) try {
    const Options o = parse(argc, argv);
    const auto context = GlContext::headless();
    const Tileset tiles = readTileset(o.world);
    const glm::dvec3 a(o.street.x, 1.7, o.street.y), b(o.street.z, 1.7, o.street.w);
    const Path path{a, glm::normalize(b - a), glm::dvec3(0.5 * (tiles.boundsMin.x + tiles.boundsMax.x), 0.0,
                                                         0.5 * (tiles.boundsMin.z + tiles.boundsMax.z)),
                    o.streetFrames, o.climbFrames};

    SceneFile scene;
    scene.file = o.world / "scene.json";
    scene.worldDir = o.world;
    RendererOptions ro;
    ro.size = o.size;
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<Sample> street, climb;
    {
        Renderer renderer(scene, ro);
        for (int k = 0; k < o.streetFrames + o.climbFrames; ++k) {
            const auto start = std::chrono::steady_clock::now();
            const FrameStats s = renderer.render(path.frame(k));
            if (o.fps > 0.0) std::this_thread::sleep_until(start + std::chrono::duration<double>(1.0 / o.fps));
            const StreamingStats& st = s.streaming;
            (k < o.streetFrames ? street : climb)
                .push_back({s.frameMs, s.triangles, st.residentMB, st.uploadMs, !st.complete, st.loads, st.evictions});
        }
    }
    const double flySeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::vector<Sample> all = street;
    all.insert(all.end(), climb.begin(), climb.end());
    Json out{{"device", context->description()},
             {"world", o.world.string()},
             {"size", {o.size.x, o.size.y}},
             {"fps", o.fps},
             {"street", {o.street.x, o.street.y, o.street.z, o.street.w}},
             {"street_phase", summary(street)},
             {"climb_phase", summary(climb)},
             {"all", summary(all)},
             {"seconds", std::round(flySeconds * 10.0) / 10.0},
             {"peak_rss_mb", std::round(peakRssMB())}};

    // The same street and aerial views: streamed (waiting for their tiles) and, with --city, loaded whole.
    const FrameSettings views[2] = {path.frame(o.streetFrames / 2), path.frame(o.streetFrames + o.climbFrames - 1)};
    const char* names[2] = {"street_view", "aerial_view"};
    RendererOptions waiting = ro;
    waiting.streaming.wait = true;
    Renderer settled(scene, waiting);
    for (int v = 0; v < 2; ++v) {
        FrameStats s;
        out[names[v]]["streamed_ms"] = std::round(viewMs(settled, views[v], &s) * 10.0) / 10.0;
        out[names[v]]["streamed_triangles"] = s.triangles;
    }
    if (!o.city.empty()) {
        SceneFile whole;
        whole.file = o.city / "scene.json";
        whole.cityDir = o.city;
        const auto c0 = std::chrono::steady_clock::now();
        Renderer city(whole, ro);
        out["whole_city_load_s"] = std::round(std::chrono::duration<double>(std::chrono::steady_clock::now() - c0).count() * 10.0) / 10.0;
        for (int v = 0; v < 2; ++v) {
            FrameStats s;
            const double ms = viewMs(city, views[v], &s);
            out[names[v]]["whole_city_ms"] = std::round(ms * 10.0) / 10.0;
            out[names[v]]["whole_city_triangles"] = s.triangles;
            out[names[v]]["ratio"] = std::round(out[names[v]]["streamed_ms"].get<double>() / ms * 1000.0) / 1000.0;
        }
        out["peak_rss_mb_with_whole_city"] = std::round(peakRssMB());
    }
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "stream_bench: %s\n", e.what());
    return 2;
}
