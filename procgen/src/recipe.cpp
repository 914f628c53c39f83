#include <dawnforge/procgen/recipe.hpp>

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <variant>
#include <vector>

namespace dawnforge::procgen {

namespace {

using Json = nlohmann::ordered_json;  // keeps the order of the document (first error) and of the table (output)

constexpr double kInf = std::numeric_limits<double>::infinity();

// The values a field accepts; open ends exclude the bound.
struct Range {
    double lo = -kInf;
    double hi = kInf;
    bool loOpen = false;
    bool hiOpen = false;

    bool contains(double v) const {
        return (loOpen ? v > lo : v >= lo) && (hiOpen ? v < hi : v <= hi);
    }
    std::string describe() const {
        if (hi == kInf) return format(loOpen ? "> {}" : ">= {}", lo);
        return format("in {}{}, {}{}", loOpen ? "(" : "[", lo, hi, hiOpen ? ")" : "]");
    }
};

constexpr Range kPositive{0.0, kInf, true, false};     // lengths where 0 makes no sense
constexpr Range kNonNegative{0.0, kInf, false, false}; // lengths and weights where 0 means "none"
constexpr Range kChance{0.0, 1.0, false, false};
constexpr Range kWater{0.0, 0.9, false, false};        // some land must remain
constexpr Range kAngle{-360.0, 360.0, false, false};
constexpr Range kPitch{0.0, 3.0, true, false};
constexpr Range kFloors{1.0, 200.0, false, false};
constexpr Range kExtraFloors{0.0, 200.0, false, false};
constexpr Range kBool{};
constexpr Range kScaleJitter{0.0, 0.5, false, false};
constexpr Range kLampHeight{2.5, 15.0, false, false};
constexpr Range kLampArm{0.0, 3.0, false, false};
constexpr Range kMargin{0.0, 2000.0, false, false};
constexpr Range kHillHeight{0.0, 200.0, false, false};
constexpr Range kHillWavelength{20.0, 20000.0, false, false};

using Ref = std::variant<double*, int*, bool*>;
using Value = std::variant<double, int, bool>;

template <auto Section, auto Member>
Ref refOf(CityRecipe& r) {
    return &(r.*Section.*Member);
}
template <auto Section, auto Member>
Value valueOf(const CityRecipe& r) {
    return r.*Section.*Member;
}

// One recipe parameter: where it lives in JSON and in CityRecipe, and what it accepts.
struct Field {
    const char* section;
    const char* member;  // the C++ name; the JSON key is its snake_case
    Ref (*ref)(CityRecipe&);
    Value (*value)(const CityRecipe&);
    Range range;
};

// The JSON names are the C++ names (section as is, member in snake_case), so they cannot drift apart.
#define DAWNFORGE_RECIPE_FIELD(section, member, range)                                          \
    Field {                                                                                     \
        #section, #member, &refOf<&CityRecipe::section, &decltype(CityRecipe::section)::member>, \
            &valueOf<&CityRecipe::section, &decltype(CityRecipe::section)::member>, range        \
    }

// Every parameter, once: parse, validate and recipeJson all walk this table.
const std::array kFields{
    DAWNFORGE_RECIPE_FIELD(streets, majorSpacing, kPositive),
    DAWNFORGE_RECIPE_FIELD(streets, minorSpacing, kPositive),
    DAWNFORGE_RECIPE_FIELD(streets, majorWidth, kPositive),
    DAWNFORGE_RECIPE_FIELD(streets, minorWidth, kPositive),
    DAWNFORGE_RECIPE_FIELD(streets, sidewalkWidth, kPositive),
    DAWNFORGE_RECIPE_FIELD(streets, curbHeight, kNonNegative),
    DAWNFORGE_RECIPE_FIELD(streets, bend, kNonNegative),
    DAWNFORGE_RECIPE_FIELD(streets, bendWavelength, kPositive),
    DAWNFORGE_RECIPE_FIELD(streets, angle, kAngle),

    DAWNFORGE_RECIPE_FIELD(coast, water, kWater),
    DAWNFORGE_RECIPE_FIELD(coast, amplitude, kNonNegative),
    DAWNFORGE_RECIPE_FIELD(coast, wavelength, kPositive),
    DAWNFORGE_RECIPE_FIELD(coast, promenadeWidth, kPositive),
    DAWNFORGE_RECIPE_FIELD(coast, seabedDepth, kPositive),
    DAWNFORGE_RECIPE_FIELD(coast, seabedSlope, kPositive),

    DAWNFORGE_RECIPE_FIELD(lots, minFrontage, kPositive),
    DAWNFORGE_RECIPE_FIELD(lots, maxFrontage, kPositive),
    DAWNFORGE_RECIPE_FIELD(lots, maxDepth, kPositive),
    DAWNFORGE_RECIPE_FIELD(lots, minArea, kPositive),
    DAWNFORGE_RECIPE_FIELD(lots, setback, kNonNegative),
    DAWNFORGE_RECIPE_FIELD(lots, setbackJitter, kNonNegative),

    DAWNFORGE_RECIPE_FIELD(buildings, minFloors, kFloors),
    DAWNFORGE_RECIPE_FIELD(buildings, maxFloors, kFloors),
    DAWNFORGE_RECIPE_FIELD(buildings, storeyHeight, kPositive),
    DAWNFORGE_RECIPE_FIELD(buildings, groundStoreyHeight, kPositive),
    DAWNFORGE_RECIPE_FIELD(buildings, wallThickness, kPositive),
    DAWNFORGE_RECIPE_FIELD(buildings, bayWidth, kPositive),
    DAWNFORGE_RECIPE_FIELD(buildings, windowWidth, kPositive),
    DAWNFORGE_RECIPE_FIELD(buildings, windowHeight, kPositive),
    DAWNFORGE_RECIPE_FIELD(buildings, sillHeight, kNonNegative),
    DAWNFORGE_RECIPE_FIELD(buildings, doorWidth, kPositive),
    DAWNFORGE_RECIPE_FIELD(buildings, doorHeight, kPositive),
    DAWNFORGE_RECIPE_FIELD(buildings, shopChance, kChance),
    DAWNFORGE_RECIPE_FIELD(buildings, balconyChance, kChance),
    DAWNFORGE_RECIPE_FIELD(buildings, towerChance, kChance),
    DAWNFORGE_RECIPE_FIELD(buildings, towerExtraFloors, kExtraFloors),
    DAWNFORGE_RECIPE_FIELD(buildings, towerSetback, kNonNegative),
    DAWNFORGE_RECIPE_FIELD(buildings, trimDepth, kNonNegative),

    DAWNFORGE_RECIPE_FIELD(interiors, enabled, kBool),
    DAWNFORGE_RECIPE_FIELD(interiors, corridorWidth, kPositive),
    DAWNFORGE_RECIPE_FIELD(interiors, roomWidth, kPositive),
    DAWNFORGE_RECIPE_FIELD(interiors, minRoomDepth, kPositive),
    DAWNFORGE_RECIPE_FIELD(interiors, wallThickness, kPositive),
    DAWNFORGE_RECIPE_FIELD(interiors, slabThickness, kPositive),
    DAWNFORGE_RECIPE_FIELD(interiors, doorWidth, kPositive),
    DAWNFORGE_RECIPE_FIELD(interiors, doorHeight, kPositive),

    DAWNFORGE_RECIPE_FIELD(roofs, flat, kNonNegative),
    DAWNFORGE_RECIPE_FIELD(roofs, hip, kNonNegative),
    DAWNFORGE_RECIPE_FIELD(roofs, gable, kNonNegative),
    DAWNFORGE_RECIPE_FIELD(roofs, shed, kNonNegative),
    DAWNFORGE_RECIPE_FIELD(roofs, pitch, kPitch),
    DAWNFORGE_RECIPE_FIELD(roofs, parapetHeight, kNonNegative),
    DAWNFORGE_RECIPE_FIELD(roofs, parapetWidth, kPositive),
    DAWNFORGE_RECIPE_FIELD(roofs, maxPitchedFloors, kExtraFloors),

    DAWNFORGE_RECIPE_FIELD(dressing, treeSpacing, kNonNegative),
    DAWNFORGE_RECIPE_FIELD(dressing, treeChance, kChance),
    DAWNFORGE_RECIPE_FIELD(dressing, treeScaleJitter, kScaleJitter),
    DAWNFORGE_RECIPE_FIELD(dressing, lampSpacing, kNonNegative),
    DAWNFORGE_RECIPE_FIELD(dressing, lampHeight, kLampHeight),
    DAWNFORGE_RECIPE_FIELD(dressing, lampArm, kLampArm),
    DAWNFORGE_RECIPE_FIELD(dressing, lampRed, kChance),
    DAWNFORGE_RECIPE_FIELD(dressing, lampGreen, kChance),
    DAWNFORGE_RECIPE_FIELD(dressing, lampBlue, kChance),

    DAWNFORGE_RECIPE_FIELD(terrain, margin, kMargin),
    DAWNFORGE_RECIPE_FIELD(terrain, hillHeight, kHillHeight),
    DAWNFORGE_RECIPE_FIELD(terrain, hillWavelength, kHillWavelength),
};

#undef DAWNFORGE_RECIPE_FIELD

constexpr std::array<const char*, 8> kSections{"streets", "coast",     "lots",     "buildings",
                                               "interiors", "roofs", "dressing", "terrain"};
constexpr const char* kDescription = "description";  // free text for humans, ignored

std::string snakeCase(std::string_view camel) {
    std::string out;
    for (char c : camel) {
        if (c >= 'A' && c <= 'Z') {
            out += '_';
            out += char(c - 'A' + 'a');
        } else {
            out += c;
        }
    }
    return out;
}

std::string keyOf(const Field& f) { return snakeCase(f.member); }
std::string pathOf(const Field& f) { return std::string(f.section) + "." + keyOf(f); }

const Field& fieldNamed(std::string_view section, std::string_view member) {
    for (const Field& f : kFields)
        if (section == f.section && member == f.member) return f;
    assertionFailed("procgen::fieldNamed()", "no such recipe field");
}

// Optimal string alignment distance: insertions, deletions, substitutions and swaps of neighbours.
std::size_t editDistance(std::string_view a, std::string_view b) {
    std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
    for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
    for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    }
    return d[a.size()][b.size()];
}

// `recipe.json: unknown key "buildings.max_flors" (did you mean "buildings.max_floors"?)`.
// Near misses (edit distance <= 2) among all known paths win; else a key that exists in
// another section (or at top level, a key that belongs in a section) is suggested.
[[noreturn]] void unknownKey(std::string_view source, const std::string& path, std::string_view key) {
    std::vector<std::string> known{kDescription};
    for (const char* s : kSections) known.emplace_back(s);
    for (const Field& f : kFields) known.push_back(pathOf(f));

    std::string suggestion;
    std::size_t best = 3;
    for (const std::string& k : known) {
        const std::size_t d = editDistance(path, k);
        if (d < best) {
            best = d;
            suggestion = k;
        }
    }
    if (suggestion.empty())
        for (const Field& f : kFields)
            if (keyOf(f) == key) {
                suggestion = pathOf(f);
                break;
            }
    // The key as JSON writes it: control characters and broken UTF-8 cannot split the line.
    const std::string quoted = Json(path).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    if (suggestion.empty()) throw InputError(format("{}: unknown key {}", source, quoted));
    throw InputError(format("{}: unknown key {} (did you mean \"{}\"?)", source, quoted, suggestion));
}

void checkRange(const Field& f, double v, std::string_view source) {
    if (!std::isfinite(v)) throw InputError(format("{}: {} must be a finite number (got {})", source, pathOf(f), v));
    if (!f.range.contains(v))
        throw InputError(format("{}: {} must be {} (got {})", source, pathOf(f), f.range.describe(), v));
}

void readField(const Field& f, const Json& j, CityRecipe& recipe, std::string_view source) {
    std::visit(
        [&](auto* target) {
            using T = std::remove_pointer_t<decltype(target)>;
            if constexpr (std::is_same_v<T, bool>) {
                if (!j.is_boolean()) throw InputError(format("{}: {} must be true or false", source, pathOf(f)));
                *target = j.get<bool>();
            } else if constexpr (std::is_same_v<T, int>) {
                if (!j.is_number_integer())
                    throw InputError(format("{}: {} must be a whole number", source, pathOf(f)));
                // Range-check before narrowing, so that 1e12-sized integers are reported, not wrapped.
                const double wide = j.is_number_unsigned() ? double(j.get<std::uint64_t>())
                                                           : double(j.get<std::int64_t>());
                checkRange(f, wide, source);
                *target = int(j.get<std::int64_t>());
            } else {
                if (!j.is_number()) throw InputError(format("{}: {} must be a number", source, pathOf(f)));
                *target = j.get<double>();
            }
        },
        f.ref(recipe));
}

double number(const CityRecipe& r, std::string_view section, std::string_view member) {
    return std::visit([](auto v) { return double(v); }, fieldNamed(section, member).value(r));
}


}  // namespace

