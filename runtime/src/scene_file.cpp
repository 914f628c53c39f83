// scene.json (scene_file.hpp): a strict reader (unknown keys and out-of-range values are
// errors that name the key) and the writer it round-trips with.
#include <dawnforge/runtime/scene_file.hpp>

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/read_file.hpp>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <sstream>

namespace dawnforge::runtime {

namespace {

using Json = nlohmann::ordered_json;  // keeps the document's order: the first bad key is reported

constexpr const char* kFormat = "dawnforge.scene";
constexpr int kVersion = 1;
constexpr int kMinGrid = 2, kMaxGrid = 1024;
constexpr double kInf = std::numeric_limits<double>::infinity();


// A value as the user wrote it, short enough for a one-line message.
std::string shown(const Json& j) {
    std::string s = j.dump();
    if (s.size() > 40) s = s.substr(0, 37) + "...";
    return s;
}

std::string join(std::initializer_list<const char*> keys) {
    std::string out;
    for (const char* k : keys) out += (out.empty() ? "" : ", ") + std::string(k);
    return out;
}

// `p` without "." and ".." segments or a trailing separator.
std::filesystem::path normalPath(const std::filesystem::path& p) {
    std::filesystem::path n = p.lexically_normal();
    if (n.has_relative_path() && n.filename().empty()) n = n.parent_path();
    return n;
}

struct Reader {
    std::string file;  // for messages
    std::filesystem::path folder;  // relative paths start here

    [[noreturn]] void fail(const std::string& what) const { throw InputError(file + ": " + what); }

    static std::string child(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }

    void object(const Json& j, const std::string& path, std::initializer_list<const char*> allowed) const {
        if (!j.is_object())
            fail(format("\"{}\" must be an object with keys {} (got {})", path, join(allowed), shown(j)));
        for (const auto& item : j.items())
            if (std::none_of(allowed.begin(), allowed.end(), [&](const char* k) { return item.key() == k; }))
                fail(format("unknown key \"{}\" (allowed: {})", child(path, item.key()), join(allowed)));
    }

    double number(const Json& j, const std::string& path) const {
        if (!j.is_number()) fail(format("\"{}\" must be a number (got {})", path, shown(j)));
        const double v = j.get<double>();
        if (!std::isfinite(v)) fail(format("\"{}\" must be a finite number (got {})", path, shown(j)));
        return v;
    }

    // A number in [lo, hi] with either end open; `range` spells it out for the message.
    double number(const Json& j, const std::string& path, double lo, bool loOpen, double hi, bool hiOpen) const {
        const double v = number(j, path);
        if (!(loOpen ? v > lo : v >= lo) || !(hiOpen ? v < hi : v <= hi)) {
            const std::string range = std::isinf(hi) ? format("{} {}", loOpen ? ">" : ">=", lo)
                                                     : format("in {}{}, {}{}", loOpen ? "(" : "[", lo, hi, hiOpen ? ")" : "]");
            fail(format("\"{}\" must be {} (got {})", path, range, shown(j)));
        }
        return v;
    }

    int integer(const Json& j, const std::string& path, int lo, int hi) const {
        if (!j.is_number_integer()) fail(format("\"{}\" must be an integer (got {})", path, shown(j)));
        const bool inRange = j.is_number_unsigned()
                                 ? j.get<std::uint64_t>() <= std::uint64_t(hi) && std::int64_t(j.get<std::uint64_t>()) >= lo
                                 : j.get<std::int64_t>() >= lo && j.get<std::int64_t>() <= hi;
        if (!inRange) fail(format("\"{}\" must be an integer in {}..{} (got {})", path, lo, hi, shown(j)));
        return int(j.get<std::int64_t>());
    }

    bool boolean(const Json& j, const std::string& path) const {
        if (!j.is_boolean()) fail(format("\"{}\" must be true or false (got {})", path, shown(j)));
        return j.get<bool>();
    }

