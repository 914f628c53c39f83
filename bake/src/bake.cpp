// dawnforge bake: a city folder in, CITY_DIR/bake/ out (bake.hpp, bake_folder.hpp).
#include <dawnforge/bake/bake.hpp>
#include <dawnforge/bake/bake_folder.hpp>
#include <dawnforge/bake/overlook.hpp>
#include <dawnforge/bake/proxies.hpp>
#include <dawnforge/bake/ray_scene.hpp>

#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/materials.hpp>
#include <dawnforge/core/read_file.hpp>
#include <dawnforge/exporters/image.hpp>

#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>
#include <cstdlib>
#include <unistd.h>

namespace dawnforge::bake {

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

constexpr float kSurfaceOffset = 0.001f;  // LOD0 and ground samples start 1 mm off their surface
constexpr float kShellOffset = 0.01f;     // LOD1 shells lie on LOD0's outer faces: 1 cm
constexpr double kRevealToRoom = 0.2;     // glass to the wall's inner face, about (lamp placement)
// Memory the bake holds per texel (bytes), measured (README, Figures): atlas buffers and samples.
constexpr double kBytesPerAtlasTexel = 96.0;
constexpr double kBytesPerTriangle = 160.0;  // the city's meshes, the ray scene, charts

// A mesh of city.glb in world space.
Mesh worldMesh(const MeshNode& node) {
    Mesh m = node.mesh;
    const glm::mat3 normalMatrix = glm::transpose(glm::inverse(glm::mat3(node.world)));
    for (glm::vec3& p : m.positions) p = glm::vec3(node.world * glm::vec4(p, 1.0f));
    for (glm::vec3& n : m.normals) n = glm::normalize(normalMatrix * n);
    return m;
}

struct CityBuilding {
    bool halo = false;      // a world tile's neighbour: lit and traced, not written
    std::string name;       // building_NNNNN
    std::uint32_t id = 0;   // NNNNN (the runtime's instance id), else its order
    std::string lod0Node, lod1Node;
    Mesh lod0, lod1;
};

struct CityStatic {
    bool halo = false;
    std::string name;
    Mesh mesh;
};

struct CityInput {
    double haloTexelScale = 1.0;  // halo receivers' texels are this many times as large
    std::vector<CityBuilding> buildings;
    std::vector<CityStatic> statics;
    std::vector<glm::vec3> streetLamps;  // city.json's lamps' lights, glTF axes
    std::string cityJson;
    std::vector<std::byte> glb;
};

// Sorts city.glb's nodes (world matrices; `halo` per node, or empty for none) into
// buildings and other receivers.
void addNodes(CityInput& city, std::span<const MeshNode> nodes, const std::vector<bool>& halo) {
    std::map<std::string, std::size_t> index;
    for (std::size_t k = 0; k < nodes.size(); ++k) {
        const MeshNode& node = nodes[k];
        const std::string& name = node.name;
        const bool lod0 = name.ends_with("_lod0"), lod1 = name.ends_with("_lod1");
        const bool inHalo = !halo.empty() && halo[k];
        // Trees sway, lamps are thin and the far land is a backdrop kilometres wide: the
        // runtime lights them by sun and sky, unbaked.
        if (name.starts_with("tree_") || name.starts_with("lamp_") || name.starts_with("land_")) continue;
        if (!lod0 && !lod1) {
            city.statics.push_back({inHalo, name, worldMesh(node)});
            continue;
        }
        const std::string key = name.substr(0, name.size() - 5);
        auto [it, added] = index.try_emplace(key, city.buildings.size());
        if (added) {
            CityBuilding b;
            b.halo = inHalo;
            b.name = key;
            b.id = std::uint32_t(city.buildings.size());
            if (key.starts_with("building_")) b.id = std::uint32_t(std::strtoul(key.c_str() + 9, nullptr, 10));
            city.buildings.push_back(std::move(b));
        }
        CityBuilding& b = city.buildings[it->second];
        (lod0 ? b.lod0Node : b.lod1Node) = name;
        (lod0 ? b.lod0 : b.lod1) = worldMesh(node);
    }
}

std::size_t writtenBuildings(const CityInput& city) {
    return std::size_t(std::count_if(city.buildings.begin(), city.buildings.end(), [](const CityBuilding& b) { return !b.halo; }));
}

// city.json's street lamps' lights in glTF axes. A world's tile has city.glb in its own frame,
// whose origin city.json gives.
std::vector<glm::vec3> streetLamps(const nlohmann::json& j) {
    const auto origin = j.contains("origin") ? j["origin"].get<std::array<double, 2>>() : std::array<double, 2>{0.0, 0.0};
    std::vector<glm::vec3> lamps;
    if (j.contains("lamps"))
        for (const nlohmann::json& lamp : j["lamps"]) {
            const auto l = lamp.at("light").get<std::array<double, 3>>();
            lamps.emplace_back(float(l[0] - origin[0]), float(l[2]), float(origin[1] - l[1]));
        }
    return lamps;
}

CityInput readCity(const std::filesystem::path& cityDir) {
    namespace fs = std::filesystem;
    if (!fs::is_directory(cityDir))
        throw InputError(format("{}: no such city folder", cityDir.string()));
    if (!fs::exists(cityDir / "city.glb"))
        throw InputError(format("{}: no city.glb: not a city folder (dawnforge city writes one)", cityDir.string()));
    if (!fs::exists(cityDir / "city.json"))
        throw InputError(format("{}: city.json is missing: the city folder is incomplete", cityDir.string()));
    CityInput city;
    city.glb = readBinaryFile(cityDir / "city.glb");
    city.cityJson = readTextFile(cityDir / "city.json");
    addNodes(city, loadMeshNodes(cityDir / "city.glb", ReadIn::thisProcess), {});
    // city.json and city.glb must describe the same city.
    try {
        const nlohmann::json j = nlohmann::json::parse(city.cityJson);
        if (j.contains("counts") && j["counts"].contains("buildings")) {
            const std::size_t listed = j["counts"]["buildings"].get<std::size_t>();
            if (listed != city.buildings.size())
                throw InputError(format("{}: city.json lists {} buildings but city.glb holds {}: the city folder is incomplete or mixed",
                                        cityDir.string(), listed, city.buildings.size()));
        }
        city.streetLamps = streetLamps(j);
    } catch (const nlohmann::json::exception& e) {
        throw InputError(format("{}: {}", (cityDir / "city.json").string(), oneLine(e.what())));
    }
    return city;
}

std::uint8_t triangleMaterial(const Mesh& m, std::size_t t) {
    return m.materialIds.empty() ? std::uint8_t{0} : std::uint8_t(m.materialIds[m.indices[3 * t]] & 15u);
}

// Everything one receiver's ReceiverInput points into.
struct ReceiverData {
    bool halo = false;                 // lit and traced, not written
    std::string name, kind;
    std::uint32_t building = 0;
    std::vector<std::pair<std::string, std::size_t>> meshes;  // node, vertices
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> indices;
    std::vector<std::uint8_t> materials, occluder;
    std::vector<float> texel, rayOffset;
    std::vector<std::uint8_t> group;  // per triangle: 0 LOD0 or the ground, 1 LOD1
    std::vector<glm::vec3> chartPositions;  // positions from the first vertex: what the charts see
    std::vector<std::uint32_t> glassRoom;  // per vertex: room slot + 1, 0 for none
    std::vector<std::uint32_t> roomIndex;  // per slot: the building's room index
    ChartSet charts;
    LightmapLayout layout;
};

bool isInterior(std::uint8_t material) { return material == kInteriorWall || material == kFloor; }

void appendMesh(ReceiverData& r, const Mesh& m, float texel, float interiorTexel, bool occluder, float offset) {
    const auto base = std::uint32_t(r.positions.size());
    r.positions.insert(r.positions.end(), m.positions.begin(), m.positions.end());
    for (std::uint32_t i : m.indices) r.indices.push_back(base + i);
    for (std::size_t t = 0; t < m.triangleCount(); ++t) {
        const std::uint8_t mat = triangleMaterial(m, t);
        const bool glass = mat == kGlass;
        r.materials.push_back(mat);
        r.occluder.push_back(occluder && !glass);
        r.texel.push_back(glass ? 0.0f : isInterior(mat) ? interiorTexel : texel);
        r.rayOffset.push_back(offset);
        r.group.push_back(std::uint8_t(r.meshes.size() - 1));
    }
}

// The lamp of a room, estimated from one of its window panes: the glass carries the room's
// front face (uv0: metres from its lower-left corner; uv2: width and height) and depth (uv1.x).
glm::dvec3 lampFromGlass(const Mesh& m, std::size_t t) {
    const std::uint32_t v0 = m.indices[3 * t];
    const glm::dvec3 p(m.positions[v0]);
    const glm::dvec3 a(m.positions[m.indices[3 * t]]), b(m.positions[m.indices[3 * t + 1]]), c(m.positions[m.indices[3 * t + 2]]);
    glm::dvec3 n = glm::cross(b - a, c - a);
    n = glm::length(n) > 0.0 ? glm::normalize(n) : glm::dvec3(0, 0, 1);
    glm::dvec3 along = glm::cross(glm::dvec3(0, 1, 0), n);
    along = glm::length(along) > 1e-9 ? glm::normalize(along) : glm::dvec3(1, 0, 0);
    const double s = m.uv0[v0].x, h = m.uv0[v0].y;
    for (int k = 1; k < 3; ++k) {
        const std::uint32_t v = m.indices[3 * t + std::size_t(k)];
        const double du = double(m.uv0[v].x) - s;
        if (std::abs(du) > 1e-4) {
            if (glm::dot(glm::dvec3(m.positions[v]) - p, along) * du < 0.0) along = -along;
            break;
        }
    }
    const double width = m.uv2[v0].x, height = m.uv2[v0].y, depth = m.uv1[v0].x;
    glm::dvec3 inward = -glm::dvec3(n.x, 0.0, n.z);
    inward = glm::length(inward) > 1e-9 ? glm::normalize(inward) : glm::dvec3(0.0);
    const glm::dvec3 centre = p + along * (0.5 * width - s) + inward * (kRevealToRoom + 0.5 * depth);
    return {centre.x, p.y - h + height - kLampBelowCeiling, centre.z};
}

bool isRoomGlass(const Mesh& m, std::size_t t) {
    if (triangleMaterial(m, t) != kGlass || m.uv1.empty() || m.uv2.empty()) return false;
    const std::uint32_t v = m.indices[3 * t];
    return m.uv2[v].x > 0.0f && m.uv2[v].y > 0.0f && m.uv1[v].x > 0.0f;
}

std::uint32_t roomOf(const Mesh& m, std::size_t t) { return std::uint32_t(std::lround(m.uv1[m.indices[3 * t]].y)); }


// A building's receiver: LOD0 then LOD1, its rooms (one slot per room seen through glass, in
// order of their index), a lamp in each lit room and the windows the room table looks through.
void buildingReceiver(const CityBuilding& b, std::uint32_t bi, const BakeSettings& settings, ReceiverData& r,
                      std::vector<Lamp>& lamps, std::vector<RoomWindow>& windows) {
    r.halo = b.halo;
    r.name = b.name;
    r.kind = "building";
    r.building = b.id;
    const float texel = float(settings.texel), shellTexel = float(settings.texel * settings.lod1TexelScale);
    if (!b.lod0Node.empty()) {
        r.meshes.emplace_back(b.lod0Node, b.lod0.vertexCount());
        appendMesh(r, b.lod0, texel, float(settings.interiorTexel), true, kSurfaceOffset);
    }
    if (!b.lod1Node.empty()) {
        r.meshes.emplace_back(b.lod1Node, b.lod1.vertexCount());
        appendMesh(r, b.lod1, shellTexel, shellTexel, b.lod0Node.empty(), b.lod0Node.empty() ? kSurfaceOffset : kShellOffset);
    }
    // room index -> lamp estimate sum, count. LOD0's panes place the lamps; LOD1's only for a
    // room that LOD0 shows no window of (count < 0: estimated from LOD1 panes only).
    std::map<std::uint32_t, std::pair<glm::dvec3, int>> rooms;
    const Mesh* lods[2] = {&b.lod0, &b.lod1};
    for (int lod = 0; lod < 2; ++lod)
        for (std::size_t t = 0; t < lods[lod]->triangleCount(); ++t) {
            if (!isRoomGlass(*lods[lod], t)) continue;
            auto [it, added] = rooms.try_emplace(roomOf(*lods[lod], t), glm::dvec3(0.0), 0);
            if (lod == 0 || added || it->second.second < 0) {
                it->second.first += lampFromGlass(*lods[lod], t);
                it->second.second = lod == 0 ? std::abs(it->second.second) + 1 : it->second.second - 1;
            }
        }
    std::map<std::uint32_t, std::uint32_t> slotOf;
    for (const auto& [room, lamp] : rooms) {
        slotOf[room] = std::uint32_t(r.roomIndex.size());
        r.roomIndex.push_back(room);
        if (roomLampLit(b.id, room)) lamps.push_back({glm::vec3(lamp.first / double(std::abs(lamp.second))), bi});
    }
    r.glassRoom.assign(r.positions.size(), 0);
    std::uint32_t base = 0;
    for (const Mesh* m : lods) {
        for (std::size_t t = 0; t < m->triangleCount(); ++t) {
            if (!isRoomGlass(*m, t)) continue;
            const std::uint32_t slot = slotOf[roomOf(*m, t)];
            const std::uint32_t* idx = &m->indices[3 * t];
            for (int k = 0; k < 3; ++k) r.glassRoom[base + idx[k]] = slot + 1;
            const glm::vec3 a = m->positions[idx[0]], bb = m->positions[idx[1]], c = m->positions[idx[2]];
            const glm::vec3 n = glm::cross(bb - a, c - a);
            if (glm::length(n) <= 0.0f) continue;
            windows.push_back({bi, slot, a, bb, c, -glm::normalize(n)});
        }
        base += std::uint32_t(m->vertexCount());
    }
}

// Every receiver of the city: the buildings, then the other meshes (ground tiles, kerbs).
struct Receivers {
    std::vector<ReceiverData> data;
    std::vector<Lamp> lamps;
    std::vector<RoomWindow> windows;
};

// Each street lamp lights every receiver that comes within its range (the ground, the
// buildings along its street), in lamp order, then receiver order.
void addStreetLamps(std::span<const glm::vec3> streetLamps, Receivers& out) {
    std::vector<Bounds> bounds;
    for (const ReceiverData& r : out.data) bounds.push_back(computeBounds(r.positions));
    for (const glm::vec3& lamp : streetLamps)
        for (std::size_t r = 0; r < bounds.size(); ++r) {
            const glm::dvec3 nearest = glm::clamp(glm::dvec3(lamp), bounds[r].min, bounds[r].max);
            if (!out.data[r].positions.empty() && glm::length(nearest - glm::dvec3(lamp)) < kLampRange)
                out.lamps.push_back({lamp, std::uint32_t(r), kStreetLampIntensity});
        }
}

// The settings of a halo receiver: texels `scale` times as large. A halo only bounces light
// onto its tile and shades it; a coarser lightmap does that as well for a fraction of the work.
BakeSettings haloSettings(BakeSettings s, double scale) {
    s.texel *= scale, s.interiorTexel *= scale, s.groundTexel *= scale;
    return s;
}

Receivers cityReceivers(const CityInput& city, const BakeSettings& settings) {
    const BakeSettings halo = haloSettings(settings, city.haloTexelScale);
    Receivers out;
    out.data.resize(city.buildings.size() + city.statics.size());
    std::vector<std::vector<Lamp>> lamps(city.buildings.size());
    std::vector<std::vector<RoomWindow>> windows(city.buildings.size());
    tbb::parallel_for(std::size_t{0}, city.buildings.size(), [&](std::size_t bi) {
        const CityBuilding& b = city.buildings[bi];
        buildingReceiver(b, std::uint32_t(bi), b.halo ? halo : settings, out.data[bi], lamps[bi], windows[bi]);
    });
    for (std::size_t bi = 0; bi < city.buildings.size(); ++bi) {
        out.lamps.insert(out.lamps.end(), lamps[bi].begin(), lamps[bi].end());
        out.windows.insert(out.windows.end(), windows[bi].begin(), windows[bi].end());
    }
    tbb::parallel_for(std::size_t{0}, city.statics.size(), [&](std::size_t si) {
        ReceiverData& r = out.data[city.buildings.size() + si];
        const CityStatic& s = city.statics[si];
        r.halo = s.halo;
        r.name = s.name;
        r.kind = s.name.starts_with("ground_") ? "ground" : "mesh";
        r.meshes.emplace_back(s.name, s.mesh.vertexCount());
        const float texel = float((s.halo ? halo : settings).groundTexel);
        appendMesh(r, s.mesh, texel, texel, true, kSurfaceOffset);
    });
    addStreetLamps(city.streetLamps, out);
    return out;
}

// A receiver's positions less its first vertex's, each difference exact: the charts and their
// packing then do not depend on where the receiver stands, so a building laid out in its
// tile's frame gets the same lightmap layout as in the whole city's (float positions moved
// by a world tile's origin are moved exactly).
std::vector<glm::vec3> fromFirstVertex(std::span<const glm::vec3> positions) {
    std::vector<glm::vec3> out(positions.size());
    if (positions.empty()) return out;
    const glm::dvec3 origin(positions.front());
    for (std::size_t i = 0; i < positions.size(); ++i) out[i] = glm::vec3(glm::dvec3(positions[i]) - origin);
    return out;
}

// Polygons inside the receiver's own solids (caps between storeys, faces buried in walls) get
// no texels; then every receiver's charts. Both see the receiver alone, in its own frame
// (fromFirstVertex), so its layout does not depend on its neighbours or on where it stands. A
// polygon too large for a chart at this texel size is a budget error.
std::size_t chartReceivers(std::vector<ReceiverData>& data, std::span<const ReceiverInput> inputs, const BakeSettings& settings) {
    std::vector<std::string> errors(data.size());
    std::vector<std::size_t> hidden(data.size(), 0);
    tbb::parallel_for(std::size_t{0}, data.size(), [&](std::size_t i) {
        ReceiverData& r = data[i];
        r.chartPositions = fromFirstVertex(r.positions);
        ReceiverInput alone = inputs[i];
        alone.positions = r.chartPositions;
        const std::unique_ptr<RayScene> scene = occluderScene(std::span(&alone, 1));
        const std::vector<std::uint8_t> buried = hiddenTriangles(*scene, std::span(&alone, 1), std::span(&r.texel, 1), 8, settings.seed)[0];
        for (std::size_t t = 0; t < buried.size(); ++t)
            if (buried[t]) r.texel[t] = 0.0f, ++hidden[i];
        try {
            r.charts = makeCharts(ChartMesh{r.chartPositions, r.indices, r.texel, r.group});
        } catch (const InputError& e) {
            errors[i] = format("{}: {}", r.name, e.what());
        }
    });
    for (const std::string& e : errors)
        if (!e.empty()) throw BakeBudgetError(e, 0.0);
    return std::accumulate(hidden.begin(), hidden.end(), std::size_t{0});
}

// The memory the bake will need, checked against the budget before anything large is
// allocated; returns the estimate (MB).
double checkBudget(const std::vector<ReceiverData>& data, std::size_t glbBytes, const BakeSettings& settings) {
    double atlasTexels = 0.0, triangles = 0.0;
    for (const ReceiverData& r : data) {
        const glm::ivec2 table = roomTableSize(std::uint32_t(r.roomIndex.size()));
        atlasTexels += 1.12 * double(r.charts.blockTexels + std::size_t(table.x) * std::size_t(table.y));
        triangles += double(r.indices.size() / 3);
    }
    const double fixedMb = (triangles * kBytesPerTriangle + 2.0 * double(glbBytes)) / 1048576.0;
    const double lightmapMb = atlasTexels * kBytesPerAtlasTexel / 1048576.0;
    const double estimate = fixedMb + lightmapMb;
    if (estimate <= settings.memoryBudgetMb) return estimate;
    // Lightmap memory goes with 1 / texel²: every texel size (outside, rooms, ground) times
    // `scale` fits, with 5 % to spare; the meshes' share does not shrink.
    const double room = settings.memoryBudgetMb - fixedMb;
    const double scale = room > 0.0 ? std::sqrt(lightmapMb / room) * 1.05 : 0.0;
    const auto up = [&](double texel) { return std::ceil(texel * scale * 100.0) / 100.0; };
    const std::string fits =
        scale > 0.0 ? format("; texels {} times as large fit ({} m outside, {} m in rooms, {} m on the ground)",
                             std::ceil(scale * 100.0) / 100.0, up(settings.texel), up(settings.interiorTexel), up(settings.groundTexel))
                    : format("; the meshes alone need about {} MB", std::lround(fixedMb));
    throw BakeBudgetError(format("a texel of {} m ({} m in rooms) needs about {} MB to bake this city, more than the budget of {} MB{}",
                                 settings.texel, settings.interiorTexel, std::lround(estimate), std::lround(settings.memoryBudgetMb), fits),
                          scale > 0.0 ? up(settings.texel) : 0.0);
}

// Packs every receiver's atlas (with its room table); window glass points at its room's block.
void packReceivers(std::vector<ReceiverData>& data, const BakeSettings& settings) {
    std::vector<std::string> errors(data.size());
    tbb::parallel_for(std::size_t{0}, data.size(), [&](std::size_t i) {
        ReceiverData& r = data[i];
        std::vector<glm::ivec2> extra;
        if (!r.roomIndex.empty()) extra.push_back(roomTableSize(std::uint32_t(r.roomIndex.size())));
        try {
            const ChartMesh mesh{r.chartPositions, r.indices, r.texel, r.group};
            r.layout = packLightmap(mesh, std::move(r.charts), extra, r.name);
        } catch (const InputError& e) {
            errors[i] = e.what();
            return;
        }
        for (std::size_t v = 0; v < r.glassRoom.size(); ++v)
            if (r.glassRoom[v] > 0) r.layout.uv[v] = glm::vec2(roomTexel(r.layout.extraOrigins[0], r.glassRoom[v] - 1)) + float(kChartAlign) * 0.5f;
    });
    for (const std::string& e : errors)
        if (!e.empty()) throw BakeBudgetError(e, std::ceil(settings.texel * 150.0) / 100.0);
}

// The proxies of the city (proxies.hpp), with the artists' overrides applied.
std::vector<ProxyBox> cityProxies(const CityInput& city, const std::string& overrides, const std::filesystem::path& cityDir) {
    std::vector<ProxyBox> proxies;
    const auto add = [&](std::vector<ProxyBox> boxes) { proxies.insert(proxies.end(), boxes.begin(), boxes.end()); };
    for (const CityBuilding& b : city.buildings)
        if (!b.halo) add(buildingProxies(b.name, b.lod1.positions.empty() ? b.lod0 : b.lod1));
    add(streetProxies(city.cityJson, (cityDir / "city.json").string()));
    for (const CityStatic& s : city.statics)
        if (!s.halo) add(groundProxies(s.name, s.mesh));
    if (!overrides.empty()) applyProxyOverrides(proxies, overrides, (cityDir / "proxy_colours.json").string());
    return proxies;
}

OverlookMap cityOverlook(const CityInput& city, const BakeSettings& settings) {
    std::vector<OverlookMesh> meshes;
    for (const CityBuilding& b : city.buildings)
        if (!b.halo) meshes.push_back({&(b.lod1.positions.empty() ? b.lod0 : b.lod1), true});
    for (const CityStatic& s : city.statics)
        if (!s.halo) meshes.push_back({&s.mesh, false});
    return bakeOverlook(meshes, settings.overlookTexel);
}

// bake.json (bake_folder.hpp).
std::string manifestJson(const CityInput& city, const BakeSettings& settings, const std::vector<ReceiverData>& data,
                         std::span<const ReceiverInput> inputs, const Lighting& lighting, const BakeReport& report) {
    nlohmann::ordered_json receivers = nlohmann::ordered_json::array();
    std::size_t written = 0;
    for (std::size_t i = 0; i < data.size(); ++i) {
        const ReceiverData& r = data[i];
        const ReceiverInput& in = inputs[i];
        if (r.halo) continue;
        ++written;
        nlohmann::ordered_json meshes = nlohmann::ordered_json::array();
        for (const auto& [node, vertices] : r.meshes) meshes.push_back({{"node", node}, {"vertices", vertices}});
        nlohmann::ordered_json j{{"name", r.name}, {"kind", r.kind}};
        if (r.kind == "building") j["building"] = r.building;
        j["lightmap"] = r.name + ".png";
        j["uv"] = r.name + ".uv";
        j["size"] = {in.layout.size.x, in.layout.size.y};
        j["meshes"] = std::move(meshes);
        j["texels"] = lighting.receivers[i].texels;
        j["rooms"] = in.rooms;
        if (in.rooms > 0) j["room_table"] = {in.layout.extraOrigins[0].x, in.layout.extraOrigins[0].y};
        receivers.push_back(std::move(j));
    }
    nlohmann::ordered_json manifest;
    manifest["format"] = "dawnforge.bake";
    manifest["version"] = 1;
    manifest["city_glb"] = {{"bytes", city.glb.size()}, {"hash", hashText(hashFileBytes(city.glb))}};
    manifest["settings"] = {{"texel", settings.texel},           {"interior_texel", settings.interiorTexel},
                            {"lod1_texel_scale", settings.lod1TexelScale},
                            {"ground_texel", settings.groundTexel}, {"samples", settings.samples},
                            {"sun_samples", settings.sunSamples}, {"bounces", settings.bounces},
                            {"ao_radius", settings.aoRadius},     {"overlook_texel", settings.overlookTexel},
                            {"seed", settings.seed}};
    manifest["channels"] = {
        {"encoding", "stored = round(255 * sqrt(clamp(value / range, 0, 1)))"},
        {"r", {{"name", "sky"}, {"range", kChannelRange[0]}, {"sky", "uniform radiance 1/pi over the upper hemisphere: 1 on an open horizontal surface"}}},
        {"g", {{"name", "sun_bounce"}, {"range", kChannelRange[1]}, {"sun", "unit irradiance, averaged over 06:00-18:00"}}},
        {"b", {{"name", "ao"}, {"range", kChannelRange[2]}, {"radius", settings.aoRadius}}},
        {"a", {{"name", "lamps"}, {"range", kChannelRange[3]}, {"lamp_intensity", kLampIntensity}, {"lamp_range", kLampRange}}}};
    manifest["mip_levels"] = kLightmapLevels;
    manifest["room_table"] = {{"columns", kRoomTableColumns}, {"block", kChartAlign}};
    manifest["counts"] = {{"receivers", written}, {"buildings", writtenBuildings(city)}, {"rooms", report.rooms},
                          {"lamps", report.lamps},    {"texels", report.texels},          {"proxies", report.proxies}};
    manifest["receivers"] = std::move(receivers);
    manifest["overlook"] = "overlook.exr";
    manifest["proxies"] = "proxies.json";
    return manifest.dump(1) + "\n";
}

// Writes every file into CITY_DIR/bake.partial-PID, then swaps it in for CITY_DIR/bake: a
// failure leaves the old bake (or none) and no partial folder.
void writeBakeFolder(const std::filesystem::path& cityDir, std::span<const ReceiverData> data, std::span<const ReceiverInput> inputs, const Lighting& lighting,
                     const OverlookMap& overlook, const std::vector<ProxyBox>& proxies, const std::string& manifest) {
    namespace fs = std::filesystem;
    const fs::path target = cityDir / "bake";
    const fs::path partial = cityDir / format("bake.partial-{}", ::getpid());
    const fs::path old = cityDir / format("bake.old-{}", ::getpid());
    struct Cleanup {
        fs::path dir;
        ~Cleanup() {
            std::error_code ec;
            if (!dir.empty()) fs::remove_all(dir, ec);
        }
    } cleanup{partial};
    std::error_code ec;
    fs::remove_all(partial, ec);
    ensureOutputDirectory(partial);
    std::vector<std::string> errors(inputs.size());
    tbb::parallel_for(std::size_t{0}, inputs.size(), [&](std::size_t i) {
        if (data[i].halo) return;
        const ReceiverInput& in = inputs[i];
        const ReceiverLighting& out = lighting.receivers[i];
        exporters::Image image{in.layout.size.x, in.layout.size.y, {}};
        image.rgba.resize(out.channels.size());
        for (std::size_t k = 0; k < out.channels.size(); ++k) image.rgba[k] = encodeChannel(out.channels[k], int(k % 4));
        std::vector<float> uv;
        uv.reserve(2 * in.layout.uv.size());
        for (const glm::vec2& t : in.layout.uv) uv.insert(uv.end(), {t.x / float(in.layout.size.x), t.y / float(in.layout.size.y)});
        try {
            exporters::writePng(image, partial / (in.name + ".png"));
            writeFileAtomically(partial / (in.name + ".uv"), std::as_bytes(std::span(uv)));
        } catch (const InputError& e) {
            errors[i] = e.what();
        }
    });
    for (const std::string& e : errors)
        if (!e.empty()) throw InputError(e);
    writeOverlook(overlook, partial / "overlook.exr");
    writeFileAtomically(partial / "proxies.json", proxiesJson(proxies));
    writeFileAtomically(partial / "bake.json", manifest);
    if (fs::exists(target)) fs::rename(target, old);
    fs::rename(partial, target);
    cleanup.dir = old;
}

LightingSettings lightingSettings(const BakeSettings& settings) {
    LightingSettings ls;
    ls.samples = settings.samples;
    ls.sunSamples = settings.sunSamples;
    ls.bounces = settings.bounces;
    ls.aoRadius = settings.aoRadius;
    ls.seed = settings.seed;
    return ls;
}

}  // namespace

