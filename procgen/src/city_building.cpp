#include <dawnforge/procgen/city_building.hpp>

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/materials.hpp>
#include <dawnforge/core/read_file.hpp>

#include <nlohmann/json.hpp>

#include <cstdio>

namespace dawnforge::procgen {

namespace {

using Json = nlohmann::json;

std::string buildingName(int id) {
    char name[32];
    std::snprintf(name, sizeof name, "building_%05d", id);
    return name;
}

Mesh toWorld(const MeshNode& node) {
    Mesh out;
    appendMesh(out, node.mesh, node.world);
    out.name = node.name;
    return out;
}

bool near(const Bounds& a, const Bounds& b, double r) {
    for (int k = 0; k < 3; ++k)
        if (a.min[k] > b.max[k] + r || b.min[k] > a.max[k] + r) return false;
    return true;
}

// The triangles of `mesh` whose bounds come within r of `b`, with the vertices they use.
Mesh nearTriangles(const Mesh& mesh, const Bounds& b, double r) {
    Mesh out;
    out.name = mesh.name;
    std::vector<std::uint32_t> index(mesh.positions.size(), UINT32_MAX);
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const glm::vec3 p[3] = {mesh.positions[mesh.indices[3 * t]], mesh.positions[mesh.indices[3 * t + 1]],
                                mesh.positions[mesh.indices[3 * t + 2]]};
        const Bounds tb = computeBounds(p);
        if (!near(tb, b, r)) continue;
        for (std::size_t k = 0; k < 3; ++k) {
            const std::uint32_t v = mesh.indices[3 * t + k];
            if (index[v] == UINT32_MAX) {
                index[v] = std::uint32_t(out.positions.size());
                out.positions.push_back(mesh.positions[v]);
            }
            out.indices.push_back(index[v]);
        }
    }
    return out;
}

std::uint8_t materialFromName(const std::string& name, const std::filesystem::path& file) {
    for (int id = 0; id < kMaterialCount; ++id)
        if (name == materialName(std::uint8_t(id))) return std::uint8_t(id);
    throw InputError(format("{}: unknown material \"{}\" in a building's parts", file.string(), name));
}

// The building's entry in city.json, with the error a user can act on when it is not there.
Json buildingEntry(const Json& city, int id, const std::filesystem::path& file) {
    if (!city.contains("buildings") || !city["buildings"].is_array())
        throw InputError(format("{}: no \"buildings\" list; is this a city.json written by 'dawnforge city'?", file.string()));
    for (const Json& b : city["buildings"])
        if (b.value("id", -1) == id) return b;
    if (city.contains("tile") && city["tile"].is_array())
        throw InputError(format("{}: no building {} in this folder, which holds tile {},{} only (it may be on another tile)",
                                file.string(), id, city["tile"][0].get<int>(), city["tile"][1].get<int>()));
    throw InputError(format("{}: no building {} in this city ({} buildings; see \"buildings\" for their ids)",
                            file.string(), id, city["buildings"].size()));
}

std::vector<BuildingPart> partsOf(const Json& entry, const std::filesystem::path& file, int id) {
    if (!entry.contains("parts") || !entry["parts"].is_array() || entry["parts"].empty())
        throw InputError(format("{}: building {} lists no parts (a city written before parts were listed: run 'dawnforge "
                                "city' again)", file.string(), id));
    std::vector<BuildingPart> parts;
    for (const Json& p : entry["parts"]) {
        if (!p.is_array() || p.size() != 4 || !p[0].is_string() || !p[1].is_string() || !p[2].is_number_unsigned() ||
            !p[3].is_number_unsigned())
            throw InputError(format("{}: building {}: a part is not [kind, material, first_triangle, triangles]",
                                    file.string(), id));
        const auto kind = partKindFromName(p[0].get<std::string>());
        if (!kind) throw InputError(format("{}: building {}: unknown part kind \"{}\"", file.string(), id, p[0].get<std::string>()));
        parts.push_back({*kind, materialFromName(p[1].get<std::string>(), file), p[2].get<std::uint32_t>(),
                         p[3].get<std::uint32_t>()});
    }
    return parts;
}

}  // namespace

CityBuilding loadCityBuilding(const std::filesystem::path& cityDir, int id, double neighbourRadius) {
    const std::filesystem::path jsonFile = cityDir / "city.json", glbFile = cityDir / "city.glb";
    if (!std::filesystem::is_regular_file(jsonFile))
        throw InputError(format("{}: not a city folder (no city.json in it)", cityDir.string()));
    Json city;
    try {
        city = Json::parse(readTextFile(jsonFile));
    } catch (const Json::exception& e) {
        throw InputError(format("{}: {}", jsonFile.string(), oneLine(e.what())));
    }
    const Json entry = buildingEntry(city, id, jsonFile);
    const std::vector<BuildingPart> parts = partsOf(entry, jsonFile, id);
    if (!std::filesystem::is_regular_file(glbFile))
        throw InputError(format("{}: not a city folder (no city.glb in it)", cityDir.string()));

    CityBuilding out;
    out.id = id;
    out.name = buildingName(id);
    const std::string lod0Name = out.name + "_lod0";
    std::vector<MeshNode> nodes = loadMeshNodes(glbFile, ReadIn::thisProcess);
    bool found = false;
    for (const MeshNode& node : nodes)
        if (node.name == lod0Name) {
            out.lod0 = toWorld(node);
            found = true;
        }
    if (!found) throw InputError(format("{}: no node {} although city.json lists the building", glbFile.string(), lod0Name));
    out.bounds = computeBounds(out.lod0.positions);
    for (const BuildingPart& part : parts) {
        CityBuildingPart p{part.kind, part.material, partMesh(out.lod0, part)};
        out.parts.push_back(std::move(p));
    }
    for (MeshNode& node : nodes) {
        const bool lod1 = node.name.size() > 5 && node.name.ends_with("_lod1") && node.name.starts_with("building_");
        if (node.name.starts_with("ground_")) {
            Mesh ground = toWorld(node);
            if (!near(computeBounds(ground.positions), out.bounds, neighbourRadius)) continue;
            Mesh nearby = nearTriangles(ground, out.bounds, neighbourRadius);
            if (!nearby.indices.empty()) out.ground.push_back(std::move(nearby));
        }
        else if (lod1 && node.name != out.name + "_lod1") {
            Mesh shell = toWorld(node);
            if (near(computeBounds(shell.positions), out.bounds, neighbourRadius)) out.neighbours.push_back(std::move(shell));
        }
    }
    return out;
}

}  // namespace dawnforge::procgen