CityRecipe parseRecipe(std::string_view json, std::string_view source) {
    Json root;
    try {
        root = Json::parse(json.begin(), json.end());
    } catch (const Json::exception& e) {
        throw InputError(format("{}: not valid JSON: {}", source, oneLine(e.what())));
    }
    if (!root.is_object())
        throw InputError(format("{}: a recipe must be a JSON object ({{\"buildings\": {{...}}, ...}})", source));

    CityRecipe recipe;
    // Items by key() and value(), not structured bindings: lambdas may not capture those
    // before clang 16.
    for (const auto& item : root.items()) {
        const std::string& name = item.key();
        const Json& section = item.value();
        if (name == kDescription) {
            if (!section.is_string()) throw InputError(format("{}: description must be a string", source));
            continue;
        }
        if (std::find_if(kSections.begin(), kSections.end(), [&](const char* s) { return name == s; }) ==
            kSections.end())
            unknownKey(source, name, name);
        if (!section.is_object())
            throw InputError(format("{}: {} must be an object of parameters ({{\"key\": value, ...}})", source, name));
        for (const auto& entry : section.items()) {
            const std::string& key = entry.key();
            const Json& value = entry.value();
            const auto field = std::find_if(kFields.begin(), kFields.end(), [&](const Field& f) {
                return name == f.section && key == keyOf(f);
            });
            if (field == kFields.end()) unknownKey(source, name + "." + key, key);
            readField(*field, value, recipe, source);
        }
    }
    validateRecipe(recipe, source);
    return recipe;
}