void checkBakeSettings(const BakeSettings& s) {
    const auto check = [](bool ok, const char* what, double value, const char* range) {
        if (!ok) throw InputError(format("the bake's {} must be {} (got {})", what, range, value));
    };
    check(std::isfinite(s.texel) && s.texel >= 0.01 && s.texel <= 10.0, "texel size", s.texel, "0.01 to 10 m");
    check(std::isfinite(s.interiorTexel) && s.interiorTexel >= 0.01 && s.interiorTexel <= 10.0, "interior texel size", s.interiorTexel, "0.01 to 10 m");
    check(std::isfinite(s.lod1TexelScale) && s.lod1TexelScale >= 1.0 && s.lod1TexelScale <= 16.0, "LOD1 texel scale", s.lod1TexelScale, "1 to 16");
    check(std::isfinite(s.groundTexel) && s.groundTexel >= 0.05 && s.groundTexel <= 50.0, "ground texel size", s.groundTexel, "0.05 to 50 m");
    check(s.samples >= 1 && s.samples <= 65536, "sample count", s.samples, "1 to 65536");
    check(s.sunSamples >= 1 && s.sunSamples <= 4096, "sun sample count", s.sunSamples, "1 to 4096");
    check(s.bounces >= 0 && s.bounces <= 16, "bounce count", s.bounces, "0 to 16");
    check(std::isfinite(s.aoRadius) && s.aoRadius > 0.0 && s.aoRadius <= 100.0, "AO radius", s.aoRadius, "above 0 and at most 100 m");
    check(std::isfinite(s.overlookTexel) && s.overlookTexel >= 0.05 && s.overlookTexel <= 100.0, "overlook texel size", s.overlookTexel, "0.05 to 100 m");
    check(std::isfinite(s.memoryBudgetMb) && s.memoryBudgetMb >= 64.0, "memory budget", s.memoryBudgetMb, "at least 64 MB");
}

