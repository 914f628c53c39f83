#pragma once
// City dressing: street trees and street lamps along the sidewalks. Placed from the whole plan (each slot with its
// own sub-seed), so a tile generated alone holds the same trees and lamps as that tile of
// the whole city.
//
// A tree species is a node hierarchy of elements (trunk, branches, twigs with leaf cards),
// each element's mesh in its own frame with +X along it from its pivot (the node's origin):
// what Pivot Painter (exporters/pivot_painter.hpp) and the runtime's wind read.
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/mesh.hpp>
#include <dawnforge/procgen/plan.hpp>
#include <dawnforge/procgen/recipe.hpp>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace dawnforge::procgen {

struct TreeElement {
    std::string name;              // "trunk", "branch_2", "branch_2_twig_1"
    int parent = -1;               // index in TreeSpecies::elements; -1 for the trunk
    glm::vec3 translation{0.0f};   // in the parent's frame (the trunk's: the tree's)
    glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
    Mesh mesh;                     // in the element's frame, +X along it
};

struct TreeSpecies {
    std::string name;                   // "plane", "poplar", "linden"
    std::vector<TreeElement> elements;  // a parent before its children
    double crownRadius = 0.0;           // metres, at scale 1: how far leaves reach from the trunk
};

struct StreetTree {
    int id = 0;
    int species = 0;      // index into Dressing::species
    glm::dvec2 foot{0.0}; // plan metres
    double height = 0.0;  // of the ground under it
    double yaw = 0.0;     // radians, about +Y
    double scale = 1.0;
};

struct StreetLamp {
    int id = 0;
    glm::dvec2 foot{0.0};      // plan metres
    double height = 0.0;       // of the ground under it
    glm::dvec3 light{0.0};     // the lamp head's centre: plan x, y and height above sea level
    glm::dvec3 colour{1.0};    // linear RGB, largest component 1
    double yaw = 0.0;          // radians about +Y: the arm points along the mesh's +X turned by this
};

struct Dressing {
    std::vector<TreeSpecies> species;
    Mesh lamp;  // one lamp, its foot at the origin, its arm along +X
    std::vector<StreetTree> trees;   // in slot order; id = index
    std::vector<StreetLamp> lamps;   // in slot order; id = index
};

// The tree species of `seed`, and the lamp mesh of `recipe`.
std::vector<TreeSpecies> makeTreeSpecies(std::uint64_t seed);
Mesh makeLampMesh(const DressingRecipe& recipe);
// A species as the node list that Pivot Painter reads (each element a node, world = its chain
// of local transforms, the tree standing at the origin).
std::vector<MeshNode> speciesNodes(const TreeSpecies& species);

// Every tree and lamp of the whole plan, standing on the kerb (streets.curbHeight).
Dressing dressCity(const CityPlan& plan, const CityRecipe& recipe, std::uint64_t seed);

}  // namespace dawnforge::procgen
