// Street trees (species built as element hierarchies for Pivot Painter) and street lamps,
// placed in slots along every block's sidewalk.
#include <dawnforge/procgen/dressing.hpp>

#include <dawnforge/core/materials.hpp>
#include <dawnforge/core/seed.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace dawnforge::procgen {

namespace {

constexpr double kPi = std::numbers::pi;

// The shape of a species at scale 1: a trunk, branches off its upper part, twigs off each
// branch, crossed leaf cards along the twigs and at each branch's tip.
struct SpeciesShape {
    const char* name;
    double trunkHeight, trunkRadius;
    int branches;
    double branchStart;      // fraction of the trunk where the lowest branch starts
    double branchElevation;  // degrees from the trunk's axis
    double branchLength;
    int twigs;
    double twigLength, twigElevation;
    double leafSize;
};
constexpr SpeciesShape kShapes[] = {
    {"plane", 4.6, 0.2, 5, 0.55, 48.0, 3.4, 3, 1.9, 38.0, 1.9},
    {"poplar", 7.0, 0.17, 6, 0.3, 14.0, 3.2, 2, 1.6, 14.0, 1.5},
    {"linden", 3.8, 0.19, 5, 0.6, 58.0, 3.0, 3, 1.8, 42.0, 1.8},
};

void vertex(Mesh& m, glm::vec3 p, glm::vec3 n, glm::vec2 uv, std::uint8_t material) {
    m.positions.push_back(p);
    m.normals.push_back(n);
    m.uv0.push_back(uv);
    m.materialIds.push_back(material);
}

// A tapered tube along +X from 0 to `length`, open at both ends, smooth-shaded.
void addTube(Mesh& m, double length, double r0, double r1, std::uint8_t material, int sides = 6) {
    const auto base = std::uint32_t(m.positions.size());
    for (int ring = 0; ring < 2; ++ring)
        for (int i = 0; i <= sides; ++i) {
            const double a = 2.0 * kPi * i / sides, r = ring ? r1 : r0;
            const glm::vec3 n(0.0f, float(std::cos(a)), float(std::sin(a)));
            vertex(m, glm::vec3(float(ring * length), 0.0f, 0.0f) + float(r) * n, n,
                   {float(a * r0), float(ring * length)}, material);
        }
    const auto row = std::uint32_t(sides + 1);
    for (std::uint32_t i = 0; i < std::uint32_t(sides); ++i)
        m.indices.insert(m.indices.end(), {base + i, base + i + 1, base + row + i, base + i + 1, base + row + i + 1,
                                           base + row + i});  // counter-clockwise from outside, as glTF's front
}

// A square card centred at c spanning ±half along u and v (unit, perpendicular); uv in metres,
// or 0..1 across the card (`unitUv`: a leaf card, whose leaf picture the runtime cuts out).
void addCard(Mesh& m, glm::vec3 c, glm::vec3 u, glm::vec3 v, float half, std::uint8_t material, bool unitUv = false) {
    const auto base = std::uint32_t(m.positions.size());
    const glm::vec3 n = glm::normalize(glm::cross(u, v));
    const glm::vec2 uvs[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const glm::vec3 corners[4] = {c - half * u - half * v, c + half * u - half * v, c + half * u + half * v,
                                  c - half * u + half * v};
    for (int k = 0; k < 4; ++k) vertex(m, corners[k], n, (unitUv ? 1.0f : 2.0f * half) * uvs[k], material);
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

// Two crossed cards at x along the element's axis, turned by `turn` about it.
void addLeaves(Mesh& m, float x, float half, double turn) {
    const glm::vec3 ax(1.0f, 0.0f, 0.0f);
    const glm::vec3 a(0.0f, float(std::cos(turn)), float(std::sin(turn)));
    const glm::vec3 b(0.0f, -a.z, a.y);
    addCard(m, {x, 0.0f, 0.0f}, ax, a, half, kGround, true);
    addCard(m, {x, 0.0f, 0.0f}, ax, b, half, kGround, true);
}

// A child's frame: at `along` on its parent's axis, rolled `roll` about that axis, then
// tilted `elevation` away from it.
TreeElement child(std::string name, int parent, double along, double roll, double elevation) {
    TreeElement e;
    e.name = std::move(name);
    e.parent = parent;
    e.translation = {float(along), 0.0f, 0.0f};
    e.rotation = glm::angleAxis(float(roll), glm::vec3(1, 0, 0)) * glm::angleAxis(float(elevation), glm::vec3(0, 0, 1));
    return e;
}

TreeSpecies makeSpecies(const SpeciesShape& shape, std::uint64_t seed) {
    Rng rng(seed);
    TreeSpecies s;
    s.name = shape.name;
    TreeElement trunk;
    trunk.name = "trunk";
    addTube(trunk.mesh, shape.trunkHeight, shape.trunkRadius, 0.45 * shape.trunkRadius, kWood, 8);
    s.elements.push_back(std::move(trunk));
    const double deg = kPi / 180.0;
    for (int b = 0; b < shape.branches; ++b) {
        const double along = shape.trunkHeight * (shape.branchStart + (1.0 - shape.branchStart) * (b + 0.5) / shape.branches);
        const double roll = 2.0 * kPi * (b + rng.uniform(-0.2, 0.2)) / shape.branches + 2.4 * b;
        const double elevation = (shape.branchElevation + rng.uniform(-8.0, 8.0)) * deg;
        TreeElement branch = child("branch_" + std::to_string(b), 0, along, roll, elevation);
        const double length = shape.branchLength * rng.uniform(0.85, 1.15);
        addTube(branch.mesh, length, 0.45 * shape.trunkRadius, 0.15 * shape.trunkRadius, kWood);
        addLeaves(branch.mesh, float(length), float(0.5 * shape.leafSize), rng.uniform(0.0, kPi));
        const int branchIndex = int(s.elements.size());
        s.elements.push_back(std::move(branch));
        s.crownRadius = std::max(s.crownRadius, length * std::sin(elevation) + 0.5 * shape.leafSize);
        for (int t = 0; t < shape.twigs; ++t) {
            const double at = length * (0.45 + 0.45 * t / std::max(1, shape.twigs - 1));
            // Left and right of the branch (its +Z is level), so that no twig hangs down.
            const double twigRoll = (t % 2 ? 0.5 : -0.5) * kPi + rng.uniform(-0.3, 0.3);
            TreeElement twig = child("branch_" + std::to_string(b) + "_twig_" + std::to_string(t), branchIndex, at,
                                     twigRoll, (shape.twigElevation + rng.uniform(-6.0, 6.0)) * deg);
            addTube(twig.mesh, shape.twigLength, 0.12 * shape.trunkRadius, 0.05 * shape.trunkRadius, kWood, 4);
            for (int k = 0; k < 3; ++k)
                addLeaves(twig.mesh, float(shape.twigLength * (0.4 + 0.3 * k)), float(0.5 * shape.leafSize), 1.1 * k);
            s.elements.push_back(std::move(twig));
        }
    }
    s.crownRadius += 0.5 * shape.twigLength;
    for (TreeElement& e : s.elements) e.mesh.name = std::string("tree_") + shape.name + "_" + e.name;
    return s;
}

void addBox(Mesh& m, glm::vec3 lo, glm::vec3 hi, std::uint8_t material) {
    const glm::vec3 c = 0.5f * (lo + hi), h = 0.5f * (hi - lo);
    for (int axis = 0; axis < 3; ++axis)
        for (float side : {-1.0f, 1.0f}) {
            glm::vec3 n(0.0f), u(0.0f), v(0.0f);
            n[axis] = side * h[axis];
            u[(axis + 1) % 3] = h[(axis + 1) % 3];
            v[(axis + 2) % 3] = side * h[(axis + 2) % 3];  // cross(u, v) points along n
            addCard(m, c + n, u, v, 1.0f, material);
        }
}

// One sidewalk slot: a point on the kerb line and the direction into the block there.
struct Slot {
    glm::dvec2 point, inward;
    int edge = 0;
};

// Slots every `spacing` metres along a block's kerb (starting `phase` metres in), except
// within `clear` metres of a corner that turns by more than 30° (the crossings).
std::vector<Slot> sidewalkSlots(const Polygon2& curb, double spacing, double phase, double clear) {
    const std::size_t n = curb.size();
    std::vector<double> at(n + 1, 0.0);
    for (std::size_t i = 0; i < n; ++i) at[i + 1] = at[i] + glm::length(curb[(i + 1) % n] - curb[i]);
    const double total = at[n];
    std::vector<double> corners;
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec2 a = glm::normalize(curb[i] - curb[(i + n - 1) % n]), b = glm::normalize(curb[(i + 1) % n] - curb[i]);
        if (glm::dot(a, b) < std::cos(30.0 * kPi / 180.0)) corners.push_back(at[i]);
    }
    std::vector<Slot> slots;
    std::size_t edge = 0;
    for (double s = phase; s < total; s += spacing) {
        const bool nearCorner = std::any_of(corners.begin(), corners.end(), [&](double c) {
            const double d = std::abs(s - c);
            return std::min(d, total - d) < clear;
        });
        while (edge + 1 < n && at[edge + 1] <= s) ++edge;
        if (nearCorner) continue;
        const glm::dvec2 a = curb[edge], b = curb[(edge + 1) % n];
        const double t = (s - at[edge]) / std::max(at[edge + 1] - at[edge], 1e-9);
        slots.push_back({a + t * (b - a), inwardNormal(a, b), int(edge)});
    }
    return slots;
}

// Whether p stands on the block's sidewalk, at least `margin` metres from the kerb and from the lots.
bool onSidewalk(const Block& block, glm::dvec2 p, double margin) {
    return containsPoint(block.curb, p) && !containsPoint(block.inner, p) && distanceToBoundary(block.curb, p) >= margin &&
           distanceToBoundary(block.inner, p) >= margin;
}

glm::dvec3 lampColour(const DressingRecipe& r) {
    const glm::dvec3 c(r.lampRed, r.lampGreen, r.lampBlue);
    return c / std::max({c.r, c.g, c.b});
}

void dressBlock(const Block& block, const CityRecipe& recipe, std::uint64_t seed, int speciesCount, Dressing& out) {
    const DressingRecipe& d = recipe.dressing;
    const double sidewalk = recipe.streets.sidewalkWidth, kerb = recipe.streets.curbHeight;
    const double clear = 0.5 * recipe.streets.majorWidth + sidewalk;
    const std::size_t firstLamp = out.lamps.size();
    if (d.lampSpacing > 0.0)
        for (const Slot& slot : sidewalkSlots(block.curb, d.lampSpacing, 0.5 * d.lampSpacing, clear)) {
            const glm::dvec2 foot = slot.point + std::min(0.45, 0.3 * sidewalk) * slot.inward;
            if (!onSidewalk(block, foot, 0.1)) continue;
            StreetLamp lamp;
            lamp.id = int(out.lamps.size());
            lamp.foot = foot;
            lamp.height = kerb;
            lamp.yaw = std::atan2(-slot.inward.y, -slot.inward.x);  // the arm reaches over the street
            // Just under the lamp head's centre, so that the head does not hide its own light.
            lamp.light = {foot - (d.lampArm - 0.075) * slot.inward, kerb + d.lampHeight - 0.25};
            lamp.colour = lampColour(d);
            out.lamps.push_back(lamp);
        }
    if (d.treeSpacing <= 0.0) return;
    std::uint64_t slotIndex = 0;
    for (const Slot& slot : sidewalkSlots(block.curb, d.treeSpacing, 0.25 * d.treeSpacing, clear + 2.0)) {
        const auto key = std::uint64_t(block.id) * 65536u + slotIndex++;
        const glm::dvec2 foot = slot.point + 0.5 * sidewalk * slot.inward;
        if (!onSidewalk(block, foot, 0.3)) continue;
        const bool nearLamp = std::any_of(out.lamps.begin() + std::ptrdiff_t(firstLamp), out.lamps.end(),
                                          [&](const StreetLamp& l) { return glm::length(l.foot - foot) < 4.0; });
        if (nearLamp) continue;
        Rng rng(deriveSeed(seed, "street-tree", key));
        if (rng.uniform() >= d.treeChance) continue;
        StreetTree tree;
        tree.id = int(out.trees.size());
        // One species along each side of a block, as streets are planted.
        tree.species = int(deriveSeed(seed, "tree-species", std::uint64_t(block.id) * 4096u + std::uint64_t(slot.edge)) %
                           std::uint64_t(speciesCount));
        tree.foot = foot;
        tree.height = kerb;
        tree.yaw = rng.uniform(0.0, 2.0 * kPi);
        tree.scale = 1.0 + rng.uniform(-d.treeScaleJitter, d.treeScaleJitter);
        out.trees.push_back(tree);
    }
}

}  // namespace

std::vector<TreeSpecies> makeTreeSpecies(std::uint64_t seed) {
    std::vector<TreeSpecies> species;
    for (std::size_t k = 0; k < std::size(kShapes); ++k) species.push_back(makeSpecies(kShapes[k], deriveSeed(seed, "tree-shape", k)));
    return species;
}

Mesh makeLampMesh(const DressingRecipe& d) {
    Mesh m;
    Mesh part;
    addTube(part, d.lampHeight, 0.09, 0.06, kMetal, 8);
    // The pole along +Y: +X turned a quarter about +Z.
    appendMesh(m, part, glm::rotate(glm::mat4(1.0f), float(0.5 * kPi), glm::vec3(0, 0, 1)));
    part = {};
    addTube(part, d.lampArm, 0.045, 0.04, kMetal);
    appendMesh(m, part, glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, float(d.lampHeight - 0.05), 0.0f)));
    addBox(m, {float(d.lampArm - 0.3), float(d.lampHeight - 0.2), -0.18f}, {float(d.lampArm + 0.15), float(d.lampHeight), 0.18f},
           kTrim);
    m.name = "lamp";
    return m;
}

std::vector<MeshNode> speciesNodes(const TreeSpecies& species) {
    std::vector<MeshNode> nodes;
    for (const TreeElement& e : species.elements) {
        MeshNode n;
        n.name = e.name;
        n.parent = e.parent;
        n.mesh = e.mesh;
        const glm::mat4 local = glm::translate(glm::mat4(1.0f), e.translation) * glm::mat4_cast(e.rotation);
        // The trunk stands up: its +X along +Y.
        const glm::mat4 up = glm::rotate(glm::mat4(1.0f), float(0.5 * kPi), glm::vec3(0, 0, 1));
        n.world = e.parent < 0 ? up * local : nodes[std::size_t(e.parent)].world * local;
        nodes.push_back(std::move(n));
    }
    return nodes;
}

Dressing dressCity(const CityPlan& plan, const CityRecipe& recipe, std::uint64_t seed) {
    Dressing out;
    out.species = makeTreeSpecies(seed);
    out.lamp = makeLampMesh(recipe.dressing);
    for (const Block& block : plan.blocks) {
        if (block.curb.size() < 3 || block.inner.size() < 3) continue;
        dressBlock(block, recipe, seed, int(out.species.size()), out);
    }
    return out;
}

}  // namespace dawnforge::procgen