namespace {

// Bakes a loaded city (or a world tile with its halo) and writes CITY_DIR/bake/.
BakeReport bakeLoaded(const CityInput& city, const std::filesystem::path& cityDir, const std::string& overrides,
                      const BakeSettings& settings, const ProgressFn& progress, Clock::time_point start) {
    BakeReport report;
    report.loadSeconds = secondsSince(start);
    if (!progress(0.02)) throw Cancelled();

    // Receivers, the ray scene, charts, the memory budget, then the atlases.
    auto t0 = Clock::now();
    Receivers receivers = cityReceivers(city, settings);
    std::vector<ReceiverData>& data = receivers.data;
    for (std::size_t bi = 0; bi < city.buildings.size(); ++bi)
        if (!data[bi].halo) report.rooms += data[bi].roomIndex.size();
    std::vector<ReceiverInput> inputs(data.size());
    for (std::size_t i = 0; i < data.size(); ++i) {
        const ReceiverData& r = data[i];
        inputs[i] = ReceiverInput{r.name, r.positions, r.indices, r.materials, r.occluder, r.rayOffset, {}, std::uint32_t(r.roomIndex.size())};
    }
    const std::unique_ptr<RayScene> scene = occluderScene(inputs);
    report.hiddenTriangles = chartReceivers(data, inputs, settings);
    report.estimatedMb = checkBudget(data, city.glb.size(), settings);
    packReceivers(data, settings);
    report.layoutSeconds = secondsSince(t0);

    t0 = Clock::now();
    for (std::size_t i = 0; i < data.size(); ++i) {
        inputs[i].layout = std::move(data[i].layout);
        report.atlasTexels += std::size_t(inputs[i].layout.size.x) * std::size_t(inputs[i].layout.size.y);
        report.triangles += std::size_t(std::count(data[i].occluder.begin(), data[i].occluder.end(), std::uint8_t{1}));
    }
    const Lighting lighting = bakeLighting(inputs, receivers.lamps, receivers.windows, lightingSettings(settings),
                                           [&](double f) { return progress(0.05 + 0.85 * f); }, scene.get());
    report.lighting = lighting.stats;
    report.texels = lighting.stats.texels;
    report.lamps = receivers.lamps.size();
    report.lightingSeconds = secondsSince(t0);

    t0 = Clock::now();
    const OverlookMap overlook = cityOverlook(city, settings);
    const std::vector<ProxyBox> proxies = cityProxies(city, overrides, cityDir);
    report.proxies = proxies.size();
    report.buildings = writtenBuildings(city);
    report.receivers = std::size_t(std::count_if(data.begin(), data.end(), [](const ReceiverData& r) { return !r.halo; }));
    writeBakeFolder(cityDir, data, inputs, lighting, overlook, proxies, manifestJson(city, settings, data, inputs, lighting, report));
    report.writeSeconds = secondsSince(t0);
    report.seconds = secondsSince(start);
    return report;
}

}  // namespace