    std::string name(const Json& j, const std::string& path) const {
        if (!j.is_string()) fail(format("\"{}\" must be a string (got {})", path, shown(j)));
        std::string s = j.get<std::string>();
        if (s.empty()) fail(format("\"{}\" must not be empty", path));
        return s;
    }

    std::filesystem::path folderPath(const Json& j, const std::string& path) const {
        const std::filesystem::path p(name(j, path));
        return normalPath(p.is_absolute() ? p : folder / p);
    }

    glm::dvec3 vec3(const Json& j, const std::string& path) const {
        if (!j.is_array() || j.size() != 3) fail(format("\"{}\" must be an array of three numbers [x, y, z] (got {})", path, shown(j)));
        return {number(j[0], path + "[0]"), number(j[1], path + "[1]"), number(j[2], path + "[2]")};
    }

    const Json& required(const Json& object, const std::string& path, const char* key, const char* what) const {
        const auto it = object.find(key);
        if (it == object.end()) fail(format("\"{}\" is missing ({})", child(path, key), what));
        return *it;
    }
};

OceanSettings readOcean(const Reader& r, const Json& j) {
    r.object(j, "ocean", {"level", "grid", "shore_depth", "ripples"});
    OceanSettings ocean;
    if (j.contains("level")) ocean.level = r.number(j["level"], "ocean.level");
    if (j.contains("grid")) {
        const Json& g = j["grid"];
        if (!g.is_array() || g.size() != 2)
            r.fail(format("\"ocean.grid\" must be [columns, rows], two integers in {}..{} (got {})", kMinGrid, kMaxGrid, shown(g)));
        ocean.columns = r.integer(g[0], "ocean.grid[0]", kMinGrid, kMaxGrid);
        ocean.rows = r.integer(g[1], "ocean.grid[1]", kMinGrid, kMaxGrid);
    }
    if (j.contains("shore_depth"))
        ocean.shoreDepth = r.number(j["shore_depth"], "ocean.shore_depth", 0.0, true, kInf, false);
    if (j.contains("ripples")) ocean.ripples = r.boolean(j["ripples"], "ocean.ripples");
    return ocean;
}

WindSettings readWind(const Reader& r, const Json& j) {
    r.object(j, "wind", {"direction", "speed"});
    WindSettings wind;
    if (j.contains("direction")) {
        const glm::dvec3 d = r.vec3(j["direction"], "wind.direction");
        if (!(std::hypot(d.x, d.z) > 1e-6))
            r.fail(format("\"wind.direction\" must point somewhere level: x or z must not be 0 (got {})", shown(j["direction"])));
        wind.direction = glm::normalize(glm::dvec3(d.x, 0.0, d.z));
    }
    if (j.contains("speed")) wind.speed = r.number(j["speed"], "wind.speed", 0.0, false, 60.0, false);
    return wind;
}

ProbeSettings readProbes(const Reader& r, const Json& j) {
    r.object(j, "probes", {"preset", "face_size", "anti_leak", "multi_bounce", "show"});
    ProbeSettings probes;
    if (j.contains("preset")) {
        const Json& p = j["preset"];
        if (!p.is_string() || !isProbePreset(p.get<std::string>()))
            r.fail(format("\"probes.preset\" must be \"off\", \"low\", \"mid\" or \"high\" (got {})", shown(p)));
        probes.preset = p.get<std::string>();
    }
    if (j.contains("face_size")) probes.faceSize = r.integer(j["face_size"], "probes.face_size", 8, 256);
    if (j.contains("anti_leak")) probes.antiLeak = r.boolean(j["anti_leak"], "probes.anti_leak");
    if (j.contains("multi_bounce")) probes.multiBounce = r.boolean(j["multi_bounce"], "probes.multi_bounce");
    if (j.contains("show")) probes.show = r.boolean(j["show"], "probes.show");
    return probes;
}

ExposureSettings readExposure(const Reader& r, const Json& j) {
    r.object(j, "exposure", {"key", "night_stops", "min", "max", "night_max", "speed", "fixed"});
    ExposureSettings e;
    if (j.contains("key")) e.key = r.number(j["key"], "exposure.key", 0.0, true, kInf, false);
    if (j.contains("night_stops")) e.nightStops = r.number(j["night_stops"], "exposure.night_stops", -10.0, false, 10.0, false);
    if (j.contains("min")) e.min = r.number(j["min"], "exposure.min", 0.0, true, kInf, false);
    if (j.contains("max")) e.max = r.number(j["max"], "exposure.max", 0.0, true, kInf, false);
    if (e.min > e.max) r.fail(format("\"exposure.min\" ({}) is above \"exposure.max\" ({})", e.min, e.max));
    if (j.contains("night_max")) e.nightMax = r.number(j["night_max"], "exposure.night_max", e.min, false, e.max, false);
    e.nightMax = std::clamp(e.nightMax, e.min, e.max);
    if (j.contains("speed")) e.speed = r.number(j["speed"], "exposure.speed", 0.0, true, kInf, false);
    if (j.contains("fixed") && !j["fixed"].is_null()) e.fixed = r.number(j["fixed"], "exposure.fixed", 0.0, true, kInf, false);
    return e;
}

DestructionInstance readDestruction(const Reader& r, const Json& j, const std::string& path) {
    r.object(j, path, {"vat", "name", "position", "yaw_degrees", "start_time", "replaces"});
    DestructionInstance d;
    d.vatDir = r.folderPath(r.required(j, path, "vat", "the folder written by `dawnforge vat`"), path + ".vat");
    d.name = r.name(r.required(j, path, "name", "the VAT's name: <name>_data.json in the folder"), path + ".name");
    if (j.contains("position")) d.position = r.vec3(j["position"], path + ".position");
    if (j.contains("yaw_degrees")) d.yawDegrees = r.number(j["yaw_degrees"], path + ".yaw_degrees");
    if (j.contains("start_time")) d.startTime = r.number(j["start_time"], path + ".start_time");
    if (j.contains("replaces") && !j["replaces"].is_null())
        d.replaces = r.integer(j["replaces"], path + ".replaces", 0, std::numeric_limits<int>::max());
    return d;
}

SceneCamera readCamera(const Reader& r, const Json& j, const std::string& path) {
    r.object(j, path, {"name", "position", "target", "fov_degrees"});
    SceneCamera c;
    c.name = r.name(r.required(j, path, "name", "each camera has a name, by which it is chosen"), path + ".name");
    if (j.contains("position")) c.position = r.vec3(j["position"], path + ".position");
    if (j.contains("target")) c.target = r.vec3(j["target"], path + ".target");
    if (j.contains("fov_degrees")) c.fovDegrees = r.number(j["fov_degrees"], path + ".fov_degrees", 1.0, true, 179.0, true);
    if (c.position == c.target) r.fail(format("\"{}\": position and target are the same point, so the camera has no direction", path));
    return c;
}

const Json& array(const Reader& r, const Json& j, const std::string& path, const char* what) {
    if (!j.is_array()) r.fail(format("\"{}\" must be an array of {} (got {})", path, what, shown(j)));
    return j;
}

nlohmann::ordered_json vec(const glm::dvec3& v) { return Json::array({v.x, v.y, v.z}); }

std::string relativePath(const std::filesystem::path& p, const std::filesystem::path& base) {
    std::filesystem::path out = normalPath(p);
    if (p.is_absolute() == base.is_absolute()) {
        const std::filesystem::path r = out.lexically_relative(normalPath(base));
        if (!r.empty()) out = r;
    }
    return out.generic_string();
}

}  // namespace

SceneFile parseSceneJson(const std::string& json, const std::filesystem::path& file) {
    const Reader r{file.string(), file.parent_path()};
    Json root;
    try {
        root = Json::parse(json);
    } catch (const Json::exception& e) {
        r.fail(format("not valid JSON: {}", oneLine(e.what())));
    }
    if (!root.is_object()) r.fail(format("a scene must be a JSON object {{\"format\": \"{}\", \"version\": {}, ...}}", kFormat, kVersion));
    r.object(root, "", {"format", "version", "city", "world", "time_of_day", "time", "fps", "ocean", "wind", "destruction", "cameras",
                        "lens_flares", "probes", "exposure"});
    const Json& f = r.required(root, "", "format", "a scene starts with \"format\": \"dawnforge.scene\"");
    if (f != kFormat) r.fail(format("\"format\" is {}, expected \"{}\"", shown(f), kFormat));
    const Json& v = r.required(root, "", "version", "expected \"version\": 1");
    if (!v.is_number_integer() || v != kVersion) r.fail(format("\"version\" is {}, expected {}", shown(v), kVersion));

    SceneFile scene;
    scene.file = file;
    if (root.contains("city") && root.contains("world"))
        r.fail("\"city\" and \"world\" are both given: a scene draws one city folder or one world, not both");
    if (root.contains("city")) scene.cityDir = r.folderPath(root["city"], "city");
    if (root.contains("world")) scene.worldDir = r.folderPath(root["world"], "world");
    if (root.contains("time_of_day")) scene.timeOfDay = r.number(root["time_of_day"], "time_of_day", 0.0, false, 24.0, true);
    if (root.contains("time")) scene.time = r.number(root["time"], "time", 0.0, false, kInf, false);
    if (root.contains("fps")) scene.fps = r.number(root["fps"], "fps", 0.0, true, kInf, false);
    if (root.contains("ocean") && !root["ocean"].is_null()) scene.ocean = readOcean(r, root["ocean"]);
    if (root.contains("wind")) scene.wind = readWind(r, root["wind"]);
    if (root.contains("lens_flares")) scene.lensFlares = r.boolean(root["lens_flares"], "lens_flares");
    if (root.contains("probes")) scene.probes = readProbes(r, root["probes"]);
    if (root.contains("exposure")) scene.exposure = readExposure(r, root["exposure"]);
    if (root.contains("destruction")) {
        const Json& list = array(r, root["destruction"], "destruction", "{\"vat\": ..., \"name\": ...} objects");
        for (std::size_t i = 0; i < list.size(); ++i)
            scene.destruction.push_back(readDestruction(r, list[i], format("destruction[{}]", i)));
    }
    if (root.contains("cameras")) {
        const Json& list = array(r, root["cameras"], "cameras", "{\"name\": ..., \"position\": ..., \"target\": ...} objects");
        for (std::size_t i = 0; i < list.size(); ++i) {
            SceneCamera c = readCamera(r, list[i], format("cameras[{}]", i));
            if (findCamera(scene, c.name))
                r.fail(format("\"cameras[{}].name\": a camera named \"{}\" comes earlier; names must be unique", i, c.name));
            scene.cameras.push_back(std::move(c));
        }
    }
    return scene;
}

SceneFile loadSceneFile(const std::filesystem::path& file) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
        throw InputError(format("{}: no such file (expected a scene.json: {{\"format\": \"{}\", \"version\": {}, ...}})",
                                file.string(), kFormat, kVersion));
    SceneFile scene = parseSceneJson(readTextFile(file), file);

