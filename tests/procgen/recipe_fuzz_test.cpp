// Fuzzing what parses (docs/STYLE.md 10), as a deterministic test: mutated recipes either parse
// or fail with an InputError, and every recipe that parses generates a small city (or is
// refused with an InputError) without crashing. tests/fuzz/recipe_fuzz.cpp is the libFuzzer
// target for longer runs (clang, DAWNFORGE_BUILD_FUZZERS=ON).
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/seed.hpp>
#include <dawnforge/procgen/city.hpp>
#include <dawnforge/procgen/recipe.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <iterator>

namespace dawnforge::procgen {
namespace {

std::string example(const char* name) {
    std::ifstream in(std::string(DAWNFORGE_TEST_DATA) + "/../../examples/recipes/" + name);
    return {std::istreambuf_iterator<char>(in), {}};
}

// Byte-level damage: deletions, insertions, replacements, duplicated runs.
std::string mutateBytes(std::string text, Rng& rng) {
    const int edits = rng.range(1, 4);
    for (int e = 0; e < edits && !text.empty(); ++e) {
        const std::size_t at = rng.below(text.size());
        switch (rng.below(4)) {
            case 0: text.erase(at, 1 + rng.below(8)); break;
            case 1: text.insert(at, 1, static_cast<char>(rng.below(256))); break;
            case 2: text[at] = "{}[]\",:0123456789.-eE tfn\\"[rng.below(26)]; break;
            default: text.insert(at, text.substr(at, 1 + rng.below(16))); break;
        }
    }
    return text;
}

// Value-level damage: one parameter set to an extreme or odd value of some JSON type.
std::string mutateValue(const std::string& text, Rng& rng) {
    nlohmann::ordered_json j = nlohmann::ordered_json::parse(text);
    std::vector<std::pair<std::string, std::string>> keys;
    for (auto& [section, fields] : j.items())
        if (fields.is_object())
            for (auto& [key, value] : fields.items()) keys.emplace_back(section, key);
    const auto& [section, key] = keys[rng.below(keys.size())];
    const nlohmann::ordered_json odd[] = {0, -1, 1, 2, 1e-9, 0.5, 1e9, 1e308, -1e308, 3.5, 200, 201, true, "x", nullptr,
                                          nlohmann::ordered_json::array(), nlohmann::ordered_json::object()};
    j[section][key] = odd[rng.below(std::size(odd))];
    return j.dump();
}

TEST(RecipeFuzz, DamagedRecipesParseOrFailWithAnInputError) {
    const std::string base = example("coastal_town.json");
    ASSERT_FALSE(base.empty());
    Rng rng(deriveSeed(1, "recipe-fuzz"));
    int parsed = 0, refused = 0;
    for (int i = 0; i < 3000; ++i) {
        const std::string text = mutateBytes(base, rng);
        try {
            parseRecipe(text, "fuzz.json");
            ++parsed;
        } catch (const InputError& e) {
            EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
            ++refused;
        }
    }
    EXPECT_GT(refused, 1000);  // most damage is caught...
    EXPECT_GT(parsed, 10);     // ...and some of it is harmless (whitespace, digits)
}

TEST(RecipeFuzz, OddValuesAreRefusedOrMakeACity) {
    const std::string base = example("downtown.json");
    Rng rng(deriveSeed(2, "recipe-fuzz"));
    int cities = 0;
    const int cases = DAWNFORGE_SANITIZED ? 100 : 300;  // a third under the sanitizers: same paths, 3x slower each
    for (int i = 0; i < cases; ++i) {
        const std::string text = mutateValue(base, rng);
        CitySettings settings;
        try {
            settings.recipe = parseRecipe(text, "fuzz.json");
        } catch (const InputError&) {
            continue;
        }
        settings.size = {160.0, 140.0};
        settings.tileSize = 80.0;
        try {
            const City city = generateCity(settings);
            for (const Building& b : city.buildings) ASSERT_GT(b.floors, 0);
            ++cities;
        } catch (const InputError&) {
        }
    }
    EXPECT_GT(cities, cases / 6);
}

}  // namespace
}  // namespace dawnforge::procgen