BakeReport bakeCity(const std::filesystem::path& cityDir, const BakeSettings& settings, const ProgressFn& progress) {
    namespace fs = std::filesystem;
    const auto start = Clock::now();
    checkBakeSettings(settings);
    const CityInput city = readCity(cityDir);
    std::string overrides;
    if (fs::exists(cityDir / "proxy_colours.json")) overrides = readTextFile(cityDir / "proxy_colours.json");
    return bakeLoaded(city, cityDir, overrides, settings, progress, start);
}

BakeReport bakeRegion(const BakeRegion& region, const std::filesystem::path& cityDir, const BakeSettings& settings,
                      const ProgressFn& progress) {
    const auto start = Clock::now();
    checkBakeSettings(settings);
    DAWNFORGE_ASSERT(region.halo.size() == region.nodes.size(), "bakeRegion(): one halo flag per node");
    if (!(region.haloTexelScale >= 1.0 && region.haloTexelScale <= 64.0))
        throw InputError(format("the halo's texel scale must be 1 to 64 (got {})", region.haloTexelScale));
    CityInput city;
    city.haloTexelScale = region.haloTexelScale;
    city.glb = region.cityGlb;
    city.cityJson = region.cityJson;
    try {
        city.streetLamps = streetLamps(nlohmann::json::parse(region.regionCityJson));
    } catch (const nlohmann::json::exception& e) {
        throw InputError(format("the region's city.json: {}", oneLine(e.what())));
    }
    addNodes(city, region.nodes, region.halo);
    return bakeLoaded(city, cityDir, {}, settings, progress, start);
}

}  // namespace dawnforge::bake