    const std::string source = file.string();
    // A folder the scene names, and the file that makes it what the key says.
    const auto folder = [&](const char* key, const std::filesystem::path& dir, const char* writer, const char* file,
                            const char* missing) {
        if (!std::filesystem::is_directory(dir, ec))
            throw InputError(format("{}: \"{}\": the folder {} does not exist (expected a folder written by `{}`)", source, key,
                                    dir.string(), writer));
        if (!std::filesystem::is_regular_file(dir / file, ec))
            throw InputError(format("{}: \"{}\": {} is missing ({})", source, key, (dir / file).string(), missing));
    };
    if (scene.cityDir)
        folder("city", *scene.cityDir, "dawnforge city", "city.glb", "the city folder must hold city.glb from `dawnforge city`");
    if (scene.worldDir)
        folder("world", *scene.worldDir, "dawnforge world build", "tileset.json",
               "run `dawnforge world build` on the world until it finishes");
    for (std::size_t i = 0; i < scene.destruction.size(); ++i) {
        const DestructionInstance& d = scene.destruction[i];
        if (!std::filesystem::is_directory(d.vatDir, ec))
            throw InputError(format("{}: \"destruction[{}].vat\": the folder {} does not exist (expected a folder written by "
                                    "`dawnforge vat`)",
                                    source, i, d.vatDir.string()));
        if (!std::filesystem::is_regular_file(d.vatDir / (d.name + "_data.json"), ec))
            throw InputError(format("{}: \"destruction[{}].name\": {} is missing (no VAT named \"{}\" in that folder)", source,
                                    i, (d.vatDir / (d.name + "_data.json")).string(), d.name));
    }
    return scene;
}

