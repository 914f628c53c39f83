#include <dawnforge/sim/fracture_io.hpp>

#include <dawnforge/core/materials.hpp>

#include <nlohmann/json.hpp>

namespace dawnforge::sim {

namespace {

nlohmann::ordered_json vec(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

}  // namespace

Scene fractureScene(const FractureResult& result) {
    Scene scene;
    for (const FracturePiece& piece : result.pieces) {
        const std::uint32_t node = scene.addMeshNode(piece.mesh, glm::vec3(piece.mass.centerOfMass));
        scene.nodes[node].name = piece.name;
        nlohmann::ordered_json extras;
        extras["mass"] = piece.mass.mass;
        extras["volume"] = piece.mass.volume;
        scene.nodes[node].extrasJson = extras.dump();
    }
    nlohmann::ordered_json extras;
    extras["generator"] = "dawnforge fracture";
    extras["pieces"] = result.pieces.size();
    extras["bonds"] = result.bonds.size();
    scene.extrasJson = extras.dump();
    return scene;
}

std::string fractureJson(const FractureResult& result, const FractureSettings& settings, std::string_view inputFile,
                         int building) {
    nlohmann::ordered_json j;
    j["format"] = "dawnforge.fracture";
    j["version"] = 1;
    j["input"] = {{"file", std::string(inputFile)}, {"triangles", result.inputTriangles}, {"volume", result.inputVolume}};
    if (building >= 0) j["input"]["building"] = building;
    j["seed"] = settings.seed;
    nlohmann::ordered_json s;
    s["pieces"] = settings.points.empty() ? settings.pieces : int(settings.points.size());
    s["seeds_from_file"] = !settings.points.empty();
    s["density"] = settings.density;
    s["interior_material"] = settings.interiorMaterial;
    s["interior_uv_scale"] = settings.interiorUvScale;
    s["impact"] = settings.impact ? vec(*settings.impact) : nlohmann::ordered_json(nullptr);
    s["radius"] = settings.impactRadius;
    s["min_volume"] = settings.minVolume;
    s["levels"] = settings.levels;
    s["level_pieces"] = settings.levelPieces;
    s["method"] = fractureMethodName(settings.method);
    j["settings"] = std::move(s);

    double total = 0.0;
    nlohmann::ordered_json pieces = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < result.pieces.size(); ++i) {
        const FracturePiece& p = result.pieces[i];
        total += p.mass.volume;
        nlohmann::ordered_json e;
        e["id"] = i;
        e["name"] = p.name;
        e["volume"] = p.mass.volume;
        e["mass"] = p.mass.mass;
        e["center_of_mass"] = vec(p.mass.centerOfMass);
        const glm::dmat3& I = p.mass.inertia;
        e["inertia"] = {{I[0][0], I[1][0], I[2][0]}, {I[0][1], I[1][1], I[2][1]}, {I[0][2], I[1][2], I[2][2]}};
        e["triangles"] = p.mesh.triangleCount();
        e["closed"] = p.closed;
        e["cell"] = p.cell;
        e["level"] = p.level;
        if (!result.parts.empty()) {  // a building's pieces: the part each came from
            e["part"] = p.part;
            e["material"] = materialName(p.material);
        }
        pieces.push_back(std::move(e));
    }
    if (!result.parts.empty()) {
        nlohmann::ordered_json parts = nlohmann::ordered_json::array();
        for (const PartResult& p : result.parts)
            parts.push_back({{"kind", p.kind}, {"material", materialName(p.material)}, {"style", breakStyleName(p.style)},
                             {"volume", p.volume}, {"triangles", p.triangles}, {"cells", p.cells}, {"pieces", p.pieces}});
        j["parts"] = std::move(parts);
    }
    j["volume"] = total;
    j["merged"] = result.merged;
    j["cells"] = {{"cut", result.cells}, {"by_corefinement", result.fallbackCells}};
    j["pieces"] = std::move(pieces);
    nlohmann::ordered_json bonds = nlohmann::ordered_json::array();
    for (const Bond& b : result.bonds) {
        nlohmann::ordered_json e{{"a", b.a}, {"b", b.b}, {"area", b.area}, {"centroid", vec(b.centroid)}, {"normal", vec(b.normal)}};
        if (b.strength > 0.0) e["strength"] = b.strength;
        bonds.push_back(std::move(e));
    }
    j["bonds"] = std::move(bonds);
    return j.dump(1) + "\n";
}

}  // namespace dawnforge::sim