void validateRecipe(const CityRecipe& recipe, std::string_view source) {
    for (const Field& f : kFields)
        std::visit(
            [&](auto v) {
                if constexpr (!std::is_same_v<decltype(v), bool>) checkRange(f, double(v), source);
            },
            f.value(recipe));

    const auto get = [&](std::string_view section, std::string_view member) {
        return number(recipe, section, member);
    };
    const auto path = [](std::string_view section, std::string_view member) {
        return pathOf(fieldNamed(section, member));
    };
    // a <= b (a < b when strict), where `a` may be a sum that `what` spells out.
    const auto require = [&](double a, const std::string& what, bool strict, std::string_view bSection,
                             std::string_view bMember) {
        const double b = get(bSection, bMember);
        if (strict ? a < b : a <= b) return;
        throw InputError(format("{}: {} must be {} {} (got {} vs {})", source, what, strict ? "<" : "<=",
                                path(bSection, bMember), a, b));
    };
    const auto one = [&](std::string_view section, std::string_view member) {
        return std::pair{get(section, member), path(section, member)};
    };
    const auto order = [&](std::string_view aSection, std::string_view aMember, bool strict,
                           std::string_view bSection, std::string_view bMember) {
        const auto [a, what] = one(aSection, aMember);
        require(a, what, strict, bSection, bMember);
    };

    order("streets", "minorSpacing", false, "streets", "majorSpacing");
    for (const char* width : {"majorWidth", "minorWidth"}) {
        const auto [w, wPath] = one("streets", width);
        const auto [s, sPath] = one("streets", "sidewalkWidth");
        require(w + 2 * s, wPath + " + 2 * " + sPath, true, "streets", "minorSpacing");
    }
    order("lots", "minFrontage", false, "lots", "maxFrontage");
    order("buildings", "minFloors", false, "buildings", "maxFloors");
    order("buildings", "windowWidth", true, "buildings", "bayWidth");
    {
        const auto [sill, sillPath] = one("buildings", "sillHeight");
        const auto [h, hPath] = one("buildings", "windowHeight");
        require(sill + h, sillPath + " + " + hPath, true, "buildings", "storeyHeight");
    }
    order("buildings", "doorHeight", true, "buildings", "groundStoreyHeight");
    order("interiors", "doorWidth", true, "interiors", "roomWidth");
    for (const char* storey : {"storeyHeight", "groundStoreyHeight"}) {
        // An interior door stands under the slab of the floor above.
        const auto [door, doorPath] = one("interiors", "doorHeight");
        const auto [slab, slabPath] = one("interiors", "slabThickness");
        require(door + slab, doorPath + " + " + slabPath, true, "buildings", storey);
    }
    const RoofRecipe& roofs = recipe.roofs;
    if (!(roofs.flat + roofs.hip + roofs.gable + roofs.shed > 0.0))
        throw InputError(format("{}: roofs.flat, roofs.hip, roofs.gable and roofs.shed are weights; at least one "
                                "must be > 0",
                                source));
    const DressingRecipe& dressing = recipe.dressing;
    for (const char* spacing : {"treeSpacing", "lampSpacing"}) {
        const auto [v, vPath] = one("dressing", spacing);
        if (v > 0.0 && v < 4.0)
            throw InputError(format("{}: {} must be 0 (none) or at least 4 (got {})", source, vPath, v));
    }
    if (!(std::max({dressing.lampRed, dressing.lampGreen, dressing.lampBlue}) > 0.0))
        throw InputError(format("{}: dressing.lamp_red, lamp_green and lamp_blue are a colour; one must be > 0", source));
}

std::string recipeJson(const CityRecipe& recipe) {
    Json out = Json::object();
    for (const Field& f : kFields)
        std::visit([&](auto v) { out[f.section][keyOf(f)] = v; }, f.value(recipe));
    return out.dump(2);
}

}  // namespace dawnforge::procgen
