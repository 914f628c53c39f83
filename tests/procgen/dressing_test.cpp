// Street trees and lamps: where city.json says they stand, checked with the test's own plan
// geometry (not procgen's), and tree species that Pivot Painter reads as hierarchies.
#include <dawnforge/core/error.hpp>
#include <dawnforge/exporters/pivot_painter.hpp>
#include <dawnforge/procgen/city.hpp>
#include <dawnforge/procgen/recipe.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <set>

namespace dawnforge::procgen {
namespace {

using Json = nlohmann::json;
using Ring = std::vector<glm::dvec2>;

Ring ring(const Json& points) {
    Ring r;
    for (const Json& p : points) r.push_back({p[0].get<double>(), p[1].get<double>()});
    return r;
}

// Crossing-number point-in-polygon and distance to a ring's edges, written here.
bool inside(const Ring& poly, glm::dvec2 p) {
    bool in = false;
    for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
        const glm::dvec2 a = poly[i], b = poly[j];
        if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) in = !in;
    }
    return in;
}
double distance(const Ring& poly, glm::dvec2 p) {
    double best = INFINITY;
    for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
        const glm::dvec2 a = poly[j], ab = poly[i] - a;
        const double t = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
        best = std::min(best, glm::length(p - (a + t * ab)));
    }
    return best;
}

CitySettings dressedCity() {
    CitySettings s;
    s.size = {300.0, 240.0};
    s.tileSize = 150.0;
    s.seed = 5;
    s.recipe.buildings.maxFloors = 3;
    s.recipe.interiors.enabled = false;
    return s;
}

const Json& report() {
    static const Json j = [] {
        const City city = generateCity(dressedCity());
        return Json::parse(cityReportJson(city));
    }();
    return j;
}

// What stands on the ground: a foot, and how close the next thing may be.
struct Standing {
    std::string name;
    glm::dvec2 foot;
};

TEST(Dressing, TreesAndLampsStandOnSidewalksNeverInAStreetABuildingOrEachOther) {
    const Json& j = report();
    std::vector<Standing> all;
    for (const char* kind : {"trees", "lamps"})
        for (const Json& e : j[kind]) all.push_back({e["name"].get<std::string>(), ring(Json::array({e["foot"]}))[0]});
    ASSERT_GT(j["trees"].size(), 20u);
    ASSERT_GT(j["lamps"].size(), 20u);
    std::vector<Ring> curbs, footprints;
    std::vector<Ring> lots;
    for (const Json& b : j["blocks"]) {
        curbs.push_back(ring(b["curb"]));
        for (const Json& lot : b["lots"]) lots.push_back(ring(lot["polygon"]));
    }
    for (const Json& b : j["buildings"]) footprints.push_back(ring(b["footprint"]));
    for (const Standing& s : all) {
        // On a block (not in a street): inside one kerb, at least 0.3 m from its edge.
        bool onBlock = false;
        for (const Ring& c : curbs) onBlock = onBlock || (inside(c, s.foot) && distance(c, s.foot) >= 0.25);
        EXPECT_TRUE(onBlock) << s.name << " stands in a street";
        for (const Ring& lot : lots) EXPECT_FALSE(inside(lot, s.foot)) << s.name << " stands in a lot";
        for (const Ring& f : footprints) EXPECT_GT(distance(f, s.foot), 1.5) << s.name << " stands against a building";
    }
    for (std::size_t a = 0; a < all.size(); ++a)
        for (std::size_t b = a + 1; b < all.size(); ++b)
            EXPECT_GE(glm::length(all[a].foot - all[b].foot), 3.9) << all[a].name << " and " << all[b].name;
}

TEST(Dressing, LampsReachOverTheStreetAndTreesAreOfTheListedSpecies) {
    const Json& j = report();
    const DressingRecipe d;
    std::vector<Ring> curbs;
    for (const Json& b : j["blocks"]) curbs.push_back(ring(b["curb"]));
    for (const Json& lamp : j["lamps"]) {
        const glm::dvec2 foot = ring(Json::array({lamp["foot"]}))[0];
        const glm::dvec2 light{lamp["light"][0].get<double>(), lamp["light"][1].get<double>()};
        EXPECT_NEAR(glm::length(light - foot), d.lampArm - 0.075, 2e-3) << lamp["name"];
        EXPECT_NEAR(lamp["light"][2].get<double>(), d.lampHeight + 0.15 - 0.25, 2e-3) << lamp["name"];
        // The light hangs over the kerb or the street, not over the sidewalk's inner half.
        bool overBlockInside = false;
        for (const Ring& c : curbs) overBlockInside = overBlockInside || (inside(c, light) && distance(c, light) > 0.5);
        EXPECT_FALSE(overBlockInside) << lamp["name"];
        EXPECT_DOUBLE_EQ(std::max({lamp["colour"][0].get<double>(), lamp["colour"][1].get<double>(),
                                   lamp["colour"][2].get<double>()}),
                         1.0);
    }
    std::set<std::string> names;
    for (const Json& s : j["tree_species"]) names.insert(s["name"].get<std::string>());
    EXPECT_EQ(names.size(), 3u);
    std::set<std::string> used;
    for (const Json& t : j["trees"]) {
        EXPECT_TRUE(names.count(t["species"].get<std::string>())) << t["name"];
        used.insert(t["species"].get<std::string>());
        EXPECT_NEAR(t["scale"].get<double>(), 1.0, d.treeScaleJitter + 1e-9);
    }
    EXPECT_GE(used.size(), 2u);
    EXPECT_EQ(j["counts"]["trees"].get<std::size_t>(), j["trees"].size());
    EXPECT_EQ(j["counts"]["lamps"].get<std::size_t>(), j["lamps"].size());
}

