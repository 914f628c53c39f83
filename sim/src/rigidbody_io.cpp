#include <dawnforge/sim/rigidbody_io.hpp>

#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/read_file.hpp>
#include <dawnforge/core/import.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

namespace dawnforge::sim {

namespace fs = std::filesystem;

namespace {

static_assert(std::endian::native == std::endian::little, "transforms.bin is written as native little-endian floats");

nlohmann::json readJson(const fs::path& file, std::string_view what) {
    std::error_code ec;
    if (!fs::is_regular_file(file, ec))
        throw InputError(format("{}: no such file (is {} a {} folder?)", file.string(), file.parent_path().string(), what));
    const std::string text = readTextFile(file);
    try {
        return nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {
        throw InputError(format("{}: not valid JSON ({})", file.string(), e.what()));
    }
}

// DIR/<file> of a dawnforge folder: the folder exists, the JSON parses and names `formatName`.
nlohmann::json readFolderJson(const fs::path& dir, const char* file, const char* formatName, std::string_view what) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw InputError(format("{}: no such folder", dir.string()));
    const fs::path jsonFile = dir / file;
    nlohmann::json j = readJson(jsonFile, what);
    if (!j.is_object() || j.value("format", "") != formatName)
        throw InputError(format("{}: not a dawnforge {} file (format is not '{}')", jsonFile.string(), what, formatName));
    return j;
}

// A float32 file of `frames` × `pieces` × `perPiece` values, size checked before reading.
std::vector<float> readFloats(const fs::path& file, int frames, std::int64_t pieces, std::size_t perPiece) {
    const std::size_t count = std::size_t(frames) * std::size_t(pieces) * perPiece;
    std::error_code ec;
    const std::uintmax_t size = fs::file_size(file, ec);
    if (ec || size != count * sizeof(float))
        throw InputError(format("{}: is {} bytes, but {} frames of {} pieces need {}", file.string(), size, frames,
                                pieces, count * sizeof(float)));
    const std::vector<std::byte> bytes = readBinaryFile(file);
    if (bytes.size() != count * sizeof(float)) throw InputError(format("{}: changed while being read", file.string()));
    std::vector<float> values(count);
    std::memcpy(values.data(), bytes.data(), bytes.size());
    return values;
}

// The meshes of `glb` (a folder's fragments.glb or debris.glb), one per piece in order,
// relative to each pivot, world axes.
// The nodes must be the pieces `names` in order, each at its pivot within float rounding;
// `source` is the file that lists them.
std::vector<Mesh> loadFragments(const fs::path& glb, std::span<const std::string> names,
                                std::span<const glm::dvec3> pivots, const fs::path& source, std::string_view what) {
    std::error_code ec;
    if (!fs::is_regular_file(glb, ec))
        throw InputError(format("{}: no such file (the {} folder is incomplete)", glb.string(), what));
    std::vector<MeshNode> nodes = loadMeshNodes(glb, ReadIn::thisProcess);
    if (nodes.size() != names.size())
        throw InputError(format("{}: has {} pieces but {} lists {}; they do not belong together", glb.string(),
                                nodes.size(), source.string(), names.size()));
    std::vector<Mesh> meshes;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        if (nodes[i].name != names[i])
            throw InputError(format("{}: node {} is '{}' but {} names piece {} '{}'", glb.string(), i, nodes[i].name,
                                    source.string(), i, names[i]));
        const glm::dvec3 t(nodes[i].world[3]);
        const glm::dvec3& pivot = pivots[i];
        if (glm::length(t - pivot) > 1e-5 * std::max(1.0, glm::length(pivot)))
            throw InputError(format("{}: piece '{}' sits at ({}, {}, {}) but {} puts its pivot at ({}, {}, {})",
                                    glb.string(), names[i], t.x, t.y, t.z, source.string(), pivot.x, pivot.y, pivot.z));
        Mesh mesh = std::move(nodes[i].mesh);
        for (glm::vec3& p : mesh.positions) p = glm::vec3(glm::dmat3(nodes[i].world) * glm::dvec3(p));
        meshes.push_back(std::move(mesh));
    }
    return meshes;
}

// Typed access that turns a missing key or a wrong type into an InputError naming both.
template <typename T>
T get(const nlohmann::json& j, const char* key, const fs::path& file) {
    if (!j.is_object() || !j.contains(key)) throw InputError(format("{}: '{}' is missing", file.string(), key));
    try {
        return j.at(key).get<T>();
    } catch (const nlohmann::json::exception&) {
        throw InputError(format("{}: '{}' has the wrong type", file.string(), key));
    }
}

glm::dvec3 vec3(const nlohmann::json& j, const char* key, const fs::path& file) {
    const auto v = get<std::vector<double>>(j, key, file);
    if (v.size() != 3 || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
        throw InputError(format("{}: '{}' must be three finite numbers", file.string(), key));
    return {v[0], v[1], v[2]};
}

nlohmann::ordered_json vec(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

// sim.json's debris.chips: how many of the last pieces are chips (0 for a folder from before debris).
std::size_t debrisChips(const nlohmann::json& j, std::size_t pieces, const fs::path& file) {
    if (!j.contains("debris")) return 0;
    const auto chips = get<std::int64_t>(get<nlohmann::json>(j, "debris", file), "chips", file);
    if (chips < 0 || std::size_t(chips) >= pieces)
        throw InputError(format("{}: debris.chips is {}, but there are {} pieces in all", file.string(), chips, pieces));
    return std::size_t(chips);
}

// DIR/dust.bin when sim.json's debris.dust counts puffs: each value finite, sizes and
// opacities in range.
void loadDust(const fs::path& dir, const nlohmann::json& j, SimulationFolder& out) {
    if (!j.contains("debris") || !j["debris"].contains("dust")) return;
    const fs::path jsonFile = dir / "sim.json", bin = dir / "dust.bin";
    const auto puffs = get<std::int64_t>(j["debris"]["dust"], "puffs", jsonFile);
    if (puffs < 0) throw InputError(format("{}: debris.dust.puffs is negative", jsonFile.string()));
    if (puffs == 0) return;
    std::error_code ec;
    if (!fs::is_regular_file(bin, ec)) throw InputError(format("{}: no such file (sim.json counts {} puffs of dust)", bin.string(), puffs));
    out.dust = readFloats(bin, out.frames, puffs, 5);
    for (std::size_t v = 0; v < out.dust.size(); v += 5) {
        const bool finite = std::all_of(out.dust.begin() + std::ptrdiff_t(v), out.dust.begin() + std::ptrdiff_t(v + 5),
                                        [](float x) { return std::isfinite(x); });
        if (!finite || out.dust[v + 3] < 0.0f || out.dust[v + 4] < 0.0f || out.dust[v + 4] > 1.0f)
            throw InputError(format("{}: puff {} at frame {} is not a place, a size ≥ 0 and an opacity in [0, 1]",
                                    bin.string(), (v / 5) % std::size_t(puffs), v / 5 / std::size_t(puffs)));
    }
    out.dustPuffs = std::size_t(puffs);
}

}  // namespace

Scene debrisScene(const SimulationResult& result) {
    Scene scene;
    for (const RigidPiece& chip : result.chips) {
        const std::uint32_t node = scene.addMeshNode(chip.mesh, glm::vec3(chip.centerOfMass));
        scene.nodes[node].name = chip.name;
        scene.nodes[node].extrasJson = nlohmann::ordered_json{{"mass", chip.mass}}.dump();
    }
    scene.extrasJson = nlohmann::ordered_json{{"generator", "dawnforge simulate"}, {"chips", result.chips.size()}}.dump();
    return scene;
}

FractureFolder loadFracture(const fs::path& dir) {
    std::error_code ec;
    const fs::path jsonFile = dir / "fracture.json";
    const nlohmann::json j = readFolderJson(dir, "fracture.json", "dawnforge.fracture", "fracture");
    if (get<int>(j, "version", jsonFile) != 1)
        throw InputError(format("{}: version {} is not supported (expected 1)", jsonFile.string(), j["version"].dump()));

    FractureFolder out;
    out.seed = get<std::uint64_t>(j, "seed", jsonFile);
    if (j.contains("input") && j["input"].is_object()) {
        const nlohmann::json& input = j["input"];
        if (input.contains("file") && input["file"].is_string()) out.input = input["file"].get<std::string>();
        if (input.contains("building")) out.building = get<int>(input, "building", jsonFile);
    }
    const auto pieces = get<nlohmann::json>(j, "pieces", jsonFile);
    if (!pieces.is_array() || pieces.empty()) throw InputError(format("{}: 'pieces' is empty", jsonFile.string()));
    for (std::size_t i = 0; i < pieces.size(); ++i) {
        const nlohmann::json& p = pieces[i];
        RigidPiece piece;
        piece.name = get<std::string>(p, "name", jsonFile);
        piece.mass = get<double>(p, "mass", jsonFile);
        if (!(piece.mass > 0.0) || !std::isfinite(piece.mass))
            throw InputError(format("{}: piece {} has mass {}; it must be positive", jsonFile.string(), i, piece.mass));
        piece.centerOfMass = vec3(p, "center_of_mass", jsonFile);
        const auto inertia = get<std::vector<std::vector<double>>>(p, "inertia", jsonFile);
        if (inertia.size() != 3) throw InputError(format("{}: piece {}: 'inertia' must be 3×3", jsonFile.string(), i));
        for (int r = 0; r < 3; ++r) {
            if (inertia[std::size_t(r)].size() != 3)
                throw InputError(format("{}: piece {}: 'inertia' must be 3×3", jsonFile.string(), i));
            for (int c = 0; c < 3; ++c) {
                const double v = inertia[std::size_t(r)][std::size_t(c)];
                if (!std::isfinite(v)) throw InputError(format("{}: piece {}: 'inertia' is not finite", jsonFile.string(), i));
                piece.inertia[c][r] = v;  // rows in the file, columns in glm
            }
        }
        out.pieces.push_back(std::move(piece));
    }
    for (const nlohmann::json& b : get<nlohmann::json>(j, "bonds", jsonFile)) {
        Bond bond;
        const auto a = get<std::int64_t>(b, "a", jsonFile), c = get<std::int64_t>(b, "b", jsonFile);
        if (a < 0 || c < 0 || std::size_t(a) >= out.pieces.size() || std::size_t(c) >= out.pieces.size() || a == c)
            throw InputError(format("{}: a bond joins pieces {} and {}, but there are {} pieces", jsonFile.string(), a,
                                    c, out.pieces.size()));
        bond.a = std::uint32_t(a);
        bond.b = std::uint32_t(c);
        bond.area = get<double>(b, "area", jsonFile);
        bond.centroid = b.contains("centroid") ? vec3(b, "centroid", jsonFile)
                                               : 0.5 * (out.pieces[bond.a].centerOfMass + out.pieces[bond.b].centerOfMass);
        const glm::dvec3 across = out.pieces[bond.b].centerOfMass - out.pieces[bond.a].centerOfMass;
        bond.normal = b.contains("normal") ? vec3(b, "normal", jsonFile) : across;
        if (!(glm::length(bond.normal) > 0.0)) bond.normal = glm::dvec3(0.0, 1.0, 0.0);  // two pieces at one place
        bond.normal = glm::normalize(bond.normal);
        if (!(bond.area >= 0.0)) throw InputError(format("{}: a bond has a negative area", jsonFile.string()));
        if (b.contains("strength")) bond.strength = get<double>(b, "strength", jsonFile);
        if (!(bond.strength >= 0.0) || !std::isfinite(bond.strength))
            throw InputError(format("{}: a bond's strength must be a number of pascals, not negative", jsonFile.string()));
        out.bonds.push_back(bond);
    }

    std::vector<std::string> names;
    std::vector<glm::dvec3> pivots;
    for (const RigidPiece& p : out.pieces) {
        names.push_back(p.name);
        pivots.push_back(p.centerOfMass);
    }
    std::vector<Mesh> meshes = loadFragments(dir / "fragments.glb", names, pivots, jsonFile, "fracture");
    for (std::size_t i = 0; i < meshes.size(); ++i) out.pieces[i].mesh = std::move(meshes[i]);
    return out;
}

std::string simulationJson(const SimulationResult& result, const SimulationSettings& settings,
                           std::span<const RigidPiece> pieces, std::string_view fractureDir) {
    nlohmann::ordered_json j;
    j["format"] = "dawnforge.sim";
    j["version"] = 1;
    j["fracture"] = std::string(fractureDir);
    j["frames"] = result.frames;
    j["fps"] = result.fps;
    j["pieces"] = result.pieces;
    j["substeps"] = settings.substeps;
    j["gravity"] = vec(settings.gravity);
    j["seed"] = settings.seed;
    nlohmann::ordered_json triggers = nlohmann::ordered_json::array();
    if (settings.projectile) {
        const Projectile& p = *settings.projectile;
        triggers.push_back({{"type", "projectile"}, {"time", settings.triggerTime}, {"target", vec(p.target)},
                            {"direction", vec(glm::normalize(p.direction))}, {"mass", p.mass}, {"speed", p.speed},
                            {"radius", p.radius}});
    }
    if (settings.explosion) {
        const Explosion& x = *settings.explosion;
        triggers.push_back({{"type", "explosion"}, {"time", settings.triggerTime}, {"center", vec(x.center)},
                            {"radius", x.radius}, {"speed", x.speed},
                            {"clamped_pieces", result.clampedThrows}});
    }
    if (settings.collapse) triggers.push_back({{"type", "collapse"}, {"time", settings.triggerTime}});
    j["triggers"] = std::move(triggers);
    j["ground"] = {{"enabled", settings.ground}, {"height", result.groundHeight}};
    j["colliders"] = settings.colliders.size();
    if (settings.support)
        j["support"] = {{"height", settings.support->height},
                        {"min", {settings.support->min.x, settings.support->min.y}},
                        {"max", {settings.support->max.x, settings.support->max.y}}};
    j["glue"] = {{"strength", settings.strength},
                 {"variation", settings.strengthVariation},
                 {"impact_time", settings.impactTime},
                 {"damage", {{"transmission", settings.damageTransmission},
                             {"hops", settings.damageHops},
                             {"half_life", settings.damageHalfLife}}},
                 {"bonds", result.bonds},
                 {"broken", result.brokenBonds},
                 {"anchor", settings.anchor},
                 {"bodies", result.actors},
                 {"fixed_bodies", result.fixedActors}};
    j["solver"] = {{"iterations", settings.solverIterations}, {"hull_vertices", settings.hullVertices},
                   {"margin", settings.margin},           {"friction", settings.friction},
                   {"restitution", settings.restitution}, {"linear_damping", settings.linearDamping},
                   {"angular_damping", settings.angularDamping}, {"sleep", settings.sleep},
                   {"overlapping_hulls", result.overlappingHulls}};
    double maxEnergy = result.energy.empty() ? 0.0 : result.energy.front();
    for (double e : result.energy) maxEnergy = std::max(maxEnergy, e);
    j["energy"] = {{"initial", result.energy.empty() ? 0.0 : result.energy.front()},
                   {"max", maxEnergy},
                   {"final", result.energy.empty() ? 0.0 : result.energy.back()},
                   {"injected", result.injectedEnergy}};
    j["max_speed"] = result.maxSpeed;
    j["transforms"] = {{"file", "transforms.bin"},
                       {"layout", "float32 little-endian, frame-major, per piece px py pz qx qy qz qw"}};
    j["turns"] = {{"file", "turns.bin"},
                  {"layout", "float32 little-endian, frame-major, per piece the signed turns to the next frame"}};
    const DebrisSettings& d = settings.debris;
    j["debris"] = {{"chips", result.chips.size()},
                   {"file", result.chips.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json("debris.glb")},
                   {"first_chip", result.pieces - result.chips.size()},
                   {"bonds", result.chipBonds},
                   {"enabled", d.chips},
                   {"per_square_metre", d.chipsPerSquareMetre},
                   {"max_per_bond", d.maxChipsPerBond},
                   {"max", d.maxChips},
                   {"size", d.chipSize},
                   {"spray_speed", d.spraySpeed},
                   {"dust", {{"puffs", result.dustPuffs},
                             {"file", result.dustPuffs == 0 ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json("dust.bin")},
                             {"layout", "float32 little-endian, frame-major, per puff x y z size opacity"},
                             {"enabled", d.dust},
                             {"per_square_metre", d.puffsPerSquareMetre},
                             {"max", d.maxPuffs},
                             {"size", d.puffSize},
                             {"life", d.puffLife}}}};
    nlohmann::ordered_json names = nlohmann::ordered_json::array();
    for (const RigidPiece& p : pieces) names.push_back(p.name);
    for (const RigidPiece& p : result.chips) names.push_back(p.name);
    j["piece_names"] = std::move(names);
    return j.dump(1) + "\n";
}

void writeSimulation(const fs::path& dir, const SimulationResult& result, const SimulationSettings& settings,
                     std::span<const RigidPiece> pieces, std::string_view fractureDir) {
    ensureOutputDirectory(dir);
    writeFileAtomically(dir / "transforms.bin", std::as_bytes(std::span<const float>(result.transforms)));
    writeFileAtomically(dir / "turns.bin", std::as_bytes(std::span<const float>(result.turns)));
    if (result.dustPuffs > 0) writeFileAtomically(dir / "dust.bin", std::as_bytes(std::span<const float>(result.dust)));
    else fs::remove(dir / "dust.bin");  // an earlier run's, which sim.json no longer counts
    writeFileAtomically(dir / "sim.json", simulationJson(result, settings, pieces, fractureDir));
}

SimulationFolder loadSimulation(const fs::path& dir) {
    std::error_code ec;
    const fs::path jsonFile = dir / "sim.json";
    const nlohmann::json j = readFolderJson(dir, "sim.json", "dawnforge.sim", "simulation");
    SimulationFolder out;
    out.frames = get<int>(j, "frames", jsonFile);
    out.fps = get<double>(j, "fps", jsonFile);
    const auto pieces = get<std::int64_t>(j, "pieces", jsonFile);
    out.names = get<std::vector<std::string>>(j, "piece_names", jsonFile);
    if (out.frames < 1) throw InputError(format("{}: frames is {}; it must be at least 1", jsonFile.string(), out.frames));
    if (!(out.fps > 0.0)) throw InputError(format("{}: fps must be positive", jsonFile.string()));
    if (pieces < 1 || std::size_t(pieces) != out.names.size())
        throw InputError(format("{}: 'pieces' ({}) does not match 'piece_names' ({})", jsonFile.string(), pieces,
                                out.names.size()));

    const fs::path bin = dir / "transforms.bin";
    if (!fs::is_regular_file(bin, ec)) throw InputError(format("{}: no such file", bin.string()));
    out.transforms = readFloats(bin, out.frames, pieces, 7);
    for (std::size_t t = 0; t < out.transforms.size(); t += 7) {
        for (std::size_t c = 0; c < 7; ++c)
            if (!std::isfinite(out.transforms[t + c]))
                throw InputError(format("{}: a value of piece {} at frame {} is not finite", bin.string(),
                                        (t / 7) % std::size_t(pieces), t / 7 / std::size_t(pieces)));
        const double len = std::sqrt(double(out.transforms[t + 3]) * out.transforms[t + 3] +
                                     double(out.transforms[t + 4]) * out.transforms[t + 4] +
                                     double(out.transforms[t + 5]) * out.transforms[t + 5] +
                                     double(out.transforms[t + 6]) * out.transforms[t + 6]);
        if (std::abs(len - 1.0) > 1e-3)
            throw InputError(format("{}: the orientation of piece {} at frame {} is not a unit quaternion",
                                    bin.string(), (t / 7) % std::size_t(pieces), t / 7 / std::size_t(pieces)));
    }
    const fs::path turns = dir / "turns.bin";
    if (fs::exists(turns, ec)) {
        out.turns = readFloats(turns, out.frames, pieces, 1);
        for (float v : out.turns)
            if (!std::isfinite(v)) throw InputError(format("{}: a value is not finite", turns.string()));
    }
    std::vector<glm::dvec3> rest;  // frame 0: where each piece's pivot starts
    for (std::size_t i = 0; i < out.names.size(); ++i) rest.push_back(glm::dvec3(out.transforms[i * 7], out.transforms[i * 7 + 1], out.transforms[i * 7 + 2]));
    const std::size_t chips = debrisChips(j, out.names.size(), jsonFile);
    const std::size_t first = out.names.size() - chips;
    const auto part = [](const auto& all, std::size_t from, std::size_t count) {
        return std::span(all).subspan(from, count);
    };
    out.meshes = loadFragments(dir / "fragments.glb", part(out.names, 0, first), part(rest, 0, first), jsonFile, "simulation");
    if (chips > 0) {
        std::vector<Mesh> debris = loadFragments(dir / "debris.glb", part(out.names, first, chips), part(rest, first, chips),
                                                 jsonFile, "simulation");
        std::move(debris.begin(), debris.end(), std::back_inserter(out.meshes));
    }
    out.chips = chips;
    loadDust(dir, j, out);
    return out;
}

}  // namespace dawnforge::sim
