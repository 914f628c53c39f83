#pragma once
// scene.json: what the runtime draws (ARCHITECTURE.md, File formats).
//
//   {
//     "format": "dawnforge.scene", "version": 1,        required
//     "city": "city",                                    a folder with city.glb (and city.json)
//     "time_of_day": 17.5,                               hours, [0, 24); default 15
//     "time": 3.0,                                       seconds since the scene started, >= 0; default 0
//     "fps": 30,                                         > 0; `render --frame F` draws time F / fps; default 30
//     "ocean": { "level": -0.8,                          sea level (m); default -0.8
//                "grid": [192, 160],                     projected grid columns, rows: 2..1024; default [192, 160]
//                "shore_depth": 4.0,                     depth (m, > 0) at which waves reach full amplitude; default 4
//                "ripples": true },                      per-pixel ripples from the noise texture near the camera; default true
//     "wind": { "direction": [1, 0, 0.3],                where the wind blows to; only x and z count; default [1, 0, 0.3]
//               "speed": 4 },                            m/s in [0, 60]: how far trees bend; default 4
//     "destruction": [ { "vat": "vat",                   required: a folder written by `dawnforge vat`
//                        "name": "tower_native",         required: the VAT's <name> (<name>_data.json, ...)
//                        "position": [0, 0, 0],          where the VAT's origin goes (m); default [0, 0, 0]
//                        "yaw_degrees": 0,               turn about +Y; default 0
//                        "start_time": 1.0,              scene time (s) of the VAT's frame 0; default 0
//                        "replaces": 5 } ],              a city building (its id): drawn until start_time, the VAT
//                                                        from then on (none before); default none
//     "cameras": [ { "name": "overview",                 required, unique, not empty; the first is the default
//                    "position": [0, 40, 120],           default [0, 0, 0]
//                    "target": [0, 0, 0],                default [0, 0, -1]; must differ from position
//                    "fov_degrees": 50 } ],              vertical field of view, in (1, 179); default 50
//     "lens_flares": true,                               flares of the sun by day and of city.json's street
//                                                        lamps by night (true or false); default true
//     "probes": { "preset": "mid",                       irradiance probes: "off", "low", "mid", "high"; default "off";
//                                                        any other needs the city's bake (CITY/bake/proxies.json)
//                 "face_size": 64,                       capture pixels per cube face, 8..256; default 64
//                 "anti_leak": true,                     IN/OUT tags: indoor surfaces read indoor probes only; default true
//                 "multi_bounce": true,                  probes lit by the probes already captured; default true
//                 "show": false },                       the debug view: a sphere at each probe, lit by it; default false
//     "exposure": { "key": 0.18,                         auto exposure: the scene's log-average luminance is brought
//                                                        to this (> 0); default 0.18
//                   "night_stops": -3,                   the key's change at night, in stops, [-10, 10] (night keeps
//                                                        looking like night); default -3
//                   "min": 0.0625, "max": 256,           the exposure's range (multipliers of the HDR colour,
//                                                        0 < min <= max); default 1/16 and 256 (a room by day)
//                   "night_max": 8,                      the top of the range at night, in [min, max]: an unlit
//                                                        street at night stays dark; default 8
//                   "speed": 1.5,                        `view`: adaptation per second (> 0; 1.5 closes 78 % of
//                                                        the gap, in stops, in a second); `render` converges at once
//                   "fixed": 1.2 }                       pins the exposure to this multiplier (> 0); default none (auto)
//   }
//
// Every key but "format" and "version" is optional; "ocean" absent or null means no ocean.
// Unknown keys at any level are errors (a misspelt key would otherwise be silently ignored).
// Relative paths are relative to the folder that holds scene.json.
#include <glm/vec3.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace dawnforge::runtime {

struct SceneCamera {
    std::string name;
    glm::dvec3 position{0.0};
    glm::dvec3 target{0.0, 0.0, -1.0};
    double fovDegrees = 50.0;  // vertical
};

struct OceanSettings {
    double level = -0.8;
    int columns = 192;
    int rows = 160;
    double shoreDepth = 4.0;  // waves reach full amplitude this deep
    bool ripples = true;      // per-pixel normals from the noise texture (ocean.frag)
};

// What sways the city's trees (wind.glsl).
struct WindSettings {
    glm::dvec3 direction{0.957826, 0.0, 0.287348};  // unit and level: where it blows to
    double speed = 4.0;                              // m/s
};

// Irradiance probes (probes.hpp; issue 14).
struct ProbeSettings {
    std::string preset = "off";  // "off", "low", "mid" or "high" (probe_placement.hpp's presets)
    int faceSize = 64;
    bool antiLeak = true;
    bool multiBounce = true;
    bool show = false;  // the debug view
};

// The frame's exposure (exposure.comp): automatic unless pinned.
struct ExposureSettings {
    double key = 0.18;             // the scene's log-average luminance is exposed to this by day
    double nightStops = -3.0;      // and to key * 2^nightStops at night (runtime::Lighting::night)
    double min = 0.0625, max = 256.0;  // the automatic exposure's range: a room by day needs about 100
    double nightMax = 8.0;             // the range's top at night (between, log-linear in the night factor)
    double speed = 1.5;           // `view`: 1 - exp(-speed * dt) of the way in stops each frame
    std::optional<double> fixed;  // pinned (scene key or --exposure)
};

struct DestructionInstance {
    std::filesystem::path vatDir;
    std::string name;
    glm::dvec3 position{0.0};
    double yawDegrees = 0.0;
    double startTime = 0.0;
    std::optional<int> replaces;  // a building of the city (its id) drawn until startTime, then not
};

struct SceneFile {
    std::filesystem::path file;                    // the scene.json itself
    std::optional<std::filesystem::path> cityDir;  // holds city.glb (required there) and city.json
    std::optional<std::filesystem::path> worldDir; // a world (tileset.json), streamed; never with cityDir
    double timeOfDay = 15.0;                       // hours [0, 24)
    double time = 0.0;                             // seconds since the scene started (what `render` draws unless --frame)
    double fps = 30.0;                             // for --frame F: time = F / fps
    std::optional<OceanSettings> ocean;
    WindSettings wind;
    std::vector<DestructionInstance> destruction;
    std::vector<SceneCamera> cameras;              // the first is the default
    bool lensFlares = true;                        // the sun's and the street lamps' lens flares
    ProbeSettings probes;
    ExposureSettings exposure;
};

// Reads and parses `file`, then checks that the city folder holds city.glb and that each
// destruction's VAT folder holds <name>_data.json. Throws InputError (one line, starting
// with the file's path) on any problem.
SceneFile loadSceneFile(const std::filesystem::path& file);

// Parses and checks the document without touching the disk. `file` names the document in
// messages, and relative paths are resolved against its folder.
SceneFile parseSceneJson(const std::string& json, const std::filesystem::path& file);

// The document for `scene`, with paths relative to `relativeTo` (the folder the scene.json
// will be written to); parseSceneJson reads it back to the same scene.
std::string sceneFileJson(const SceneFile& scene, const std::filesystem::path& relativeTo);

// Whether `name` is a probe preset: "off", "low", "mid" or "high".
bool isProbePreset(std::string_view name);

// The camera called `name`, or nullptr.
const SceneCamera* findCamera(const SceneFile& scene, std::string_view name);

}  // namespace dawnforge::runtime
