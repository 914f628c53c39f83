// Where bonds broke, chips: how many, how big, of what, where and how fast (debris.hpp).
//
// A bond that broke emits chips by its area and its pieces' material (SimulationSettings::debris
// gives the rate for masonry; glass shatters into twice as many half-size chips, wood splinters
// into half as many, metal tears into a fifth). A chip is a small octahedron with random radii
// and axes, of the broken face's material (what the nearest face of its piece is: the cut
// face's), as dense as its piece. It rests at the crack's centroid, riding in one of the two
// pieces, no longer than 70 % of either piece's thickness, so that it stays hidden until the
// bond breaks. Every random number comes from (seed, bond): the same chips on any thread count.
#include "debris.hpp"

#include <dawnforge/core/materials.hpp>
#include <dawnforge/core/seed.hpp>
#include <dawnforge/sim/mass_properties.hpp>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>

namespace dawnforge::sim {

namespace {

struct MaterialDebris {
    double count = 1.0;  // times the masonry rate
    double size = 1.0;   // times the mean chip size
};

MaterialDebris debrisOf(std::uint8_t material) {
    switch (material) {
        case kGlass: return {2.0, 0.5};
        case kWood: return {0.5, 1.0};
        case kMetal: return {0.2, 0.6};
        default: return {1.0, 1.0};
    }
}

std::uint8_t materialOf(const Mesh& mesh, std::size_t triangle) {
    return mesh.materialIds.empty() ? std::uint8_t(kRubble) : mesh.materialIds[mesh.indices[3 * triangle]];
}

// The material of the piece's face whose centroid is nearest `p` (relative to its pivot).
std::uint8_t faceMaterial(const Mesh& mesh, const glm::dvec3& p) {
    double best = std::numeric_limits<double>::max();
    std::size_t nearest = 0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const glm::dvec3 c = (glm::dvec3(mesh.positions[mesh.indices[3 * t]]) +
                              glm::dvec3(mesh.positions[mesh.indices[3 * t + 1]]) +
                              glm::dvec3(mesh.positions[mesh.indices[3 * t + 2]])) / 3.0;
        const double d = glm::dot(c - p, c - p);
        if (d < best) best = d, nearest = t;
    }
    return materialOf(mesh, nearest);
}

// The thickness of the box with the piece's principal moments: c² = 6 (I1 + I2 − I3) / m.
double thickness(const RigidPiece& piece) {
    const glm::dvec3 m = principalInertia(piece.inertia).moments;
    const double lo = std::min({m.x, m.y, m.z}), hi = std::max({m.x, m.y, m.z});
    const double mid = m.x + m.y + m.z - lo - hi;
    return std::sqrt(std::max(0.0, 6.0 * (lo + mid - hi) / piece.mass));
}

// What the chips of one piece need to know of it, computed once.
struct PieceDebris {
    std::uint8_t material = 0;
    double density = 0.0;    // kg/m³
    double thickness = 0.0;  // m
};

PieceDebris pieceDebris(const RigidPiece& piece) {
    std::vector<glm::dvec3> positions(piece.mesh.positions.begin(), piece.mesh.positions.end());
    const double volume = std::abs(computeMassProperties(positions, piece.mesh.indices, 1.0).volume);
    return {mainMaterial(piece.mesh), volume > 0.0 ? piece.mass / volume : 0.0, thickness(piece)};
}

// An octahedron with vertices at ±radii along `axes`, flat-shaded, box-mapped UVs in metres.
Mesh octahedron(const glm::dvec3& radii, const glm::dquat& axes, std::uint8_t material) {
    Mesh mesh;
    for (int octant = 0; octant < 8; ++octant) {
        const glm::dvec3 s((octant & 1) ? -1.0 : 1.0, (octant & 2) ? -1.0 : 1.0, (octant & 4) ? -1.0 : 1.0);
        std::array<glm::dvec3, 3> v{axes * glm::dvec3(s.x * radii.x, 0, 0), axes * glm::dvec3(0, s.y * radii.y, 0),
                                    axes * glm::dvec3(0, 0, s.z * radii.z)};
        if (s.x * s.y * s.z < 0.0) std::swap(v[1], v[2]);  // outward, counter-clockwise
        const glm::dvec3 n = glm::normalize(glm::cross(v[1] - v[0], v[2] - v[0]));
        const glm::dvec3 a = glm::abs(n);
        for (const glm::dvec3& p : v) {
            mesh.indices.push_back(std::uint32_t(mesh.positions.size()));
            mesh.positions.emplace_back(p);
            mesh.normals.emplace_back(n);
            mesh.uv0.emplace_back(a.x >= a.y && a.x >= a.z ? glm::dvec2(p.z, p.y)
                                  : a.y >= a.z             ? glm::dvec2(p.x, p.z)
                                                           : glm::dvec2(p.x, p.y));
            mesh.materialIds.push_back(material);
        }
    }
    return mesh;
}

glm::dquat randomRotation(Rng& rng) {  // Shoemake's uniform quaternion
    const double u1 = rng.uniform(), u2 = rng.uniform(0.0, glm::two_pi<double>()), u3 = rng.uniform(0.0, glm::two_pi<double>());
    const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
    return glm::normalize(glm::dquat(b * std::cos(u3), a * std::sin(u2), a * std::cos(u2), b * std::sin(u3)));
}

// Two unit vectors across `normal` (any two for a zero normal).
std::pair<glm::dvec3, glm::dvec3> tangents(glm::dvec3 normal) {
    normal = glm::length(normal) > 0.0 ? glm::normalize(normal) : glm::dvec3(0.0, 1.0, 0.0);
    const glm::dvec3 helper = std::abs(normal.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
    const glm::dvec3 t = glm::normalize(glm::cross(normal, helper));
    return {t, glm::cross(normal, t)};
}

class Emitter {
public:
    Emitter(std::span<const RigidPiece> pieces, std::span<const Bond> bonds, const SimulationSettings& settings)
        : pieces_(pieces), bonds_(bonds), settings_(settings), d_(settings.debris) {}

    // Appends the chips of `bond`, which broke at `time`, to `out` (at most `room`).
    void emit(std::size_t bondIndex, double time, std::size_t room, std::vector<ChipSeed>& out) {
        const Bond& bond = bonds_[bondIndex];
        const PieceDebris& a = of(bond.a);
        const PieceDebris& b = of(bond.b);
        const MaterialDebris kind = debrisOf(a.material), kindB = debrisOf(b.material);
        Rng rng(deriveSeed(settings_.seed, "debris-chips", bondIndex));
        const double expected = bond.area * d_.chipsPerSquareMetre * 0.5 * (kind.count + kindB.count);
        const int count = std::min({int(std::floor(expected + rng.uniform())), d_.maxChipsPerBond, int(room)});
        const double largest = 0.7 * std::min(a.thickness, b.thickness);
        const int release = releaseFrame(time, settings_);
        const auto [t1, t2] = tangents(bond.normal);
        for (int k = 0; k < count; ++k) {
            const bool inA = (k % 2) == 0;
            const std::uint32_t parent = inA ? bond.a : bond.b;
            const PieceDebris& from = inA ? a : b;
            const double size = std::min(largest, d_.chipSize * (inA ? kind : kindB).size * rng.uniform(0.6, 1.4));
            if (!(size > 1e-3) || !(from.density > 0.0)) continue;
            ChipSeed chip;
            chip.parent = parent;
            chip.other = inA ? bond.b : bond.a;
            chip.releaseFrame = release;
            chip.radii = 0.5 * size * glm::dvec3(rng.uniform(0.6, 1.0), rng.uniform(0.4, 0.8), rng.uniform(0.25, 0.6));
            chip.axes = randomRotation(rng);
            const glm::dvec3 place = bond.centroid + 0.25 * size * (rng.uniform(-1.0, 1.0) * t1 + rng.uniform(-1.0, 1.0) * t2);
            const glm::dvec3 out2 = glm::normalize(randomUnitVector(rng) + glm::dvec3(0.0, 0.5, 0.0));
            chip.spray = d_.spraySpeed * rng.uniform(0.5, 1.5) * out2;
            chip.piece = chipPiece(chip, place, faceMaterial(pieces_[parent].mesh, place - pieces_[parent].centerOfMass),
                                   from.density);
            out.push_back(std::move(chip));
        }
    }

private:
    const PieceDebris& of(std::uint32_t piece) {
        auto it = cache_.find(piece);
        if (it == cache_.end()) it = cache_.emplace(piece, pieceDebris(pieces_[piece])).first;
        return it->second;
    }

    static RigidPiece chipPiece(const ChipSeed& chip, const glm::dvec3& place, std::uint8_t material, double density) {
        const glm::dvec3 r = chip.radii;
        RigidPiece piece;
        piece.mesh = octahedron(r, chip.axes, material);
        piece.mass = density * 4.0 / 3.0 * r.x * r.y * r.z;
        piece.centerOfMass = place;
        const glm::dvec3 moments = octahedronMoments(piece.mass, r);
        const glm::dmat3 axes = glm::mat3_cast(chip.axes);
        piece.inertia = axes * glm::dmat3(moments.x, 0, 0, 0, moments.y, 0, 0, 0, moments.z) * glm::transpose(axes);
        return piece;
    }

    std::span<const RigidPiece> pieces_;
    std::span<const Bond> bonds_;
    const SimulationSettings& settings_;
    const DebrisSettings& d_;
    std::map<std::uint32_t, PieceDebris> cache_;
};

}  // namespace

std::uint8_t mainMaterial(const Mesh& mesh) {
    std::array<double, kMaterialIdCount> area{};
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const glm::dvec3 a(mesh.positions[mesh.indices[3 * t]]), b(mesh.positions[mesh.indices[3 * t + 1]]),
            c(mesh.positions[mesh.indices[3 * t + 2]]);
        area[materialOf(mesh, t)] += glm::length(glm::cross(b - a, c - a));
    }
    return std::uint8_t(std::max_element(area.begin(), area.end()) - area.begin());
}

