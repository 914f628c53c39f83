#include <dawnforge/procgen/recipe.hpp>

#include <dawnforge/core/error.hpp>

#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <string>

using namespace dawnforge;
using namespace dawnforge::procgen;

namespace {

// The InputError message parseRecipe throws for `json`, or "" when it parses.
std::string parseError(const std::string& json) {
    try {
        parseRecipe(json, "recipe.json");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

std::string validateError(const std::function<void(CityRecipe&)>& change) {
    CityRecipe recipe;
    change(recipe);
    try {
        validateRecipe(recipe, "code");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

std::string readExample(const std::string& name) {
    const std::string path = std::string(DAWNFORGE_TEST_DATA) + "/../../examples/recipes/" + name;
    std::ifstream in(path);
    EXPECT_TRUE(in) << path;
    return {std::istreambuf_iterator<char>(in), {}};
}

}  // namespace

TEST(RecipeParse, EmptyObjectGivesDefaults) {
    EXPECT_EQ(recipeJson(parseRecipe("{}", "recipe.json")), recipeJson(CityRecipe{}));
    EXPECT_EQ(recipeJson(parseRecipe(R"({"description": "x", "roofs": {}})", "r")), recipeJson(CityRecipe{}));
    EXPECT_NO_THROW(validateRecipe(CityRecipe{}, "defaults"));
}

TEST(RecipeParse, KeysSetTheirFields) {
    const CityRecipe r = parseRecipe(R"({
        "streets": {"major_spacing": 300, "bend_wavelength": 250.5, "angle": -15},
        "coast": {"water": 0, "seabed_slope": 0.2},
        "lots": {"setback_jitter": 0, "max_frontage": 30},
        "buildings": {"min_floors": 3, "max_floors": 12, "ground_storey_height": 4.5, "tower_extra_floors": 0},
        "interiors": {"enabled": false, "min_room_depth": 4},
        "roofs": {"gable": 0.7, "max_pitched_floors": 3}
    })", "recipe.json");
    EXPECT_EQ(r.streets.majorSpacing, 300.0);
    EXPECT_EQ(r.streets.bendWavelength, 250.5);
    EXPECT_EQ(r.streets.angle, -15.0);
    EXPECT_EQ(r.streets.minorSpacing, StreetRecipe{}.minorSpacing);
    EXPECT_EQ(r.coast.water, 0.0);
    EXPECT_EQ(r.coast.seabedSlope, 0.2);
    EXPECT_EQ(r.lots.setbackJitter, 0.0);
    EXPECT_EQ(r.lots.maxFrontage, 30.0);
    EXPECT_EQ(r.buildings.minFloors, 3);
    EXPECT_EQ(r.buildings.maxFloors, 12);
    EXPECT_EQ(r.buildings.groundStoreyHeight, 4.5);
    EXPECT_EQ(r.buildings.towerExtraFloors, 0);
    EXPECT_FALSE(r.interiors.enabled);
    EXPECT_EQ(r.interiors.minRoomDepth, 4.0);
    EXPECT_EQ(r.roofs.gable, 0.7);
    EXPECT_EQ(r.roofs.maxPitchedFloors, 3);
}

TEST(RecipeParse, UnknownKeysNameTheirPath) {
    const std::string top = parseError(R"({"weather": {}})");
    EXPECT_NE(top.find("recipe.json"), std::string::npos) << top;
    EXPECT_NE(top.find("\"weather\""), std::string::npos) << top;
    EXPECT_EQ(top.find("did you mean"), std::string::npos) << top;

    const std::string inner = parseError(R"({"buildings": {"colour": "red"}})");
    EXPECT_NE(inner.find("recipe.json"), std::string::npos) << inner;
    EXPECT_NE(inner.find("\"buildings.colour\""), std::string::npos) << inner;

    EXPECT_NE(parseError(R"({"$schema": "x"})").find("\"$schema\""), std::string::npos);
}

TEST(RecipeParse, NearMissesGetASuggestion) {
    EXPECT_EQ(parseError(R"({"buildings": {"max_flors": 12}})"),
              "recipe.json: unknown key \"buildings.max_flors\" (did you mean \"buildings.max_floors\"?)");
    EXPECT_NE(parseError(R"({"bulidings": {}})").find("(did you mean \"buildings\"?)"), std::string::npos);
    // A key in the wrong section, or at top level, points to where it belongs.
    EXPECT_NE(parseError(R"({"streets": {"water": 0.1}})").find("(did you mean \"coast.water\"?)"),
              std::string::npos);
    EXPECT_NE(parseError(R"({"max_floors": 12})").find("(did you mean \"buildings.max_floors\"?)"),
              std::string::npos);
}

TEST(RecipeParse, WrongTypesAreErrors) {
    EXPECT_EQ(parseError(R"({"buildings": {"storey_height": "3"}})"),
              "recipe.json: buildings.storey_height must be a number");
    EXPECT_NE(parseError(R"({"buildings": {"max_floors": 12.5}})").find("buildings.max_floors must be a whole"),
              std::string::npos);
    EXPECT_NE(parseError(R"({"interiors": {"enabled": 1}})").find("interiors.enabled"), std::string::npos);
    EXPECT_NE(parseError(R"({"roofs": {"flat": null}})").find("roofs.flat"), std::string::npos);
    EXPECT_NE(parseError(R"({"roofs": [1, 2]})").find("roofs must be an object"), std::string::npos);
    EXPECT_NE(parseError(R"([])").find("recipe.json: "), std::string::npos);
    EXPECT_NE(parseError(R"({"description": 3})").find("description"), std::string::npos);
    EXPECT_NE(parseError(R"({"buildings": {"max_floors": 99999999999}})").find("buildings.max_floors must be in"),
              std::string::npos);
}

TEST(RecipeParse, OutOfRangeValuesAreErrors) {
    EXPECT_EQ(parseError(R"({"buildings": {"storey_height": 0}})"),
              "recipe.json: buildings.storey_height must be > 0 (got 0)");
    EXPECT_NE(parseError(R"({"streets": {"minor_width": -2}})").find("streets.minor_width must be > 0"),
              std::string::npos);
    EXPECT_NE(parseError(R"({"lots": {"setback": -1}})").find("lots.setback must be >= 0"), std::string::npos);
    EXPECT_NE(parseError(R"({"coast": {"water": 1.0}})").find("coast.water must be in [0, 0.9]"), std::string::npos);
    EXPECT_NE(parseError(R"({"buildings": {"shop_chance": 1.5}})").find("buildings.shop_chance"), std::string::npos);
    EXPECT_NE(parseError(R"({"buildings": {"min_floors": 0}})").find("buildings.min_floors"), std::string::npos);
    EXPECT_NE(parseError(R"({"roofs": {"pitch": 0}})").find("roofs.pitch must be in (0, 3]"), std::string::npos);
    EXPECT_NE(parseError(R"({"buildings": {"min_floors": 8, "max_floors": 6}})")
                  .find("buildings.min_floors must be <= buildings.max_floors"),
              std::string::npos);
    // Zero is meaningful where it means "none".
    EXPECT_EQ(parseError(R"({"streets": {"bend": 0}, "coast": {"water": 0, "amplitude": 0},
                             "buildings": {"tower_extra_floors": 0, "trim_depth": 0},
                             "roofs": {"parapet_height": 0, "hip": 0}})"),
              "");
}

TEST(RecipeParse, RelationsBetweenParametersAreChecked) {
    EXPECT_NE(parseError(R"({"streets": {"minor_spacing": 300}})").find("streets.minor_spacing must be <="),
              std::string::npos);
    EXPECT_NE(parseError(R"({"lots": {"min_frontage": 40}})").find("lots.min_frontage"), std::string::npos);
    EXPECT_NE(parseError(R"({"buildings": {"window_width": 3}})").find("must be < buildings.bay_width"),
              std::string::npos);
    EXPECT_NE(parseError(R"({"buildings": {"window_height": 2.5}})")
                  .find("buildings.sill_height + buildings.window_height must be < buildings.storey_height"),
              std::string::npos);
    EXPECT_NE(parseError(R"({"buildings": {"door_height": 4}})").find("buildings.ground_storey_height"),
              std::string::npos);
    EXPECT_NE(parseError(R"({"interiors": {"door_height": 3.1}})").find("interiors.door_height"), std::string::npos);
    EXPECT_NE(parseError(R"({"streets": {"minor_spacing": 20}})")
                  .find("streets.major_width + 2 * streets.sidewalk_width must be < streets.minor_spacing"),
              std::string::npos);
    EXPECT_NE(parseError(R"({"roofs": {"flat": 0, "hip": 0, "gable": 0, "shed": 0}})").find("roofs."),
              std::string::npos);
}

TEST(RecipeValidate, RecipesBuiltInCodeAreChecked) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    EXPECT_NE(validateError([&](CityRecipe& r) { r.coast.amplitude = nan; })
                  .find("code: coast.amplitude must be a finite number"),
              std::string::npos);
    EXPECT_NE(validateError([&](CityRecipe& r) { r.streets.majorSpacing = inf; }).find("streets.major_spacing"),
              std::string::npos);
    EXPECT_NE(validateError([&](CityRecipe& r) { r.streets.angle = nan; }).find("streets.angle"), std::string::npos);
    EXPECT_NE(validateError([](CityRecipe& r) { r.buildings.maxFloors = 201; }).find("buildings.max_floors"),
              std::string::npos);
    EXPECT_NE(validateError([](CityRecipe& r) { r.interiors.corridorWidth = -1; }).find("interiors.corridor_width"),
              std::string::npos);
    EXPECT_EQ(validateError([](CityRecipe&) {}), "");
}

TEST(RecipeParse, InvalidJsonNamesTheSource) {
    const std::string message = parseError("{\"buildings\": {\"max_floors\": 12,\n}");
    EXPECT_EQ(message.rfind("recipe.json: not valid JSON: ", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_NE(parseError("").find("recipe.json: not valid JSON"), std::string::npos);
}

TEST(RecipeJson, RoundTrips) {
    CityRecipe r;
    r.streets.angle = 12.345678901234567;
    r.coast.water = 0.1;
    r.buildings.maxFloors = 17;
    r.interiors.enabled = false;
    r.roofs.pitch = 1.0 / 3.0;
    const std::string json = recipeJson(r);
    EXPECT_NE(json.find("\"max_pitched_floors\""), std::string::npos);
    EXPECT_NE(json.find("\"enabled\": false"), std::string::npos);
    const CityRecipe back = parseRecipe(json, "city.json");
    EXPECT_EQ(recipeJson(back), json);
    EXPECT_EQ(back.roofs.pitch, r.roofs.pitch);
    EXPECT_EQ(back.streets.angle, r.streets.angle);
}

TEST(RecipeExamples, Parse) {
    const CityRecipe downtown = parseRecipe(readExample("downtown.json"), "downtown.json");
    const CityRecipe coastal = parseRecipe(readExample("coastal_town.json"), "coastal_town.json");
    // They contrast as their descriptions say.
    EXPECT_GT(downtown.buildings.minFloors, coastal.buildings.maxFloors);
    EXPECT_LT(downtown.coast.water, coastal.coast.water);
    EXPECT_LT(downtown.streets.minorSpacing, coastal.streets.minorSpacing);
    EXPECT_GT(downtown.roofs.flat, coastal.roofs.flat);
    EXPECT_EQ(coastal.buildings.towerChance, 0.0);
}