std::string sceneFileJson(const SceneFile& scene, const std::filesystem::path& relativeTo) {
    Json j;
    j["format"] = kFormat;
    j["version"] = kVersion;
    if (scene.cityDir) j["city"] = relativePath(*scene.cityDir, relativeTo);
    if (scene.worldDir) j["world"] = relativePath(*scene.worldDir, relativeTo);
    j["time_of_day"] = scene.timeOfDay;
    j["time"] = scene.time;
    j["fps"] = scene.fps;
    if (scene.ocean)
        j["ocean"] = {{"level", scene.ocean->level},
                      {"grid", Json::array({scene.ocean->columns, scene.ocean->rows})},
                      {"shore_depth", scene.ocean->shoreDepth},
                      {"ripples", scene.ocean->ripples}};
    j["wind"] = {{"direction", vec(scene.wind.direction)}, {"speed", scene.wind.speed}};
    j["destruction"] = Json::array();
    for (const DestructionInstance& d : scene.destruction) {
        j["destruction"].push_back({{"vat", relativePath(d.vatDir, relativeTo)},
                                    {"name", d.name},
                                    {"position", vec(d.position)},
                                    {"yaw_degrees", d.yawDegrees},
                                    {"start_time", d.startTime}});
        if (d.replaces) j["destruction"].back()["replaces"] = *d.replaces;
    }
    j["cameras"] = Json::array();
    for (const SceneCamera& c : scene.cameras)
        j["cameras"].push_back(
            {{"name", c.name}, {"position", vec(c.position)}, {"target", vec(c.target)}, {"fov_degrees", c.fovDegrees}});
    j["lens_flares"] = scene.lensFlares;
    j["probes"] = {{"preset", scene.probes.preset},
                   {"face_size", scene.probes.faceSize},
                   {"anti_leak", scene.probes.antiLeak},
                   {"multi_bounce", scene.probes.multiBounce},
                   {"show", scene.probes.show}};
    const ExposureSettings& e = scene.exposure;
    j["exposure"] = {{"key", e.key}, {"night_stops", e.nightStops}, {"min", e.min}, {"max", e.max}, {"night_max", e.nightMax}, {"speed", e.speed}};
    if (e.fixed) j["exposure"]["fixed"] = *e.fixed;
    return j.dump(2) + "\n";
}

bool isProbePreset(std::string_view name) { return name == "off" || name == "low" || name == "mid" || name == "high"; }

const SceneCamera* findCamera(const SceneFile& scene, std::string_view name) {
    for (const SceneCamera& c : scene.cameras)
        if (c.name == name) return &c;
    return nullptr;
}

}  // namespace dawnforge::runtime