glm::dvec3 randomUnitVector(Rng& rng) {
    const double z = rng.uniform(-1.0, 1.0), phi = rng.uniform(0.0, glm::two_pi<double>());
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return {r * std::cos(phi), z, r * std::sin(phi)};
}

glm::dvec3 octahedronMoments(double mass, const glm::dvec3& r) {
    return mass / 10.0 * glm::dvec3(r.y * r.y + r.z * r.z, r.x * r.x + r.z * r.z, r.x * r.x + r.y * r.y);
}

int releaseFrame(double time, const SimulationSettings& settings) {
    return std::clamp(int(std::ceil(time * settings.fps - 1e-9)), 1, std::max(1, settings.frames - 1));
}

std::vector<ChipSeed> emitChips(std::span<const RigidPiece> pieces, std::span<const Bond> bonds,
                                const SimulationResult& result, const SimulationSettings& settings) {
    std::vector<ChipSeed> chips;
    if (!settings.debris.chips || settings.frames < 2) return chips;
    Emitter emitter(pieces, bonds, settings);
    for (const BondBreak& b : result.breaks) {
        if (chips.size() >= settings.debris.maxChips) break;
        emitter.emit(b.bond, b.time, settings.debris.maxChips - chips.size(), chips);
    }
    const std::size_t width = std::to_string(std::max<std::size_t>(chips.size(), 1) - 1).size();
    for (std::size_t k = 0; k < chips.size(); ++k) {
        std::string digits = std::to_string(k);
        chips[k].piece.name = "chip_" + std::string(width - std::min(width, digits.size()), '0') + digits;
    }
    return chips;
}

}  // namespace dawnforge::sim
