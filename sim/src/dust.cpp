// Dust where bonds broke (debris.hpp): puffs that leave the crack, rise, spread and fade.
//
// A bond that broke gives ⌊area × rate × material + u⌋ puffs (masonry 1, wood 0.5, glass 0.2,
// metal none), at most four a bond and `maxPuffs` in all. A puff leaves the crack's centroid
// (carried by the bond's first piece) in the first frame after the break, with 0.4 of that
// piece's velocity there, 1 m/s out of the crack (either way along its normal), a random
// 0.6 m/s and 0.4 m/s up; the air slows it with a time constant
// of 0.8 s towards a rise of 0.3 m/s (the closed form of v' = (w − v) / τ), it never sinks
// below the ground plane, it grows from its size to four times that (time constant 1.5 s), and
// its opacity rises to 0.55 in 0.2 s and falls as (1 − t / life)². Every random number comes
// from (seed, bond): the same dust on any thread count. No collisions but the ground: dust is
// air, and it is drawn soft.
#include "debris.hpp"

#include <dawnforge/core/materials.hpp>
#include <dawnforge/core/seed.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace dawnforge::sim {

namespace {

constexpr double kDrag = 0.8;         // s: the air's time constant
constexpr double kRise = 0.3;         // m/s: the warm dust's rise in still air
constexpr double kGrowth = 1.5;       // s: time constant of a puff's growth
constexpr double kFadeIn = 0.2;       // s
constexpr double kOpacity = 0.55;     // at its densest
constexpr int kPuffsPerBond = 4;
constexpr double kBillow = 1.0;     // m/s out of the crack, either way along its normal

double dustOf(std::uint8_t material) {
    switch (material) {
        case kGlass: return 0.2;
        case kWood: return 0.5;
        case kMetal: return 0.0;
        default: return 1.0;
    }
}

struct Puff {
    int born = 0;             // frame
    glm::dvec3 start{0.0};    // m
    glm::dvec3 velocity{0.0}; // m/s at birth
    double size = 0.0;        // m, at birth
    double life = 0.0;        // s
};

// A point carried by `piece` from its rest place, at `frame`.
glm::dvec3 carried(const SimulationResult& r, std::span<const RigidPiece> pieces, std::size_t piece, int frame,
                   const glm::dvec3& rest) {
    const float* t = r.transforms.data() + (std::size_t(frame) * r.pieces + piece) * 7;
    const glm::dquat q(t[6], t[3], t[4], t[5]);
    return glm::dvec3(t[0], t[1], t[2]) + q * (rest - pieces[piece].centerOfMass);
}

// The puffs of every broken bond, in the order they broke.
std::vector<Puff> emitPuffs(std::span<const RigidPiece> pieces, std::span<const Bond> bonds, const SimulationSettings& s,
                            const SimulationResult& r) {
    const DebrisSettings& d = s.debris;
    std::vector<Puff> puffs;
    std::vector<double> dustiness(pieces.size(), -1.0);
    const auto of = [&](std::uint32_t piece) {
        if (dustiness[piece] < 0.0) dustiness[piece] = dustOf(mainMaterial(pieces[piece].mesh));
        return dustiness[piece];
    };
    for (const BondBreak& b : r.breaks) {
        const Bond& bond = bonds[b.bond];
        Rng rng(deriveSeed(s.seed, "debris-dust", b.bond));
        const double expected = bond.area * d.puffsPerSquareMetre * 0.5 * (of(bond.a) + of(bond.b));
        const int count = std::min({int(std::floor(expected + rng.uniform())), kPuffsPerBond, int(d.maxPuffs - puffs.size())});
        const int born = releaseFrame(b.time, s);
        const glm::dvec3 here = carried(r, pieces, bond.a, born, bond.centroid);
        const glm::dvec3 before = carried(r, pieces, bond.a, born - 1, bond.centroid);
        for (int k = 0; k < count; ++k) {
            Puff p;
            p.born = born;
            p.size = d.puffSize * rng.uniform(0.7, 1.3);
            p.start = here + 0.25 * p.size * randomUnitVector(rng);
            const double side = rng.uniform() < 0.5 ? -1.0 : 1.0;
            p.velocity = 0.4 * (here - before) * s.fps + 0.6 * randomUnitVector(rng) + kBillow * side * bond.normal +
                         glm::dvec3(0.0, 0.4, 0.0);
            p.life = d.puffLife * rng.uniform(0.7, 1.3);
            puffs.push_back(p);
        }
        if (puffs.size() >= d.maxPuffs) break;
    }
    return puffs;
}

// x y z size opacity of `p` at `frame`.
std::array<float, 5> puffAt(const Puff& p, int frame, double fps, double ground) {
    const double t = std::max(0.0, double(frame - p.born) / fps);
    const glm::dvec3 air(0.0, kRise, 0.0);
    glm::dvec3 x = p.start + air * t + (p.velocity - air) * kDrag * (1.0 - std::exp(-t / kDrag));
    const double size = p.size * (1.0 + 3.0 * (1.0 - std::exp(-t / kGrowth)));
    x.y = std::max(x.y, ground + 0.5 * size);
    const double fade = std::max(0.0, 1.0 - t / p.life);
    const double opacity = frame < p.born ? 0.0 : kOpacity * std::min(1.0, t / kFadeIn) * fade * fade;
    return {float(x.x), float(x.y), float(x.z), float(size), float(opacity)};
}

}  // namespace

void addDust(std::span<const RigidPiece> pieces, std::span<const Bond> bonds, const SimulationSettings& settings,
             SimulationResult& result) {
    if (!settings.debris.dust || settings.frames < 2) return;
    const std::vector<Puff> puffs = emitPuffs(pieces, bonds, settings, result);
    result.dustPuffs = puffs.size();
    result.dust.clear();
    result.dust.reserve(std::size_t(settings.frames) * puffs.size() * 5);
    for (int f = 0; f < settings.frames; ++f)
        for (const Puff& p : puffs) {
            const std::array<float, 5> v = puffAt(p, f, settings.fps, result.groundHeight);
            result.dust.insert(result.dust.end(), v.begin(), v.end());
        }
}

}  // namespace dawnforge::sim