// Each species is a three-level hierarchy whose children sit on their parent's axis.
TEST(Dressing, SpeciesArePivotPainterHierarchiesWithChildrenOnTheirParentsAxis) {
    for (const TreeSpecies& s : makeTreeSpecies(5)) {
        const exporters::PivotPainter pp =
            exporters::buildPivotPainter(speciesNodes(s), exporters::PivotPreset::Native, s.name);
        EXPECT_EQ(pp.levels, 3) << s.name;
        ASSERT_EQ(pp.elements.size(), s.elements.size());
        EXPECT_NEAR(glm::length(pp.elements[0].pivot), 0.0, 1e-6);
        EXPECT_NEAR(pp.elements[0].xAxis.y, 1.0, 1e-6) << "the trunk stands up";
        for (std::size_t i = 1; i < pp.elements.size(); ++i) {
            const exporters::PivotElement& e = pp.elements[i];
            const exporters::PivotElement& parent = pp.elements[std::size_t(e.parent)];
            const glm::dvec3 along = e.pivot - parent.pivot;
            const double t = glm::dot(along, parent.xAxis);
            EXPECT_LT(glm::length(along - t * parent.xAxis), 1e-4) << s.name << " " << e.name;
            EXPECT_GT(t, 0.0) << e.name;
            EXPECT_LE(t, parent.extent + 1e-4) << e.name;
            EXPECT_GT(e.xAxis.y, 0.0) << e.name << " grows downwards";
        }
        for (const TreeElement& e : s.elements) validateMeshData(e.mesh, e.name);
    }
}

// Every triangle of a tree and of the lamp faces where its vertices' normals point: glTF's
// front is counter-clockwise, and consumers that cull back faces (Blender, three.js, Unreal)
// showed the trunks, branches and lamp poles inside out until Blender's import found it
// (tests/consumers/blender.sh).
void expectWoundOutwards(const Mesh& m, const std::string& name) {
    std::size_t against = 0;
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        const std::uint32_t a = m.indices[t], b = m.indices[t + 1], c = m.indices[t + 2];
        const glm::vec3 face = glm::cross(m.positions[b] - m.positions[a], m.positions[c] - m.positions[a]);
        for (const std::uint32_t v : {a, b, c}) against += glm::dot(face, m.normals[v]) < 0.0f;
    }
    EXPECT_EQ(against, 0u) << name << ": corners facing against their triangle's winding";
}

TEST(Dressing, TreesAndLampsAreWoundCounterClockwiseFromOutside) {
    for (const TreeSpecies& s : makeTreeSpecies(5))
        for (const TreeElement& e : s.elements) expectWoundOutwards(e.mesh, s.name + " " + e.name);
    expectWoundOutwards(makeLampMesh(DressingRecipe{}), "lamp");
}

TEST(Dressing, ATileAloneHasTheSameTreesAndLampsAsTheWholeCity) {
    CitySettings s = dressedCity();
    s.tile = glm::ivec2(1, 0);
    const Json alone = Json::parse(cityReportJson(generateCity(s)));
    for (const char* kind : {"trees", "lamps"}) {
        Json expected = Json::array();
        for (const Json& e : report()[kind])
            if (e["tile"] == Json::array({1, 0})) expected.push_back(e);
        EXPECT_GT(expected.size(), 3u) << kind;
        EXPECT_EQ(alone[kind], expected) << kind;
    }
}

TEST(Dressing, RecipeValuesOutOfRangeAreRefused) {
    for (const char* bad : {R"({"dressing": {"tree_spacing": 2}})", R"({"dressing": {"lamp_spacing": 0.5}})",
                            R"({"dressing": {"lamp_height": 40}})", R"({"dressing": {"tree_chance": 1.5}})",
                            R"({"dressing": {"lamp_red": 0, "lamp_green": 0, "lamp_blue": 0}})",
                            R"({"dressing": {"tree_spacingg": 10}})"})
        EXPECT_THROW(parseRecipe(bad, "r.json"), InputError) << bad;
    CitySettings s = dressedCity();
    s.recipe = parseRecipe(R"({"dressing": {"tree_spacing": 0, "lamp_spacing": 0}})", "r.json");
    const Json none = Json::parse(cityReportJson(generateCity(s)));
    EXPECT_TRUE(none["trees"].empty());
    EXPECT_TRUE(none["lamps"].empty());
}

}  // namespace
}  // namespace dawnforge::procgen
