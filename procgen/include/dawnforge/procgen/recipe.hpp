#pragma once
// Every parameter of `dawnforge city`, with its default (docs/STYLE.md 4). A JSON recipe sets any
// of them by the same names (`{"buildings": {"max_floors": 12}}`); an unknown key is an error
// that names it. Lengths in metres; chances in [0, 1].
#include <cstdint>
#include <string>
#include <string_view>

namespace dawnforge::procgen {

struct StreetRecipe {
    double majorSpacing = 240.0;   // distance between major roads (a multiple of minor spacing is not needed)
    double minorSpacing = 90.0;    // distance between neighbouring roads of either kind
    double majorWidth = 16.0;      // kerb to kerb
    double minorWidth = 10.0;
    double sidewalkWidth = 3.0;
    double curbHeight = 0.15;
    double bend = 12.0;            // sideways amplitude of the noise that bends the grid
    double bendWavelength = 320.0; // wavelength of that noise
    double angle = 0.0;            // rotation of the grid in degrees
};

struct CoastRecipe {
    double water = 0.25;           // fraction of the city's depth (south side) under water; 0: no sea
    double amplitude = 30.0;       // sideways amplitude of the coastline's noise
    double wavelength = 400.0;
    double promenadeWidth = 12.0;  // a street along the coast
    double seabedDepth = 8.0;      // depth of the sea floor away from the shore
    double seabedSlope = 0.12;     // fall of the sea floor per metre from the shore
};

struct LotRecipe {
    double minFrontage = 10.0;     // no lot is split below this width along its street
    double maxFrontage = 28.0;     // lots wider than this along their street are split
    double maxDepth = 34.0;        // lots deeper than this from their street are split (if both halves keep a street)
    double minArea = 120.0;        // smaller pieces stay unsplit; lots smaller than this are left empty
    double setback = 1.5;          // footprint inset from the lot
    double setbackJitter = 1.0;    // + up to this, per lot
};

struct BuildingRecipe {
    int minFloors = 2;
    int maxFloors = 6;
    double storeyHeight = 3.2;
    double groundStoreyHeight = 4.0;
    double wallThickness = 0.3;
    double bayWidth = 3.0;         // target width of a facade bay (one window)
    double windowWidth = 1.3;
    double windowHeight = 1.6;
    double sillHeight = 0.9;
    double doorWidth = 1.8;
    double doorHeight = 2.6;
    double shopChance = 0.4;       // ground floor with shop windows
    double balconyChance = 0.2;    // per building: some upper bays get balconies
    double towerChance = 0.1;      // per building: a setback tower on top
    int towerExtraFloors = 10;     // up to this many floors added by a tower
    double towerSetback = 3.0;
    double trimDepth = 0.12;       // floor bands and cornice stick out this far
};

struct InteriorRecipe {
    bool enabled = true;
    double corridorWidth = 1.8;
    double roomWidth = 4.5;        // target room width along the corridor
    double minRoomDepth = 3.5;     // a corridor with rooms on both sides needs 2x this + corridor
    double wallThickness = 0.12;
    double slabThickness = 0.25;
    double doorWidth = 0.9;
    double doorHeight = 2.1;
};

struct RoofRecipe {
    double flat = 0.4;             // relative weights of the roof types
    double hip = 0.25;
    double gable = 0.25;
    double shed = 0.1;
    double pitch = 0.6;            // rise per metre of run for hip, gable and shed roofs
    double parapetHeight = 0.9;
    double parapetWidth = 0.3;
    int maxPitchedFloors = 8;      // taller buildings get flat roofs
};

// The land beyond the city's edge: fields rising into gentle hills, where it is not sea.
struct TerrainRecipe {
    double margin = 160.0;         // how far the ground reaches beyond the city; 0: none
    double hillHeight = 10.0;      // the highest hills, metres above the city's ground
    double hillWavelength = 220.0; // distance between hilltops
};

// Street trees and street lamps (dressing.hpp). A spacing of 0 means none.
struct DressingRecipe {
    double treeSpacing = 14.0;     // between street-tree slots along a sidewalk: 0 or >= 4
    double treeChance = 0.75;      // a slot holds a tree
    double treeScaleJitter = 0.2;  // a tree's scale is 1 ± this
    double lampSpacing = 26.0;     // between lamps along a sidewalk: 0 or >= 4
    double lampHeight = 5.5;       // of the lamp head above the sidewalk
    double lampArm = 1.2;          // the arm reaches this far towards the street
    double lampRed = 1.0;          // the light's linear colour (the largest component is scaled to 1)
    double lampGreen = 0.72;
    double lampBlue = 0.42;
};

struct CityRecipe {
    StreetRecipe streets;
    CoastRecipe coast;
    LotRecipe lots;
    BuildingRecipe buildings;
    InteriorRecipe interiors;
    RoofRecipe roofs;
    DressingRecipe dressing;
    TerrainRecipe terrain;
};

// Reads a recipe: every key optional; unknown keys, wrong types and out-of-range values
// throw InputError naming `source` and the key (e.g. "city.json: buildings.max_floors ...").
CityRecipe parseRecipe(std::string_view json, std::string_view source);
// Checks ranges (also for recipes built in code); throws InputError naming `source`.
void validateRecipe(const CityRecipe& recipe, std::string_view source);
// The whole recipe as a JSON object, every key present (what city.json records).
std::string recipeJson(const CityRecipe& recipe);

}  // namespace dawnforge::procgen
